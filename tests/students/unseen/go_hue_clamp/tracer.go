// HW4 ray tracer (Go version)
// usage: ./tracer scene.txt out.ppm
//
// camera at the origin looking down -z, image plane 1x1 at z = -1
// spheres + finite planes, point lights, shadows, recursive reflection.
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

const (
	EPS      = 1e-4
	KA       = 0.1 // ambient constant
	MAXDEPTH = 5   // max reflection bounces
)

type Vec struct{ X, Y, Z float64 }

func (a Vec) Add(b Vec) Vec       { return Vec{a.X + b.X, a.Y + b.Y, a.Z + b.Z} }
func (a Vec) Sub(b Vec) Vec       { return Vec{a.X - b.X, a.Y - b.Y, a.Z - b.Z} }
func (a Vec) Scale(s float64) Vec { return Vec{a.X * s, a.Y * s, a.Z * s} }
func (a Vec) Mul(b Vec) Vec       { return Vec{a.X * b.X, a.Y * b.Y, a.Z * b.Z} }
func (a Vec) Dot(b Vec) float64   { return a.X*b.X + a.Y*b.Y + a.Z*b.Z }
func (a Vec) Cross(b Vec) Vec {
	return Vec{a.Y*b.Z - a.Z*b.Y, a.Z*b.X - a.X*b.Z, a.X*b.Y - a.Y*b.X}
}
func (a Vec) Len() float64 { return math.Sqrt(a.Dot(a)) }
func (a Vec) Norm() Vec {
	l := a.Len()
	if l == 0 {
		return a
	}
	return a.Scale(1 / l)
}

// ---------------------------------------------------------------- textures

type Texture struct {
	W, H int
	Pix  []Vec
}

// reads P3 or P6
func loadPPM(path string) (*Texture, error) {
	data, err := os.ReadFile(path)
	if err != nil {
		return nil, err
	}
	pos := 0
	// next header token, skipping whitespace and # comments
	token := func() (string, error) {
		for pos < len(data) {
			c := data[pos]
			if c == '#' {
				for pos < len(data) && data[pos] != '\n' {
					pos++
				}
			} else if c == ' ' || c == '\t' || c == '\n' || c == '\r' {
				pos++
			} else {
				break
			}
		}
		start := pos
		for pos < len(data) && !strings.ContainsRune(" \t\r\n#", rune(data[pos])) {
			pos++
		}
		if start == pos {
			return "", fmt.Errorf("%s: unexpected end of file", path)
		}
		return string(data[start:pos]), nil
	}
	number := func() (int, error) {
		t, err := token()
		if err != nil {
			return 0, err
		}
		n, err := strconv.Atoi(t)
		if err != nil {
			return 0, fmt.Errorf("%s: bad number %q", path, t)
		}
		return n, nil
	}
	magic, err := token()
	if err != nil {
		return nil, err
	}
	if magic != "P3" && magic != "P6" {
		return nil, fmt.Errorf("%s: not a P3/P6 ppm", path)
	}
	w, err := number()
	if err != nil {
		return nil, err
	}
	h, err := number()
	if err != nil {
		return nil, err
	}
	maxv, err := number()
	if err != nil {
		return nil, err
	}
	if w <= 0 || h <= 0 || maxv <= 0 || maxv > 65535 {
		return nil, fmt.Errorf("%s: bad header", path)
	}
	tex := &Texture{W: w, H: h, Pix: make([]Vec, w*h)}
	vals := make([]float64, 3*w*h)
	if magic == "P3" {
		for i := range vals {
			n, err := number()
			if err != nil {
				return nil, err
			}
			vals[i] = float64(n) / float64(maxv)
		}
	} else {
		pos++ // the single whitespace after maxval
		bps := 1
		if maxv > 255 {
			bps = 2
		}
		if len(data)-pos < len(vals)*bps {
			return nil, fmt.Errorf("%s: file too short", path)
		}
		for i := range vals {
			var n int
			if bps == 1 {
				n = int(data[pos])
			} else {
				n = int(data[pos])<<8 | int(data[pos+1])
			}
			pos += bps
			vals[i] = float64(n) / float64(maxv)
		}
	}
	for i := range tex.Pix {
		tex.Pix[i] = Vec{vals[3*i], vals[3*i+1], vals[3*i+2]}
	}
	return tex, nil
}

// nearest texel, u wraps around, v is clamped. (0,0) = top left of the image
func (t *Texture) At(u, v float64) Vec {
	u = u - math.Floor(u)
	x := int(u * float64(t.W))
	y := int(v * float64(t.H))
	if x < 0 {
		x = 0
	}
	if x >= t.W {
		x = t.W - 1
	}
	if y < 0 {
		y = 0
	}
	if y >= t.H {
		y = t.H - 1
	}
	return t.Pix[y*t.W+x]
}

// ---------------------------------------------------------------- scene

const (
	SPHERE = iota
	PLANE
)

type Object struct {
	Kind   int
	Center Vec
	Radius float64 // sphere
	W, H   float64 // plane: W along right, H along headup
	Normal Vec
	Headup Vec
	Right  Vec
	Up     Vec
	Color  Vec
	Refl   float64
	Tex    *Texture
}

type Light struct {
	Pos   Vec
	Color Vec
}

type Scene struct {
	N       int
	Objects []*Object
	Lights  []*Light
}

func parseFloats(f []string, n int, lineNo int) ([]float64, error) {
	if len(f)-1 < n {
		return nil, fmt.Errorf("line %d: %s needs %d numbers", lineNo, f[0], n)
	}
	out := make([]float64, n)
	for i := 0; i < n; i++ {
		v, err := strconv.ParseFloat(f[i+1], 64)
		if err != nil {
			return nil, fmt.Errorf("line %d: bad number %q", lineNo, f[i+1])
		}
		out[i] = v
	}
	return out, nil
}

func parseScene(path string) (*Scene, error) {
	file, err := os.Open(path)
	if err != nil {
		return nil, err
	}
	defer file.Close()
	dir := filepath.Dir(path)

	sc := &Scene{}
	var obj *Object
	var light *Light
	lineNo := 0
	scanner := bufio.NewScanner(file)
	for scanner.Scan() {
		lineNo++
		f := strings.Fields(scanner.Text())
		if len(f) == 0 || strings.HasPrefix(f[0], "#") {
			continue
		}
		key := strings.ToLower(f[0])
		switch key {
		case "camera":
			if len(f) < 2 {
				return nil, fmt.Errorf("line %d: camera needs a resolution", lineNo)
			}
			n, err := strconv.Atoi(f[1])
			if err != nil || n <= 0 {
				return nil, fmt.Errorf("line %d: bad camera resolution %q", lineNo, f[1])
			}
			sc.N = n
			obj, light = nil, nil
		case "sphere", "plane":
			obj = &Object{Kind: SPHERE, Radius: 1, Color: Vec{1, 1, 1},
				Normal: Vec{0, 1, 0}, Headup: Vec{0, 0, -1}, W: 1, H: 1}
			if key == "plane" {
				obj.Kind = PLANE
			}
			light = nil
			sc.Objects = append(sc.Objects, obj)
		case "light":
			light = &Light{Color: Vec{1, 1, 1}}
			obj = nil
			sc.Lights = append(sc.Lights, light)
		case "dimension":
			if obj == nil {
				return nil, fmt.Errorf("line %d: dimension outside an object", lineNo)
			}
			if obj.Kind == SPHERE {
				v, err := parseFloats(f, 1, lineNo)
				if err != nil {
					return nil, err
				}
				obj.Radius = v[0]
			} else {
				n := 2
				if len(f) == 2 {
					n = 1
				}
				v, err := parseFloats(f, n, lineNo)
				if err != nil {
					return nil, err
				}
				obj.W, obj.H = v[0], v[n-1]
			}
		case "center", "color", "normal", "headup", "location":
			v, err := parseFloats(f, 3, lineNo)
			if err != nil {
				return nil, err
			}
			vec := Vec{v[0], v[1], v[2]}
			if light != nil {
				if key == "location" || key == "center" {
					light.Pos = vec
				} else if key == "color" {
					light.Color = vec
				}
			} else if obj != nil {
				switch key {
				case "center", "location":
					obj.Center = vec
				case "color":
					obj.Color = vec
				case "normal":
					obj.Normal = vec
				case "headup":
					obj.Headup = vec
				}
			} else {
				return nil, fmt.Errorf("line %d: %s outside a section", lineNo, key)
			}
		case "reflectivity":
			if obj == nil {
				return nil, fmt.Errorf("line %d: reflectivity outside an object", lineNo)
			}
			v, err := parseFloats(f, 1, lineNo)
			if err != nil {
				return nil, err
			}
			obj.Refl = v[0]
		case "texture":
			if obj == nil || len(f) < 2 {
				return nil, fmt.Errorf("line %d: bad texture line", lineNo)
			}
			tpath := f[1]
			if !filepath.IsAbs(tpath) {
				tpath = filepath.Join(dir, tpath)
			}
			tex, err := loadPPM(tpath)
			if err != nil {
				return nil, fmt.Errorf("line %d: texture: %v", lineNo, err)
			}
			obj.Tex = tex
		default:
			fmt.Fprintf(os.Stderr, "warning: line %d: unknown keyword %q ignored\n", lineNo, f[0])
		}
	}
	if err := scanner.Err(); err != nil {
		return nil, err
	}
	if sc.N == 0 {
		return nil, fmt.Errorf("no camera line in scene")
	}
	// set up the plane frames
	for _, o := range sc.Objects {
		if o.Kind != PLANE {
			continue
		}
		o.Normal = o.Normal.Norm()
		if o.Normal.Len() == 0 {
			o.Normal = Vec{0, 1, 0}
		}
		up := o.Headup.Sub(o.Normal.Scale(o.Headup.Dot(o.Normal)))
		if up.Len() < 1e-9 { // headup parallel to normal, pick anything
			up = Vec{1, 0, 0}.Sub(o.Normal.Scale(o.Normal.X))
			if up.Len() < 1e-9 {
				up = Vec{0, 0, 1}.Sub(o.Normal.Scale(o.Normal.Z))
			}
		}
		o.Up = up.Norm()
		o.Right = o.Up.Cross(o.Normal)
	}
	return sc, nil
}

// ---------------------------------------------------------------- geometry

// returns distance along the ray (dir is normalized), ok=false if no hit
func intersect(o *Object, orig, dir Vec) (float64, bool) {
	if o.Kind == SPHERE {
		oc := orig.Sub(o.Center)
		a := dir.Dot(dir)
		b := 2 * dir.Dot(oc)
		c := oc.Dot(oc) - o.Radius*o.Radius
		disc := b*b - 4*a*c
		if disc < 0 {
			return 0, false
		}
		d := math.Sqrt(disc)
		t1 := (-b - d) / (2 * a)
		t2 := (-b + d) / (2 * a)
		if t1 > EPS {
			return t1, true
		}
		if t2 > EPS {
			return t2, true
		}
		return 0, false
	}
	// plane: n.(p - c) = 0
	denom := o.Normal.Dot(dir)
	if math.Abs(denom) < 1e-12 {
		return 0, false
	}
	t := o.Normal.Dot(o.Center.Sub(orig)) / denom
	if t <= EPS {
		return 0, false
	}
	p := orig.Add(dir.Scale(t))
	d := p.Sub(o.Center)
	if math.Abs(d.Dot(o.Right)) > o.W/2 || math.Abs(d.Dot(o.Up)) > o.H/2 {
		return 0, false
	}
	return t, true
}

func normalAt(o *Object, p Vec) Vec {
	if o.Kind == SPHERE {
		return p.Sub(o.Center).Scale(1 / o.Radius)
	}
	return o.Normal
}

func colorAt(o *Object, p Vec) Vec {
	if o.Tex == nil {
		return o.Color
	}
	var u, v float64
	if o.Kind == SPHERE {
		q := p.Sub(o.Center).Norm()
		u = 0.5 - math.Atan2(q.Z, q.X)/(2*math.Pi)
		y := math.Max(-1, math.Min(1, q.Y))
		v = math.Acos(y) / math.Pi
	} else {
		d := p.Sub(o.Center)
		u = 0.5 + d.Dot(o.Right)/o.W
		v = 0.5 - d.Dot(o.Up)/o.H
	}
	return o.Tex.At(u, v)
}

func closest(sc *Scene, orig, dir Vec) (*Object, float64) {
	var best *Object
	bestT := math.Inf(1)
	for _, o := range sc.Objects {
		if t, ok := intersect(o, orig, dir); ok && t < bestT {
			best, bestT = o, t
		}
	}
	return best, bestT
}

func inShadow(sc *Scene, p, L Vec, dist float64) bool {
	for _, o := range sc.Objects {
		if t, ok := intersect(o, p, L); ok && t < dist {
			return true
		}
	}
	return false
}

// ---------------------------------------------------------------- shading

func trace(sc *Scene, orig, dir Vec, depth int) Vec {
	o, t := closest(sc, orig, dir)
	if o == nil {
		return Vec{0, 0, 0} // background
	}
	p := orig.Add(dir.Scale(t))
	n := normalAt(o, p)
	if n.Dot(dir) > 0 { // back side of plane / inside sphere
		n = n.Scale(-1)
	}
	col := colorAt(o, p)

	result := col.Scale(KA)
	for _, l := range sc.Lights {
		toL := l.Pos.Sub(p)
		dist := toL.Len()
		L := toL.Scale(1 / dist)
		ndl := n.Dot(L)
		if ndl <= 0 {
			continue
		}
		if inShadow(sc, p.Add(n.Scale(EPS)), L, dist) {
			continue
		}
		result = result.Add(col.Mul(l.Color).Scale(ndl))
	}

	if o.Refl > 0 && depth < MAXDEPTH {
		r := dir.Sub(n.Scale(2 * dir.Dot(n))).Norm()
		rc := trace(sc, p.Add(n.Scale(EPS)), r, depth+1)
		result = result.Add(rc.Scale(o.Refl))
	}
	return result
}

// final colour -> displayable colour
// if a channel goes over 1, scale the whole colour down so the brightest
// channel is exactly 1 (keeps the hue instead of washing out to white)
func finish(c Vec) Vec {
	c = Vec{math.Max(0, c.X), math.Max(0, c.Y), math.Max(0, c.Z)}
	m := math.Max(c.X, math.Max(c.Y, c.Z))
	if m > 1 {
		c = c.Scale(1 / m)
	}
	return Vec{clamp(c.X), clamp(c.Y), clamp(c.Z)}
}

func clamp(x float64) float64 {
	if x < 0 {
		return 0
	}
	if x > 1 {
		return 1
	}
	return x
}

func main() {
	if len(os.Args) != 3 {
		fmt.Fprintln(os.Stderr, "usage: ./tracer scene_description_file output_image")
		os.Exit(2)
	}
	sc, err := parseScene(os.Args[1])
	if err != nil {
		fmt.Fprintln(os.Stderr, "error reading scene:", err)
		os.Exit(1)
	}
	N := sc.N
	img := make([]byte, 3*N*N)
	for j := 0; j < N; j++ { // scan lines, top to bottom
		for i := 0; i < N; i++ {
			// centre of the pixel on the image plane z = -1
			x := -0.5 + (float64(i)+0.5)/float64(N)
			y := 0.5 - (float64(j)+0.5)/float64(N)
			dir := Vec{x, y, -1}.Norm()
			c := finish(trace(sc, Vec{0, 0, 0}, dir, 0))
			k := 3 * (j*N + i)
			img[k] = byte(math.Round(c.X * 255))
			img[k+1] = byte(math.Round(c.Y * 255))
			img[k+2] = byte(math.Round(c.Z * 255))
		}
	}
	out, err := os.Create(os.Args[2])
	if err != nil {
		fmt.Fprintln(os.Stderr, "cannot write image:", err)
		os.Exit(1)
	}
	w := bufio.NewWriter(out)
	fmt.Fprintf(w, "P6\n%d %d\n255\n", N, N)
	w.Write(img)
	if err := w.Flush(); err != nil {
		fmt.Fprintln(os.Stderr, "cannot write image:", err)
		os.Exit(1)
	}
	out.Close()
}
