//! Shadows: which lit points are shadowed, on objects that neither
//! reflect nor are textured. The student's brightness (in linear light,
//! [`super::tone`]) is fitted per object as `a + b·lit` on the pixels no shadow and no highlight touch;
//! a pixel ours shadows that is as bright as the fit says it would be
//! unshadowed looks lit, and a fully lit pixel darker by half its light
//! looks shadowed.

use super::evidence::{clipped, Evidence, Whose};
use super::fit::robust_fit;
use super::{fraction_words, ratio, verdict, Aspect, AspectResult, AspectThresholds};

/// Judge shadows, marking `map`.
pub(super) fn judge(e: &Evidence, thresholds: &AspectThresholds, map: &mut [u8]) -> AspectResult {
    let (mut shadowed, mut shadowed_bad, mut lit, mut lit_bad) = (0usize, 0usize, 0usize, 0usize);
    for &object in &e.plain {
        let ks: Vec<usize> = e
            .pixels_of(object, &|p| p.visible)
            .into_iter()
            .filter(|&k| !clipped(&e.student_px(k)))
            .collect();
        let rows: Vec<([f64; 1], f64)> = ks
            .iter()
            .filter(|&&k| {
                let p = &e.buffers.centres[k];
                // Not where a specular highlight may brighten it.
                p.unshadowed - p.lit < 1e-9 && p.highlight < 0.8
            })
            .map(|&k| ([e.buffers.centres[k].lit], e.luminance(Whose::Theirs, k)))
            .collect();
        let Some(beta) = robust_fit(&rows) else {
            continue;
        };
        let (a, b) = (beta[0], beta[1].max(0.05));
        for &k in &ks {
            let probe = &e.buffers.centres[k];
            let s = e.luminance(Whose::Theirs, k);
            let r = s - (a + b * probe.lit);
            let blocked = probe.unshadowed - probe.lit;
            if blocked > 0.05 {
                shadowed += 1;
                let bad = r > 0.5 * b * blocked && r > 4.0 / 255.0;
                shadowed_bad += usize::from(bad);
                map[k] = 1 + u8::from(bad);
            } else if blocked < 1e-9 && probe.lit > 0.05 {
                lit += 1;
                let bad = r < -0.5 * b * probe.lit && r < -4.0 / 255.0;
                lit_bad += usize::from(bad);
                map[k] = 1 + u8::from(bad);
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
        parts.join("; ")
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
