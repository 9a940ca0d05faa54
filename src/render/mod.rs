//! The tracer: renders a [`crate::ir::Scene`] to 8-bit RGB.
//!
//! One camera ray per pixel through its centre (docs/rendering.md), or `spp`
//! stratified samples on a jittered √spp×√spp grid; each sample's colour is
//! clamped to [0, 1] before the samples are averaged and rounded to 8 bits.
//! Rows are rendered in parallel on the current rayon pool; every pixel
//! depends only on the scene and its own position (the jitter is a hash
//! of the pixel and sample), so the image is identical for any number of
//! threads. Everything is generic over the precision [`Real`].
//!
//! [`real`] has the two precisions, [`geometry`] the rays, primitives and
//! their intersection, [`world`] the primitives of a scene (each a [`prim::Prim`]), [`bvh`] the
//! hierarchy that finds them fast, and [`trace`] the integrator.

pub mod bvh;
pub mod geometry;
mod prim;
pub mod real;
pub mod trace;
pub mod world;

use std::ops::Range;

use glam::DVec3;
use rayon::prelude::*;
use serde::Serialize;

use crate::ir;
use geometry::Ray;
pub use real::Real;
use real::Vector;
pub use trace::Counters;
use trace::Tracer;
pub use world::Accel;

/// How to render. Its serialisation is the part of the options hash of
/// tiles ([`crate::tile::PixelOptions`]) that is not the precision: a field
/// that can change a pixel must serialise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Options {
    /// Samples per pixel; a square number (1, 4, 9, …).
    pub spp: u32,
    /// Maximum reflections per camera ray.
    pub max_depth: u32,
    /// Skip work that cannot change an 8-bit value.
    pub skip: bool,
    /// How rays find primitives (never changes the image, so it is not
    /// serialised).
    #[serde(skip)]
    pub accel: Accel,
}

impl Default for Options {
    /// The render model of docs/rendering.md.
    fn default() -> Self {
        Options {
            spp: 1,
            max_depth: 8,
            skip: true,
            accel: Accel::Auto,
        }
    }
}

/// A rendered image: `size × size` pixels, 3 bytes each, row 0 at the top.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    pub size: u32,
    pub rgb: Vec<u8>,
}

/// Render `scene` in precision `R`, calling `row_done` once per finished
/// row (from any thread).
pub fn render<R: Real>(
    scene: &ir::Scene,
    options: &Options,
    row_done: &(dyn Fn() + Sync),
) -> (Image, Counters) {
    let size = scene.resolution;
    let (rgb, counters) = render_rows::<R>(scene, options, 0..size, row_done);
    (Image { size, rgb }, counters)
}

/// Render rows `rows` of `scene`'s frame (the whole frame is `0..size`):
/// their pixels, 3 bytes each, top row first, and what it took. A pixel's
/// value does not depend on which rows are rendered with it, so these rows
/// are those of the whole render (a tile of `render --tile`).
pub fn render_rows<R: Real>(
    scene: &ir::Scene,
    options: &Options,
    rows: Range<u32>,
    row_done: &(dyn Fn() + Sync),
) -> (Vec<u8>, Counters) {
    let size = scene.resolution;
    let tracer = Tracer::<R>::with_accel(scene, options.max_depth, options.skip, options.accel);
    let grid = options.spp.isqrt().max(1);
    let mut rgb = vec![0u8; size as usize * rows.len() * 3];
    let counters = rgb
        .par_chunks_mut(size as usize * 3)
        .zip(rows)
        .map(|(row, j)| {
            let mut counters = Counters::default();
            for (i, pixel) in row.chunks_exact_mut(3).enumerate() {
                let samples = (0..grid * grid).map(|sample| {
                    let (u, v) = sample_offset(i as u32, j, sample, grid);
                    let ray = camera_ray::<R>(size, i as f64 + u, f64::from(j) + v);
                    tracer
                        .radiance(ray, &mut counters)
                        .clamp(DVec3::ZERO, DVec3::ONE)
                });
                pixel.copy_from_slice(&quantize(mean(samples)));
            }
            row_done();
            counters
        })
        .reduce(Counters::default, |mut a, b| {
            a += b;
            a
        });
    let counters = Counters {
        bvh_nodes: tracer.bvh_nodes(),
        ..counters
    };
    (rgb, counters)
}

/// The ray through image-plane position (x, y), in pixels from the top
/// left: towards `(−0.5 + x/N, 0.5 − y/N, −1)` from the origin.
pub fn camera_ray<R: Real>(size: u32, x: f64, y: f64) -> Ray<R> {
    let n = f64::from(size);
    let target = R::Vec::new(R::of(-0.5 + x / n), R::of(0.5 - y / n), -R::one());
    Ray {
        origin: R::Vec::new(R::zero(), R::zero(), R::zero()),
        dir: target.normalize(),
        from: None,
    }
}

/// Where in pixel (i, j) sample `s` of a `grid × grid` stratification
/// lies: the centre for one sample, else a jittered point in its cell.
fn sample_offset(i: u32, j: u32, s: u32, grid: u32) -> (f64, f64) {
    if grid == 1 {
        return (0.5, 0.5);
    }
    let key = (u64::from(i) << 40) ^ (u64::from(j) << 20) ^ u64::from(s);
    let (a, b) = (unit_hash(key), unit_hash(key ^ 0x9E37_79B9_7F4A_7C15));
    let cell = f64::from(grid);
    (
        (f64::from(s % grid) + a) / cell,
        (f64::from(s / grid) + b) / cell,
    )
}

/// A uniform value in [0, 1) from `key` (the SplitMix64 finaliser).
fn unit_hash(key: u64) -> f64 {
    let mut z = key.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// The mean of the samples as `first + Σ(cᵢ − first)/n`: the same value
/// when every sample is the same (a plain `Σcᵢ/n` drifts by rounding and
/// flips values that sit on a rounding boundary, like the ambient 0.1·255
/// = 25.5), and a sum of small deviations elsewhere.
fn mean(samples: impl Iterator<Item = DVec3>) -> DVec3 {
    let mut first = None;
    let mut deviation = DVec3::ZERO;
    let mut count = 0u32;
    for sample in samples {
        count += 1;
        match first {
            None => first = Some(sample),
            Some(first) => deviation += sample - first,
        }
    }
    first.map_or(DVec3::ZERO, |first| first + deviation / f64::from(count))
}

/// The output of docs/rendering.md: clamp to [0, 1], then `round(c·255)`, halves up.
/// Rounded by hand: `f64::round` is a libm call on baseline x86-64 (4 % of
/// the sample scene's render); the fraction `x − ⌊x⌋` is exact here.
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
    fn samples_stay_in_their_cells() {
        for s in 0..9 {
            let (u, v) = sample_offset(7, 3, s, 3);
            let (cu, cv) = (f64::from(s % 3), f64::from(s / 3));
            assert!((cu / 3.0..(cu + 1.0) / 3.0).contains(&u), "{s}: {u}");
            assert!((cv / 3.0..(cv + 1.0) / 3.0).contains(&v), "{s}: {v}");
        }
        assert_eq!(sample_offset(7, 3, 0, 1), (0.5, 0.5));
    }

    #[test]
    fn the_mean_of_equal_samples_is_that_sample() {
        for n in [1, 4, 9, 16, 64, 256, 1024] {
            let one = DVec3::new(0.1, 0.7 * 0.1, 1.0 / 3.0);
            assert_eq!(mean(std::iter::repeat_n(one, n)), one, "{n} samples");
        }
        let mixed = [
            DVec3::ZERO,
            DVec3::ONE,
            DVec3::splat(0.5),
            DVec3::splat(0.5),
        ];
        assert_eq!(mean(mixed.into_iter()), DVec3::splat(0.5));
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
