//! What naive ray-tracing numerics get wrong, measured against the
//! product, for docs/numerics.md.
//!
//! ```text
//! cargo run --release --example naive_demo -- docs/img
//! ```
//!
//! A small tracer of its own, on the product's IR and types, with the
//! textbook choices the product avoids: the quadratic `b² − c` for spheres,
//! and secondary rays that start exactly at the hit point with no offset
//! and no own-primitive rule, accepting hits at `t > ε` for a fixed ε
//! (`0`, or `1e-4` as many course tracers do). Each case renders the naive
//! image and the product's, writes them side by side (naive left, product
//! right, 4× enlarged) to the output folder, and prints a markdown table:
//! pixels off by more than 1/255 from the product's f64 image, and for the
//! far spheres the disk's area against π·R². The planet case puts the
//! product's f32 image beside its f64 one. It ends with the measured
//! error of both sphere forms over random far spheres.

use std::path::{Path, PathBuf};

use glam::DVec3;
use raytracer_render::ir::{self, Shape};
use raytracer_render::render::geometry::{self, Ray};
use raytracer_render::render::model::AMBIENT;
use raytracer_render::render::real::{Real, Vector};
use raytracer_render::render::trace::{sphere_uv, texel};
use raytracer_render::render::Precision;
use raytracer_render::render::{camera_ray, render, Image, Options};

/// How the naive tracer spawns shadow and reflection rays: from the hit
/// point itself, accepting any hit beyond `epsilon`.
#[derive(Clone, Copy)]
struct Naive {
    textbook_spheres: bool,
    epsilon: f64,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "docs/img".into()));
    std::fs::create_dir_all(&out)?;
    println!("| case | precision | method | pixels off > 1/255 | note |");
    println!("|---|---|---|---:|---|");
    for exponent in [3, 4] {
        far_sphere(&out, exponent)?;
    }
    let no_offset = Naive {
        textbook_spheres: false,
        epsilon: 0.0,
    };
    let fixed = Naive {
        textbook_spheres: false,
        epsilon: 1e-4,
    };
    for (scene, naive, label) in [
        ("shadow_acne.txt", no_offset, "no offset, t > 0"),
        ("scaled_1.txt", fixed, "fixed ε = 1e-4"),
        ("scaled_1e-3.txt", fixed, "fixed ε = 1e-4"),
        ("scaled_1e6.txt", fixed, "fixed ε = 1e-4"),
    ] {
        spawn_case(&out, scene, naive, label)?;
    }
    precision_case(&out, "planet.txt")?;
    println!();
    sphere_error_table();
    Ok(())
}

fn hard_scene(name: &str) -> ir::Scene {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/hard");
    let bytes = std::fs::read(dir.join(name)).expect("scenes/hard/ is part of the repository");
    let loaded = raytracer_scene::frontend::load_bytes(name, &dir, &bytes);
    ir::lower(loaded.checked.expect("the hard scenes check clean"))
}

/// A far sphere of radius/distance 10^-exponent, a 64 px window of a
/// virtual image where the disk is 20 px in radius, in f32.
fn far_sphere(out: &Path, exponent: i32) -> Result<(), Box<dyn std::error::Error>> {
    let scene = hard_scene(&format!("far_sphere_1e-{exponent}.txt"));
    let ratio = 10f64.powi(-exponent);
    let n = (20.0 / ratio).round() as u32;
    let side = 64;
    let radius = f64::from(n) * ratio / (1.0 - ratio * ratio).sqrt();
    let area = std::f64::consts::PI * radius * radius;
    let window = |naive: Option<Naive>| -> Image {
        let first = n / 2 - side / 2;
        let mut rgb = Vec::new();
        for j in first..first + side {
            for i in first..first + side {
                let ray = camera_ray::<f32>(n, f64::from(i) + 0.5, f64::from(j) + 0.5);
                let color = match naive {
                    Some(naive) => trace(&scene, naive, ray, 0),
                    None => {
                        let tracer =
                            raytracer_render::render::trace::Tracer::<f32>::new(&scene, 8, true);
                        tracer.radiance(ray, &mut Default::default())
                    }
                };
                rgb.extend(bytes(color));
            }
        }
        Image { size: side, rgb }
    };
    let textbook = window(Some(Naive {
        textbook_spheres: true,
        epsilon: 0.0,
    }));
    let stable = window(None);
    let lit = |image: &Image| {
        image
            .rgb
            .chunks(3)
            .filter(|p| p.iter().any(|&c| c > 0))
            .count() as f64
    };
    for (method, image) in [
        ("textbook b² − c", &textbook),
        ("stable (RTG ch. 7)", &stable),
    ] {
        let count = lit(image);
        println!(
            "| far sphere 1e-{exponent} | f32 | {method} | — | disk {count} px vs π·R² = {area:.0} ({:+.1}%) |",
            100.0 * (count - area) / area
        );
    }
    save_pair(
        &out.join(format!("far_sphere_1e-{exponent}.png")),
        &textbook,
        &stable,
    )
}

/// A scene through the naive spawning in f32, beside the product's f32.
fn spawn_case(
    out: &Path,
    name: &str,
    naive: Naive,
    label: &str,
) -> Result<(), Box<dyn std::error::Error>> {
    let scene = hard_scene(name);
    let options = Options::default();
    let (truth, _) = render(Precision::F64, &scene, &options, &|| {});
    let (product, _) = render(Precision::F32, &scene, &options, &|| {});
    let n = scene.resolution;
    let mut rgb = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let ray = camera_ray::<f32>(n, f64::from(i) + 0.5, f64::from(j) + 0.5);
            rgb.extend(bytes(trace(&scene, naive, ray, 0)));
        }
    }
    let naive_image = Image { size: n, rgb };
    let off = |image: &Image| {
        image
            .rgb
            .chunks(3)
            .zip(truth.rgb.chunks(3))
            .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 1))
            .count()
    };
    let total = (n * n) as f64;
    for (method, image) in [
        (label, &naive_image),
        ("product (error-bound offset, own-primitive rule)", &product),
    ] {
        let count = off(image);
        println!(
            "| {name} | f32 | {method} | {count} ({:.1}%) | against the product in f64 |",
            100.0 * count as f64 / total
        );
    }
    let stem = name.trim_end_matches(".txt");
    let tag = if naive.epsilon > 0.0 {
        "epsilon"
    } else {
        "no_offset"
    };
    save_pair(
        &out.join(format!("{stem}_{tag}.png")),
        &naive_image,
        &product,
    )
}

/// The product in f32 beside the product in f64: where f32 is not enough.
fn precision_case(out: &Path, name: &str) -> Result<(), Box<dyn std::error::Error>> {
    let scene = hard_scene(name);
    let options = Options::default();
    let (wide, _) = render(Precision::F64, &scene, &options, &|| {});
    let (narrow, _) = render(Precision::F32, &scene, &options, &|| {});
    let off = narrow
        .rgb
        .chunks(3)
        .zip(wide.rgb.chunks(3))
        .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 1))
        .count();
    println!(
        "| {name} | f32 | product | {off} ({:.1}%) | against the product in f64 |",
        100.0 * off as f64 / f64::from(scene.resolution * scene.resolution)
    );
    let stem = name.trim_end_matches(".txt");
    save_pair(&out.join(format!("{stem}_f32_f64.png")), &narrow, &wide)
}

/// The naive Whitted tracer: same shading as the product, naive numerics.
fn trace<R: Real>(scene: &ir::Scene, naive: Naive, ray: Ray<R>, depth: u32) -> DVec3 {
    let Some((t, index)) = closest(scene, naive, &ray, R::infinity(), depth > 0) else {
        return DVec3::ZERO;
    };
    let object = &scene.objects[index];
    let p = ray.origin + ray.dir * t;
    let (outward, uv) = match object.shape {
        Shape::Sphere { center, radius } => {
            let m = (p.wide() - center) / radius;
            (R::Vec::of(m).normalize(), sphere_uv(m))
        }
        Shape::Rect {
            center,
            normal,
            right,
            up,
            width,
            height,
        } => {
            let local = p.wide() - center;
            (
                R::Vec::of(normal),
                (local.dot(right) / width + 0.5, local.dot(up) / height + 0.5),
            )
        }
    };
    let n = if outward.dot(ray.dir) > R::zero() {
        -outward
    } else {
        outward
    };
    let albedo = match scene.material(object).texture {
        Some(k) => texel(&scene.textures[k], uv.0, uv.1),
        None => scene.material(object).color,
    };
    let mut color = albedo * AMBIENT;
    for light in &scene.lights {
        let to_light = R::Vec::of(light.position) - p;
        let distance = to_light.length();
        let l = to_light * distance.recip();
        let cos = n.dot(l).wide();
        if cos <= 0.0 {
            continue;
        }
        let shadow = Ray {
            origin: p,
            dir: l,
            from: Ray::<R>::FROM_NO_PRIMITIVE,
        };
        if closest(scene, naive, &shadow, distance, true).is_none() {
            color += albedo * light.color * cos;
        }
    }
    let k = scene.material(object).reflectivity;
    if k > 0.0 && depth < 8 {
        let dir = (ray.dir - n * (R::of(2.0) * ray.dir.dot(n))).normalize();
        color += trace(
            scene,
            naive,
            Ray::<R> {
                origin: p,
                dir,
                from: Ray::<R>::FROM_NO_PRIMITIVE,
            },
            depth + 1,
        ) * k;
    }
    color
}

/// The nearest hit in `(ε, t_max)`; `secondary` rays use the fixed ε.
fn closest<R: Real>(
    scene: &ir::Scene,
    naive: Naive,
    ray: &Ray<R>,
    t_max: R,
    secondary: bool,
) -> Option<(R, usize)> {
    let t_min = if secondary {
        R::of(naive.epsilon)
    } else {
        R::zero()
    };
    let mut best: Option<(R, usize)> = None;
    for (index, object) in scene.objects.iter().enumerate() {
        let roots = match object.shape {
            Shape::Sphere { center, radius } if naive.textbook_spheres => {
                textbook(ray, R::Vec::of(center), R::of(radius))
            }
            Shape::Sphere { center, radius } => stable(ray, R::Vec::of(center), R::of(radius)),
            Shape::Rect { .. } => {
                let rect = geometry::Shape::<R>::from(&object.shape);
                // Shift the origin back by t_min so the product's `t > 0`
                // test becomes `t > ε`.
                let back = Ray {
                    origin: ray.origin + ray.dir * t_min,
                    ..*ray
                };
                [
                    rect.hit(&back, t_max - t_min, false).map(|t| t + t_min),
                    None,
                ]
            }
        };
        for t in roots.into_iter().flatten() {
            if t > t_min && t < t_max && best.is_none_or(|(b, _)| t < b) {
                best = Some((t, index));
            }
        }
    }
    best
}

/// The textbook roots `−b ± √(b² − c)` with `b = f·d`, `c = f·f − r²`.
fn textbook<R: Real>(ray: &Ray<R>, center: R::Vec, radius: R) -> [Option<R>; 2] {
    let f = ray.origin - center;
    let b = f.dot(ray.dir);
    let c = f.dot(f) - radius * radius;
    let disc = b * b - c;
    if disc < R::zero() {
        return [None, None];
    }
    let s = disc.sqrt();
    [Some(-b - s), Some(-b + s)]
}

/// Both roots by the stable form (Ray Tracing Gems ch. 7), as the product.
fn stable<R: Real>(ray: &Ray<R>, center: R::Vec, radius: R) -> [Option<R>; 2] {
    let f = ray.origin - center;
    let b = f.dot(ray.dir);
    let l = f - ray.dir * b;
    let delta = radius * radius - l.dot(l);
    if delta < R::zero() {
        return [None, None];
    }
    let q = -b - b.signum() * delta.sqrt();
    let c = f.dot(f) - radius * radius;
    if q.is_zero() {
        return [None, None];
    }
    [Some(c / q), Some(q)]
}

fn bytes(color: DVec3) -> [u8; 3] {
    [color.x, color.y, color.z].map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
}

/// Two images side by side, 4× enlarged, with a 4 px grey gap.
fn save_pair(path: &Path, left: &Image, right: &Image) -> Result<(), Box<dyn std::error::Error>> {
    let (n, zoom, gap) = (left.size, 4, 4);
    let width = 2 * n * zoom + gap;
    let mut out = image::RgbImage::from_pixel(width, n * zoom, image::Rgb([128, 128, 128]));
    for (offset, image) in [(0, left), (n * zoom + gap, right)] {
        for y in 0..n * zoom {
            for x in 0..n * zoom {
                let k = ((y / zoom) * n + x / zoom) as usize * 3;
                out.put_pixel(
                    offset + x,
                    y,
                    image::Rgb([image.rgb[k], image.rgb[k + 1], image.rgb[k + 2]]),
                );
            }
        }
    }
    out.save(path)?;
    Ok(())
}

/// Over random rays at far spheres: how far the hit point lies off the
/// surface, in units of ε·(|o − c| + r), and how many clear hits are lost.
fn sphere_error_table() {
    println!("| sphere form | precision | radius/distance | max off-surface (ε·scale) | median | clear hits lost |");
    println!("|---|---|---|---:|---:|---:|");
    for ratio in [1e-1, 1e-2, 1e-3, 1e-4, 1e-5] {
        for textbook_form in [true, false] {
            measure::<f32>(ratio, textbook_form);
            measure::<f64>(ratio, textbook_form);
        }
    }
}

fn measure<R: Real>(ratio: f64, textbook_form: bool) {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut random = move || {
        // SplitMix64.
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut offs = Vec::new();
    let mut lost = 0;
    let trials = 20_000;
    for _ in 0..trials {
        let distance = 10f64.powf(random() * 4.0 - 1.0);
        let radius = distance * ratio;
        let toward = DVec3::new(random() - 0.5, random() - 0.5, random() - 0.5).normalize();
        let center = R::Vec::of(toward * distance);
        let r = R::of(radius);
        // Aim within 90% of the disk so the ray clearly hits.
        let across = DVec3::new(random() - 0.5, random() - 0.5, random() - 0.5).normalize();
        let side = (across - toward * across.dot(toward)).normalize();
        let target = center.wide() + side * (radius * 0.9 * random());
        let ray = Ray {
            origin: R::Vec::of(DVec3::ZERO),
            dir: R::Vec::of(target.normalize()).normalize(),
            from: Ray::<R>::FROM_NO_PRIMITIVE,
        };
        let roots = if textbook_form {
            textbook(&ray, center, r)
        } else {
            stable(&ray, center, r)
        };
        let t = roots
            .into_iter()
            .flatten()
            .filter(|&t| t > R::zero())
            .reduce(|a, b| a.min(b));
        let Some(t) = t else {
            lost += 1;
            continue;
        };
        let p = ray.origin.wide() + ray.dir.wide() * t.wide();
        let scale = (ray.origin.wide() - center.wide()).length() + r.wide();
        offs.push(((p - center.wide()).length() - r.wide()).abs() / (R::epsilon().wide() * scale));
    }
    offs.sort_by(f64::total_cmp);
    let (max, median) = (
        offs.last().copied().unwrap_or(f64::NAN),
        offs.get(offs.len() / 2).copied().unwrap_or(f64::NAN),
    );
    let form = if textbook_form {
        "textbook b² − c"
    } else {
        "stable (RTG ch. 7)"
    };
    let precision = if R::epsilon().wide() > 1e-10 {
        "f32"
    } else {
        "f64"
    };
    println!(
        "| {form} | {precision} | {ratio:.0e} | {max:.2} | {median:.2} | {lost} of {trials} ({:.1}%) |",
        100.0 * f64::from(lost) / f64::from(trials)
    );
}
