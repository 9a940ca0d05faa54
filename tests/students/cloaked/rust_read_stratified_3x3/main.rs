// HW4 ray tracer in Rust
// usage: ./tracer <scene> <output.ppm>
use std::env;
use std::fs;
use std::io::Write;
use std::path::Path;
use std::process;

#[derive(Clone, Copy, Debug, PartialEq)]
struct V3 {
    x: f64,
    y: f64,
    z: f64,
}

fn v3(x: f64, y: f64, z: f64) -> V3 {
    V3 { x, y, z }
}

impl V3 {
    fn add(self, o: V3) -> V3 {
        v3(self.x + o.x, self.y + o.y, self.z + o.z)
    }
    fn sub(self, o: V3) -> V3 {
        v3(self.x - o.x, self.y - o.y, self.z - o.z)
    }
    fn scale(self, s: f64) -> V3 {
        v3(self.x * s, self.y * s, self.z * s)
    }
    fn hadamard(self, o: V3) -> V3 {
        v3(self.x * o.x, self.y * o.y, self.z * o.z)
    }
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
    fn length(self) -> f64 {
        self.dot(self).sqrt()
    }
    fn unit(self) -> V3 {
        let l = self.length();
        if l > 0.0 {
            self.scale(1.0 / l)
        } else {
            self
        }
    }
}

fn fail(msg: &str) -> ! {
    eprintln!("raytracer: {}", msg);
    process::exit(1);
}

struct Texture {
    w: usize,
    h: usize,
    data: Vec<V3>,
}

impl Texture {
    fn load(path: &Path) -> Texture {
        let bytes = match fs::read(path) {
            Ok(b) => b,
            Err(e) => fail(&format!("cannot read texture {}: {}", path.display(), e)),
        };
        let mut pos = 0usize;
        let mut header: Vec<String> = Vec::new();
        while header.len() < 4 {
            while pos < bytes.len() {
                if bytes[pos] == b'#' {
                    while pos < bytes.len() && bytes[pos] != b'\n' {
                        pos += 1;
                    }
                } else if bytes[pos].is_ascii_whitespace() {
                    pos += 1;
                } else {
                    break;
                }
            }
            let start = pos;
            while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() && bytes[pos] != b'#' {
                pos += 1;
            }
            if start == pos {
                fail(&format!("truncated texture header in {}", path.display()));
            }
            header.push(String::from_utf8_lossy(&bytes[start..pos]).to_string());
        }
        let magic = header[0].as_str();
        let num = |s: &str| -> usize {
            s.parse::<usize>()
                .unwrap_or_else(|_| fail(&format!("bad texture header value '{}'", s)))
        };
        let w = num(&header[1]);
        let h = num(&header[2]);
        let maxv = num(&header[3]);
        if w == 0 || h == 0 || maxv == 0 || maxv > 65535 {
            fail(&format!("bad texture header in {}", path.display()));
        }
        let count = w * h * 3;
        let mut vals: Vec<f64> = Vec::with_capacity(count);
        match magic {
            "P6" => {
                pos += 1;
                let two = maxv > 255;
                let need = if two { count * 2 } else { count };
                if bytes.len() < pos + need {
                    fail(&format!("texture {} is truncated", path.display()));
                }
                for k in 0..count {
                    let v = if two {
                        ((bytes[pos + 2 * k] as usize) << 8) | bytes[pos + 2 * k + 1] as usize
                    } else {
                        bytes[pos + k] as usize
                    };
                    vals.push(v as f64 / maxv as f64);
                }
            }
            "P3" => {
                let rest = String::from_utf8_lossy(&bytes[pos..]).to_string();
                let mut cleaned = String::new();
                for line in rest.lines() {
                    let l = match line.find('#') {
                        Some(i) => &line[..i],
                        None => line,
                    };
                    cleaned.push_str(l);
                    cleaned.push(' ');
                }
                for t in cleaned.split_whitespace().take(count) {
                    vals.push(num(t) as f64 / maxv as f64);
                }
                if vals.len() < count {
                    fail(&format!("texture {} is truncated", path.display()));
                }
            }
            _ => fail(&format!("{} is not a PPM texture", path.display())),
        }
        let data = vals.chunks(3).map(|c| v3(c[0], c[1], c[2])).collect();
        Texture { w, h, data }
    }

    fn get(&self, x: usize, y: usize) -> V3 {
        self.data[y.min(self.h - 1) * self.w + x.min(self.w - 1)]
    }

    // bilinear lookup, (u, v) in [0,1), v = 0 is the bottom row of the image
    fn sample(&self, u: f64, v: f64) -> V3 {
        let u = u - u.floor();
        let v = v - v.floor();
        let fx = u * self.w as f64 - 0.5;
        let fy = (1.0 - v) * self.h as f64 - 0.5;
        let x0 = fx.floor();
        let y0 = fy.floor();
        let ax = fx - x0;
        let ay = fy - y0;
        let wrapx = |x: f64| -> usize { (x as i64).rem_euclid(self.w as i64) as usize };
        let clampy = |y: f64| -> usize { (y.max(0.0) as usize).min(self.h - 1) };
        let (xa, xb) = (wrapx(x0), wrapx(x0 + 1.0));
        let (ya, yb) = (clampy(y0), clampy(y0 + 1.0));
        let top = self.get(xa, ya).scale(1.0 - ax).add(self.get(xb, ya).scale(ax));
        let bot = self.get(xa, yb).scale(1.0 - ax).add(self.get(xb, yb).scale(ax));
        top.scale(1.0 - ay).add(bot.scale(ay))
    }
}

enum Shape {
    Ball { c: V3, r: f64 },
    Quad { c: V3, n: V3, up: V3, side: V3, h: f64, w: f64 },
}

struct Thing {
    shape: Shape,
    color: V3,
    mirror: f64,
    tex: Option<Texture>,
}

struct Lamp {
    at: V3,
    rgb: V3,
}

struct World {
    size: usize,
    things: Vec<Thing>,
    lamps: Vec<Lamp>,
}

// raw attributes collected while reading a block
#[derive(Default)]
struct Block {
    kind: String,
    dims: Vec<f64>,
    center: Option<V3>,
    color: Option<V3>,
    refl: Option<f64>,
    normal: Option<V3>,
    headup: Option<V3>,
    texture: Option<String>,
    location: Option<V3>,
}

fn number(tok: Option<&str>, what: &str) -> f64 {
    match tok {
        None => fail(&format!("missing number for '{}'", what)),
        Some(t) => match t.parse::<f64>() {
            Ok(v) if v.is_finite() => v,
            _ => fail(&format!("bad number '{}' for '{}'", t, what)),
        },
    }
}

fn finish(b: Block, dir: &Path, w: &mut World) {
    match b.kind.as_str() {
        "light" => {
            let at = b.location.unwrap_or_else(|| fail("light without location"));
            let rgb = b.color.unwrap_or(v3(1.0, 1.0, 1.0));
            w.lamps.push(Lamp { at, rgb });
        }
        "sphere" | "plane" => {
            let tex = b.texture.as_ref().map(|name| {
                let p = Path::new(name);
                if p.is_absolute() {
                    Texture::load(p)
                } else {
                    Texture::load(&dir.join(p))
                }
            });
            let c = b.center.unwrap_or(v3(0.0, 0.0, 0.0));
            let shape = if b.kind == "sphere" {
                let r = *b.dims.first().unwrap_or(&1.0);
                if r <= 0.0 {
                    fail("sphere dimension must be positive");
                }
                Shape::Ball { c, r }
            } else {
                let n = b.normal.unwrap_or(v3(0.0, 0.0, 1.0));
                if n.length() == 0.0 {
                    fail("plane normal must not be zero");
                }
                let n = n.unit();
                let hu = b.headup.unwrap_or(v3(0.0, 1.0, 0.0));
                let mut up = hu.sub(n.scale(hu.dot(n)));
                if up.length() < 1e-9 {
                    // headup along the normal: use the world axis least aligned with it
                    let ax = if n.x.abs() <= n.y.abs() && n.x.abs() <= n.z.abs() {
                        v3(1.0, 0.0, 0.0)
                    } else if n.y.abs() <= n.z.abs() {
                        v3(0.0, 1.0, 0.0)
                    } else {
                        v3(0.0, 0.0, 1.0)
                    };
                    up = ax.sub(n.scale(ax.dot(n)));
                }
                let up = up.unit();
                let side = n.cross(up).unit();
                // first dimension runs along headup, second across it
                let h = *b.dims.first().unwrap_or(&1.0);
                let wd = *b.dims.get(1).unwrap_or(&h);
                Shape::Quad { c, n, up, side, h, w: wd }
            };
            w.things.push(Thing {
                shape,
                color: b.color.unwrap_or(v3(0.5, 0.5, 0.5)),
                mirror: b.refl.unwrap_or(0.0),
                tex,
            });
        }
        _ => {}
    }
}

fn read_world(path: &str) -> World {
    let text = match fs::read(path) {
        Ok(b) => String::from_utf8_lossy(&b).to_string(),
        Err(e) => fail(&format!("cannot read scene {}: {}", path, e)),
    };
    let dir = Path::new(path).parent().unwrap_or(Path::new("")).to_path_buf();
    let mut toks = text.split(|c: char| c.is_whitespace()).filter(|t| !t.is_empty());
    let mut w = World { size: 0, things: Vec::new(), lamps: Vec::new() };
    let mut cam = false;
    let mut cur: Option<Block> = None;
    while let Some(tok) = toks.next() {
        match tok {
            "camera" => {
                if let Some(b) = cur.take() {
                    finish(b, &dir, &mut w);
                }
                let t = toks.next().unwrap_or_else(|| fail("missing camera resolution"));
                w.size = match t.parse::<usize>() {
                    Ok(n) if n > 0 && n <= 20000 => n,
                    _ => fail(&format!("bad camera resolution '{}'", t)),
                };
                cam = true;
            }
            "sphere" | "plane" | "light" => {
                if let Some(b) = cur.take() {
                    finish(b, &dir, &mut w);
                }
                cur = Some(Block { kind: tok.to_string(), ..Default::default() });
            }
            _ => {
                let b = match cur.as_mut() {
                    Some(b) => b,
                    None => fail(&format!("'{}' outside of any object or light", tok)),
                };
                let is_obj = b.kind != "light";
                let three = |what: &str, toks: &mut dyn Iterator<Item = &str>| -> V3 {
                    let x = number(toks.next(), what);
                    let y = number(toks.next(), what);
                    let z = number(toks.next(), what);
                    v3(x, y, z)
                };
                match tok {
                    "dimension" if is_obj => {
                        let k = if b.kind == "plane" { 2 } else { 1 };
                        b.dims = (0..k).map(|_| number(toks.next(), tok)).collect();
                    }
                    "center" if is_obj => b.center = Some(three(tok, &mut toks)),
                    "color" => b.color = Some(three(tok, &mut toks)),
                    "reflectivity" if is_obj => b.refl = Some(number(toks.next(), tok)),
                    "normal" if b.kind == "plane" => b.normal = Some(three(tok, &mut toks)),
                    "headup" if b.kind == "plane" => b.headup = Some(three(tok, &mut toks)),
                    "texture" if is_obj => {
                        let t = toks.next().unwrap_or_else(|| fail("missing texture file name"));
                        b.texture = Some(t.to_string());
                    }
                    "location" if !is_obj => b.location = Some(three(tok, &mut toks)),
                    _ => fail(&format!("unknown keyword '{}' in {} block", tok, b.kind)),
                }
            }
        }
    }
    if let Some(b) = cur.take() {
        finish(b, &dir, &mut w);
    }
    if !cam {
        fail("scene has no camera line");
    }
    w
}

const AMBIENT: f64 = 0.15;
const SPEC_K: f64 = 0.3;
const SPEC_EXP: i32 = 32;
const MAX_BOUNCES: u32 = 8;
const T_MIN: f64 = 1e-6;

fn intersect(s: &Shape, o: V3, d: V3) -> Option<f64> {
    match *s {
        Shape::Ball { c, r } => {
            let oc = o.sub(c);
            let a = d.dot(d);
            let b = 2.0 * d.dot(oc);
            let cc = oc.dot(oc) - r * r;
            let disc = b * b - 4.0 * a * cc;
            if disc < 0.0 {
                return None;
            }
            let sq = disc.sqrt();
            let near = (-b - sq) / (2.0 * a);
            let far = (-b + sq) / (2.0 * a);
            if near > T_MIN {
                Some(near)
            } else if far > T_MIN {
                Some(far)
            } else {
                None
            }
        }
        Shape::Quad { c, n, up, side, h, w } => {
            let den = n.dot(d);
            if den.abs() < 1e-12 {
                return None;
            }
            let t = n.dot(c.sub(o)) / den;
            if t <= T_MIN {
                return None;
            }
            let q = o.add(d.scale(t)).sub(c);
            if q.dot(up).abs() <= h * 0.5 && q.dot(side).abs() <= w * 0.5 {
                Some(t)
            } else {
                None
            }
        }
    }
}

fn nearest(w: &World, o: V3, d: V3, skip: Option<usize>) -> Option<(usize, f64)> {
    let mut best: Option<(usize, f64)> = None;
    for (i, th) in w.things.iter().enumerate() {
        if Some(i) == skip {
            continue;
        }
        if let Some(t) = intersect(&th.shape, o, d) {
            if best.map_or(true, |(_, bt)| t < bt) {
                best = Some((i, t));
            }
        }
    }
    best
}

fn albedo(th: &Thing, p: V3) -> V3 {
    let tex = match &th.tex {
        None => return th.color,
        Some(t) => t,
    };
    let (u, v) = match th.shape {
        Shape::Ball { c, .. } => {
            let n = p.sub(c).unit();
            let u = n.x.atan2(-n.z) / (2.0 * std::f64::consts::PI);
            let u = u - u.floor();
            let v = 1.0 - n.y.max(-1.0).min(1.0).acos() / std::f64::consts::PI;
            (u, v)
        }
        Shape::Quad { c, up, side, h, w, .. } => {
            let q = p.sub(c);
            (q.dot(side) / w + 0.5, q.dot(up) / h + 0.5)
        }
    };
    tex.sample(u, v)
}

fn radiance(w: &World, o: V3, d: V3, bounce: u32, from: Option<usize>) -> V3 {
    let (idx, t) = match nearest(w, o, d, from) {
        None => return v3(0.0, 0.0, 0.0),
        Some(h) => h,
    };
    let th = &w.things[idx];
    let p = o.add(d.scale(t));
    let mut n = match th.shape {
        Shape::Ball { c, .. } => p.sub(c).unit(),
        Shape::Quad { n, .. } => n,
    };
    if n.dot(d) > 0.0 {
        n = n.scale(-1.0);
    }
    let kd = albedo(th, p);
    let view = d.scale(-1.0);

    let mut local = kd.scale(AMBIENT);
    for lamp in &w.lamps {
        let to = lamp.at.sub(p);
        let dist = to.length();
        let l = to.scale(1.0 / dist);
        // shadow ray: does any other object sit between the point and the lamp?
        let shadowed = w.things.iter().enumerate().any(|(j, other)| {
            j != idx && intersect(&other.shape, p, l).map_or(false, |s| s < dist)
        });
        if shadowed {
            continue;
        }
        let ndotl = n.dot(l);
        let diff = ndotl.max(0.0);
        local = local.add(kd.hadamard(lamp.rgb).scale(diff));
        if ndotl > 0.0 {
            let r = n.scale(2.0 * ndotl).sub(l);
            let rv = r.dot(view).max(0.0);
            local = local.add(lamp.rgb.scale(SPEC_K * rv.powi(SPEC_EXP)));
        }
    }

    if th.mirror <= 0.0 || bounce >= MAX_BOUNCES {
        return local;
    }
    let rdir = n.scale(2.0 * n.dot(view)).sub(view).unit();
    let bounced = radiance(w, p, rdir, bounce + 1, Some(idx));
    let k = th.mirror.min(1.0);
    local.scale(1.0 - k).add(bounced.scale(k))
}

fn to_byte(c: f64) -> u8 {
    (c.max(0.0).min(1.0) * 255.999) as u8
}

fn main() {
    let args: Vec<String> = env::args().collect();
    if args.len() != 3 {
        fail("usage: tracer <scene file> <output image>");
    }
    let world = read_world(&args[1]);
    let n = world.size;
    let mut img = vec![0u8; n * n * 3];
    // 3x3 stratified jittered samples per pixel, fixed-seed xorshift32
    let mut seed: u32 = 0x2545_F491;
    let mut rnd = move || -> f64 {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed as f64 / 4294967296.0
    };
    for row in 0..n {
        for col in 0..n {
            let mut c = v3(0.0, 0.0, 0.0);
            for sy in 0..3 {
                for sx in 0..3 {
                    let jx = (sx as f64 + rnd()) / 3.0;
                    let jy = (sy as f64 + rnd()) / 3.0;
                    let px = (col as f64 + jx) / n as f64 - 0.5;
                    let py = 0.5 - (row as f64 + jy) / n as f64;
                    let dir = v3(px, py, -1.0).unit();
                    c = c.add(radiance(&world, v3(0.0, 0.0, 0.0), dir, 0, None));
                }
            }
            let c = c.scale(1.0 / 9.0);
            let k = (row * n + col) * 3;
            img[k] = to_byte(c.x);
            img[k + 1] = to_byte(c.y);
            img[k + 2] = to_byte(c.z);
        }
    }
    let mut out: Vec<u8> = format!("P6\n{} {}\n255\n", n, n).into_bytes();
    out.extend_from_slice(&img);
    let mut f = fs::File::create(&args[2])
        .unwrap_or_else(|e| fail(&format!("cannot create {}: {}", args[2], e)));
    if let Err(e) = f.write_all(&out) {
        fail(&format!("cannot write {}: {}", args[2], e));
    }
}
