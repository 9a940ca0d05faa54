// HW4 ray tracer (Go)
//
//	./tracer scene_file output_image
//
// Output is a binary PPM (P6), N x N where N is the camera resolution.
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
	"unicode"
)

// ----- vectors -----

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
func (a Vec) Unit() Vec {
	l := a.Len()
	if l == 0 {
		return a
	}
	return a.Scale(1 / l)
}

// ----- lighting constants -----

const (
	ambient   = 0.2  // ka, times the object colour
	diffuseK  = 1.0  // kd scale (kd itself is the object colour)
	specularK = 0.4  // ks, white highlight
	shininess = 20.0 // Phong exponent
	maxDepth  = 6    // reflection bounces
	eps       = 1e-4 // ray start offset / minimum t
)

// ----- textures -----

type Texture struct {
	W, H int
	Pix  []Vec
}

func readPPM(path string) (*Texture, error) {
	f, err := os.Open(path)
	if err != nil {
		return nil, err
	}
	defer f.Close()
	r := bufio.NewReader(f)
	header := make([]int, 0, 3)
	word := func() (string, error) {
		var sb strings.Builder
		for {
			c, err := r.ReadByte()
			if err != nil {
				if sb.Len() > 0 {
					return sb.String(), nil
				}
				return "", err
			}
			if c == '#' && sb.Len() == 0 {
				for c != '\n' {
					if c, err = r.ReadByte(); err != nil {
						return "", err
					}
				}
				continue
			}
			if c == ' ' || c == '\n' || c == '\r' || c == '\t' {
				if sb.Len() > 0 {
					return sb.String(), nil
				}
				continue
			}
			sb.WriteByte(c)
		}
	}
	magic, err := word()
	if err != nil || magic != "P6" {
		return nil, errors.New("not a P6 ppm file")
	}
	for len(header) < 3 {
		w, err := word()
		if err != nil {
			return nil, errors.New("truncated ppm header")
		}
		n, err := strconv.Atoi(w)
		if err != nil || n <= 0 {
			return nil, errors.New("bad ppm header")
		}
		header = append(header, n)
	}
	w, h, maxv := header[0], header[1], header[2]
	if maxv > 255 {
		return nil, errors.New("16-bit ppm not supported")
	}
	raw := make([]byte, w*h*3)
	if _, err := ioReadFull(r, raw); err != nil {
		return nil, errors.New("truncated ppm data")
	}
	t := &Texture{W: w, H: h, Pix: make([]Vec, w*h)}
	for i := range t.Pix {
		t.Pix[i] = Vec{float64(raw[3*i]), float64(raw[3*i+1]), float64(raw[3*i+2])}.Scale(1 / float64(maxv))
	}
	return t, nil
}

func ioReadFull(r *bufio.Reader, buf []byte) (int, error) {
	n := 0
	for n < len(buf) {
		m, err := r.Read(buf[n:])
		n += m
		if err != nil {
			return n, err
		}
	}
	return n, nil
}

// Sample with bilinear filtering; (u,v) in [0,1], v=0 is the bottom row.
func (t *Texture) Sample(u, v float64) Vec {
	u = math.Max(0, math.Min(1, u))
	v = math.Max(0, math.Min(1, v))
	x := u*float64(t.W) - 0.5
	y := (1-v)*float64(t.H) - 0.5
	x0, y0 := math.Floor(x), math.Floor(y)
	fx, fy := x-x0, y-y0
	at := func(i, j int) Vec {
		if i < 0 {
			i = 0
		}
		if j < 0 {
			j = 0
		}
		if i >= t.W {
			i = t.W - 1
		}
		if j >= t.H {
			j = t.H - 1
		}
		return t.Pix[j*t.W+i]
	}
	i, j := int(x0), int(y0)
	top := at(i, j).Scale(1 - fx).Add(at(i+1, j).Scale(fx))
	bot := at(i, j+1).Scale(1 - fx).Add(at(i+1, j+1).Scale(fx))
	return top.Scale(1 - fy).Add(bot.Scale(fy))
}

// ----- objects -----

type Material struct {
	Color Vec
	Refl  float64
	Tex   *Texture
}

type Object interface {
	Intersect(o, d Vec) (float64, bool)
	NormalAt(p Vec) Vec
	ColorAt(p Vec) Vec
	Mat() *Material
}

type Sphere struct {
	Center Vec
	Radius float64
	M      Material
}

func (s *Sphere) Mat() *Material { return &s.M }

func (s *Sphere) Intersect(o, d Vec) (float64, bool) {
	oc := o.Sub(s.Center)
	a := d.Dot(d)
	b := 2 * d.Dot(oc)
	c := oc.Dot(oc) - s.Radius*s.Radius
	disc := b*b - 4*a*c
	if disc < 0 {
		return 0, false
	}
	sq := math.Sqrt(disc)
	if t := (-b - sq) / (2 * a); t > eps {
		return t, true
	}
	if t := (-b + sq) / (2 * a); t > eps {
		return t, true
	}
	return 0, false
}

func (s *Sphere) NormalAt(p Vec) Vec { return p.Sub(s.Center).Unit() }

func (s *Sphere) ColorAt(p Vec) Vec {
	if s.M.Tex == nil {
		return s.M.Color
	}
	n := s.NormalAt(p)
	u := 0.5 + math.Atan2(n.X, n.Z)/(2*math.Pi)
	v := 0.5 + math.Asin(math.Max(-1, math.Min(1, n.Y)))/math.Pi
	return s.M.Color.Mul(s.M.Tex.Sample(u, v))
}

// Plane is a finite rectangle: Height along the head-up direction,
// Width along Side (both taken from "dimension H W").
type Plane struct {
	Center, Normal, HeadUp Vec
	Up, Side               Vec
	Height, Width          float64
	M                      Material
}

func (p *Plane) Mat() *Material { return &p.M }

func (p *Plane) init() {
	p.Normal = p.Normal.Unit()
	up := p.HeadUp.Sub(p.Normal.Scale(p.HeadUp.Dot(p.Normal)))
	if up.Len() < 1e-8 {
		// head-up along the normal: fall back to -z, or y if that fails too
		up = Vec{0, 0, -1}.Sub(p.Normal.Scale(-p.Normal.Z))
		if up.Len() < 1e-8 {
			up = Vec{0, 1, 0}.Sub(p.Normal.Scale(p.Normal.Y))
		}
	}
	p.Up = up.Unit()
	p.Side = p.Up.Cross(p.Normal).Unit()
}

func (p *Plane) Intersect(o, d Vec) (float64, bool) {
	den := p.Normal.Dot(d)
	if math.Abs(den) < 1e-10 {
		return 0, false
	}
	t := p.Center.Sub(o).Dot(p.Normal) / den
	if t <= eps {
		return 0, false
	}
	q := o.Add(d.Scale(t)).Sub(p.Center)
	if math.Abs(q.Dot(p.Up)) > p.Height/2 || math.Abs(q.Dot(p.Side)) > p.Width/2 {
		return 0, false
	}
	return t, true
}

func (p *Plane) NormalAt(Vec) Vec { return p.Normal }

func (p *Plane) ColorAt(x Vec) Vec {
	if p.M.Tex == nil {
		return p.M.Color
	}
	q := x.Sub(p.Center)
	u := q.Dot(p.Side)/p.Width + 0.5
	v := q.Dot(p.Up)/p.Height + 0.5
	return p.M.Color.Mul(p.M.Tex.Sample(u, v))
}

type Light struct {
	Pos, Color Vec
}

type Scene struct {
	Size    int
	Objects []Object
	Lights  []Light
}

// ----- parser -----

func parseScene(path string) (*Scene, error) {
	data, err := os.ReadFile(path)
	if err != nil {
		return nil, err
	}
	// FieldsFunc with unicode.IsSpace also splits on U+2028 and friends.
	toks := strings.FieldsFunc(string(data), unicode.IsSpace)
	dir := filepath.Dir(path)
	sc := &Scene{}
	var mat *Material
	var sph *Sphere
	var pl *Plane
	var lightPos, lightCol []Vec
	inLight := false
	i := 0
	nums := func(n int, key string) ([]float64, error) {
		if i+n > len(toks) {
			return nil, fmt.Errorf("%s: expected %d numbers", key, n)
		}
		out := make([]float64, n)
		for k := 0; k < n; k++ {
			f, err := strconv.ParseFloat(toks[i+k], 64)
			if err != nil {
				return nil, fmt.Errorf("%s: bad number %q", key, toks[i+k])
			}
			out[k] = f
		}
		i += n
		return out, nil
	}
	vec := func(key string) (Vec, error) {
		f, err := nums(3, key)
		if err != nil {
			return Vec{}, err
		}
		return Vec{f[0], f[1], f[2]}, nil
	}
	for i < len(toks) {
		key := toks[i]
		i++
		switch key {
		case "camera":
			f, err := nums(1, key)
			if err != nil {
				return nil, err
			}
			if f[0] < 1 || f[0] > 20000 || f[0] != math.Floor(f[0]) {
				return nil, fmt.Errorf("camera: bad resolution %v", f[0])
			}
			sc.Size = int(f[0])
		case "sphere":
			sph, pl, inLight = &Sphere{Radius: 1, M: Material{Color: Vec{1, 1, 1}}}, nil, false
			mat = &sph.M
			sc.Objects = append(sc.Objects, sph)
		case "plane":
			pl, sph, inLight = &Plane{Height: 1, Width: 1, Normal: Vec{0, 0, 1}, HeadUp: Vec{0, 1, 0}, M: Material{Color: Vec{1, 1, 1}}}, nil, false
			mat = &pl.M
			sc.Objects = append(sc.Objects, pl)
		case "light":
			lightPos = append(lightPos, Vec{})
			lightCol = append(lightCol, Vec{1, 1, 1})
			inLight, mat, sph, pl = true, nil, nil, nil
		case "location":
			if !inLight {
				return nil, errors.New("location outside a light")
			}
			v, err := vec(key)
			if err != nil {
				return nil, err
			}
			lightPos[len(lightPos)-1] = v
		case "color":
			v, err := vec(key)
			if err != nil {
				return nil, err
			}
			switch {
			case inLight:
				lightCol[len(lightCol)-1] = v
			case mat != nil:
				mat.Color = v
			default:
				return nil, errors.New("color outside an object or light")
			}
		case "dimension":
			switch {
			case sph != nil:
				f, err := nums(1, key)
				if err != nil {
					return nil, err
				}
				if f[0] <= 0 {
					return nil, errors.New("sphere dimension must be positive")
				}
				sph.Radius = f[0]
			case pl != nil:
				f, err := nums(2, key)
				if err != nil {
					return nil, err
				}
				if f[0] <= 0 || f[1] <= 0 {
					return nil, errors.New("plane dimension must be positive")
				}
				pl.Height, pl.Width = f[0], f[1]
			default:
				return nil, errors.New("dimension outside an object")
			}
		case "center":
			v, err := vec(key)
			if err != nil {
				return nil, err
			}
			switch {
			case sph != nil:
				sph.Center = v
			case pl != nil:
				pl.Center = v
			default:
				return nil, errors.New("center outside an object")
			}
		case "normal", "headup":
			if pl == nil {
				return nil, fmt.Errorf("%s outside a plane", key)
			}
			v, err := vec(key)
			if err != nil {
				return nil, err
			}
			if key == "normal" {
				if v.Len() == 0 {
					return nil, errors.New("zero plane normal")
				}
				pl.Normal = v
			} else {
				pl.HeadUp = v
			}
		case "reflectivity":
			if mat == nil {
				return nil, errors.New("reflectivity outside an object")
			}
			f, err := nums(1, key)
			if err != nil {
				return nil, err
			}
			if f[0] < 0 || f[0] > 1 {
				return nil, errors.New("reflectivity must be between 0 and 1")
			}
			mat.Refl = f[0]
		case "texture":
			if mat == nil || i >= len(toks) {
				return nil, errors.New("texture outside an object or missing file name")
			}
			name := toks[i]
			i++
			if !filepath.IsAbs(name) {
				name = filepath.Join(dir, name)
			}
			t, err := readPPM(name)
			if err != nil {
				return nil, fmt.Errorf("texture %s: %v", name, err)
			}
			mat.Tex = t
		default:
			return nil, fmt.Errorf("unknown keyword %q", key)
		}
	}
	if sc.Size == 0 {
		return nil, errors.New("no camera line")
	}
	for _, o := range sc.Objects {
		if p, ok := o.(*Plane); ok {
			p.init()
		}
	}
	for k := range lightPos {
		sc.Lights = append(sc.Lights, Light{Pos: lightPos[k], Color: lightCol[k]})
	}
	return sc, nil
}

// ----- tracing -----

func (sc *Scene) nearest(o, d Vec) (Object, float64) {
	var best Object
	bt := math.Inf(1)
	for _, ob := range sc.Objects {
		if t, ok := ob.Intersect(o, d); ok && t < bt {
			best, bt = ob, t
		}
	}
	return best, bt
}

func (sc *Scene) inShadow(p, toLight Vec) bool {
	dist := toLight.Len()
	dir := toLight.Scale(1 / dist)
	start := p.Add(dir.Scale(eps))
	for _, ob := range sc.Objects {
		if t, ok := ob.Intersect(start, dir); ok && t < dist {
			return true
		}
	}
	return false
}

func (sc *Scene) trace(o, d Vec, depth int) Vec {
	obj, t := sc.nearest(o, d)
	if obj == nil {
		return Vec{}
	}
	p := o.Add(d.Scale(t))
	n := obj.NormalAt(p)
	if n.Dot(d) > 0 {
		n = n.Scale(-1)
	}
	col := obj.ColorAt(p)
	view := d.Scale(-1)

	local := col.Scale(ambient)
	for _, l := range sc.Lights {
		toL := l.Pos.Sub(p)
		L := toL.Unit()
		ndl := n.Dot(L)
		if ndl <= 0 {
			continue
		}
		if sc.inShadow(p, toL) {
			continue
		}
		local = local.Add(col.Mul(l.Color).Scale(diffuseK * ndl))
		r := n.Scale(2 * ndl).Sub(L)
		if rv := r.Dot(view); rv > 0 {
			local = local.Add(l.Color.Scale(specularK * math.Pow(rv, shininess)))
		}
	}

	refl := obj.Mat().Refl
	if refl <= 0 || depth >= maxDepth {
		return local
	}
	rd := d.Sub(n.Scale(2 * d.Dot(n))).Unit()
	rc := sc.trace(p.Add(n.Scale(eps)), rd, depth+1)
	return local.Scale(1 - refl).Add(rc.Scale(refl))
}

func toByte(c float64) byte {
	const white = 2.0 // extended Reinhard, white point 2
	c = c * (1 + c/(white*white)) / (1 + c)
	c = math.Max(0, math.Min(1, c))
	return byte(c * 255.99)
}

func main() {
	if len(os.Args) != 3 {
		fmt.Fprintln(os.Stderr, "usage: tracer scene_file output_image")
		os.Exit(1)
	}
	sc, err := parseScene(os.Args[1])
	if err != nil {
		fmt.Fprintln(os.Stderr, "tracer:", err)
		os.Exit(1)
	}
	n := sc.Size
	buf := make([]byte, 0, n*n*3+32)
	buf = append(buf, fmt.Sprintf("P6\n%d %d\n255\n", n, n)...)
	for y := 0; y < n; y++ {
		for x := 0; x < n; x++ {
			px := Vec{-0.5 + (float64(x)+0.5)/float64(n), 0.5 - (float64(y)+0.5)/float64(n), -1}
			c := sc.trace(Vec{}, px.Unit(), 0)
			buf = append(buf, toByte(c.X), toByte(c.Y), toByte(c.Z))
		}
	}
	if err := os.WriteFile(os.Args[2], buf, 0644); err != nil {
		fmt.Fprintln(os.Stderr, "tracer:", err)
		os.Exit(1)
	}
}
