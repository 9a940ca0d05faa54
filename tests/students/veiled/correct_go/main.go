// Ray tracer for HW4.
//
//	./tracer scene_description_file output_image
//
// The scene file is read as a stream of words: a section keyword (camera, sphere,
// plane, light) or an attribute keyword followed by its values. The picture is
// written as a binary PPM (P6).
package main

import (
	"bufio"
	"fmt"
	"math"
	"os"
	"path/filepath"
	"strconv"
	"strings"
)

// ----------------------------------------------------------------------------
// vectors

type Vec3 struct{ X, Y, Z float64 }

func (a Vec3) Add(b Vec3) Vec3      { return Vec3{a.X + b.X, a.Y + b.Y, a.Z + b.Z} }
func (a Vec3) Sub(b Vec3) Vec3      { return Vec3{a.X - b.X, a.Y - b.Y, a.Z - b.Z} }
func (a Vec3) Mul(b Vec3) Vec3      { return Vec3{a.X * b.X, a.Y * b.Y, a.Z * b.Z} }
func (a Vec3) Scale(s float64) Vec3 { return Vec3{a.X * s, a.Y * s, a.Z * s} }
func (a Vec3) Dot(b Vec3) float64   { return a.X*b.X + a.Y*b.Y + a.Z*b.Z }
func (a Vec3) Len() float64         { return math.Sqrt(a.Dot(a)) }
func (a Vec3) Neg() Vec3            { return Vec3{-a.X, -a.Y, -a.Z} }
func (a Vec3) Cross(b Vec3) Vec3 {
	return Vec3{a.Y*b.Z - a.Z*b.Y, a.Z*b.X - a.X*b.Z, a.X*b.Y - a.Y*b.X}
}
func (a Vec3) Unit() Vec3 {
	l := a.Len()
	if l == 0 {
		return a
	}
	return a.Scale(1 / l)
}
func clampf(x float64) float64 {
	if x < 0 {
		return 0
	}
	if x > 1 {
		return 1
	}
	return x
}
func (a Vec3) Clamp01() Vec3 { return Vec3{clampf(a.X), clampf(a.Y), clampf(a.Z)} }

type Ray struct {
	Orig, Dir Vec3 // Dir is a unit vector
}

func (r Ray) At(t float64) Vec3 { return r.Orig.Add(r.Dir.Scale(t)) }

// ----------------------------------------------------------------------------
// textures

type Image struct {
	W, H int
	Px   []Vec3 // row-major, top row first, values in [0,1]
}

// Sample does a bilinear lookup; u runs left to right, v top to bottom.
func (im *Image) Sample(u, v float64) Vec3 {
	x := clampf(u)*float64(im.W) - 0.5
	y := clampf(v)*float64(im.H) - 0.5
	x0 := int(math.Floor(x))
	y0 := int(math.Floor(y))
	fx := x - float64(x0)
	fy := y - float64(y0)
	at := func(i, j int) Vec3 {
		if i < 0 {
			i = 0
		}
		if j < 0 {
			j = 0
		}
		if i >= im.W {
			i = im.W - 1
		}
		if j >= im.H {
			j = im.H - 1
		}
		return im.Px[j*im.W+i]
	}
	top := at(x0, y0).Scale(1 - fx).Add(at(x0+1, y0).Scale(fx))
	bot := at(x0, y0+1).Scale(1 - fx).Add(at(x0+1, y0+1).Scale(fx))
	return top.Scale(1 - fy).Add(bot.Scale(fy))
}

type ppmReader struct {
	data []byte
	pos  int
}

func isSpace(c byte) bool {
	return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'
}

func (r *ppmReader) word() (string, bool) {
	for r.pos < len(r.data) {
		c := r.data[r.pos]
		if c == '#' {
			for r.pos < len(r.data) && r.data[r.pos] != '\n' && r.data[r.pos] != '\r' {
				r.pos++
			}
		} else if isSpace(c) {
			r.pos++
		} else {
			break
		}
	}
	start := r.pos
	for r.pos < len(r.data) && !isSpace(r.data[r.pos]) && r.data[r.pos] != '#' {
		r.pos++
	}
	return string(r.data[start:r.pos]), r.pos > start
}

func (r *ppmReader) number() (int, error) {
	w, ok := r.word()
	if !ok {
		return 0, fmt.Errorf("unexpected end of file")
	}
	n, err := strconv.Atoi(w)
	if err != nil || n < 0 {
		return 0, fmt.Errorf("bad number %q", w)
	}
	return n, nil
}

func readPPM(path string) (*Image, error) {
	data, err := os.ReadFile(path)
	if err != nil {
		return nil, err
	}
	r := &ppmReader{data: data}
	magic, _ := r.word()
	if magic != "P3" && magic != "P6" {
		return nil, fmt.Errorf("%s: not a P3 or P6 file", path)
	}
	var hdr [3]int
	for i := range hdr {
		if hdr[i], err = r.number(); err != nil {
			return nil, fmt.Errorf("%s: header: %v", path, err)
		}
	}
	w, h, maxv := hdr[0], hdr[1], hdr[2]
	if w <= 0 || h <= 0 || maxv <= 0 || maxv > 65535 || w*h > 100000000 {
		return nil, fmt.Errorf("%s: bad header values", path)
	}
	im := &Image{W: w, H: h, Px: make([]Vec3, w*h)}
	m := float64(maxv)
	vals := make([]float64, 3*w*h)
	if magic == "P3" {
		for i := range vals {
			n, err := r.number()
			if err != nil {
				return nil, fmt.Errorf("%s: pixel data: %v", path, err)
			}
			vals[i] = float64(n) / m
		}
	} else {
		p := r.pos + 1 // single whitespace byte after maxval
		size := 1
		if maxv > 255 {
			size = 2
		}
		if p+len(vals)*size > len(data) {
			return nil, fmt.Errorf("%s: pixel data too short", path)
		}
		for i := range vals {
			var n int
			if size == 1 {
				n = int(data[p+i])
			} else {
				n = int(data[p+2*i])<<8 | int(data[p+2*i+1])
			}
			vals[i] = float64(n) / m
		}
	}
	for i := range im.Px {
		im.Px[i] = Vec3{vals[3*i], vals[3*i+1], vals[3*i+2]}
	}
	return im, nil
}

// ----------------------------------------------------------------------------
// scene objects

type Material struct {
	Color Vec3
	Refl  float64
	Tex   *Image
}

type Shape interface {
	// Hit returns the nearest distance along r greater than tmin, if any.
	Hit(r Ray, tmin float64) (float64, bool)
	NormalAt(p Vec3) Vec3
	UV(p Vec3) (float64, float64)
	Mat() *Material
}

type Sphere struct {
	C Vec3
	R float64
	M Material
}

func (s *Sphere) Mat() *Material { return &s.M }

func (s *Sphere) Hit(r Ray, tmin float64) (float64, bool) {
	oc := r.Orig.Sub(s.C)
	b := oc.Dot(r.Dir)
	c := oc.Dot(oc) - s.R*s.R
	disc := b*b - c
	if disc < 0 {
		return 0, false
	}
	sq := math.Sqrt(disc)
	if t := -b - sq; t > tmin {
		return t, true
	}
	if t := -b + sq; t > tmin {
		return t, true
	}
	return 0, false
}

func (s *Sphere) NormalAt(p Vec3) Vec3 { return p.Sub(s.C).Scale(1 / s.R) }

// UV: longitude around the y axis (u = 0.5 faces the camera), latitude from the top.
func (s *Sphere) UV(p Vec3) (float64, float64) {
	q := p.Sub(s.C).Scale(1 / s.R)
	u := 0.5 + math.Atan2(q.X, q.Z)/(2*math.Pi)
	v := 0.5 - math.Asin(math.Max(-1, math.Min(1, q.Y)))/math.Pi
	return u, v
}

type Plane struct {
	C          Vec3
	W, H       float64
	N, Up, Rgt Vec3
	M          Material
}

func (pl *Plane) Mat() *Material { return &pl.M }

func (pl *Plane) Hit(r Ray, tmin float64) (float64, bool) {
	den := pl.N.Dot(r.Dir)
	if math.Abs(den) < 1e-12 {
		return 0, false
	}
	t := pl.C.Sub(r.Orig).Dot(pl.N) / den
	if t <= tmin {
		return 0, false
	}
	d := r.At(t).Sub(pl.C)
	if math.Abs(d.Dot(pl.Rgt)) > pl.W/2 || math.Abs(d.Dot(pl.Up)) > pl.H/2 {
		return 0, false
	}
	return t, true
}

func (pl *Plane) NormalAt(p Vec3) Vec3 { return pl.N }

// UV stretches the texture over the rectangle, top edge towards headup.
func (pl *Plane) UV(p Vec3) (float64, float64) {
	d := p.Sub(pl.C)
	return d.Dot(pl.Rgt)/pl.W + 0.5, 0.5 - d.Dot(pl.Up)/pl.H
}

type Light struct {
	Pos, Col Vec3
}

type Scene struct {
	Size   int
	Shapes []Shape
	Lights []Light
}

// ----------------------------------------------------------------------------
// parsing

type token struct {
	text string
	line int
}

type parser struct {
	toks    []token
	i       int
	dir     string
	texture map[string]*Image
}

func (p *parser) more() bool { return p.i < len(p.toks) }

func (p *parser) next() token {
	t := p.toks[p.i]
	p.i++
	return t
}

func (p *parser) nums(key token, n int) ([]float64, error) {
	out := make([]float64, n)
	for k := 0; k < n; k++ {
		if !p.more() {
			return nil, fmt.Errorf("line %d: %s needs %d numbers", key.line, key.text, n)
		}
		t := p.next()
		if t.line != key.line {
			return nil, fmt.Errorf("line %d: %s needs %d numbers", key.line, key.text, n)
		}
		v, err := strconv.ParseFloat(t.text, 64)
		if err != nil || math.IsInf(v, 0) || math.IsNaN(v) {
			return nil, fmt.Errorf("line %d: %q is not a number", t.line, t.text)
		}
		out[k] = v
	}
	// anything else left on the same line is one number too many
	if p.more() && p.toks[p.i].line == key.line {
		return nil, fmt.Errorf("line %d: too many values for %s", key.line, key.text)
	}
	return out, nil
}

func (p *parser) vec(key token) (Vec3, error) {
	v, err := p.nums(key, 3)
	if err != nil {
		return Vec3{}, err
	}
	return Vec3{v[0], v[1], v[2]}, nil
}

func (p *parser) loadTexture(name string) (*Image, error) {
	cands := []string{name}
	if !filepath.IsAbs(name) {
		cands = []string{filepath.Join(p.dir, name), name}
	}
	for _, c := range cands {
		if im, ok := p.texture[c]; ok {
			return im, nil
		}
		if st, err := os.Stat(c); err != nil || st.IsDir() {
			continue
		}
		im, err := readPPM(c)
		if err != nil {
			return nil, err
		}
		p.texture[c] = im
		return im, nil
	}
	return nil, fmt.Errorf("texture %q not found", name)
}

func isSection(w string) bool {
	return w == "camera" || w == "sphere" || w == "plane" || w == "light"
}

func parseScene(path string) (*Scene, error) {
	raw, err := os.ReadFile(path)
	if err != nil {
		return nil, fmt.Errorf("cannot read scene: %v", err)
	}
	p := &parser{dir: filepath.Dir(path), texture: map[string]*Image{}}
	for n, line := range strings.Split(string(raw), "\n") {
		line = strings.TrimSpace(line)
		if strings.HasPrefix(line, "#") {
			continue
		}
		for _, f := range strings.Fields(line) {
			p.toks = append(p.toks, token{f, n + 1})
		}
	}

	sc := &Scene{}
	camera := false
	for p.more() {
		key := p.next()
		word := strings.ToLower(key.text)
		switch word {
		case "camera":
			if camera {
				return nil, fmt.Errorf("line %d: second camera", key.line)
			}
			v, err := p.nums(key, 1)
			if err != nil {
				return nil, err
			}
			if v[0] < 1 || v[0] > 20000 || v[0] != math.Trunc(v[0]) {
				return nil, fmt.Errorf("line %d: bad resolution", key.line)
			}
			sc.Size = int(v[0])
			camera = true
		case "sphere", "plane", "light":
			if _, err := p.nums(key, 0); err != nil {
				return nil, err
			}
			if err := p.section(sc, word, key.line); err != nil {
				return nil, err
			}
		default:
			return nil, fmt.Errorf("line %d: unknown keyword %q", key.line, key.text)
		}
	}
	if !camera {
		return nil, fmt.Errorf("no camera in scene")
	}
	return sc, nil
}

// section reads the attributes of one sphere / plane / light until the next section word.
func (p *parser) section(sc *Scene, kind string, line int) error {
	mat := Material{Color: Vec3{1, 1, 1}}
	var center, normal, headup, loc Vec3
	lcol := Vec3{1, 1, 1}
	var dims []float64
	seen := map[string]bool{}
	for p.more() && !isSection(strings.ToLower(p.toks[p.i].text)) {
		key := p.next()
		attr := strings.ToLower(key.text)
		var err error
		switch {
		case kind != "light" && attr == "dimension":
			n := 1
			if kind == "plane" {
				n = 2
			}
			dims, err = p.nums(key, n)
		case kind != "light" && attr == "center":
			center, err = p.vec(key)
		case kind != "light" && attr == "color":
			mat.Color, err = p.vec(key)
		case kind != "light" && attr == "reflectivity":
			var v []float64
			v, err = p.nums(key, 1)
			if err == nil {
				mat.Refl = v[0]
			}
		case kind != "light" && attr == "texture":
			if !p.more() || p.toks[p.i].line != key.line {
				return fmt.Errorf("line %d: texture needs a file name", key.line)
			}
			name := p.next()
			if p.more() && p.toks[p.i].line == key.line {
				return fmt.Errorf("line %d: too many values for texture", key.line)
			}
			mat.Tex, err = p.loadTexture(name.text)
		case kind == "plane" && attr == "normal":
			normal, err = p.vec(key)
		case kind == "plane" && attr == "headup":
			headup, err = p.vec(key)
		case kind == "light" && attr == "location":
			loc, err = p.vec(key)
		case kind == "light" && attr == "color":
			lcol, err = p.vec(key)
		default:
			return fmt.Errorf("line %d: unknown keyword %q in %s", key.line, key.text, kind)
		}
		if err != nil {
			return err
		}
		seen[attr] = true
	}

	need := func(attrs ...string) error {
		for _, a := range attrs {
			if !seen[a] {
				return fmt.Errorf("%s starting on line %d has no %s", kind, line, a)
			}
		}
		return nil
	}
	switch kind {
	case "light":
		if err := need("location"); err != nil {
			return err
		}
		sc.Lights = append(sc.Lights, Light{Pos: loc, Col: lcol})
	case "sphere":
		if err := need("center", "dimension"); err != nil {
			return err
		}
		if dims[0] <= 0 {
			return fmt.Errorf("sphere on line %d: dimension must be positive", line)
		}
		sc.Shapes = append(sc.Shapes, &Sphere{C: center, R: dims[0], M: mat})
	case "plane":
		if err := need("center", "dimension", "normal"); err != nil {
			return err
		}
		if dims[0] <= 0 || dims[1] <= 0 {
			return fmt.Errorf("plane on line %d: dimension must be positive", line)
		}
		if normal.Len() < 1e-12 {
			return fmt.Errorf("plane on line %d: zero normal", line)
		}
		n := normal.Unit()
		if !seen["headup"] {
			headup = Vec3{0, 1, 0}
		}
		up := headup.Sub(n.Scale(headup.Dot(n)))
		if up.Len() < 1e-9 {
			headup = Vec3{0, 0, -1}
			if math.Abs(n.Z) > 0.9 {
				headup = Vec3{0, 1, 0}
			}
			up = headup.Sub(n.Scale(headup.Dot(n)))
		}
		up = up.Unit()
		sc.Shapes = append(sc.Shapes, &Plane{C: center, W: dims[0], H: dims[1], N: n, Up: up,
			Rgt: up.Cross(n).Unit(), M: mat})
	}
	return nil
}

// ----------------------------------------------------------------------------
// shading

const (
	tMin      = 1e-6
	offset    = 1e-3
	maxDepth  = 6
	ka        = 0.12
	kdWeight  = 0.9
	ks        = 0.5
	shininess = 32
)

type hitRec struct {
	t     float64
	shape Shape
}

func (sc *Scene) nearest(r Ray) (hitRec, bool) {
	best := hitRec{t: math.Inf(1)}
	found := false
	for _, s := range sc.Shapes {
		if t, ok := s.Hit(r, tMin); ok && t < best.t {
			best = hitRec{t, s}
			found = true
		}
	}
	return best, found
}

// occluded reports whether something lies on the segment from p towards a light dist away.
func (sc *Scene) occluded(p, dir Vec3, dist float64) bool {
	r := Ray{p, dir}
	for _, s := range sc.Shapes {
		if t, ok := s.Hit(r, tMin); ok && t < dist {
			return true
		}
	}
	return false
}

// background is what a ray that hits nothing sees.
func background(dir Vec3) Vec3 {
	return Vec3{}
}

func (sc *Scene) trace(r Ray, depth int) Vec3 {
	h, ok := sc.nearest(r)
	if !ok {
		return background(r.Dir)
	}
	p := r.At(h.t)
	m := h.shape.Mat()
	n := h.shape.NormalAt(p)
	if _, isPlane := h.shape.(*Plane); isPlane && n.Dot(r.Dir) > 0 {
		n = n.Neg() // planes are two-sided: use the side facing the ray
	}
	base := m.Color
	if m.Tex != nil {
		base = base.Mul(m.Tex.Sample(h.shape.UV(p)))
	}
	view := r.Dir.Neg()
	lifted := p.Add(n.Scale(offset))

	col := base.Scale(ka)
	for _, l := range sc.Lights {
		toL := l.Pos.Sub(lifted)
		dist := toL.Len()
		L := toL.Scale(1 / dist)
		ndl := n.Dot(L)
		if ndl <= 0 {
			continue
		}
		if sc.occluded(lifted, L, dist) {
			continue
		}
		col = col.Add(l.Col.Mul(base).Scale(kdWeight * ndl))
		refl := n.Scale(2 * ndl).Sub(L)
		if rv := refl.Dot(view); rv > 0 {
			col = col.Add(l.Col.Scale(ks * math.Pow(rv, shininess)))
		}
	}

	if m.Refl > 0 && depth < maxDepth {
		rd := n.Scale(2 * n.Dot(view)).Sub(view).Unit()
		rc := sc.trace(Ray{lifted, rd}, depth+1)
		col = col.Add(rc.Scale(m.Refl))
	}
	return col
}

// ----------------------------------------------------------------------------

func render(sc *Scene) []byte {
	n := sc.Size
	img := make([]byte, 0, 3*n*n)
	for j := 0; j < n; j++ {
		for i := 0; i < n; i++ {
			// corner of the pixel on the image plane z = -1
			x := -0.5 + float64(i)/float64(n)
			y := 0.5 - float64(j)/float64(n)
			c := sc.trace(Ray{Vec3{}, Vec3{x, y, -1}.Unit()}, 0).Clamp01()
			img = append(img, byte(c.X*255.999), byte(c.Y*255.999), byte(c.Z*255.999))
		}
	}
	return img
}

func writePPM(path string, n int, px []byte) error {
	f, err := os.Create(path)
	if err != nil {
		return err
	}
	w := bufio.NewWriter(f)
	fmt.Fprintf(w, "P6\n%d %d\n255\n", n, n)
	w.Write(px)
	err = w.Flush()
	if cerr := f.Close(); err == nil {
		err = cerr
	}
	if err != nil {
		os.Remove(path)
	}
	return err
}

func main() {
	if len(os.Args) != 3 {
		fmt.Fprintln(os.Stderr, "usage: tracer scene_description_file output_image")
		os.Exit(1)
	}
	sc, err := parseScene(os.Args[1])
	if err != nil {
		fmt.Fprintln(os.Stderr, "error:", err)
		os.Exit(1)
	}
	if err := writePPM(os.Args[2], sc.Size, render(sc)); err != nil {
		fmt.Fprintln(os.Stderr, "error:", err)
		os.Exit(1)
	}
}
