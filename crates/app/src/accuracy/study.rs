//! What `raytracer accuracy` measures over several scenes: the tuning
//! scenes at every candidate threshold, the threshold the rule of
//! [`summary::choose`] picks from them, and the held-out scenes measured
//! after the choice at that threshold alone, so no held-out scene plays a
//! part in it.

use super::summary::{self, Measured};
use super::{measure, measured_size, Plan};
use raytracer_render::ir;

/// How every scene of a study is measured.
pub struct Settings {
    /// Timed repetitions of every setting.
    pub reps: usize,
    /// Samples per pixel of each half of a reference (a square).
    pub reference_spp: u32,
    /// The side every scene is measured at; each scene's own
    /// [`measured_size`] when not given.
    pub size: Option<u32>,
    /// The candidate thresholds, in steps of 1/255 (one, or several to
    /// choose among).
    pub candidates: Vec<f64>,
}

/// The pools a study renders on: every core for the references, one
/// thread for the timed renders.
pub struct Pools<'a> {
    pub all: &'a rayon::ThreadPool,
    pub single: &'a rayon::ThreadPool,
}

/// A study's measurements and the candidate it chose.
pub struct Study {
    pub tuning: Vec<Measured>,
    /// The index of the chosen candidate in [`Settings::candidates`].
    pub chosen: usize,
    /// The held-out scenes, measured at the chosen threshold alone.
    pub held_out: Vec<Measured>,
}

impl Study {
    /// Every scene measured, the tuning scenes first.
    pub fn measured(&self) -> impl Iterator<Item = &Measured> {
        self.tuning.iter().chain(&self.held_out)
    }
}

/// Measure the `tuning` scenes (each named) at every candidate, choose,
/// then measure the `held_out` ones at the choice; `progress` is told
/// each step with the scene's index among all of them.
pub fn study(
    tuning: Vec<(String, ir::Scene)>,
    held_out: Vec<(String, ir::Scene)>,
    settings: &Settings,
    pools: &Pools,
    progress: &(dyn Fn(usize, &str) + Sync),
) -> Study {
    let measure_one = |k: usize, (name, mut scene): (String, ir::Scene), thresholds: Vec<f64>| {
        let own_size = scene.resolution;
        scene.resolution = settings.size.unwrap_or_else(|| measured_size(own_size));
        let plan = Plan {
            reps: settings.reps,
            reference_spp: settings.reference_spp,
            thresholds,
            own_size,
        };
        let step = |step: &str| progress(k, step);
        let measurement = pools
            .all
            .install(|| measure(&scene, &plan, pools.single, &step));
        (name, measurement)
    };
    let tuning_count = tuning.len();
    let tuning: Vec<Measured> = tuning
        .into_iter()
        .enumerate()
        .map(|(k, scene)| measure_one(k, scene, settings.candidates.clone()))
        .collect();
    let chosen = summary::choose(&tuning);
    let threshold = settings.candidates[chosen];
    let held_out = held_out
        .into_iter()
        .enumerate()
        .map(|(k, scene)| measure_one(tuning_count + k, scene, vec![threshold]))
        .collect();
    Study {
        tuning,
        chosen,
        held_out,
    }
}
