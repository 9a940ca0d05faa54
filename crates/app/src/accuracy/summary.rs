//! Several scenes' measurements as the verdict tables of docs/accuracy.md,
//! computed from the unrounded numbers the findings are: the choice of
//! adaptive sampling's threshold on a tuning set of scenes, and the
//! verdict of adaptive against uniform sampling at every measured count,
//! scene by scene, with each miss and what missed.
//!
//! The choice is a rule applied to the tuning scenes alone: the threshold
//! under which the most (scene, samples per pixel) pairs meet the target
//! ([`Verdict::meets`]), and among equals the largest (the cheapest). The
//! scenes held out are measured at the chosen threshold only, after it is
//! chosen, so nothing they show can move it.

use std::fmt::Write as _;

use super::report::{Verdict, ADAPTIVE_RMSE, ADAPTIVE_TIME};
use super::{Measurement, SPPS};
use raytracer_render::render::adaptive::DEFAULT_THRESHOLD;

/// A scene's name (its path as given) and its measurement.
pub type Measured = (String, Measurement);

/// How many (scene, spp) pairs of `scenes` meet the target at threshold
/// index `threshold`.
fn met(scenes: &[Measured], threshold: usize) -> usize {
    scenes
        .iter()
        .flat_map(|(_, m)| SPPS.map(|spp| Verdict::of(m, spp, threshold)))
        .filter(Verdict::meets)
        .count()
}

/// The index of the threshold the tuning rule chooses among the
/// candidates every scene of `tuning` was measured at (the module header).
pub fn choose(tuning: &[Measured]) -> usize {
    let thresholds = &tuning[0].1.thresholds;
    (0..thresholds.len())
        .max_by(|&a, &b| {
            met(tuning, a)
                .cmp(&met(tuning, b))
                .then(thresholds[a].total_cmp(&thresholds[b]))
        })
        .expect("at least one threshold")
}

/// The tuning table: per candidate threshold, how many scenes meet the
/// target at each count, the worst RMSE and time ratios, and the pairs
/// met in all.
pub fn tuning_table(tuning: &[Measured]) -> String {
    let thresholds = &tuning[0].1.thresholds;
    let n = tuning.len();
    let mut out = String::from("| threshold |");
    for spp in SPPS {
        let _ = write!(out, " meet at {spp} spp |");
    }
    out.push_str(" worst RMSE × | worst time × | pairs met |\n|---:|");
    out.push_str(&"---:|".repeat(SPPS.len() + 3));
    out.push('\n');
    for (t, threshold) in thresholds.iter().enumerate() {
        let verdicts: Vec<Verdict> = tuning
            .iter()
            .flat_map(|(_, m)| SPPS.map(|spp| Verdict::of(m, spp, t)))
            .collect();
        let _ = write!(out, "| {threshold} |");
        for spp in SPPS {
            let count = verdicts
                .iter()
                .filter(|v| v.spp == spp && v.meets())
                .count();
            let _ = write!(out, " {count} of {n} |");
        }
        let worst = |f: fn(&Verdict) -> f64| verdicts.iter().map(f).fold(0.0, f64::max);
        let _ = writeln!(
            out,
            " {:.2} | {:.2} | {} of {} |",
            worst(|v| v.rmse),
            worst(|v| v.time.median),
            met(tuning, t),
            verdicts.len()
        );
    }
    out
}

/// The verdict of adaptive against uniform for every scene of `scenes`
/// and every measured count, at threshold index `threshold` of each
/// scene's measurement, and a line counting the scenes that meet the
/// target at each count.
pub fn verdict_table(scenes: &[Measured], threshold: impl Fn(&Measurement) -> usize) -> String {
    let mut out = String::from(
        "| scene | spp | RMSE uniform | RMSE adaptive | RMSE × | time × (range) | \
         pixels refined: all, 4 | verdict |\n|---|---:|---:|---:|---:|---:|---:|---|\n",
    );
    let mut counts = [0; SPPS.len()];
    for (name, m) in scenes {
        for (k, spp) in SPPS.into_iter().enumerate() {
            let v = Verdict::of(m, spp, threshold(m));
            counts[k] += usize::from(v.meets());
            let [all, four] = v.refined_shares();
            let _ = writeln!(
                out,
                "| `{name}` | {spp} | {:.3} | {:.3} | {:.2} | {} | {all}, {four} | {} |",
                v.uniform_rmse,
                v.adaptive_rmse,
                v.rmse,
                v.time_spread(),
                v.outcome(),
            );
        }
    }
    let tally: Vec<String> = SPPS
        .iter()
        .zip(counts)
        .map(|(spp, count)| format!("at {spp} spp {count} of {}", scenes.len()))
        .collect();
    let _ = writeln!(
        out,
        "\nMeet the target (RMSE ≤ {ADAPTIVE_RMSE}× uniform's in ≤ {ADAPTIVE_TIME}× its time, \
         the median of adaptive's time over uniform's within each repetition): {}.",
        tally.join(", ")
    );
    out
}

/// The verdict tables that open a report of several scenes or thresholds:
/// the tuning table and the rule's choice when there are several
/// candidates, then the verdicts on the SCENES and on the held-out ones.
pub fn verdicts(tuning: &[Measured], held_out: &[Measured], chosen: usize) -> String {
    let thresholds = &tuning[0].1.thresholds;
    let threshold = thresholds[chosen];
    let mut out = String::new();
    let names = |scenes: &[Measured]| {
        scenes
            .iter()
            .map(|(name, _)| format!("`{name}`"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    if thresholds.len() > 1 {
        let default = if threshold == DEFAULT_THRESHOLD {
            "the same".to_string()
        } else {
            format!("not the same: the rule picks {threshold}, the default is {DEFAULT_THRESHOLD}")
        };
        out.push_str(&format!(
            "## Choosing the threshold on the tuning set\n\n\
             The tuning set: {}. Each is measured at every candidate threshold; the rule \
             picks the threshold under which the most (scene, spp) pairs meet the target, and \
             among equals the largest. It picks **{threshold}**; the default of the binary measured \
             (`DEFAULT_THRESHOLD`, crates/render/src/render/adaptive.rs) is {default}.\n\n{}\n",
            names(tuning),
            tuning_table(tuning),
        ));
    }
    out.push_str(&format!(
        "## Adaptive against uniform at threshold {threshold}: the {} scenes\n\n{}\n",
        if held_out.is_empty() {
            "measured"
        } else {
            "tuning"
        },
        verdict_table(tuning, |_| chosen),
    ));
    if !held_out.is_empty() {
        out.push_str(&format!(
            "## Adaptive against uniform at threshold {threshold}: the held-out scenes\n\n\
             Scenes that played no part in the choice, measured after it at the chosen \
             threshold only: {}.\n\n{}\n",
            names(held_out),
            verdict_table(held_out, |_| 0),
        ));
    }
    out
}
