//! Reflection: what mirrors show, on mirrors without a texture. The
//! student's brightness (in linear light, [`super::tone`]) is fitted per
//! mirror as `a + b·lit + c·(what ours sees in the mirror)ⁿ`, the power
//! `n` being the student's to choose (the assignment offers
//! `(reflected colour)ⁿ · reflectivity` beside the plain term:
//! [`fit_shape`]); a pixel the fit does not explain differs, and a mirror
//! whose gain `c` on what ours shows is below a share of its reflectivity
//! does not show it at all, as one whose gain `b` on its own light is
//! below that share of `1 − k`, the weight a blended reflection gives
//! it (the least either reading gives), does not show its own light: the
//! assignment adds what a mirror shows to the local colour. Every
//! reading gives each mirror a gain `c` of one weight times `k`, so the
//! gains of a scene's mirrors must follow their reflectivities, not
//! their squares ([`reflectivity_power`]). The student may add what a
//! mirror shows as it arrives or tinted by the mirror's own colour
//! ([`Tint`]); the image is read under the one that fits it, the same
//! for all its mirrors, so a black mirror that shows nothing may be a
//! tinting tracer's, unless another black mirror of the same image shows
//! what ours shows. What a mirror shows of a texture (the mapping is
//! open) is not judged, nor what it shows of another mirror where the
//! readings (added or blended, any depth of two reflections or more)
//! differ ([`Probe::reflection_settled`]), nor where a highlight may
//! brighten it. Where they agree, as in a mirror showing a black mirror
//! that shows a coloured object, recursion is judged.
//!
//! What a mirror shows of a lit point is that point's light, which the
//! student's shadow rays decide. Where the student's shadows fail on the
//! scene ([`super::shadows`], judged before), a mirror is judged only on
//! pixels whose shown points no light could reach were nothing in the
//! way ([`Probe::reflected_direct`]), and its own light is not held to a
//! share (which lights reach it is theirs too): a shadow bug costs
//! shadows, not reflection as well.
//!
//! [`Probe::reflection_settled`]: raytracer_render::render::probe::Probe::reflection_settled
//! [`Probe::reflected_direct`]: raytracer_render::render::probe::Probe::reflected_direct

use super::evidence::{clipped, Evidence, Whose, HIGHLIGHT_CONE};
use super::fit::{predict, robust_fit, spread};
use super::tone::FLAT;
use super::{failed, fraction_words, ratio, verdict, Aspect, AspectResult, AspectThresholds};
use raytracer_render::render::probe::Probe;

/// The powers of what a mirror shows tried: the assignment's own variant
/// of the reflection's term is `(reflected colour)ⁿ · reflectivity`.
const POWERS: [f64; 4] = [1.0, 1.5, 2.0, 3.0];

/// The share of the plain term's (`n` = 1) root-mean-square residual
/// another power must leave less than to be read into the mirror, as a
/// tone curve must earn its place over clamping ([`super::tone`]).
const KEEP_PLAIN: f64 = 0.9;

/// The student's brightness over mirror pixels `ks` fitted as
/// `a + b·lit + c·(what ours sees in the mirror, under `tint`)ⁿ + d·(it
/// meets nothing)`, with the power `n` of [`POWERS`] that explains it, kept
/// only where it earns its place ([`KEEP_PLAIN`]); `None` when nothing
/// fits. The last term is the student's background as their mirror shows
/// it, as the background's colour is theirs to choose
/// ([`super::background`]); fitted only when their background is
/// `coloured` (not black), else a mirror that shows something where ours
/// shows nothing differs.
fn fit_shape(e: &Evidence, ks: &[usize], coloured_background: bool, tint: Tint) -> Option<Shape> {
    let fit = |n: f64| {
        let rows: Vec<([f64; 3], f64)> = ks
            .iter()
            .map(|&k| {
                let p = &e.buffers.centres[k];
                let meets_nothing = coloured_background && p.reflected.is_none();
                (
                    [
                        p.lit,
                        tint.shown(p).max(0.0).powf(n),
                        f64::from(u8::from(meets_nothing)),
                    ],
                    e.luminance(Whose::Theirs, k),
                )
            })
            .collect();
        let beta = robust_fit(&rows)?;
        let squares: f64 = rows
            .iter()
            .map(|(x, y)| (y - predict(&beta, x)).powi(2))
            .sum();
        let left = (squares / rows.len() as f64).sqrt();
        Some(Shape {
            power: n,
            rows,
            beta,
            left,
        })
    };
    let plain = fit(POWERS[0])?;
    let bound = KEEP_PLAIN * plain.left;
    let best = POWERS[1..]
        .iter()
        .filter_map(|&n| fit(n))
        .filter(|f| f.left < bound)
        .min_by(|a, b| a.left.total_cmp(&b.left))
        .unwrap_or(plain);
    Some(best)
}

/// A mirror's fit ([`fit_shape`]): the power of what it shows, each
/// pixel's row (`lit`, what ours sees there to that power, whether it
/// meets nothing where the student's background is coloured; the
/// student's luminance), the fit, and its root-mean-square residual.
struct Shape {
    power: f64,
    rows: Vec<([f64; 3], f64)>,
    beta: Vec<f64>,
    left: f64,
}

/// The light the lights could bring to a mirror pixel's shown points
/// before what it shows depends on the student's shadows: what a mirror
/// must show to show something at all.
const SHOWS: f64 = 0.03;

/// How a student's mirror adds what it shows: as it arrives (the
/// assignment's "reflected colour times reflectivity"), or tinted by the
/// mirror's own colour, channel by channel, as a coloured metal would
/// (the assignment lets a student "try different things" there). A black
/// mirror tinted shows nothing; a grey one shows what it shows scaled
/// down by its grey.
#[derive(Clone, Copy, PartialEq)]
enum Tint {
    AsItArrives,
    Tinted,
}

impl Tint {
    /// What ours sees in the mirror at `p` under this reading.
    fn shown(self, p: &Probe) -> f64 {
        match self {
            Tint::AsItArrives => p.reflected_radiance,
            Tint::Tinted => p.reflected_tinted,
        }
    }
}

/// Judge reflection, marking `map`, leaving what the student's failed
/// shadows decide to `earlier`'s shadows verdict. The image is judged
/// under each [`Tint`], and read as tinted when that leaves fewer pixels
/// differing, unless a mirror the tint leaves nothing to show shows what
/// ours shows: a student's mirrors all add what they show one way, so a
/// black mirror that shows it refutes the tint for all of them.
pub(super) fn judge(
    e: &Evidence,
    thresholds: &AspectThresholds,
    earlier: &[AspectResult],
    map: &mut [u8],
) -> AspectResult {
    let shadows_differ = failed(earlier, Aspect::Shadows);
    let as_it_arrives = judge_as(e, thresholds, shadows_differ, Tint::AsItArrives);
    let tinted = judge_as(e, thresholds, shadows_differ, Tint::Tinted);
    // A mirror the tint leaves nothing to show (a black one) that shows
    // what ours shows all the same tells that the student does not tint.
    let refuted = as_it_arrives.gains.iter().any(|(object, gain)| {
        gain.is_some_and(|g| g >= thresholds.reflection_gain)
            && tinted
                .gains
                .iter()
                .any(|(other, tinted_gain)| other == object && tinted_gain.is_none())
    });
    let read = if !refuted && tinted.measure() < as_it_arrives.measure() {
        tinted
    } else {
        as_it_arrives
    };
    for &(k, mark) in &read.marks {
        map[k] = mark;
    }
    let counts = &read.counts;
    verdict(
        Aspect::Reflection,
        counts.showing >= 20,
        read.measure(),
        thresholds.reflection,
        counts.showing + counts.dark,
        detail(counts, thresholds.reflection_gain),
    )
}

/// The mirrors judged under one [`Tint`]: the counts, each judged
/// pixel's mark for the aspect's map, and each mirror fitted with its
/// gain on what ours shows, where told.
struct Judged {
    counts: Counts,
    marks: Vec<(usize, u8)>,
    gains: Vec<(u32, Option<f64>)>,
}

impl Judged {
    /// Each fraction over its own base: the pixels whose reflection shows
    /// something, and those where ours shows nothing (judged when there
    /// are enough of them).
    fn measure(&self) -> f64 {
        let c = &self.counts;
        ratio(c.showing_bad, c.showing).max(if c.dark >= 20 {
            ratio(c.dark_bad, c.dark)
        } else {
            0.0
        })
    }
}

/// Judge every mirror of `e` under `tint`, what the student's failed
/// shadows decide left out when `shadows_differ`.
fn judge_as(
    e: &Evidence,
    thresholds: &AspectThresholds,
    shadows_differ: bool,
    tint: Tint,
) -> Judged {
    let mut counts = Counts {
        weakest_gain: f64::INFINITY,
        weakest_own_gain: f64::INFINITY,
        tinted: tint == Tint::Tinted,
        ..Counts::default()
    };
    let (mut gains, mut fitted) = (Vec::new(), Vec::new());
    // Whether the student's background is coloured: told once, for the
    // first mirror, as it is the image's, not the mirror's.
    let mut coloured_background = None;
    for &object in &e.objects {
        let first = e.first_probe(object);
        if first.reflectivity == 0.0 || first.uv.is_some() {
            continue;
        }
        let coloured_background =
            *coloured_background.get_or_insert_with(|| !e.background().is_black());
        let mut ks: Vec<usize> = e
            .pixels_of(object, &|p| {
                p.visible ^ (u64::from(p.reflected.map_or(u32::MAX, |r| r)) << 32)
            })
            .into_iter()
            .filter(|&k| {
                let p = &e.buffers.centres[k];
                // What a mirror shows of a texture depends on the
                // mapping; of another mirror, on the readings, unless
                // every reading shows the same there (settled).
                let indirect = !p.reflection_settled
                    || p.reflected
                        .is_some_and(|r| e.buffers.textured.get(r as usize) == Some(&true));
                !clipped(&e.student_px(k)) && p.highlight < 0.95 && !indirect
            })
            .collect();
        if shadows_differ {
            let before = ks.len();
            ks.retain(|&k| e.buffers.centres[k].reflected_direct <= SHOWS);
            counts.left_to_shadows += before - ks.len();
        }
        let Some(shape) = fit_shape(e, &ks, coloured_background, tint) else {
            continue;
        };
        counts.mirrors += 1;
        counts.power = counts.power.max(shape.power);
        // Whether the student's mirror shows what ours shows at all: the
        // fit's gain on it against the mirror's reflectivity, told only
        // where what ours shows varies over the mirror by more than
        // rounding could hide ([`FLAT`]; never on a black mirror tinted).
        let shown: Vec<f64> = ks
            .iter()
            .map(|&k| tint.shown(&e.buffers.centres[k]))
            .collect();
        let gain = (spread(&shown) >= FLAT).then(|| shape.beta[2] / first.reflectivity);
        gains.push((object, gain));
        if let Some(gain) = gain {
            counts.weakest_gain = counts.weakest_gain.min(gain);
        }
        // Whether the student's mirror shows its own light at all: the
        // fit's gain on the light that reaches it against `1 − k`, its
        // weight when blended (the least either reading gives it), told
        // only where that light varies over the mirror by more than
        // rounding could hide, and the student's shadows, which decide
        // it, pass.
        let own_light: Vec<f64> = ks
            .iter()
            .map(|&k| (1.0 - first.reflectivity) * e.buffers.centres[k].lit)
            .collect();
        let own_gain = (!shadows_differ && spread(&own_light) >= FLAT)
            .then(|| shape.beta[1] / (1.0 - first.reflectivity));
        if let Some(gain) = own_gain {
            counts.weakest_own_gain = counts.weakest_own_gain.min(gain);
        }
        fitted.push(Fitted {
            reflectivity: first.reflectivity,
            ks,
            shape,
            own_light,
            missing: gain.is_some_and(|g| g < thresholds.reflection_gain),
            unlit: own_gain.is_some_and(|g| g < thresholds.reflection_gain),
            gain,
        });
    }
    counts.reflectivity_power = reflectivity_power(&fitted);
    let off_power = counts
        .reflectivity_power
        .is_some_and(|p| (p - 1.0).abs() > POWER_OFF);
    let marks = mark(e, &fitted, off_power, &mut counts);
    Judged {
        counts,
        marks,
        gains,
    }
}

/// Mark each judged pixel of the `fitted` mirrors, counting it in
/// `counts`: a pixel differs where the fit does not explain it, where its
/// mirror shows too little of what ours shows (or all do, their gains
/// following another power of the reflectivity: `off_power`) and ours
/// shows something there, or where its mirror shows too little of its own
/// light and it has some.
fn mark(e: &Evidence, fitted: &[Fitted], off_power: bool, counts: &mut Counts) -> Vec<(usize, u8)> {
    let mut marks = Vec::new();
    for mirror in fitted {
        let rows = mirror
            .ks
            .iter()
            .zip(&mirror.shape.rows)
            .zip(&mirror.own_light);
        for ((&k, (x, s)), &own) in rows {
            let r = s - predict(&mirror.shape.beta, x);
            // A highlight only brightens: not a reflection's error.
            let highlight = r > 0.0 && e.buffers.centres[k].highlight > HIGHLIGHT_CONE;
            // Whether ours shows something there, the same base under
            // either reading: a tinted black mirror must show nothing.
            let shows = e.buffers.centres[k].reflected_radiance > SHOWS;
            let bad = (r.abs() > 0.06 && !highlight)
                || ((mirror.missing || off_power) && shows)
                || (mirror.unlit && own > SHOWS);
            if shows {
                counts.showing += 1;
                counts.showing_bad += usize::from(bad);
            } else {
                counts.dark += 1;
                counts.dark_bad += usize::from(bad);
            }
            marks.push((k, 1 + u8::from(bad)));
        }
    }
    marks
}

/// One mirror fitted: its reflectivity, the pixels judged, its fit, its
/// own light at the blended weight on each pixel, whether it shows too
/// little of what ours shows or of its own light, and its gain on what
/// ours shows against its reflectivity, where told.
struct Fitted {
    reflectivity: f64,
    ks: Vec<usize>,
    shape: Shape,
    own_light: Vec<f64>,
    missing: bool,
    unlit: bool,
    gain: Option<f64>,
}

/// How far from 1 the power of the reflectivity a scene's mirrors follow
/// may be: half the step to the next whole power (a reflection weighed
/// by the reflectivity squared, or not at all).
const POWER_OFF: f64 = 0.5;

/// The least ratio between a scene's largest and smallest reflectivity
/// that tells the power their gains follow: a gain off by a tenth (the
/// gains of tune's correct readings agree within 5 %) then moves the
/// power read by less than [`POWER_OFF`] (`ln 1.1 / ln 1.25` is 0.43).
const TELLS_POWER: f64 = 1.25;

/// The power `p` of the reflectivity `k` that the gains `c` of a scene's
/// mirrors follow, `c ∝ kᵖ`: every reading the assignment allows gives
/// `c = w·k` with one weight `w` for all the mirrors (their gains
/// against `k` agree), where a reflection weighed by `k²` gives `c ∝ k²`.
/// A least-squares slope of `ln(c/k)` on `ln k`, plus one; told where
/// two mirrors or more have a gain, one power of what they show
/// ([`fit_shape`]), and reflectivities apart by [`TELLS_POWER`].
fn reflectivity_power(fitted: &[Fitted]) -> Option<f64> {
    let told: Vec<(f64, f64, f64)> = fitted
        .iter()
        .filter_map(|m| {
            m.gain
                .filter(|&g| g > 0.0)
                .map(|g| (m.reflectivity.ln(), g.ln(), m.shape.power))
        })
        .collect();
    let powers_agree = told.windows(2).all(|w| w[0].2 == w[1].2);
    let (low, high) = told
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| {
            (lo.min(t.0), hi.max(t.0))
        });
    if told.len() < 2 || !powers_agree || high - low < TELLS_POWER.ln() {
        return None;
    }
    let n = told.len() as f64;
    let (mx, my) = (
        told.iter().map(|t| t.0).sum::<f64>() / n,
        told.iter().map(|t| t.1).sum::<f64>() / n,
    );
    let sxy: f64 = told.iter().map(|t| (t.0 - mx) * (t.1 - my)).sum();
    let sxx: f64 = told.iter().map(|t| (t.0 - mx).powi(2)).sum();
    Some(1.0 + sxy / sxx)
}

/// The pixels of mirrors judged, whether they show something in ours
/// and whether they differ; the mirrors fitted, and the weakest gain on
/// what ours shows of them.
#[derive(Default)]
struct Counts {
    showing: usize,
    showing_bad: usize,
    dark: usize,
    dark_bad: usize,
    mirrors: usize,
    weakest_gain: f64,
    /// The weakest gain on a mirror's own light, against `1 − k`
    /// (infinite where none was told).
    weakest_own_gain: f64,
    /// The power of the reflectivity the mirrors' gains follow, where
    /// told ([`reflectivity_power`]).
    reflectivity_power: Option<f64>,
    /// The largest power of what a mirror shows read into a mirror.
    power: f64,
    /// The mirror pixels showing points a light could reach, left out
    /// as the student's shadows fail on the scene.
    left_to_shadows: usize,
    /// Whether the mirrors were read as tinted by their own colour.
    tinted: bool,
}

/// The verdict's words for `counts`, the gain a mirror must reach being
/// `least_gain`.
fn detail(counts: &Counts, least_gain: f64) -> String {
    let Counts {
        showing,
        showing_bad,
        dark,
        dark_bad,
        mirrors,
        weakest_gain,
        weakest_own_gain,
        reflectivity_power,
        power,
        left_to_shadows,
        tinted,
    } = *counts;
    let left_out = (left_to_shadows > 0).then(|| {
        format!(
            "{left_to_shadows} mirror pixels that show points a light could reach are left to shadows, as yours differ from ours here"
        )
    });
    if showing >= 20 {
        let mut parts: Vec<String> = [
            fraction_words(
                showing_bad,
                showing,
                "mirror pixels that show something are not what ours shows",
            ),
            (dark >= 20)
                .then(|| {
                    fraction_words(
                        dark_bad,
                        dark,
                        "mirror pixels where ours shows nothing differ",
                    )
                })
                .flatten(),
        ]
        .into_iter()
        .flatten()
        .collect();
        if weakest_gain.is_finite() {
            parts.push(format!(
                "the mirror shows {:.0} % of what ours shows{} (at least {:.0} %)",
                100.0 * weakest_gain,
                if tinted { " tinted by its colour" } else { "" },
                100.0 * least_gain
            ));
        }
        if weakest_own_gain.is_finite() {
            parts.push(format!(
                "a mirror shows {:.0} % of its own light as a blended reflection weighs it (at least {:.0} %)",
                100.0 * weakest_own_gain.max(0.0),
                100.0 * least_gain
            ));
        }
        if let Some(p) = reflectivity_power {
            parts.push(format!(
                "your mirrors show what ours shows as their reflectivity to the power {p:.1} (the assignment's is 1: at most {POWER_OFF} from it)"
            ));
        }
        if tinted {
            parts.push(
                "your mirrors read as tinting what they show by their own colour".to_string(),
            );
        }
        if power > 1.0 {
            parts.push(format!(
                "your mirrors read as adding what they show to the power {power}"
            ));
        }
        parts.extend(left_out);
        parts.join("; ")
    } else if let Some(left_out) = left_out {
        format!("{left_out}: only {showing} others show something (20 needed)")
    } else if mirrors == 0 {
        "no mirror without a texture to judge".to_string()
    } else {
        format!(
            "only {showing} mirror pixels show something ours judges (20 needed): the others show nothing, a texture or another mirror"
        )
    }
}
