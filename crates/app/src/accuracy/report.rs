//! A [`Measurement`] as text: a Markdown table of every setting, the
//! error split by source, and findings read off the numbers against the
//! thresholds below; and the series behind the plots of docs/accuracy.md
//! as `series,x,y[,label]` CSV.

use std::fmt::Write as _;

use super::error::{compare, difference_map, Error};
use super::{
    measured_size, total_rays, Kind, Measurement, DEEP, DEPTHS, MAX_MEASURED_SIZE,
    MIN_MEASURED_SIZE, SPPS,
};
use raytracer_render::render::Image;

/// Sampling has converged for this scene once the linear RMSE is at most
/// this (in 1/255): half an 8-bit step.
pub const CONVERGED_RMSE: f64 = 0.5;
/// f32 is enough when it changes at most this share of 8-bit pixels (a
/// silhouette pixel that one precision hits and the other misses)…
pub const F32_CHANGED: f64 = 0.001;
/// …or no channel by more than this (linear, in 1/255: no 8-bit value
/// moves by more than one step).
pub const F32_MAX: f64 = 1.0;
/// Adaptive sampling meets its target at N spp when its RMSE is at most
/// this multiple of uniform N's…
pub const ADAPTIVE_RMSE: f64 = 1.25;
/// …in at most this share of uniform N's time.
pub const ADAPTIVE_TIME: f64 = 0.5;
/// An error within this multiple of the reference's own error is not
/// resolved by the reference.
pub const RESOLVED: f64 = 2.0;

/// How the side measured relates to the scene's own, when they differ.
fn scaled(m: &Measurement) -> String {
    match m.size {
        size if size == m.own_size => String::new(),
        size if size == measured_size(m.own_size) && size < m.own_size => format!(
            " (its own {own} ÷ {k}, the largest side of at most {MAX_MEASURED_SIZE} px it is an \
             odd multiple of, which keeps every pixel centre of the smaller frame)",
            k = m.own_size / size,
            own = m.own_size,
        ),
        size if size == measured_size(m.own_size) => format!(
            " ({k} × its own {own}, the smallest odd multiple of at least {MIN_MEASURED_SIZE} px, \
             which keeps every pixel centre of its own frame)",
            k = size / m.own_size,
            own = m.own_size,
        ),
        _ => format!(" (`--size`; its own is {own}×{own})", own = m.own_size),
    }
}

/// The full report: setup, table, splits and findings.
pub fn markdown(m: &Measurement, scene: &str) -> String {
    let mut out = String::new();
    let (r, deep) = (&m.reference, &m.deep);
    let default = m.row(Kind::Default);
    let _ = writeln!(
        out,
        "`{scene}` at {size}×{size}{scaled}. References: f64, each the mean of two renders of \
         {spp} spp with independent jitter, at depth {depth} ({rays} rays, {secs:.1} s; its own \
         RMSE, estimated from its halves, {own:.3}/255), which every row but the depths is \
         judged against, and at depth {DEEP} ({deep_rays} rays, {deep_secs:.1} s; own RMSE \
         {deep_own:.3}/255), which the depths are. Times: whole frames on one thread (its CPU \
         time), {reps}, the settings in a fresh random order in each; × is the \
         median over repetitions of the ratio to the default in the same repetition (range in \
         brackets); the default takes {median:.4} CPU s ({min:.4}–{max:.4}).\n",
        size = m.size,
        scaled = scaled(m),
        spp = r.spp,
        depth = r.depth,
        rays = r.rays,
        secs = r.seconds,
        own = r.own_rmse,
        deep_rays = deep.rays,
        deep_secs = deep.seconds,
        deep_own = deep.own_rmse,
        reps = plural(m.reps, "repetition"),
        median = default.seconds.median,
        min = default.seconds.min,
        max = default.seconds.max,
    );
    out.push_str(
        "| setting | time × | rays | RMSE | max | 8-bit RMSE | pixels ≠ reference |\n\
         |---|---:|---:|---:|---:|---:|---:|\n",
    );
    for row in &m.rows {
        let e = &row.error;
        let _ = writeln!(
            out,
            "| {} | {:.2} ({:.2}–{:.2}) | {} | {:.3} | {:.2} | {:.3} | {:.2}% |",
            row.kind.name(&m.thresholds),
            row.ratio.median,
            row.ratio.min,
            row.ratio.max,
            total_rays(&row.counters),
            e.rmse,
            e.max,
            e.rmse_8bit,
            100.0 * e.changed,
        );
    }
    let _ = writeln!(
        out,
        "\nRMSE and max: linear radiance (the mean of clamped samples) before \
         quantization, in units of 1/255, against the depth-{} reference (the depth rows: \
         against the depth-{DEEP} one); 8-bit RMSE in steps; rays: camera, shadow and \
         reflection.\n",
        r.depth
    );

    let numeric = numeric(m);
    let _ = writeln!(
        out,
        "**Numeric error** (f32 against f64, both 1 spp, depth 8): RMSE {:.4}, max {:.3}, \
         {:.2}% of pixels changed in 8 bits.\n",
        numeric.rmse,
        numeric.max,
        100.0 * numeric.changed
    );
    let truncation = m.truncation();
    let _ = writeln!(
        out,
        "**Depth truncation**, a source of its own: the depth-{} reference against the \
         depth-{DEEP} one differs by RMSE {:.3} (max {:.2}, {:.2}% of pixels changed in 8 bits; \
         the two references' own RMSE is {:.3} and {:.3}). Each depth against depth {DEEP} at \
         1 spp, pixel for pixel (the same samples, so only the depth differs):\n",
        r.depth,
        truncation.rmse,
        truncation.max,
        100.0 * truncation.changed,
        r.own_rmse,
        deep.own_rmse,
    );
    out.push_str("| depth | rays | RMSE | max | pixels changed |\n|---:|---:|---:|---:|---:|\n");
    for (depth, error, rays) in depth_split(m) {
        let _ = writeln!(
            out,
            "| {depth} | {rays} | {:.3} | {:.2} | {:.2}% |",
            error.rmse,
            error.max,
            100.0 * error.changed
        );
    }
    out.push_str("\nFindings:\n\n");
    for finding in findings(m) {
        let _ = writeln!(out, "- {finding}");
    }
    out
}

/// f32 against f64, pixel for pixel, at the default sampling.
pub fn numeric(m: &Measurement) -> Error {
    compare(&m.row(Kind::F32).radiance, &m.row(Kind::Default).radiance)
}

/// The f32 − f64 difference map on an absolute scale (black equal, white
/// a difference of [`MAP_WHITE`]/255 or more), each pixel a block of
/// pixels so the map is at least [`MAP_SIZE`] a side.
pub fn numeric_map(m: &Measurement) -> Image {
    let map = difference_map(
        &m.row(Kind::F32).radiance,
        &m.row(Kind::Default).radiance,
        MAP_WHITE / 255.0,
    );
    enlarge(&map, MAP_SIZE.div_ceil(map.size.max(1)))
}

/// The difference, in 1/255, that a difference map shows white: one 8-bit
/// step, the difference that can change a pixel's output.
pub const MAP_WHITE: f64 = 1.0;

/// The smallest side of a difference map: a 17-pixel scene's is legible.
pub const MAP_SIZE: u32 = 256;

/// `image` with every pixel repeated `factor` times each way.
fn enlarge(image: &Image, factor: u32) -> Image {
    let (size, factor) = (image.size as usize, factor.max(1) as usize);
    let mut rgb = Vec::with_capacity(image.rgb.len() * factor * factor);
    for row in image.rgb.chunks_exact(3 * size.max(1)) {
        let wide: Vec<u8> = row
            .chunks_exact(3)
            .flat_map(|pixel| pixel.repeat(factor))
            .collect();
        for _ in 0..factor {
            rgb.extend_from_slice(&wide);
        }
    }
    Image {
        size: image.size * factor as u32,
        rgb,
    }
}

/// Each measured depth (the default's 8 among them) against depth 64.
fn depth_split(m: &Measurement) -> Vec<(u32, Error, u64)> {
    let deep = &m.row(Kind::Depth(DEEP)).radiance;
    let mut depths: Vec<(u32, Kind)> = DEPTHS.iter().map(|&d| (d, Kind::Depth(d))).collect();
    depths.push((8, Kind::Default));
    depths.sort_by_key(|&(d, _)| d);
    depths
        .into_iter()
        .map(|(d, kind)| {
            let row = m.row(kind);
            (d, compare(&row.radiance, deep), total_rays(&row.counters))
        })
        .collect()
}

/// The least-squares slope of ln RMSE against ln spp over the jittered
/// uniform counts ([`SPPS`], 4 to 64: 1 spp is the pixel centre, not a
/// jittered sample), where the RMSE is not 0; `None` with fewer than two
/// points.
pub fn sampling_slope(m: &Measurement) -> Option<f64> {
    let points: Vec<(f64, f64)> = SPPS
        .iter()
        .map(|&n| (n, m.row(Kind::Uniform(n)).error))
        .filter(|&(_, e)| e.rmse > 0.0)
        .map(|(n, e)| (f64::from(n).ln(), e.rmse.ln()))
        .collect();
    if points.len() < 2 {
        return None;
    }
    let count = points.len() as f64;
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(x, y), p| (x + p.0 / count, y + p.1 / count));
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(sxy, sxx), &(x, y)| {
        (sxy + (x - mx) * (y - my), sxx + (x - mx) * (x - mx))
    });
    Some(sxy / sxx)
}

/// The range of spp [`sampling_slope`] fits over, as a report names it.
pub fn fitted_range() -> String {
    format!(
        "{}–{} spp, jittered counts only",
        SPPS[0],
        SPPS[SPPS.len() - 1]
    )
}

/// (spp, error) of uniform sampling, 1 spp (the default) first.
fn uniform(m: &Measurement) -> impl Iterator<Item = (u32, Error)> + '_ {
    std::iter::once((1, m.row(Kind::Default).error))
        .chain(SPPS.iter().map(|&n| (n, m.row(Kind::Uniform(n)).error)))
}

/// Adaptive sampling at `spp` and threshold index `threshold` against
/// uniform at `spp`: what [`ADAPTIVE_RMSE`] and [`ADAPTIVE_TIME`] judge.
#[derive(Clone, Copy, Debug)]
pub struct Verdict {
    pub spp: u32,
    pub uniform_rmse: f64,
    pub adaptive_rmse: f64,
    /// Adaptive's RMSE over uniform's (1 when both are 0).
    pub rmse: f64,
    /// Adaptive's time over uniform's, within each repetition.
    pub time: super::timing::Spread,
    /// Shares of the pixels that took all `spp` samples, and 4.
    pub refined: f64,
    pub partly_refined: f64,
}

impl Verdict {
    /// Adaptive at `spp` with threshold index `threshold` in `m`.
    pub fn of(m: &Measurement, spp: u32, threshold: usize) -> Verdict {
        let kind = Kind::Adaptive { spp, threshold };
        let (a, u) = (m.row(kind), m.row(Kind::Uniform(spp)));
        let share = |count: u64| count as f64 / f64::from(m.size).powi(2);
        Verdict {
            spp,
            uniform_rmse: u.error.rmse,
            adaptive_rmse: a.error.rmse,
            rmse: ratio(a.error.rmse, u.error.rmse),
            time: m.time_ratio(kind, Kind::Uniform(spp)),
            refined: share(a.counters.pixels_refined),
            partly_refined: share(a.counters.pixels_partly_refined),
        }
    }

    /// Whether the RMSE is within [`ADAPTIVE_RMSE`]× uniform's.
    pub fn rmse_met(&self) -> bool {
        self.rmse <= ADAPTIVE_RMSE
    }

    /// Whether the median time is within [`ADAPTIVE_TIME`]× uniform's.
    pub fn time_met(&self) -> bool {
        self.time.median <= ADAPTIVE_TIME
    }

    pub fn meets(&self) -> bool {
        self.rmse_met() && self.time_met()
    }

    /// Adaptive's time over uniform's, the median and the range:
    /// `1.23 (1.10–1.40)`.
    pub fn time_spread(&self) -> String {
        let t = &self.time;
        format!("{:.2} ({:.2}–{:.2})", t.median, t.min, t.max)
    }

    /// The shares of pixels that took all samples, and 4, as percentages:
    /// `["12.5%", "3.0%"]` (see [`percent`]).
    pub fn refined_shares(&self) -> [String; 2] {
        [self.refined, self.partly_refined].map(percent)
    }

    /// "meets", or "misses" with what missed.
    pub fn outcome(&self) -> String {
        match (self.rmse_met(), self.time_met()) {
            (true, true) => "meets".into(),
            (false, true) => format!("**misses**: RMSE ×{:.2} > {ADAPTIVE_RMSE}", self.rmse),
            (true, false) => format!(
                "**misses**: time ×{:.2} > {ADAPTIVE_TIME}",
                self.time.median
            ),
            (false, false) => format!(
                "**misses**: RMSE ×{:.2} > {ADAPTIVE_RMSE} and time ×{:.2} > {ADAPTIVE_TIME}",
                self.rmse, self.time.median
            ),
        }
    }
}

/// What the numbers say, each against a stated threshold.
pub fn findings(m: &Measurement) -> Vec<String> {
    let mut findings = Vec::new();
    let own = m.reference.own_rmse;
    let default = m.row(Kind::Default);

    // Sampling.
    let slope = sampling_slope(m).map_or_else(
        || "the RMSE is 0 at every jittered sample count".to_string(),
        |s| {
            format!(
                "the RMSE falls as N^{s:.2} (least squares over {})",
                fitted_range()
            )
        },
    );
    let converged = uniform(m).find(|(_, e)| e.rmse <= CONVERGED_RMSE);
    let verdict = match converged {
        Some((1, _)) => format!(
            "1 spp is already within {CONVERGED_RMSE}/255 RMSE of the reference: \
             supersampling buys nothing here"
        ),
        Some((n, e)) => format!(
            "{n} spp is the first to bring the RMSE to {CONVERGED_RMSE}/255 or less \
             ({:.3}, ×{:.1} the time of the default)",
            e.rmse,
            m.row(Kind::Uniform(n)).ratio.median
        ),
        None => format!("no measured count (up to 64 spp) brings the RMSE to {CONVERGED_RMSE}/255"),
    };
    findings.push(format!("**Sampling**: {slope}; {verdict}."));
    let unresolved: Vec<String> = uniform(m)
        .filter(|(_, e)| e.rmse > 0.0 && e.rmse <= RESOLVED * own)
        .map(|(n, _)| format!("{n} spp"))
        .collect();
    if !unresolved.is_empty() {
        findings.push(format!(
            "**Reference**: the error of {} is within {RESOLVED}× the reference's own \
             ({own:.3}/255), so its value there is an upper bound, not a measurement.",
            unresolved.join(", ")
        ));
    }

    // Adaptive against uniform.
    for (t, &threshold) in m.thresholds.iter().enumerate() {
        let comparisons: Vec<String> = SPPS
            .iter()
            .map(|&n| {
                let v = Verdict::of(m, n, t);
                let [all, four] = v.refined_shares();
                format!(
                    "{n} spp: RMSE ×{:.2}, time ×{}, {all} of the pixels took all {n} samples \
                     and {four} took 4 samples ({})",
                    v.rmse,
                    v.time_spread(),
                    v.outcome()
                )
            })
            .collect();
        findings.push(format!(
            "**Adaptive** (threshold {threshold}/255) against uniform at the same N, time as \
             adaptive's over uniform's in each repetition; the target is RMSE ≤ \
             {ADAPTIVE_RMSE}× in ≤ {ADAPTIVE_TIME}× the time: {}.",
            comparisons.join("; ")
        ));
    }

    // Precision.
    let numeric = numeric(m);
    let f32_time = m.row(Kind::F32).ratio.median;
    let enough = numeric.changed <= F32_CHANGED || numeric.max <= F32_MAX;
    findings.push(format!(
        "**f32 is {}enough here**: it changes {:.2}% of 8-bit pixels and moves a channel by \
         up to {:.3}/255, at ×{f32_time:.2} the time of f64 (enough means at most {:.1}% of pixels \
         change, or no channel moves by more than {F32_MAX}/255).",
        if enough { "" } else { "not " },
        100.0 * numeric.changed,
        numeric.max,
        100.0 * F32_CHANGED,
    ));

    // Depth.
    let split = depth_split(m);
    let exact = split.iter().find(|(_, e, _)| e.changed == 0.0);
    let eight = split
        .iter()
        .find(|(d, _, _)| *d == 8)
        .map(|(_, e, _)| e)
        .expect("the default is depth 8");
    let shallowest = match exact {
        Some((d, ..)) if *d < DEEP => {
            format!("depth {d} is the shallowest whose 8-bit image equals depth {DEEP}'s")
        }
        _ => format!("no measured depth below {DEEP} gives depth {DEEP}'s 8-bit image"),
    };
    findings.push(format!(
        "**Reflection depth**: {shallowest}; the default depth 8 changes {:.2}% of \
         pixels (RMSE {:.3}).",
        100.0 * eight.changed,
        eight.rmse
    ));

    // Skipping.
    let no_skip = m.row(Kind::NoSkip);
    let same = no_skip.radiance.quantize() == default.radiance.quantize();
    let saved = total_rays(&no_skip.counters) - total_rays(&default.counters);
    findings.push(format!(
        "**Skipping** invisible work saves {saved} rays ({:.1}% of --no-skip's); \
         --no-skip takes ×{:.2} the time of the default (range {:.2}–{:.2}); the 8-bit image \
         is {}.",
        100.0 * saved as f64 / total_rays(&no_skip.counters).max(1) as f64,
        no_skip.ratio.median,
        no_skip.ratio.min,
        no_skip.ratio.max,
        if same { "the same" } else { "different" }
    ));
    findings
}

/// `a / b`, with 0/0 = 1 (both exact) and a/0 = ∞.
fn ratio(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        if a == 0.0 {
            1.0
        } else {
            f64::INFINITY
        }
    } else {
        a / b
    }
}

/// The guide series of [`sampling_csv`] for error falling as N^-1/2, the
/// rate of noise.
pub const GUIDE_HALF: &str = "N^-1/2";
/// The guide series for error falling as N^-1, the rate of stratified
/// sampling across edges.
pub const GUIDE_ONE: &str = "N^-1";
/// The series of the reference's own RMSE: the floor under which no
/// error is resolved.
pub const FLOOR: &str = "reference's own RMSE";

/// The name of the adaptive series at threshold index `t`.
fn adaptive_series(m: &Measurement, t: usize) -> String {
    match m.thresholds.len() {
        1 => "adaptive".into(),
        _ => format!("adaptive {}", m.thresholds[t]),
    }
}

/// `series,x,y` rows of RMSE against spp: uniform (named with its
/// slope fitted over the jittered counts), adaptive (one series per
/// threshold), guide lines ([`GUIDE_HALF`], [`GUIDE_ONE`]) through uniform
/// 4 spp, and the reference's own RMSE ([`FLOOR`]). Rows with RMSE 0 are
/// left out (a log axis cannot show them); empty when every jittered
/// uniform RMSE is 0.
pub fn sampling_csv(m: &Measurement) -> String {
    let mut csv = String::from("series,spp,rmse\n");
    let Some(slope) = sampling_slope(m) else {
        return csv;
    };
    let name = format!("uniform (slope {slope:.2} over 4–64)");
    for (n, e) in uniform(m).filter(|(_, e)| e.rmse > 0.0) {
        let _ = writeln!(csv, "{name},{n},{}", e.rmse);
    }
    for t in 0..m.thresholds.len() {
        let series = adaptive_series(m, t);
        let adaptive = std::iter::once((1, m.row(Kind::Default).error)).chain(
            SPPS.iter()
                .map(|&spp| (spp, m.row(Kind::Adaptive { spp, threshold: t }).error)),
        );
        for (n, e) in adaptive.filter(|(_, e)| e.rmse > 0.0) {
            let _ = writeln!(csv, "{series},{n},{}", e.rmse);
        }
    }
    let start = m.row(Kind::Uniform(SPPS[0])).error.rmse;
    if start > 0.0 {
        for (guide, power) in [(GUIDE_HALF, 0.5), (GUIDE_ONE, 1.0)] {
            for n in SPPS {
                let relative = f64::from(n) / f64::from(SPPS[0]);
                let _ = writeln!(csv, "{guide},{n},{}", start / relative.powf(power));
            }
        }
    }
    let own = m.reference.own_rmse;
    if own > 0.0 {
        for n in [1, 64] {
            let _ = writeln!(csv, "{FLOOR},{n},{own}");
        }
    }
    csv
}

/// `series,x,y,label` rows of RMSE against time (× the default) for
/// uniform and adaptive sampling (a series per threshold), labelled with
/// their spp.
pub fn pareto_csv(m: &Measurement) -> String {
    let mut csv = String::from("series,time,rmse,spp\n");
    let mut series = vec![("uniform".to_string(), SPPS.map(Kind::Uniform))];
    for t in 0..m.thresholds.len() {
        series.push((
            adaptive_series(m, t),
            SPPS.map(|spp| Kind::Adaptive { spp, threshold: t }),
        ));
    }
    for (series, kinds) in series {
        for kind in std::iter::once(Kind::Default).chain(kinds) {
            let row = m.row(kind);
            let spp = match kind {
                Kind::Uniform(n) | Kind::Adaptive { spp: n, .. } => n,
                _ => 1,
            };
            if row.error.rmse > 0.0 {
                let _ = writeln!(
                    csv,
                    "{series},{},{},{spp}",
                    row.ratio.median, row.error.rmse
                );
            }
        }
    }
    csv
}

/// A share of 0 to 1 as a percentage with one decimal: `12.5%`; `none`
/// for 0, and `under 0.1%` for a share that one decimal would show as
/// `0.0%` though it is not 0.
pub fn percent(share: f64) -> String {
    if share <= 0.0 {
        "none".into()
    } else if share < 0.0005 {
        "under 0.1%".into()
    } else {
        format!("{:.1}%", 100.0 * share)
    }
}

/// `count` and `noun`, plural unless it is 1: `1 repetition`, `5 repetitions`.
pub fn plural(count: usize, noun: &str) -> String {
    if count == 1 {
        format!("1 {noun}")
    } else {
        format!("{count} {noun}s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_repetition_is_singular() {
        assert_eq!(plural(1, "repetition"), "1 repetition");
        assert_eq!(plural(5, "repetition"), "5 repetitions");
        assert_eq!(plural(0, "repetition"), "0 repetitions");
    }

    #[test]
    fn shares_are_never_a_misleading_zero() {
        assert_eq!(percent(0.0), "none");
        assert_eq!(percent(0.0001), "under 0.1%");
        assert_eq!(percent(0.125), "12.5%");
        assert_eq!(percent(1.0), "100.0%");
    }
}
