//! What accuracy costs for one scene: the measurement behind
//! `raytracer accuracy` and docs/accuracy.md.
//!
//! The scene is rendered under each setting ([`Kind`]: precision,
//! reflection depth, uniform and adaptive supersampling, the skip of
//! invisible work) and compared, as linear radiance before quantization
//! and as 8-bit output ([`error`]), with a reference at the same depth:
//! f64, the mean of two renders of [`Plan::reference_spp`] samples per
//! pixel with independent jitter, at the default depth 8 for every setting
//! but the depths, and at depth 64 for those. The two halves' difference
//! estimates a reference's own error (each half's error is independent, so
//! the mean's RMSE is half the halves' RMSE apart). Depth truncation is its
//! own source: the depth-8 reference against the depth-64 one, and each
//! depth against depth 64 at one sample, pixel for pixel; numeric error is
//! f32 against f64 at one sample. Timings ([`timing`]) are whole frames on
//! one thread, every setting once per repetition in a fresh random order,
//! and a ratio of two settings is taken within each repetition, then
//! summarised over them. [`report`] turns one scene's numbers into a table
//! and findings, [`summary`] several scenes' into the verdict tables.

pub mod error;
pub mod report;
pub mod study;
pub mod summary;
pub mod timing;

use error::{average, compare, Error};
use raytracer_render::ir;
use raytracer_render::render::{self, Antialias, Counters, Options, Precision, Radiance};
use timing::{seconds_per_run, shuffled, Spread};

/// The smallest frame measured: a side at which a frame is mostly flat
/// areas and not mostly edges, as the images people render are. At 17 px
/// (tangent_sphere's own size) a quarter of the pixels straddle an edge,
/// which no sampler can save work on.
pub const MIN_MEASURED_SIZE: u32 = 128;

/// The largest frame measured: the side of scenes/'s own scenes. A larger
/// scene is measured at its own side divided by its smallest odd divisor
/// that brings it to this or below (the course's 1000-px scenes at 200).
pub const MAX_MEASURED_SIZE: u32 = 400;

/// The side a scene of side `own` is measured at when the user gives none:
/// `own`, or its smallest odd multiple of at least [`MIN_MEASURED_SIZE`],
/// or its largest side of at most [`MAX_MEASURED_SIZE`] that `own` is an
/// odd multiple of (`own` itself when it has none). An odd multiple
/// `k·own` keeps every pixel centre of the scene's own frame: pixel `i` of
/// `own` is pixel `k·i + (k − 1)/2` of `k·own`, whose centre
/// `k·(i + ½) / (k·own)` is the same division, so the camera ray is the
/// same bit for bit, and a scene built around one pixel's ray (the ray
/// exactly tangent to tangent_sphere's sphere) keeps it; dividing by an
/// odd `k` keeps every pixel centre of the smaller frame in the larger.
pub fn measured_size(own: u32) -> u32 {
    let own = own.max(1);
    if own > MAX_MEASURED_SIZE {
        return (3..=own)
            .step_by(2)
            .find(|k| own % k == 0 && own / k <= MAX_MEASURED_SIZE)
            .map_or(own, |k| own / k);
    }
    let k = MIN_MEASURED_SIZE.div_ceil(own);
    own * (k | 1)
}

/// How much to measure.
#[derive(Clone, Debug)]
pub struct Plan {
    /// Timed repetitions of every setting.
    pub reps: usize,
    /// Samples per pixel of each half of the reference (a square).
    pub reference_spp: u32,
    /// The adaptive rows' thresholds, in steps of 1/255: one, or the
    /// candidates a tuning run chooses among. Every adaptive count is
    /// measured at each.
    pub thresholds: Vec<f64>,
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
    /// Adaptive sampling at `spp`, with the threshold at this index of
    /// [`Plan::thresholds`].
    Adaptive {
        spp: u32,
        threshold: usize,
    },
}

/// Reflection depths measured against depth 64.
pub const DEPTHS: [u32; 6] = [0, 1, 2, 4, 16, 64];
/// Samples per pixel measured, uniform and adaptive: the jittered counts
/// (1 spp is the pixel centre, the default).
pub const SPPS: [u32; 3] = [4, 16, 64];
/// The depth the deep reference and the depth split count as exact.
pub const DEEP: u32 = 64;

impl Kind {
    /// Every setting for `thresholds` adaptive thresholds, the default
    /// first.
    pub fn all(thresholds: usize) -> Vec<Kind> {
        let mut kinds = vec![Kind::Default, Kind::F32, Kind::NoSkip];
        kinds.extend(DEPTHS.map(Kind::Depth));
        kinds.extend(SPPS.map(Kind::Uniform));
        for threshold in 0..thresholds {
            kinds.extend(SPPS.map(|spp| Kind::Adaptive { spp, threshold }));
        }
        kinds
    }

    /// The precision and options of this setting.
    pub fn configure(self, thresholds: &[f64]) -> (Precision, Options) {
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
            Kind::Adaptive { spp, threshold } => (
                Precision::F64,
                Options {
                    spp,
                    antialias: Antialias::Adaptive {
                        threshold: thresholds[threshold],
                    },
                    ..default
                },
            ),
        }
    }

    /// The setting as a table row names it (an adaptive row names its
    /// threshold when there are several).
    pub fn name(self, thresholds: &[f64]) -> String {
        match self {
            Kind::Default => "default (f64, 1 spp, depth 8)".into(),
            Kind::F32 => "f32".into(),
            Kind::NoSkip => "--no-skip".into(),
            Kind::Depth(d) => format!("depth {d}"),
            Kind::Uniform(n) => format!("uniform {n} spp"),
            Kind::Adaptive { spp, .. } if thresholds.len() == 1 => format!("adaptive {spp} spp"),
            Kind::Adaptive { spp, threshold } => {
                format!("adaptive {spp} spp, threshold {}", thresholds[threshold])
            }
        }
    }
}

/// One setting, measured.
#[derive(Clone, Debug)]
pub struct Row {
    pub kind: Kind,
    /// CPU seconds per frame in each repetition, in repetition order.
    pub times: Vec<f64>,
    /// Time as a multiple of the default render's, over the repetitions.
    pub ratio: Spread,
    /// Seconds per frame, over the repetitions.
    pub seconds: Spread,
    pub counters: Counters,
    /// Against the reference of its depth (the deep one for the depth
    /// rows, else the one at depth 8).
    pub error: Error,
    pub radiance: Radiance,
}

/// A reference render: the mean of two halves with independent jitter.
#[derive(Clone, Debug)]
pub struct Reference {
    /// Samples per pixel of each half.
    pub spp: u32,
    /// Its reflection depth.
    pub depth: u32,
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
    /// multiple or divisor of unless the user chose another.
    pub own_size: u32,
    /// The adaptive rows' thresholds, in steps of 1/255.
    pub thresholds: Vec<f64>,
    pub reps: usize,
    /// At the default depth (8): what every setting but the depths is
    /// judged against.
    pub reference: Reference,
    /// At depth [`DEEP`]: what the depths are judged against.
    pub deep: Reference,
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

    /// The time of `a` over the time of `b`, taken within each repetition
    /// (both ran in it, in a random order), over the repetitions.
    pub fn time_ratio(&self, a: Kind, b: Kind) -> Spread {
        let (a, b) = (self.row(a), self.row(b));
        let ratios: Vec<f64> = a.times.iter().zip(&b.times).map(|(a, b)| a / b).collect();
        Spread::of(&ratios)
    }

    /// Depth 8's truncation at convergence: the depth-8 reference against
    /// the depth-64 one.
    pub fn truncation(&self) -> Error {
        compare(&self.reference.radiance, &self.deep.radiance)
    }
}

/// Render in the given precision to linear radiance.
fn render(scene: &ir::Scene, precision: Precision, options: &Options) -> (Radiance, Counters) {
    render::render_radiance(precision, scene, options, &|| {})
}

/// The reference of `scene` at reflection depth `depth`: two renders of
/// `spp` samples per pixel with independent jitter, and their mean.
fn reference(scene: &ir::Scene, spp: u32, depth: u32) -> Reference {
    let clock = std::time::Instant::now();
    let half = |seed| Options {
        spp,
        max_depth: depth,
        seed,
        ..Options::default()
    };
    let (first, first_counters) = render(scene, Precision::F64, &half(1));
    let (second, second_counters) = render(scene, Precision::F64, &half(2));
    Reference {
        spp,
        depth,
        seconds: clock.elapsed().as_secs_f64(),
        rays: total_rays(&first_counters) + total_rays(&second_counters),
        own_rmse: compare(&first, &second).rmse / 2.0,
        radiance: average(&first, &second),
    }
}

/// Measure `scene`: the references on the current rayon pool, the timed
/// settings on `single`, a pool of one thread. `progress` hears what is
/// being done.
pub fn measure(
    scene: &ir::Scene,
    plan: &Plan,
    single: &rayon::ThreadPool,
    progress: &dyn Fn(&str),
) -> Measurement {
    let depth = Options::default().max_depth;
    progress(&format!("reference at depth {depth}"));
    let reference = reference(scene, plan.reference_spp, depth);
    progress(&format!("reference at depth {DEEP}"));
    let deep = self::reference(scene, plan.reference_spp, DEEP);

    let kinds = Kind::all(plan.thresholds.len());
    // Untimed: the first render of a process pays for cold caches and
    // page faults, which would fall on whichever setting came first.
    single.install(|| render(scene, Precision::F64, &Options::default()));
    let mut outputs: Vec<Option<(Radiance, Counters)>> = vec![None; kinds.len()];
    let mut seconds = vec![Vec::new(); kinds.len()];
    let reps = plan.reps.max(1);
    for rep in 0..reps {
        progress(&format!("repetition {} of {reps}", rep + 1));
        for k in shuffled(kinds.len()) {
            let (precision, options) = kinds[k].configure(&plan.thresholds);
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
        .zip(seconds.iter().cloned())
        .map(|((&kind, output), times)| {
            let (radiance, counters) = output.expect("measured");
            let ratios: Vec<f64> = times.iter().zip(&seconds[0]).map(|(t, d)| t / d).collect();
            let judge = match kind {
                Kind::Depth(_) => &deep,
                _ => &reference,
            };
            Row {
                kind,
                ratio: Spread::of(&ratios),
                seconds: Spread::of(&times),
                times,
                counters,
                error: compare(&radiance, &judge.radiance),
                radiance,
            }
        })
        .collect();
    Measurement {
        size: scene.resolution,
        own_size: plan.own_size,
        thresholds: plan.thresholds.clone(),
        reps,
        reference,
        deep,
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
    use raytracer_render::render::camera_ray;

    #[test]
    fn scenes_are_measured_at_an_odd_multiple_or_divisor_of_their_own_side() {
        for (own, measured) in [
            (17, 153),
            (16, 144),
            (63, 189),
            (64, 192),
            (127, 381),
            (128, 128),
            (400, 400),
            (1000, 200),
            (1024, 1024),
            (2000, 400),
        ] {
            assert_eq!(measured_size(own), measured, "{own}");
        }
    }

    #[test]
    fn an_odd_multiple_keeps_every_pixel_centre_ray_bit_for_bit() {
        let pairs = [1, 2, 5, 16, 17, 63, 64]
            .map(|own| (own, measured_size(own)))
            .into_iter()
            .chain([(measured_size(1000), 1000)]);
        for (own, big) in pairs {
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
