//! The tracer: renders a [`crate::ir::Scene`] to 8-bit RGB, or to the
//! linear radiance the 8-bit values are rounded from.
//!
//! One camera ray per pixel through its centre (docs/rendering.md), or `spp`
//! stratified samples on a jittered √spp×√spp grid ([`sampling`]); each
//! sample's colour is clamped to [0, 1] before the samples are averaged
//! and rounded to 8 bits. Adaptive antialiasing ([`adaptive`]) takes the
//! whole grid only where its corners, then four of its samples, disagree. Rows are rendered in
//! parallel on the current rayon pool; every pixel depends only on the
//! scene, the options and its own position (the jitter is a hash of the
//! pixel and sample), so the image is identical for any number of
//! threads. Everything is generic over the precision [`Real`].
//!
//! [`real`] has the two precisions, [`geometry`] the rays, primitives and
//! their intersection, [`world`] the primitives of a scene (each a [`prim::Prim`]), [`bvh`] the
//! hierarchy that finds them fast, and [`trace`] the integrator; [`probe`]
//! is a separate pass that records what each pixel sees, for grading.

pub mod adaptive;
pub mod bvh;
#[cfg(test)]
mod fixture;
pub mod geometry;
pub mod model;
mod prim;
pub mod probe;
pub mod real;
mod sampling;
pub mod trace;
pub mod world;

use std::ops::Range;

use glam::DVec3;
use rayon::prelude::*;
use serde::Serialize;

use crate::ir;
use adaptive::Corners;
use geometry::Ray;
pub use model::Model;
pub use real::Real;
use real::Vector;
use sampling::{RowRays, Sampler};
pub use trace::Counters;
use trace::Tracer;
pub use world::Accel;

/// How to render. Its serialisation is the part of the options hash of
/// tiles ([`crate::tile::PixelOptions`]) that is not the precision: a field
/// that can change a pixel must serialise.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Options {
    /// Samples per pixel; a square number (1, 4, 9, …).
    pub spp: u32,
    /// Where the samples go: every pixel, or where there is contrast.
    pub antialias: Antialias,
    /// Maximum reflections per camera ray.
    pub max_depth: u32,
    /// Skip work that cannot change an 8-bit value.
    pub skip: bool,
    /// How rays find primitives (never changes the image, so it is not
    /// serialised).
    #[serde(skip)]
    pub accel: Accel,
    /// The jitter of the samples: 0 is the renderer's; another seed gives
    /// an independent stratification (for estimating a reference's error).
    pub seed: u64,
    /// The illumination model's open constants; the default one is not
    /// serialised, so the options hash of tiles rendered with it is the
    /// one it was before the model could be set.
    #[serde(skip_serializing_if = "Model::is_default")]
    pub model: Model,
}

impl Default for Options {
    /// The render model of docs/rendering.md.
    fn default() -> Self {
        Options {
            spp: 1,
            antialias: Antialias::Uniform,
            max_depth: 8,
            skip: true,
            accel: Accel::Auto,
            seed: 0,
            model: Model::default(),
        }
    }
}

/// The floating-point type every ray computation is done in: the type
/// parameter [`Real`] of [`render`], as a value (what `--precision` reads,
/// statistics print and the options hash of tiles records).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Precision {
    F32,
    #[default]
    F64,
}

impl Precision {
    /// Its name: `f32` or `f64`.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
}

impl std::fmt::Display for Precision {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Which pixels take all `spp` samples.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Antialias {
    /// Every pixel.
    Uniform,
    /// Pixels whose corners, then four of their samples, span at least
    /// `threshold`/255 in some channel; the others are the mean of their
    /// corners or of those four ([`adaptive`]).
    /// `threshold` is finite and at least 0 (the CLI refuses others).
    Adaptive { threshold: f64 },
}

/// A rendered image: `size × size` pixels, 3 bytes each, row 0 at the top.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    pub size: u32,
    pub rgb: Vec<u8>,
}

/// A rendered image before quantization: `size × size` pixels, each the
/// mean of its clamped samples in linear RGB, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct Radiance {
    pub size: u32,
    pub pixels: Vec<DVec3>,
}

impl Radiance {
    /// The 8-bit image the renderer writes for this radiance.
    pub fn quantize(&self) -> Image {
        Image {
            size: self.size,
            rgb: self.pixels.iter().flat_map(|&c| quantize(c)).collect(),
        }
    }
}

/// Render `scene` in `precision`, calling `row_done` once per finished
/// row (from any thread).
///
/// ```
/// use std::path::Path;
/// use std::time::Instant;
/// use raytracer_render::render::{render, Options, Precision};
///
/// let text = "camera 2\nsphere\n  dimension 10\n  center 0 0 -20\n  color 1 0 0\nlight\n  location 0 0 0\n  color 1 1 1\n";
/// let loaded = raytracer_scene::frontend::load_bytes("a.txt", Path::new("."), text.as_bytes());
/// let scene = raytracer_render::ir::lower(loaded.checked.unwrap());
/// let (image, counters) = render(Precision::F64, &scene, &Options::default(), &|| ());
/// assert_eq!((image.size, counters.primary_rays), (2, 4));
/// // Every pixel sees the red sphere: no green, no blue.
/// assert!(image.rgb.chunks(3).all(|p| p[0] > 0 && p[1] == 0 && p[2] == 0));
/// ```
pub fn render(
    precision: Precision,
    scene: &ir::Scene,
    options: &Options,
    row_done: &(dyn Fn() + Sync),
) -> (Image, Counters) {
    let size = scene.resolution;
    let (rgb, counters) = render_rows(precision, scene, options, 0..size, row_done);
    (Image { size, rgb }, counters)
}

/// Render rows `rows` of `scene`'s frame (the whole frame is `0..size`):
/// their pixels, 3 bytes each, top row first, and what it took. A pixel's
/// value does not depend on which rows are rendered with it (adaptive
/// sampling's first pass covers the rows beside the band too), so these
/// rows are those of the whole render (a tile of `render --tile`).
pub fn render_rows(
    precision: Precision,
    scene: &ir::Scene,
    options: &Options,
    rows: Range<u32>,
    row_done: &(dyn Fn() + Sync),
) -> (Vec<u8>, Counters) {
    let (pixels, counters) = render_pixels(precision, scene, options, rows, row_done, quantize);
    (pixels.into_flattened(), counters)
}

/// Render `scene` in `precision` to linear radiance: the values [`render`]
/// rounds to 8 bits, from the same samples.
pub fn render_radiance(
    precision: Precision,
    scene: &ir::Scene,
    options: &Options,
    row_done: &(dyn Fn() + Sync),
) -> (Radiance, Counters) {
    let size = scene.resolution;
    let (pixels, counters) = render_pixels(precision, scene, options, 0..size, row_done, |c| c);
    (Radiance { size, pixels }, counters)
}

/// The radiance of every pixel of rows `rows` in `precision`, passed
/// through `finish`: the one place a precision chosen at run time picks
/// the tracer's real type.
fn render_pixels<T: Copy + Send>(
    precision: Precision,
    scene: &ir::Scene,
    options: &Options,
    rows: Range<u32>,
    row_done: &(dyn Fn() + Sync),
    finish: impl Fn(DVec3) -> T + Sync,
) -> (Vec<T>, Counters) {
    match precision {
        Precision::F32 => pixels_in::<f32, T>(scene, options, rows, row_done, finish),
        Precision::F64 => pixels_in::<f64, T>(scene, options, rows, row_done, finish),
    }
}

/// [`render_pixels`] in the real type `R`, rows in parallel.
fn pixels_in<R: Real, T: Copy + Send>(
    scene: &ir::Scene,
    options: &Options,
    rows: Range<u32>,
    row_done: &(dyn Fn() + Sync),
    finish: impl Fn(DVec3) -> T + Sync,
) -> (Vec<T>, Counters) {
    let size = scene.resolution;
    let tracer = Tracer::<R>::with_accel(scene, options.max_depth, options.skip, options.accel)
        .with_model(options.model);
    let sampler =
        Sampler::new(size, options.spp, options.seed).shifted(options.model.pixel_shift());
    let adaptive = sampler.count() > 1;
    let (corners, mut counters) = match options.antialias {
        Antialias::Adaptive { threshold } if adaptive => {
            let (corners, counters) = Corners::rows(&sampler, &tracer, size, rows.clone());
            (Some((corners, threshold)), counters)
        }
        _ => (None, Counters::default()),
    };
    // Black, which a pixel whose camera ray misses stays
    // ([`Sampler::row`] does not hand such pixels over).
    let mut pixels = vec![finish(DVec3::ZERO); size as usize * rows.len()];
    counters += pixels
        .par_chunks_mut(size as usize)
        .zip(rows)
        .map_init(RowRays::default, |rays, (row, j)| {
            let mut counters = Counters::default();
            match &corners {
                None => sampler.row(&tracer, j, rays, &mut counters, |i, value| {
                    row[i] = finish(value);
                }),
                Some((corners, threshold)) => {
                    for (i, pixel) in (0..size).zip(row.iter_mut()) {
                        let value = adaptive::pixel(
                            &sampler,
                            &tracer,
                            corners,
                            (i, j),
                            *threshold,
                            &mut counters,
                        );
                        *pixel = finish(value);
                    }
                }
            }
            row_done();
            counters
        })
        .reduce(Counters::default, |mut a, b| {
            a += b;
            a
        });
    counters.bvh_nodes = tracer.bvh_nodes();
    (pixels, counters)
}

/// The ray through image-plane position (x, y), in pixels from the top
/// left: towards `(−0.5 + x/N, 0.5 − y/N, −1)` from the origin.
pub fn camera_ray<R: Real>(size: u32, x: f64, y: f64) -> Ray<R> {
    let n = f64::from(size);
    let target = R::Vec::new(R::of(-0.5 + x / n), R::of(0.5 - y / n), -R::one());
    Ray {
        origin: eye::<R>(),
        dir: target.normalize(),
        from: Ray::<R>::FROM_NO_PRIMITIVE,
    }
}

/// Where every camera ray starts: the origin.
fn eye<R: Real>() -> R::Vec {
    R::Vec::new(R::zero(), R::zero(), R::zero())
}

/// The output of docs/rendering.md: clamp to [0, 1], then `round(c·255)`, halves up.
/// Rounded by hand rather than with `f64::round`, which is a libm call on
/// baseline x86-64; the fraction `x − ⌊x⌋` is exact here.
fn quantize(color: DVec3) -> [u8; 3] {
    let byte = |c: f64| {
        let x = c.clamp(0.0, 1.0) * 255.0;
        // `as` truncates (NaN becomes 0).
        let whole = x as u8;
        whole + u8::from(x - f64::from(whole) >= 0.5)
    };
    [byte(color.x), byte(color.y), byte(color.z)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_centres_follow_the_spec() {
        let ray = camera_ray::<f64>(4, 0.5, 0.5);
        let expected = DVec3::new(-0.375, 0.375, -1.0).normalize();
        assert!((ray.dir - expected).length() < 1e-15);
    }

    #[test]
    fn quantize_clamps_and_rounds() {
        assert_eq!(quantize(DVec3::new(-0.2, 0.5, 2.0)), [0, 128, 255]);
        assert_eq!(quantize(DVec3::splat(1.0 / 255.0 * 0.49)), [0, 0, 0]);
        assert_eq!(quantize(DVec3::splat(f64::NAN)), [0, 0, 0]);
    }

    #[test]
    fn quantize_rounds_as_f64_round_does() {
        // Every half step, and the values a rounding step either side.
        for k in 0..=510 {
            let exact = f64::from(k) / 510.0;
            let bits = exact.to_bits();
            let around = [bits.saturating_sub(1), bits, bits + 1].map(f64::from_bits);
            for c in around {
                let expected = (c.clamp(0.0, 1.0) * 255.0).round() as u8;
                assert_eq!(quantize(DVec3::splat(c)), [expected; 3], "{c}");
            }
        }
    }
}
