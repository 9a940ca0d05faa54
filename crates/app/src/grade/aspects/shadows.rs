//! Shadows: which lit points are shadowed, on objects that neither
//! reflect nor are textured, against the scene's fit of the student's
//! light ([`super::falloff`]): brightness in linear light
//! ([`super::tone`]) as `a + b·lit` on the pixels no shadow and no
//! highlight touch, an intercept `a` per object, one gain `b` for the
//! scene, and `lit` each light's share dimmed by the student's falloff
//! with distance. A pixel ours shadows that is as bright as the fit says
//! it would be unshadowed looks lit, and a fully lit pixel darker by half
//! its light looks shadowed; a light that still reaches a shadowed pixel
//! puts its highlight there as on a lit one, so the pixel is held over
//! the student's own highlight lobe ([`super::lobe`]), read off the
//! object's fully lit pixels. A shadowed pixel that another light still
//! reaches looks shadowed from that one too when it is as dark as the
//! object where no light reaches it (a tracer that drops every light
//! where one is blocked): held against the object's own unlit level
//! (where none of it in view is unlit, the level those points' own line
//! meets with no light), not the fit's light, as a bug in the lights'
//! colours changes how bright each light looks but leaves it visible.
//! With its own intercept, an object the student draws the same lit and
//! shadowed reads as shadows that look lit, whether no shadow falls on
//! it or no light reaches it at all (a plane lit on its front alone,
//! seen from behind), so a failing report names both. A pixel whose
//! colour no light of the scene gives ([`super::palette`]) is shading's,
//! not a shadow.

use raytracer_render::render::probe::Probe;

use super::evidence::{clipped, Evidence, Whose};
use super::falloff::LightFit;
use super::fit::robust_fit;
use super::lobe::Lobe;
use super::{fraction_words, ratio, verdict, Aspect, AspectResult, AspectThresholds};

/// A running mean.
#[derive(Default)]
struct Mean {
    sum: f64,
    count: usize,
}

impl Mean {
    fn add(&mut self, v: f64) {
        self.sum += v;
        self.count += 1;
    }

    fn get(&self) -> f64 {
        self.sum / self.count.max(1) as f64
    }
}

/// The student's brightness on one object where ours is lit and where
/// ours is shadowed, and the light the fit says the shadows take.
#[derive(Default)]
struct Sides {
    lit: Mean,
    shadowed: Mean,
    taken: Mean,
}

impl Sides {
    /// Whether the object looks the same lit and shadowed: its shadowed
    /// points darker than its lit ones by less than half the light the
    /// shadows take (the bound a single pixel is held to), on 20 pixels
    /// of each. Either no shadow falls on it, or no light reaches it,
    /// which the per-object intercept of the fit cannot tell apart.
    fn alike(&self) -> bool {
        self.lit.count >= 20
            && self.shadowed.count >= 20
            && self.lit.get() - self.shadowed.get() < 0.5 * self.taken.get()
    }
}

/// Whether `probe` is a shadowed point another light still reaches,
/// with light enough to tell.
fn partly_lit(probe: &Probe, light: &LightFit) -> bool {
    probe.unshadowed - probe.lit > 0.05
        && probe.lit > 0.05
        && light.least_gain() * light.falloff.lit(probe) > 8.0 / 255.0
}

/// Whether no light of ours is blocked from `probe`'s point, and light
/// enough reaches it to tell.
fn fully_lit(probe: &Probe) -> bool {
    probe.unshadowed - probe.lit < 1e-9 && probe.lit > 0.05
}

/// The student's level on the object whose pixels are `ks` where no
/// light of ours reaches it ([`Evidence::unlit_level`]); where none of it
/// in view is unlit, [`unseen_unlit_level`] of its points another light
/// reaches ([`partly_lit`]); `None` when neither tells it.
fn unlit_level(e: &Evidence, light: &LightFit, ks: &[usize]) -> Option<f64> {
    e.unlit_level(Whose::Theirs, ks).or_else(|| {
        let rows: Vec<([f64; 1], f64)> = ks
            .iter()
            .map(|&k| (&e.buffers.centres[k], k))
            .filter(|(probe, _)| partly_lit(probe, light))
            .map(|(probe, k)| ([light.falloff.lit(probe)], e.luminance(Whose::Theirs, k)))
            .collect();
        unseen_unlit_level(&rows)
    })
}

/// An object's unlit level where no point of it in view is unlit: the
/// intercept of the line its shadowed points another light reaches
/// (`rows`: that light under the fit's falloff, and the student's
/// luminance) take against that light, when 20 tell it. A tracer that
/// drops every light where one is blocked shows them flat at that level;
/// one that lights them, rising with the light, its line meeting no light
/// at that level too. Their own line, not the scene's: the scene's fit
/// reaches these points from the fully lit ones, which a compressing
/// tone curve read on a scene whose lit points clamp leaves far off.
fn unseen_unlit_level(rows: &[([f64; 1], f64)]) -> Option<f64> {
    if rows.len() < 20 {
        return None;
    }
    robust_fit(rows).map(|beta| beta[0])
}

/// The pixels shadows counts over the scene's plain objects, and those
/// of them that look wrong.
#[derive(Default)]
struct Counts {
    shadowed: usize,
    shadowed_bad: usize,
    lit: usize,
    lit_bad: usize,
    /// Shadowed pixels another light still reaches ([`partly_lit`]).
    partly: usize,
    partly_bad: usize,
    /// Objects that look the same lit and shadowed ([`Sides::alike`]).
    alike: usize,
}

/// Judge the shadows on the plain object `object`, whose intercept in
/// the scene's fit is `a`, into `counts`, marking `map`.
fn judge_object(
    e: &Evidence,
    light: &LightFit,
    (object, a): (u32, f64),
    counts: &mut Counts,
    map: &mut [u8],
) {
    let b = light.least_gain();
    let ks: Vec<usize> = e
        .pixels_of(object, &|p| p.visible)
        .into_iter()
        .filter(|&k| !clipped(&e.student_px(k)))
        // A colour no light gives is shading's, and says nothing of
        // which lights reach the point.
        .filter(|&k| e.foreign[k] != Some(true))
        .collect();
    // Where no light of ours reaches the object ([`unlit_level`]), or,
    // not told, the fit's intercept.
    let unlit_level = unlit_level(e, light, &ks).unwrap_or(a);
    // The fully lit pixels' brightness over the fit's line tells the
    // student's highlight lobe, which a light that still reaches a
    // shadowed point puts there too.
    let lobe = Lobe::fit(
        &ks.iter()
            .map(|&k| (&e.buffers.centres[k], k))
            .filter(|(probe, _)| fully_lit(probe))
            .map(|(probe, k)| {
                let s = e.luminance(Whose::Theirs, k);
                (probe.highlight, s - (a + b * light.falloff.lit(probe)))
            })
            .collect::<Vec<_>>(),
    );
    let mut sides = Sides::default();
    for k in ks {
        let probe = &e.buffers.centres[k];
        let s = e.luminance(Whose::Theirs, k);
        let lit_here = light.falloff.lit(probe);
        if probe.unshadowed - probe.lit > 0.05 {
            counts.shadowed += 1;
            let taken = light.falloff.unshadowed(probe) - lit_here;
            sides.shadowed.add(s);
            sides.taken.add(b * taken);
            // Over the highlight the lights that reach it put there
            // ([`Probe::highlight`] is theirs alone).
            let over_line = s - (a + b * lit_here);
            let unhighlighted = over_line - lobe.at(probe.highlight);
            let looks_lit = unhighlighted > 0.5 * b * taken && unhighlighted > 4.0 / 255.0;
            counts.shadowed_bad += usize::from(looks_lit);
            // Where another light still reaches the point, it must not
            // look shadowed from that one too: as dark as the object
            // where no light reaches it.
            let mut looks_unlit = false;
            if partly_lit(probe, light) {
                counts.partly += 1;
                looks_unlit = s - unlit_level < 4.0 / 255.0;
                counts.partly_bad += usize::from(looks_unlit);
            }
            map[k] = 1 + u8::from(looks_lit || looks_unlit);
        } else if fully_lit(probe) {
            counts.lit += 1;
            sides.lit.add(s);
            let bad = light.looks_shadowed(object, probe, s) == Some(true);
            counts.lit_bad += usize::from(bad);
            map[k] = 1 + u8::from(bad);
        }
    }
    counts.alike += usize::from(sides.alike());
}

/// Judge shadows, marking `map`.
pub(super) fn judge(
    e: &Evidence,
    thresholds: &AspectThresholds,
    _earlier: &[AspectResult],
    map: &mut [u8],
) -> AspectResult {
    let mut counts = Counts::default();
    if let Some(light) = &e.light {
        for &object in &e.plain {
            if let Some(a) = light.intercept(object) {
                judge_object(e, light, (object, a), &mut counts, map);
            }
        }
    }
    let Counts {
        shadowed,
        shadowed_bad,
        lit,
        lit_bad,
        partly,
        partly_bad,
        alike,
    } = counts;
    let missing = ratio(shadowed_bad, shadowed);
    let spurious = ratio(lit_bad, lit);
    let darkened = ratio(partly_bad, partly);
    let measure = if shadowed >= 20 { missing } else { 0.0 }
        .max(if lit >= 20 { spurious } else { 0.0 })
        .max(if partly >= 20 { darkened } else { 0.0 });
    let judged = shadowed >= 20 || lit >= 20;
    let parts: Vec<String> = [
        (shadowed >= 20)
            .then(|| fraction_words(shadowed_bad, shadowed, "shadowed pixels look lit"))
            .flatten(),
        (lit >= 20)
            .then(|| fraction_words(lit_bad, lit, "fully lit pixels look shadowed"))
            .flatten(),
        (partly >= 20)
            .then(|| {
                fraction_words(
                    partly_bad,
                    partly,
                    "shadowed pixels another light reaches look shadowed from it too",
                )
            })
            .flatten(),
    ]
    .into_iter()
    .flatten()
    .collect();
    let detail = if judged {
        let mut words = parts.join("; ");
        if alike > 0 && measure > thresholds.shadows {
            words.push_str(&format!(
                "; on {alike} object{}, yours looks the same where ours is lit and where it is shadowed: no shadow falls there, or no light reaches it",
                if alike == 1 { "" } else { "s" }
            ));
        }
        if let Some(falloff) = e.light.as_ref().and_then(|l| l.falloff.words()) {
            words.push_str(&format!(" (your image read with {falloff})"));
        }
        words
    } else if e.plain.is_empty() {
        "no object that neither reflects nor is textured, where shadows are judged".to_string()
    } else {
        format!(
            "only {shadowed} shadowed and {lit} fully lit pixels on objects that neither reflect nor are textured (20 of either needed)"
        )
    };
    verdict(
        Aspect::Shadows,
        judged,
        measure,
        thresholds.shadows,
        shadowed + lit,
        detail,
    )
}

#[cfg(test)]
mod tests {
    use super::unseen_unlit_level;

    #[test]
    fn an_unseen_unlit_level_is_where_the_points_another_light_reaches_meet_no_light() {
        // Those points at an unlit level of 0.05: flat where a tracer
        // drops every light, rising with the light where it lights them.
        let rows = |gain: f64| -> Vec<([f64; 1], f64)> {
            (0..40)
                .map(|i| {
                    let light = 0.2 + 0.005 * f64::from(i);
                    ([light], 0.05 + gain * light)
                })
                .collect()
        };
        for gain in [0.0, 0.6] {
            let level = unseen_unlit_level(&rows(gain)).unwrap();
            assert!((level - 0.05).abs() < 1e-4, "{gain}: {level}");
        }
        assert_eq!(unseen_unlit_level(&rows(0.6)[..19]), None);
    }
}
