//! Reflection: what mirrors show, on mirrors without a texture. The
//! student's brightness (in linear light, [`super::tone`]) is fitted per
//! mirror as `a + b·lit + c·(what ours sees in the mirror)ⁿ`, the power
//! `n` being the student's to choose (the assignment offers
//! `(reflected colour)ⁿ · reflectivity` beside the plain term:
//! [`fit_shape`]); a pixel the fit does not explain differs, and a mirror
//! whose gain `c` on what ours shows is below a share of its reflectivity
//! does not show it at all. The student may add what a mirror shows as
//! it arrives or tinted by the mirror's own colour ([`Tint`]); the image
//! is read under the one that fits it, the same for all its mirrors, so
//! a black mirror that shows nothing may be a tinting tracer's, unless
//! another black mirror of the same image shows what ours shows. What a
//! mirror shows of a texture (the mapping is open) is not judged, nor
//! what it shows of another mirror where the readings (added or blended,
//! any depth of two reflections or more) differ
//! ([`Probe::reflection_settled`]), nor where a highlight may brighten
//! it. Where they agree, as in a mirror showing a black mirror that
//! shows a coloured object, recursion is judged.
//!
//! What a mirror shows of a lit point is that point's light, which the
//! student's shadow rays decide. Where the student's shadows fail on the
//! scene ([`super::shadows`], judged before), a mirror is judged only on
//! pixels whose shown points no light could reach were nothing in the
//! way ([`Probe::reflected_direct`]): a shadow bug costs shadows, not
//! reflection as well.
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
        tinted: tint == Tint::Tinted,
        ..Counts::default()
    };
    let (mut marks, mut gains) = (Vec::new(), Vec::new());
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
        let missing = gain.is_some_and(|g| g < thresholds.reflection_gain);
        for (&k, (x, s)) in ks.iter().zip(&shape.rows) {
            let r = s - predict(&shape.beta, x);
            // A highlight only brightens: not a reflection's error.
            let highlight = r > 0.0 && e.buffers.centres[k].highlight > HIGHLIGHT_CONE;
            // Whether ours shows something there, the same base under
            // either reading: a tinted black mirror must show nothing.
            let shows = e.buffers.centres[k].reflected_radiance > SHOWS;
            let bad = (r.abs() > 0.06 && !highlight) || (missing && shows);
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
    Judged {
        counts,
        marks,
        gains,
    }
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
