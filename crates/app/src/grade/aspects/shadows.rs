//! Shadows: which lit points are shadowed, on objects that neither
//! reflect nor are textured, against the scene's fit of the student's
//! light ([`super::falloff`]): brightness in linear light
//! ([`super::tone`]) as `a + b·lit` on the pixels no shadow and no
//! highlight touch, an intercept `a` per object, one gain `b` for the
//! scene, and `lit` each light's share dimmed by the student's falloff
//! with distance. A pixel ours shadows that is as bright as the fit says
//! it would be unshadowed looks lit, and a fully lit pixel darker by half
//! its light looks shadowed.

use super::evidence::{clipped, Evidence, Whose};
use super::{fraction_words, ratio, verdict, Aspect, AspectResult, AspectThresholds};

/// Judge shadows, marking `map`.
pub(super) fn judge(e: &Evidence, thresholds: &AspectThresholds, map: &mut [u8]) -> AspectResult {
    let (mut shadowed, mut shadowed_bad, mut lit, mut lit_bad) = (0usize, 0usize, 0usize, 0usize);
    if let Some(light) = &e.light {
        let b = light.least_gain();
        for &object in &e.plain {
            let Some(a) = light.intercept(object) else {
                continue;
            };
            let ks = e
                .pixels_of(object, &|p| p.visible)
                .into_iter()
                .filter(|&k| !clipped(&e.student_px(k)));
            for k in ks {
                let probe = &e.buffers.centres[k];
                let s = e.luminance(Whose::Theirs, k);
                let lit_here = light.falloff.lit(probe);
                let r = s - (a + b * lit_here);
                let blocked = probe.unshadowed - probe.lit;
                if blocked > 0.05 {
                    shadowed += 1;
                    let taken = light.falloff.unshadowed(probe) - lit_here;
                    let bad = r > 0.5 * b * taken && r > 4.0 / 255.0;
                    shadowed_bad += usize::from(bad);
                    map[k] = 1 + u8::from(bad);
                } else if blocked < 1e-9 && probe.lit > 0.05 {
                    lit += 1;
                    let bad = light.looks_shadowed(object, probe, s) == Some(true);
                    lit_bad += usize::from(bad);
                    map[k] = 1 + u8::from(bad);
                }
            }
        }
    }
    let missing = ratio(shadowed_bad, shadowed);
    let spurious = ratio(lit_bad, lit);
    let measure =
        if shadowed >= 20 { missing } else { 0.0 }.max(if lit >= 20 { spurious } else { 0.0 });
    let judged = shadowed >= 20 || lit >= 20;
    let parts: Vec<String> = [
        (shadowed >= 20)
            .then(|| fraction_words(shadowed_bad, shadowed, "shadowed pixels look lit"))
            .flatten(),
        (lit >= 20)
            .then(|| fraction_words(lit_bad, lit, "fully lit pixels look shadowed"))
            .flatten(),
    ]
    .into_iter()
    .flatten()
    .collect();
    let detail = if judged {
        let mut words = parts.join("; ");
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
