//! Where a pixel's samples lie and how they are averaged.
//!
//! One sample lies at the pixel centre; `spp = g²` samples lie one in each
//! cell of a g×g grid over the pixel, jittered inside its cell by a hash of
//! the pixel, the sample and the seed. A sample is therefore a function of
//! (pixel, sample, options) alone: any thread, any order and any part of
//! the frame computes the same value for it. Each sample's colour is
//! clamped to [0, 1] before the samples are averaged, so the average is the
//! linear radiance the 8-bit pixel is rounded from.

use glam::DVec3;

use super::real::{Real, Vector};
use super::trace::{Counters, FirstHits, Tracer};
use super::{camera_ray, eye};

/// The samples of a frame: resolution, grid side and seed.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sampler {
    size: u32,
    grid: u32,
    seed: u64,
    /// Added to every sample's column and row ([`super::Model::pixel_shift`]):
    /// 0, an exact identity, for rays through pixel centres.
    shift: f64,
}

impl Sampler {
    /// `spp` is rounded down to a square (callers check it is one).
    pub(super) fn new(size: u32, spp: u32, seed: u64) -> Self {
        Sampler {
            size,
            grid: spp.isqrt().max(1),
            seed,
            shift: 0.0,
        }
    }

    /// These samples moved by `shift` pixels right and down.
    pub(super) fn shifted(self, shift: f64) -> Self {
        Sampler { shift, ..self }
    }

    /// Samples per pixel.
    pub(super) fn count(&self) -> u32 {
        self.grid * self.grid
    }

    /// Where in pixel (i, j) sample `s` lies, from its top-left corner,
    /// in pixels.
    pub(super) fn offset(&self, (i, j): (u32, u32), s: u32) -> (f64, f64) {
        sample_offset(i, j, s, self.grid, self.seed)
    }

    /// The clamped colour of sample `s` of pixel (i, j).
    pub(super) fn sample<R: Real>(
        &self,
        tracer: &Tracer<'_, R>,
        (i, j): (u32, u32),
        s: u32,
        counters: &mut Counters,
    ) -> DVec3 {
        let (u, v) = self.offset((i, j), s);
        let (x, y) = (f64::from(i) + u + self.shift, f64::from(j) + v + self.shift);
        let ray = camera_ray::<R>(self.size, x, y);
        tracer
            .radiance(ray, counters)
            .clamp(DVec3::ZERO, DVec3::ONE)
    }

    /// The mean of every sample of pixel (i, j), in sample order.
    pub(super) fn pixel<R: Real>(
        &self,
        tracer: &Tracer<'_, R>,
        pixel: (u32, u32),
        counters: &mut Counters,
    ) -> DVec3 {
        mean((0..self.count()).map(|s| self.sample(tracer, pixel, s, counters)))
    }

    /// Every pixel of row `j`, left to right, each handed to `put` with its
    /// column: the values [`Sampler::pixel`] gives, except that with one
    /// sample per pixel a pixel whose camera ray hits nothing is black and
    /// is not handed over (the caller's row starts black). With one sample
    /// the row's camera rays are made first, in a loop of their own, then
    /// what each hits first, in another, and only then is each hit
    /// shaded: a camera ray needs divisions and a square root, and its hit
    /// test more, which loops of independent rays run in vector lanes,
    /// where inside the trace of a pixel their latency would stall it.
    /// (The mean of one sample is that sample.)
    pub(super) fn row<R: Real>(
        &self,
        tracer: &Tracer<'_, R>,
        j: u32,
        rays: &mut RowRays<R>,
        counters: &mut Counters,
        mut put: impl FnMut(usize, DVec3),
    ) {
        if self.count() > 1 {
            for i in 0..self.size {
                put(i as usize, self.pixel(tracer, (i, j), counters));
            }
            return;
        }
        let n = self.size as usize;
        let RowRays {
            dirs,
            distances,
            slots,
        } = rays;
        for buffer in dirs.iter_mut().chain([&mut *distances]) {
            buffer.resize(n, R::zero());
        }
        slots.resize(n, 0);
        let [dx, dy, dz] = dirs;
        camera_dirs(
            self.size,
            f64::from(j) + 0.5 + self.shift,
            self.shift,
            [dx, dy, dz],
        );
        tracer.first_hits(eye::<R>(), [dx, dy, dz], distances, slots);
        counters.primary_rays += u64::from(self.size);
        let hits = FirstHits {
            dirs: [dx, dy, dz],
            distances,
            slots,
        };
        tracer.paths(eye::<R>(), hits, counters, |i, color| {
            put(i, color.clamp(DVec3::ZERO, DVec3::ONE))
        });
    }

    /// The clamped colour at the top-left corner of pixel (x, y): the
    /// image-plane point (x, y) itself, for `x, y` in `0..=size`.
    pub(super) fn corner<R: Real>(
        &self,
        tracer: &Tracer<'_, R>,
        (x, y): (u32, u32),
        counters: &mut Counters,
    ) -> DVec3 {
        let (x, y) = (f64::from(x) + self.shift, f64::from(y) + self.shift);
        let ray = camera_ray::<R>(self.size, x, y);
        tracer
            .radiance(ray, counters)
            .clamp(DVec3::ZERO, DVec3::ONE)
    }

    /// Four samples of the grid, one in each quadrant of the pixel: the
    /// cells about a fifth of a side in from each edge, symmetric about
    /// the centre (near the two-point Gauss positions, 0.21 and 0.79, where
    /// four points average a smooth pixel best). `None` below 9 samples,
    /// where they would be most or all of the grid.
    pub(super) fn quadrants(&self) -> Option<[u32; 4]> {
        let g = self.grid;
        if g < 3 {
            return None;
        }
        let (near, far) = (g / 5, g - 1 - g / 5);
        Some([
            near * g + near,
            near * g + far,
            far * g + near,
            far * g + far,
        ])
    }
}

/// The camera rays of a row and their first hits, laid out per axis so
/// that the loops making and testing them run several rays per
/// instruction (the eye, their common origin, is not stored); kept from
/// row to row.
#[derive(Default)]
pub(super) struct RowRays<R: Real> {
    dirs: [Vec<R>; 3],
    distances: Vec<R>,
    slots: Vec<u32>,
}

/// The directions of the camera rays through the centres of row `y`'s
/// pixels ([`camera_ray`]), each moved `shift` pixels right, in AVX2 lanes
/// where the processor has them (on SSE2 the compiler already runs two
/// `f64` lanes).
fn camera_dirs<R: Real>(size: u32, y: f64, shift: f64, dirs: [&mut [R]; 3]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2, the one feature it enables.
        unsafe { camera_dirs_avx2(size, y, shift, dirs) };
        return;
    }
    camera_dirs_in_lanes(size, y, shift, dirs);
}

/// [`camera_dirs_in_lanes`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn camera_dirs_avx2<R: Real>(size: u32, y: f64, shift: f64, dirs: [&mut [R]; 3]) {
    camera_dirs_in_lanes(size, y, shift, dirs);
}

/// [`camera_dirs`], a loop the compiler vectorises.
#[inline(always)]
fn camera_dirs_in_lanes<R: Real>(size: u32, y: f64, shift: f64, [dx, dy, dz]: [&mut [R]; 3]) {
    for (i, ((x, y_), z)) in (0..size).zip(dx.iter_mut().zip(dy.iter_mut()).zip(dz)) {
        let dir = camera_ray::<R>(size, f64::from(i) + 0.5 + shift, y).dir;
        (*x, *y_, *z) = (dir.x(), dir.y(), dir.z());
    }
}

/// Where in pixel (i, j) sample `s` of a `grid × grid` stratification
/// lies: the centre for one sample, else a jittered point in its cell.
/// Seed 0 is the renderer's; another seed jitters independently.
fn sample_offset(i: u32, j: u32, s: u32, grid: u32, seed: u64) -> (f64, f64) {
    if grid == 1 {
        return (0.5, 0.5);
    }
    let key = (u64::from(i) << 40) ^ (u64::from(j) << 20) ^ u64::from(s);
    let key = key ^ seed.wrapping_mul(0xD1B5_4A32_D192_ED03);
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
pub(super) fn mean(samples: impl Iterator<Item = DVec3>) -> DVec3 {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_stay_in_their_cells() {
        for seed in [0, 1] {
            for s in 0..9 {
                let (u, v) = sample_offset(7, 3, s, 3, seed);
                let (cu, cv) = (f64::from(s % 3), f64::from(s / 3));
                assert!((cu / 3.0..(cu + 1.0) / 3.0).contains(&u), "{s}: {u}");
                assert!((cv / 3.0..(cv + 1.0) / 3.0).contains(&v), "{s}: {v}");
            }
        }
        assert_eq!(sample_offset(7, 3, 0, 1, 0), (0.5, 0.5));
    }

    #[test]
    fn another_seed_moves_every_jittered_sample() {
        for s in 0..16 {
            assert_ne!(sample_offset(5, 9, s, 4, 0), sample_offset(5, 9, s, 4, 1));
        }
    }

    /// The shared sphere on its floor, reflecting and lit, at 24²: every
    /// path of the tracer.
    fn mirror_over_floor() -> crate::ir::Scene {
        use crate::ir;
        let mut scene = crate::render::fixture::sphere_on_floor(0.6);
        scene.resolution = 24;
        scene.lights = vec![ir::Light {
            position: DVec3::new(-1.0, 2.0, -1.0),
            color: DVec3::new(1.0, 0.8, 0.8),
        }];
        scene.effects = ir::Effects {
            shadows: true,
            reflection: true,
            textures: false,
        };
        scene
    }

    /// `row`, which makes a row's camera rays before tracing them, gives
    /// every pixel bit for bit as `pixel` does, with the same counts.
    #[test]
    fn a_row_is_its_pixels() {
        let scene = mirror_over_floor();
        for spp in [1, 4] {
            let tracer = Tracer::<f64>::new(&scene, 8, true);
            let sampler = Sampler::new(scene.resolution, spp, 0);
            let mut total = Counters::default();
            for j in 0..scene.resolution {
                let (mut by_row, mut by_pixel) = (Counters::default(), Counters::default());
                // Starts black, as the renderer's rows do.
                let mut row = vec![DVec3::ZERO; scene.resolution as usize];
                let mut rays = RowRays::default();
                sampler.row(&tracer, j, &mut rays, &mut by_row, |i, c| row[i] = c);
                let pixels: Vec<_> = (0..scene.resolution)
                    .map(|i| sampler.pixel(&tracer, (i, j), &mut by_pixel))
                    .collect();
                let bits = |v: &[DVec3]| -> Vec<[u64; 3]> {
                    v.iter().map(|c| c.to_array().map(f64::to_bits)).collect()
                };
                assert_eq!(bits(&row), bits(&pixels), "spp {spp}, row {j}");
                assert_eq!(by_row, by_pixel, "spp {spp}, row {j}");
                total += by_row;
            }
            assert!(
                total.reflection_rays > 0 && total.shadow_rays > 0,
                "{total:?}"
            );
        }
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
}
