// HW4 ray tracer (Go version).
// Usage: ./tracer scene_description_file output_image
package main

import (
	"bufio"
	"errors"
	"fmt"
	"math"
	"os"
	"path/filepath"
	"strconv"
	"strings"
)

// ---------- small vector library ----------

type Vec struct{ X, Y, Z float64 }

func (a Vec) Add(b Vec) Vec       { return Vec{a.X + b.X, a.Y + b.Y, a.Z + b.Z} }
func (a Vec) Sub(b Vec) Vec       { return Vec{a.X - b.X, a.Y - b.Y, a.Z - b.Z} }
func (a Vec) Mul(s float64) Vec   { return Vec{a.X * s, a.Y * s, a.Z * s} }
func (a Vec) Dot(b Vec) float64   { return a.X*b.X + a.Y*b.Y + a.Z*b.Z }
func (a Vec) Times(b Vec) Vec     { return Vec{a.X * b.X, a.Y * b.Y, a.Z * b.Z} }
func (a Vec) Len() float64        { return math.Sqrt(a.Dot(a)) }
func (a Vec) Cross(b Vec) Vec {
	return Vec{a.Y*b.Z - a.Z*b.Y, a.Z*b.X - a.X*b.Z, a.X*b.Y - a.Y*b.X}
}
func (a Vec) Norm() Vec {
	l := a.Len()
	if l == 0 {
		return a
	}
	return a.Mul(1 / l)
}

// ---------- scene ----------

type Texture struct {
	W, H int
	Pix  []Vec // row-major, top row first, values in [0,1]
}

// nearest texel lookup, u,v in [0,1], v=0 is the top row of the image
func (t *Texture) Lookup(u, v float64) Vec {
	u = u - math.Floor(u)
	v = math.Max(0, math.Min(1, v))
	x := int(u * float64(t.W))
	y := int(v * float64(t.H))
	if x >= t.W {
		x = t.W - 1
	}
	if y >= t.H {
		y = t.H - 1
	}
	if x < 0 {
		x = 0
	}
	if y < 0 {
		y = 0
	}
	return t.Pix[y*t.W+x]
}

const (
	Sphere = iota
	Plane
)

type Object struct {
	Kind         int
	Center       Vec
	Radius       float64 // sphere: dimension = radius
	W, H         float64 // plane: dimension w h (w along "right", h along headup)
	Normal       Vec
	Up, Right    Vec
	Color        Vec
	Reflectivity float64
	Tex          *Texture
	TexName      string
	has          map[string]bool
}

type Light struct {
	Pos, Color Vec
	has        map[string]bool
}

type Scene struct {
	Res     int
	Objects []*Object
	Lights  []*Light
}

// ---------- parser ----------

func parseNums(toks []string, n int, line int) ([]float64, error) {
	if len(toks) != n {
		return nil, fmt.Errorf("line %d: expected %d numbers after %q, got %d", line, n-1, toks[0], len(toks)-1)
	}
	out := make([]float64, 0, n-1)
	for _, s := range toks[1:] {
		f, err := strconv.ParseFloat(s, 64)
		if err != nil || math.IsNaN(f) || math.IsInf(f, 0) {
			return nil, fmt.Errorf("line %d: bad number %q", line, s)
		}
		out = append(out, f)
	}
	return out, nil
}

func parseScene(path string) (*Scene, error) {
	data, err := os.ReadFile(path)
	if err != nil {
		return nil, fmt.Errorf("cannot read scene file: %v", err)
	}
	dir := filepath.Dir(path)
	sc := &Scene{Res: -1}
	var curObj *Object
	var curLight *Light
	section := ""
	lines := strings.Split(string(data), "\n")
	for i, raw := range lines {
		ln := i + 1
		raw = strings.TrimRight(raw, "\r")
		if k := strings.IndexByte(raw, '#'); k >= 0 {
			raw = raw[:k]
		}
		toks := strings.Fields(raw)
		if len(toks) == 0 {
			continue
		}
		key := strings.ToLower(toks[0])
		switch key {
		case "camera":
			if sc.Res != -1 {
				return nil, fmt.Errorf("line %d: more than one camera", ln)
			}
			if len(toks) != 2 {
				return nil, fmt.Errorf("line %d: camera needs one resolution value", ln)
			}
			n, err := strconv.Atoi(toks[1])
			if err != nil || n <= 0 {
				return nil, fmt.Errorf("line %d: bad camera resolution %q", ln, toks[1])
			}
			sc.Res = n
			section = "camera"
			curObj, curLight = nil, nil
		case "sphere", "plane":
			if len(toks) != 1 {
				return nil, fmt.Errorf("line %d: unexpected text after %s", ln, key)
			}
			o := &Object{Color: Vec{1, 1, 1}, has: map[string]bool{}}
			if key == "sphere" {
				o.Kind = Sphere
			} else {
				o.Kind = Plane
			}
			sc.Objects = append(sc.Objects, o)
			curObj, curLight = o, nil
			section = key
		case "light":
			if len(toks) != 1 {
				return nil, fmt.Errorf("line %d: unexpected text after light", ln)
			}
			l := &Light{Color: Vec{1, 1, 1}, has: map[string]bool{}}
			sc.Lights = append(sc.Lights, l)
			curObj, curLight = nil, l
			section = key
		default:
			if curLight != nil {
				switch key {
				case "location":
					v, err := parseNums(toks, 4, ln)
					if err != nil {
						return nil, err
					}
					curLight.Pos = Vec{v[0], v[1], v[2]}
				case "color", "colour":
					v, err := parseNums(toks, 4, ln)
					if err != nil {
						return nil, err
					}
					curLight.Color = Vec{v[0], v[1], v[2]}
				default:
					return nil, fmt.Errorf("line %d: unknown light attribute %q", ln, toks[0])
				}
				curLight.has[key] = true
				continue
			}
			if curObj == nil {
				return nil, fmt.Errorf("line %d: %q outside of an object or light section (section %q)", ln, toks[0], section)
			}
			o := curObj
			switch key {
			case "dimension":
				if o.Kind == Sphere {
					v, err := parseNums(toks, 2, ln)
					if err != nil {
						return nil, err
					}
					if v[0] <= 0 {
						return nil, fmt.Errorf("line %d: sphere dimension must be positive", ln)
					}
					o.Radius = v[0]
				} else {
					v, err := parseNums(toks, 3, ln)
					if err != nil {
						return nil, err
					}
					if v[0] <= 0 || v[1] <= 0 {
						return nil, fmt.Errorf("line %d: plane dimensions must be positive", ln)
					}
					o.W, o.H = v[0], v[1]
				}
			case "center", "centre":
				v, err := parseNums(toks, 4, ln)
				if err != nil {
					return nil, err
				}
				o.Center = Vec{v[0], v[1], v[2]}
			case "color", "colour":
				v, err := parseNums(toks, 4, ln)
				if err != nil {
					return nil, err
				}
				o.Color = Vec{v[0], v[1], v[2]}
			case "reflectivity":
				v, err := parseNums(toks, 2, ln)
				if err != nil {
					return nil, err
				}
				o.Reflectivity = v[0]
			case "texture":
				if len(toks) < 2 {
					return nil, fmt.Errorf("line %d: texture needs a file name", ln)
				}
				name := strings.Join(toks[1:], " ")
				p := name
				if !filepath.IsAbs(p) {
					p = filepath.Join(dir, p)
				}
				t, err := loadPPM(p)
				if err != nil {
					return nil, fmt.Errorf("line %d: texture %q: %v", ln, name, err)
				}
				o.Tex = t
				o.TexName = name
			case "normal", "headup":
				if o.Kind != Plane {
					return nil, fmt.Errorf("line %d: %q is only allowed for planes", ln, toks[0])
				}
				v, err := parseNums(toks, 4, ln)
				if err != nil {
					return nil, err
				}
				vec := Vec{v[0], v[1], v[2]}
				if vec.Len() == 0 {
					return nil, fmt.Errorf("line %d: %s must not be zero", ln, key)
				}
				if key == "normal" {
					o.Normal = vec
				} else {
					o.Up = vec
				}
			default:
				return nil, fmt.Errorf("line %d: unknown keyword %q", ln, toks[0])
			}
			o.has[key] = true
		}
	}
	if sc.Res == -1 {
		return nil, errors.New("scene has no camera line")
	}
	for i, o := range sc.Objects {
		if !o.has["dimension"] || !o.has["center"] {
			return nil, fmt.Errorf("object %d: dimension and center are required", i+1)
		}
		if o.Kind == Plane {
			if !o.has["normal"] {
				return nil, fmt.Errorf("object %d: plane needs a normal", i+1)
			}
			o.Normal = o.Normal.Norm()
			up := o.Up
			if !o.has["headup"] {
				up = Vec{0, 1, 0}
			}
			up = up.Sub(o.Normal.Mul(up.Dot(o.Normal)))
			if up.Len() < 1e-9 { // headup parallel to normal: pick something else
				up = Vec{1, 0, 0}
				up = up.Sub(o.Normal.Mul(up.Dot(o.Normal)))
				if up.Len() < 1e-9 {
					up = Vec{0, 0, 1}.Sub(o.Normal.Mul(o.Normal.Z))
				}
			}
			o.Up = up.Norm()
			o.Right = o.Up.Cross(o.Normal).Norm()
		}
	}
	for i, l := range sc.Lights {
		if !l.has["location"] {
			return nil, fmt.Errorf("light %d: location is required", i+1)
		}
	}
	return sc, nil
}

// ---------- PPM texture loader (P3 and P6) ----------

func loadPPM(path string) (*Texture, error) {
	data, err := os.ReadFile(path)
	if err != nil {
		return nil, err
	}
	pos := 0
	// reads one header token, skipping whitespace and comments
	next := func() (string, error) {
		for pos < len(data) {
			c := data[pos]
			if c == '#' {
				for pos < len(data) && data[pos] != '\n' && data[pos] != '\r' {
					pos++
				}
			} else if c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f' {
				pos++
			} else {
				break
			}
		}
		start := pos
		for pos < len(data) {
			c := data[pos]
			if c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f' || c == '#' {
				break
			}
			pos++
		}
		if start == pos {
			return "", errors.New("unexpected end of file")
		}
		return string(data[start:pos]), nil
	}
	magic, err := next()
	if err != nil {
		return nil, err
	}
	if magic != "P3" && magic != "P6" {
		return nil, fmt.Errorf("not a P3/P6 PPM file (magic %q)", magic)
	}
	var hdr [3]int
	for i := 0; i < 3; i++ {
		s, err := next()
		if err != nil {
			return nil, err
		}
		hdr[i], err = strconv.Atoi(s)
		if err != nil || hdr[i] <= 0 {
			return nil, fmt.Errorf("bad PPM header value %q", s)
		}
	}
	w, h, maxv := hdr[0], hdr[1], hdr[2]
	if maxv > 65535 {
		return nil, fmt.Errorf("bad maxval %d", maxv)
	}
	t := &Texture{W: w, H: h, Pix: make([]Vec, w*h)}
	mf := float64(maxv)
	if magic == "P3" {
		for i := 0; i < w*h; i++ {
			var c [3]float64
			for k := 0; k < 3; k++ {
				s, err := next()
				if err != nil {
					return nil, fmt.Errorf("P3 data too short")
				}
				n, err := strconv.Atoi(s)
				if err != nil {
					return nil, fmt.Errorf("bad P3 sample %q", s)
				}
				c[k] = float64(n) / mf
			}
			t.Pix[i] = Vec{c[0], c[1], c[2]}
		}
		return t, nil
	}
	// P6: exactly one whitespace byte after maxval
	pos++
	bps := 1
	if maxv > 255 {
		bps = 2
	}
	need := w * h * 3 * bps
	if len(data)-pos < need {
		return nil, fmt.Errorf("P6 data too short")
	}
	for i := 0; i < w*h; i++ {
		var c [3]float64
		for k := 0; k < 3; k++ {
			var n int
			if bps == 1 {
				n = int(data[pos])
				pos++
			} else {
				n = int(data[pos])<<8 | int(data[pos+1])
				pos += 2
			}
			c[k] = float64(n) / mf
		}
		t.Pix[i] = Vec{c[0], c[1], c[2]}
	}
	return t, nil
}

// ---------- ray tracing ----------

const (
	Eps      = 1e-4
	MaxDepth = 5
	Ka       = 0.1
)

var Background = Vec{0, 0, 0}

// returns distance t along dir (dir need not be unit) or +Inf
func (o *Object) Intersect(orig, dir Vec) float64 {
	if o.Kind == Sphere {
		oc := orig.Sub(o.Center)
		a := dir.Dot(dir)
		b := 2 * dir.Dot(oc)
		c := oc.Dot(oc) - o.Radius*o.Radius
		disc := b*b - 4*a*c
		if disc < 0 {
			return math.Inf(1)
		}
		sq := math.Sqrt(disc)
		t0 := (-b - sq) / (2 * a)
		t1 := (-b + sq) / (2 * a)
		if t0 > Eps {
			return t0
		}
		if t1 > Eps {
			return t1
		}
		return math.Inf(1)
	}
	// plane: n.p + d = 0 with d = -n.center
	denom := o.Normal.Dot(dir)
	if math.Abs(denom) < 1e-12 {
		return math.Inf(1)
	}
	d := -o.Normal.Dot(o.Center)
	t := -(o.Normal.Dot(orig) + d) / denom
	if t <= Eps {
		return math.Inf(1)
	}
	p := orig.Add(dir.Mul(t))
	q := p.Sub(o.Center)
	if math.Abs(q.Dot(o.Right)) > o.W/2 || math.Abs(q.Dot(o.Up)) > o.H/2 {
		return math.Inf(1)
	}
	return t
}

func (o *Object) SurfaceColor(p Vec) Vec {
	if o.Tex == nil {
		return o.Color
	}
	var u, v float64
	if o.Kind == Sphere {
		n := p.Sub(o.Center).Norm()
		u = 0.5 + math.Atan2(n.Z, n.X)/(2*math.Pi)
		v = 0.5 - math.Asin(math.Max(-1, math.Min(1, n.Y)))/math.Pi
	} else {
		q := p.Sub(o.Center)
		u = q.Dot(o.Right)/o.W + 0.5
		v = 0.5 - q.Dot(o.Up)/o.H
	}
	return o.Tex.Lookup(u, v)
}

func closest(sc *Scene, orig, dir Vec) (*Object, float64) {
	var best *Object
	bt := math.Inf(1)
	for _, o := range sc.Objects {
		t := o.Intersect(orig, dir)
		if t < bt {
			bt, best = t, o
		}
	}
	return best, bt
}

func inShadow(sc *Scene, p, toLight Vec, dist float64) bool {
	for _, o := range sc.Objects {
		t := o.Intersect(p, toLight)
		if t < dist {
			return true
		}
	}
	return false
}

func trace(sc *Scene, orig, dir Vec, depth int) Vec {
	obj, t := closest(sc, orig, dir)
	if obj == nil {
		return Background
	}
	p := orig.Add(dir.Mul(t))
	var n Vec
	if obj.Kind == Sphere {
		n = p.Sub(obj.Center).Mul(1 / obj.Radius)
	} else {
		n = obj.Normal
	}
	d := dir.Norm()
	if n.Dot(d) > 0 { // two-sided: face the viewer
		n = n.Mul(-1)
	}
	base := obj.SurfaceColor(p)
	col := base.Mul(Ka)
	sp := p.Add(n.Mul(Eps))
	for _, l := range sc.Lights {
		lv := l.Pos.Sub(p)
		dist := lv.Len()
		L := lv.Mul(1 / dist)
		ndl := n.Dot(L)
		if ndl <= 0 {
			continue
		}
		if inShadow(sc, sp, L, dist) {
			continue
		}
		col = col.Add(base.Times(l.Color).Mul(ndl))
	}
	if obj.Reflectivity > 0 && depth < MaxDepth {
		v := d.Mul(-1)
		r := n.Mul(2 * n.Dot(v)).Sub(v).Norm()
		rc := trace(sc, sp, r, depth+1)
		col = col.Add(rc.Mul(obj.Reflectivity))
	}
	return col
}

func clamp01(x float64) float64 {
	if x < 0 {
		return 0
	}
	if x > 1 {
		return 1
	}
	return x
}

func render(sc *Scene) []byte {
	n := sc.Res
	img := make([]byte, 0, n*n*3)
	for j := 0; j < n; j++ {
		for i := 0; i < n; i++ {
			x := -0.5 + (float64(i)+0.5)/float64(n)
			y := 0.5 - (float64(j)+0.5)/float64(n)
			dir := Vec{x, y, -1}.Norm()
			c := trace(sc, Vec{0, 0, 0}, dir, 0)
			img = append(img,
				byte(math.Round(clamp01(c.X)*255)),
				byte(math.Round(clamp01(c.Y)*255)),
				byte(math.Round(clamp01(c.Z)*255)))
		}
	}
	return img
}

func writePPM(path string, n int, img []byte) error {
	f, err := os.Create(path)
	if err != nil {
		return err
	}
	w := bufio.NewWriter(f)
	fmt.Fprintf(w, "P6\n# HW4 ray tracer output\n%d %d\n255\n", n, n)
	w.Write(img)
	if err := w.Flush(); err != nil {
		f.Close()
		return err
	}
	return f.Close()
}

func main() {
	if len(os.Args) != 3 {
		fmt.Fprintln(os.Stderr, "usage: raytracer scene_description_file output_image")
		os.Exit(1)
	}
	sc, err := parseScene(os.Args[1])
	if err != nil {
		fmt.Fprintln(os.Stderr, "error:", err)
		os.Exit(1)
	}
	img := render(sc)
	if err := writePPM(os.Args[2], sc.Res, img); err != nil {
		fmt.Fprintln(os.Stderr, "error writing image:", err)
		os.Exit(1)
	}
}
