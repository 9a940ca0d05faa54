// HW4 ray tracer -- single file, standard library only.
// Build: rustc -O -o tracer main.rs
// Usage: ./tracer scene_description_file output_image

use std::env;
use std::fs;
use std::io::Write;
use std::ops::{Add, Mul, Neg, Sub};
use std::path::{Path, PathBuf};
use std::process;

const KA: f64 = 0.1; // ambient coefficient
const MAX_DEPTH: u32 = 5; // reflection recursion limit
const EPS: f64 = 1e-4; // offset for secondary rays

#[derive(Clone, Copy, Debug)]
struct V3 {
    x: f64,
    y: f64,
    z: f64,
}

fn v3(x: f64, y: f64, z: f64) -> V3 {
    V3 { x, y, z }
}

impl Add for V3 {
    type Output = V3;
    fn add(self, o: V3) -> V3 {
        v3(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl Sub for V3 {
    type Output = V3;
    fn sub(self, o: V3) -> V3 {
        v3(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl Mul<f64> for V3 {
    type Output = V3;
    fn mul(self, s: f64) -> V3 {
        v3(self.x * s, self.y * s, self.z * s)
    }
}
impl Neg for V3 {
    type Output = V3;
    fn neg(self) -> V3 {
        v3(-self.x, -self.y, -self.z)
    }
}
impl V3 {
    fn dot(self, o: V3) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    fn cross(self, o: V3) -> V3 {
        v3(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    fn len(self) -> f64 {
        self.dot(self).sqrt()
    }
    fn norm(self) -> V3 {
        let l = self.len();
        if l > 0.0 {
            self * (1.0 / l)
        } else {
            self
        }
    }
    fn mulv(self, o: V3) -> V3 {
        v3(self.x * o.x, self.y * o.y, self.z * o.z)
    }
}

struct Texture {
    w: usize,
    h: usize,
    data: Vec<V3>, // row-major, row 0 = top of the image
}

impl Texture {
    // u, v in [0,1]; v = 0 is the top row of the image
    fn sample(&self, u: f64, v: f64) -> V3 {
        let u = u - u.floor();
        let v = v - v.floor();
        let col = ((u * self.w as f64) as usize).min(self.w - 1);
        let row = ((v * self.h as f64) as usize).min(self.h - 1);
        self.data[row * self.w + col]
    }
}

#[derive(PartialEq)]
enum Kind {
    Sphere,
    Plane,
}

struct Object {
    kind: Kind,
    dim: Vec<f64>,
    center: V3,
    color: V3,
    refl: f64,
    tex_name: Option<String>,
    tex: Option<Texture>,
    normal: V3,
    headup: V3,
    // derived plane frame
    n: V3,
    up: V3,
    right: V3,
}

struct Light {
    pos: V3,
    color: V3,
}

struct Scene {
    res: usize,
    objects: Vec<Object>,
    lights: Vec<Light>,
}

fn fail(msg: &str) -> ! {
    eprintln!("error: {}", msg);
    process::exit(1);
}

fn parse_nums(kw: &str, toks: &[&str], n: usize, lineno: usize) -> Vec<f64> {
    if toks.len() < n {
        fail(&format!("line {}: '{}' needs {} number(s)", lineno, kw, n));
    }
    let mut out = Vec::new();
    for t in &toks[..n] {
        match t.parse::<f64>() {
            Ok(v) => out.push(v),
            Err(_) => fail(&format!("line {}: bad number '{}' for '{}'", lineno, t, kw)),
        }
    }
    out
}

enum Current {
    None,
    Obj(usize),
    Light(usize),
}

fn new_object(kind: Kind) -> Object {
    Object {
        kind,
        dim: vec![1.0, 1.0],
        center: v3(0.0, 0.0, 0.0),
        color: v3(1.0, 1.0, 1.0),
        refl: 0.0,
        tex_name: None,
        tex: None,
        normal: v3(0.0, 0.0, 1.0),
        headup: v3(0.0, 1.0, 0.0),
        n: v3(0.0, 0.0, 1.0),
        up: v3(0.0, 1.0, 0.0),
        right: v3(1.0, 0.0, 0.0),
    }
}

fn parse_scene(path: &str) -> Scene {
    let text = match fs::read(path) {
        Ok(b) => String::from_utf8_lossy(&b).into_owned(),
        Err(e) => fail(&format!("cannot read scene file '{}': {}", path, e)),
    };
    let mut res: Option<usize> = None;
    let mut objects: Vec<Object> = Vec::new();
    let mut lights: Vec<Light> = Vec::new();
    let mut cur = Current::None;

    for (i, raw) in text.lines().enumerate() {
        let lineno = i + 1;
        let line = match raw.find('#') {
            Some(p) => &raw[..p],
            None => raw,
        };
        let toks: Vec<&str> = line.split_whitespace().collect();
        if toks.is_empty() {
            continue;
        }
        let kw = toks[0].to_ascii_lowercase();
        let args = &toks[1..];
        match kw.as_str() {
            "camera" => {
                let v = parse_nums("camera", args, 1, lineno)[0];
                if !(v >= 1.0) {
                    fail(&format!("line {}: camera resolution must be positive", lineno));
                }
                res = Some(v as usize);
                cur = Current::None;
            }
            "sphere" => {
                objects.push(new_object(Kind::Sphere));
                cur = Current::Obj(objects.len() - 1);
            }
            "plane" => {
                objects.push(new_object(Kind::Plane));
                cur = Current::Obj(objects.len() - 1);
            }
            "light" => {
                lights.push(Light {
                    pos: v3(0.0, 0.0, 0.0),
                    color: v3(1.0, 1.0, 1.0),
                });
                cur = Current::Light(lights.len() - 1);
            }
            _ => match cur {
                Current::Obj(k) => {
                    let o = &mut objects[k];
                    match kw.as_str() {
                        "dimension" => {
                            if o.kind == Kind::Sphere {
                                o.dim = parse_nums(&kw, args, 1, lineno);
                            } else {
                                o.dim = parse_nums(&kw, args, 2, lineno);
                            }
                        }
                        "center" => {
                            let v = parse_nums(&kw, args, 3, lineno);
                            o.center = v3(v[0], v[1], v[2]);
                        }
                        "color" => {
                            let v = parse_nums(&kw, args, 3, lineno);
                            o.color = v3(v[0], v[1], v[2]);
                        }
                        "reflectivity" => {
                            o.refl = parse_nums(&kw, args, 1, lineno)[0];
                        }
                        "normal" => {
                            let v = parse_nums(&kw, args, 3, lineno);
                            o.normal = v3(v[0], v[1], v[2]);
                        }
                        "headup" => {
                            let v = parse_nums(&kw, args, 3, lineno);
                            o.headup = v3(v[0], v[1], v[2]);
                        }
                        "texture" => {
                            if args.is_empty() {
                                fail(&format!("line {}: texture needs a file name", lineno));
                            }
                            o.tex_name = Some(args.join(" "));
                        }
                        _ => eprintln!("warning: line {}: unknown keyword '{}' ignored", lineno, kw),
                    }
                }
                Current::Light(k) => {
                    let l = &mut lights[k];
                    match kw.as_str() {
                        "location" | "center" => {
                            let v = parse_nums(&kw, args, 3, lineno);
                            l.pos = v3(v[0], v[1], v[2]);
                        }
                        "color" => {
                            let v = parse_nums(&kw, args, 3, lineno);
                            l.color = v3(v[0], v[1], v[2]);
                        }
                        _ => eprintln!("warning: line {}: unknown keyword '{}' ignored", lineno, kw),
                    }
                }
                Current::None => {
                    eprintln!("warning: line {}: '{}' outside of any object ignored", lineno, kw)
                }
            },
        }
    }

    let res = match res {
        Some(r) => r,
        None => fail("scene has no camera line"),
    };

    let base_dir: PathBuf = Path::new(path)
        .parent()
        .map(|p| p.to_path_buf())
        .unwrap_or_else(|| PathBuf::from("."));

    for o in objects.iter_mut() {
        if let Some(name) = &o.tex_name {
            let p = base_dir.join(name);
            match load_ppm(&p) {
                Ok(t) => o.tex = Some(t),
                Err(e) => fail(&format!("cannot load texture '{}': {}", p.display(), e)),
            }
        }
        if o.kind == Kind::Plane {
            let n = o.normal.norm();
            let mut up = o.headup - n * o.headup.dot(n);
            if up.len() < 1e-9 {
                // headup parallel to the normal: pick any direction in the plane
                let a = if n.x.abs() < 0.9 { v3(1.0, 0.0, 0.0) } else { v3(0.0, 1.0, 0.0) };
                up = a - n * a.dot(n);
            }
            let up = up.norm();
            o.n = n;
            o.up = up;
            o.right = up.cross(n).norm();
        }
    }

    Scene { res, objects, lights }
}

// ---------------------------------------------------------------- PPM input

fn load_ppm(p: &Path) -> Result<Texture, String> {
    let b = fs::read(p).map_err(|e| e.to_string())?;
    let mut pos = 0usize;
    // read one header token, skipping whitespace and comments
    fn token(b: &[u8], pos: &mut usize) -> Option<String> {
        loop {
            while *pos < b.len() && b[*pos].is_ascii_whitespace() {
                *pos += 1;
            }
            if *pos < b.len() && b[*pos] == b'#' {
                while *pos < b.len() && b[*pos] != b'\n' && b[*pos] != b'\r' {
                    *pos += 1;
                }
                continue;
            }
            break;
        }
        let start = *pos;
        while *pos < b.len() && !b[*pos].is_ascii_whitespace() && b[*pos] != b'#' {
            *pos += 1;
        }
        if start == *pos {
            None
        } else {
            Some(String::from_utf8_lossy(&b[start..*pos]).into_owned())
        }
    }
    let magic = token(&b, &mut pos).ok_or("empty file")?;
    if magic != "P3" && magic != "P6" {
        return Err(format!("unsupported format '{}'", magic));
    }
    let mut hdr = [0usize; 3];
    for h in hdr.iter_mut() {
        let t = token(&b, &mut pos).ok_or("truncated header")?;
        *h = t.parse::<usize>().map_err(|_| format!("bad header value '{}'", t))?;
    }
    let (w, h, maxv) = (hdr[0], hdr[1], hdr[2]);
    if w == 0 || h == 0 || maxv == 0 || maxv > 65535 {
        return Err("bad header".to_string());
    }
    let n = w * h * 3;
    let mut vals: Vec<f64> = Vec::with_capacity(n);
    if magic == "P3" {
        for _ in 0..n {
            let t = token(&b, &mut pos).ok_or("truncated pixel data")?;
            let v = t.parse::<f64>().map_err(|_| format!("bad pixel value '{}'", t))?;
            vals.push(v / maxv as f64);
        }
    } else {
        pos += 1; // single whitespace byte after maxval
        let bps = if maxv > 255 { 2 } else { 1 };
        if b.len() < pos + n * bps {
            return Err("truncated pixel data".to_string());
        }
        for i in 0..n {
            let v = if bps == 1 {
                b[pos + i] as f64
            } else {
                ((b[pos + 2 * i] as u32) << 8 | b[pos + 2 * i + 1] as u32) as f64
            };
            vals.push(v / maxv as f64);
        }
    }
    let data = vals.chunks(3).map(|c| v3(c[0], c[1], c[2])).collect();
    Ok(Texture { w, h, data })
}

// ---------------------------------------------------------------- tracing

struct Hit {
    t: f64,
    obj: usize,
}

fn intersect(o: &Object, orig: V3, dir: V3, tmin: f64) -> Option<f64> {
    match o.kind {
        Kind::Sphere => {
            let r = o.dim[0];
            let oc = orig - o.center;
            let a = dir.dot(dir);
            let b = 2.0 * dir.dot(oc);
            let c = oc.dot(oc) - r * r;
            let disc = b * b - 4.0 * a * c;
            if disc < 0.0 {
                return None;
            }
            let sq = disc.sqrt();
            let t1 = (-b - sq) / (2.0 * a);
            let t2 = (-b + sq) / (2.0 * a);
            if t1 > tmin {
                Some(t1)
            } else if t2 > tmin {
                Some(t2)
            } else {
                None
            }
        }
        Kind::Plane => {
            let denom = o.n.dot(dir);
            if denom.abs() < 1e-12 {
                return None;
            }
            let t = o.n.dot(o.center - orig) / denom;
            if t <= tmin {
                return None;
            }
            let p = orig + dir * t;
            let d = p - o.center;
            let x = d.dot(o.right);
            let y = d.dot(o.up);
            if x.abs() > o.dim[0] / 2.0 || y.abs() > o.dim[1] / 2.0 {
                return None;
            }
            Some(t)
        }
    }
}

fn closest(scene: &Scene, orig: V3, dir: V3, tmin: f64) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for (i, o) in scene.objects.iter().enumerate() {
        if let Some(t) = intersect(o, orig, dir, tmin) {
            if best.as_ref().map_or(true, |b| t < b.t) {
                best = Some(Hit { t, obj: i });
            }
        }
    }
    best
}

fn in_shadow(scene: &Scene, orig: V3, dir: V3, dist: f64) -> bool {
    for o in scene.objects.iter() {
        if let Some(t) = intersect(o, orig, dir, 0.5) {
            if t < dist {
                return true;
            }
        }
    }
    false
}

fn surface_color(o: &Object, p: V3, n_geom: V3) -> V3 {
    match &o.tex {
        None => o.color,
        Some(tex) => match o.kind {
            Kind::Sphere => {
                let n = n_geom;
                let u = 0.5 + n.x.atan2(n.z) / (2.0 * std::f64::consts::PI);
                let v = n.y.max(-1.0).min(1.0).acos() / std::f64::consts::PI;
                tex.sample(u, v)
            }
            Kind::Plane => {
                let d = p - o.center;
                let u = d.dot(o.right) / o.dim[0] + 0.5;
                let v = 0.5 - d.dot(o.up) / o.dim[1];
                tex.sample(u.max(0.0).min(0.999999), v.max(0.0).min(0.999999))
            }
        },
    }
}

fn trace(scene: &Scene, orig: V3, dir: V3, depth: u32) -> V3 {
    let hit = match closest(scene, orig, dir, 1e-9) {
        Some(h) => h,
        None => return v3(0.0, 0.0, 0.0), // background
    };
    let o = &scene.objects[hit.obj];
    let p = orig + dir * hit.t;
    // outward geometric normal
    let n_geom = match o.kind {
        Kind::Sphere => (p - o.center).norm(),
        Kind::Plane => o.n,
    };
    // shading normal faces the incoming ray
    let n = if n_geom.dot(dir) > 0.0 { -n_geom } else { n_geom };
    let base = surface_color(o, p, n_geom);

    let mut col = base * KA;
    let sp = p + n * EPS;
    for l in scene.lights.iter() {
        let to_l = l.pos - p;
        let dist = to_l.len();
        let ldir = to_l.norm();
        let ndl = n.dot(ldir);
        if ndl <= 0.0 {
            continue;
        }
        if in_shadow(scene, sp, ldir, dist) {
            continue;
        }
        col = col + base.mulv(l.color) * ndl;
    }

    if o.refl > 0.0 && depth < MAX_DEPTH {
        let v = (-dir).norm();
        let r = (n * (2.0 * n.dot(v)) - v).norm();
        let rc = trace(scene, sp, r, depth + 1);
        col = col + rc * o.refl;
    }
    col
}

fn to_byte(c: f64) -> u8 {
    let c = if c.is_nan() { 0.0 } else { c.max(0.0).min(1.0) };
    (c * 255.0 + 0.5) as u8
}

fn main() {
    let args: Vec<String> = env::args().collect();
    if args.len() != 3 {
        eprintln!("usage: {} scene_description_file output_image", args[0]);
        process::exit(1);
    }
    let scene = parse_scene(&args[1]);
    let n = scene.res;
    let mut img: Vec<u8> = Vec::with_capacity(n * n * 3);
    for row in 0..n {
        for colx in 0..n {
            // pixel centre on the 1x1 image plane at z = -1
            let x = -0.5 + (colx as f64 + 0.5) / n as f64;
            let y = 0.5 - (row as f64 + 0.5) / n as f64;
            let dir = v3(x, y, -1.0).norm();
            let c = trace(&scene, v3(0.0, 0.0, 0.0), dir, 0);
            img.push(to_byte(c.x));
            img.push(to_byte(c.y));
            img.push(to_byte(c.z));
        }
    }
    let mut out: Vec<u8> = format!("P6\n{} {}\n255\n", n, n).into_bytes();
    out.extend_from_slice(&img);
    let mut f = match fs::File::create(&args[2]) {
        Ok(f) => f,
        Err(e) => fail(&format!("cannot create '{}': {}", args[2], e)),
    };
    if let Err(e) = f.write_all(&out) {
        fail(&format!("cannot write '{}': {}", args[2], e));
    }
}
