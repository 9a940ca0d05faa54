//! What accuracy costs for one scene: the measurement behind
//! `raytracer accuracy` and docs/accuracy.md.
//!
//! The scene is rendered under each [`Setting`] (precision, reflection
//! depth, uniform and adaptive supersampling, the skip of invisible work)
//! and compared, as linear radiance before quantization and as 8-bit
//! output ([`error`]), with a reference: f64, depth 64, the mean of two
//! renders of [`Plan::reference_spp`] samples per pixel with independent
//! jitter. The two halves' difference estimates the reference's own error
//! (each half's error is independent, so the mean's RMSE is half the
//! halves' RMSE apart). Error is also split by source: numeric (f32
//! against f64 at one sample, pixel for pixel), depth truncation (each
//! depth against depth 64 at one sample). Timings ([`timing`]) are whole
//! frames on one thread, the settings interleaved across
//! [`Plan::reps`] repetitions, as ratios to the default render.
//! [`report`] turns the numbers into a table and findings.

pub mod error;
pub mod report;
pub mod timing;

use crate::ir;
use crate::render::{self, Antialias, Counters, Options, Precision, Radiance};
use error::{average, compare, Error};
use timing::{seconds_per_run, Spread};

/// The smallest frame measured: a side at which a frame is mostly flat
/// areas and not mostly edges, as the images people render are. At 17 px
/// (tangent_sphere's own size) a quarter of the pixels straddle an edge,
/// which no sampler can save work on.
pub const MIN_MEASURED_SIZE: u32 = 128;

/// The side a scene of side `own` is measured at when the user gives none:
/// `own`, or its smallest odd multiple of at least [`MIN_MEASURED_SIZE`].
/// An odd multiple `k·own` keeps every pixel centre of the scene's own
/// frame: pixel `i` of `own` is pixel `k·i + (k − 1)/2` of `k·own`, whose
/// centre `k·(i + ½) / (k·own)` is the same division, so the camera ray is
/// the same bit for bit, and a scene built around one pixel's ray (the
/// ray exactly tangent to tangent_sphere's sphere) keeps it.
pub fn measured_size(own: u32) -> u32 {
    let k = MIN_MEASURED_SIZE.div_ceil(own.max(1));
    own.max(1) * (k | 1)
}

/// How much to measure.
#[derive(Clone, Copy, Debug)]
pub struct Plan {
    /// Timed repetitions of every setting.
    pub reps: usize,
    /// Samples per pixel of each half of the reference (a square).
    pub reference_spp: u32,
    /// The adaptive rows' threshold, in steps of 1/255.
    pub threshold: f64,
    /// The scene's own side, which the report names beside the side
    /// measured.
    pub own_size: u32,
}

/// What a setting changes from the default (f64, 1 spp, depth 8, skip).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Default,
    F32,
    NoSkip,
    Depth(u32),
    Uniform(u32),
    Adaptive(u32),
}

/// Reflection depths measured against depth 64.
pub const DEPTHS: [u32; 6] = [0, 1, 2, 4, 16, 64];
/// Samples per pixel measured, uniform and adaptive.
pub const SPPS: [u32; 3] = [4, 16, 64];
/// The depth the reference and the depth split count as exact.
pub const DEEP: u32 = 64;

impl Kind {
    /// Every setting, the default first.
    pub fn all() -> Vec<Kind> {
        let mut kinds = vec![Kind::Default, Kind::F32, Kind::NoSkip];
        kinds.extend(DEPTHS.map(Kind::Depth));
        kinds.extend(SPPS.map(Kind::Uniform));
        kinds.extend(SPPS.map(Kind::Adaptive));
        kinds
    }

    /// The precision and options of this setting.
    pub fn configure(self, threshold: f64) -> (Precision, Options) {
        let default = Options::default();
        match self {
            Kind::Default => (Precision::F64, default),
            Kind::F32 => (Precision::F32, default),
            Kind::NoSkip => (
                Precision::F64,
                Options {
                    skip: false,
                    ..default
                },
            ),
            Kind::Depth(max_depth) => (
                Precision::F64,
                Options {
                    max_depth,
                    ..default
                },
            ),
            Kind::Uniform(spp) => (Precision::F64, Options { spp, ..default }),
            Kind::Adaptive(spp) => (
                Precision::F64,
                Options {
                    spp,
                    antialias: Antialias::Adaptive { threshold },
                    ..default
                },
            ),
        }
    }

    /// The setting as a table row names it.
    pub fn name(self) -> String {
        match self {
            Kind::Default => "default (f64, 1 spp, depth 8)".into(),
            Kind::F32 => "f32".into(),
            Kind::NoSkip => "--no-skip".into(),
            Kind::Depth(d) => format!("depth {d}"),
            Kind::Uniform(n) => format!("uniform {n} spp"),
            Kind::Adaptive(n) => format!("adaptive {n} spp"),
        }
    }
}

/// One setting, measured.
#[derive(Clone, Debug)]
pub struct Row {
    pub kind: Kind,
    /// Time as a multiple of the default render's, over the repetitions.
    pub ratio: Spread,
    /// Seconds per frame, over the repetitions.
    pub seconds: Spread,
    pub counters: Counters,
    /// Against the reference.
    pub error: Error,
    pub radiance: Radiance,
}

/// The reference render.
#[derive(Clone, Debug)]
pub struct Reference {
    /// Samples per pixel of each half.
    pub spp: u32,
    pub seconds: f64,
    pub rays: u64,
    /// Its own estimated error: half the RMSE (×255) between its halves.
    pub own_rmse: f64,
    pub radiance: Radiance,
}

/// Everything measured for a scene.
#[derive(Clone, Debug)]
pub struct Measurement {
    pub size: u32,
    /// The scene's own side (its `camera` line), which `size` is an odd
    /// multiple of unless the user chose another.
    pub own_size: u32,
    /// The adaptive rows' threshold, in steps of 1/255.
    pub threshold: f64,
    pub reps: usize,
    pub reference: Reference,
    /// In the order of [`Kind::all`]; the default first.
    pub rows: Vec<Row>,
}

impl Measurement {
    /// The row of `kind` (every kind of [`Kind::all`] has one).
    pub fn row(&self, kind: Kind) -> &Row {
        self.rows
            .iter()
            .find(|row| row.kind == kind)
            .expect("every setting is measured")
    }
}

/// Render in the given precision to linear radiance.
fn render(scene: &ir::Scene, precision: Precision, options: &Options) -> (Radiance, Counters) {
    match precision {
        Precision::F32 => render::render_radiance::<f32>(scene, options, &|| {}),
        Precision::F64 => render::render_radiance::<f64>(scene, options, &|| {}),
    }
}

/// Measure `scene`: the reference on the current rayon pool, the timed
/// settings on `single`, a pool of one thread. `progress` hears what is
/// being done.
pub fn measure(
    scene: &ir::Scene,
    plan: Plan,
    single: &rayon::ThreadPool,
    progress: &dyn Fn(&str),
) -> Measurement {
    progress("reference");
    let clock = std::time::Instant::now();
    let half = |seed| Options {
        spp: plan.reference_spp,
        max_depth: DEEP,
        seed,
        ..Options::default()
    };
    let (first, first_counters) = render(scene, Precision::F64, &half(1));
    let (second, second_counters) = render(scene, Precision::F64, &half(2));
    let reference = Reference {
        spp: plan.reference_spp,
        seconds: clock.elapsed().as_secs_f64(),
        rays: total_rays(&first_counters) + total_rays(&second_counters),
        own_rmse: compare(&first, &second).rmse / 2.0,
        radiance: average(&first, &second),
    };

    let kinds = Kind::all();
    // Untimed: the first render of a process pays for cold caches and
    // page faults, which would fall on the default, the first timed.
    single.install(|| render(scene, Precision::F64, &Options::default()));
    let mut outputs: Vec<Option<(Radiance, Counters)>> = vec![None; kinds.len()];
    let mut seconds = vec![Vec::new(); kinds.len()];
    for rep in 0..plan.reps.max(1) {
        progress(&format!("repetition {} of {}", rep + 1, plan.reps));
        for (k, kind) in kinds.iter().enumerate() {
            let (precision, options) = kind.configure(plan.threshold);
            let mut output = None;
            let time = single
                .install(|| seconds_per_run(|| output = Some(render(scene, precision, &options))));
            seconds[k].push(time);
            outputs[k].get_or_insert_with(|| output.expect("rendered at least once"));
        }
    }
    let rows = kinds
        .iter()
        .zip(outputs)
        .zip(&seconds)
        .map(|((&kind, output), times)| {
            let (radiance, counters) = output.expect("measured");
            let ratios: Vec<f64> = times.iter().zip(&seconds[0]).map(|(t, d)| t / d).collect();
            Row {
                kind,
                ratio: Spread::of(&ratios),
                seconds: Spread::of(times),
                counters,
                error: compare(&radiance, &reference.radiance),
                radiance,
            }
        })
        .collect();
    Measurement {
        size: scene.resolution,
        own_size: plan.own_size,
        threshold: plan.threshold,
        reps: plan.reps.max(1),
        reference,
        rows,
    }
}

/// Camera, shadow and reflection rays.
pub fn total_rays(counters: &Counters) -> u64 {
    counters.primary_rays + counters.shadow_rays + counters.reflection_rays
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::camera_ray;

    #[test]
    fn small_scenes_are_measured_at_their_smallest_odd_multiple_of_at_least_128() {
        for (own, measured) in [
            (17, 153),
            (16, 144),
            (63, 189),
            (64, 192),
            (127, 381),
            (128, 128),
            (400, 400),
        ] {
            assert_eq!(measured_size(own), measured, "{own}");
        }
    }

    #[test]
    fn an_odd_multiple_keeps_every_pixel_centre_ray_bit_for_bit() {
        for own in [1, 2, 5, 16, 17, 63, 64] {
            let big = measured_size(own);
            let k = big / own;
            let centre = |i: u32| f64::from(i) + 0.5;
            for (i, j) in (0..own).flat_map(|i| (0..own).map(move |j| (i, j))) {
                let small = camera_ray::<f64>(own, centre(i), centre(j)).dir;
                let (bi, bj) = (k * i + k / 2, k * j + k / 2);
                let large = camera_ray::<f64>(big, centre(bi), centre(bj)).dir;
                assert_eq!(
                    small.to_array(),
                    large.to_array(),
                    "pixel ({i}, {j}) of {own}"
                );
            }
        }
    }
}
