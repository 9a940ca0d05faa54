//! Shading: the colours of lit objects, by the median chromaticity of
//! each lit plain object against ours (brightness is the tracer's to
//! choose, the hue the lights' and the object's colours give is not),
//! away from highlights and clamped channels.

use super::evidence::{chroma, clipped, Evidence};
use super::{verdict, Aspect, AspectResult, AspectThresholds};

/// Judge shading, marking `map`.
pub(super) fn judge(e: &Evidence, thresholds: &AspectThresholds, map: &mut [u8]) -> AspectResult {
    let (mut worst, mut shaded) = (0.0f64, 0usize);
    for &object in &e.plain {
        let ks: Vec<usize> = e
            .pixels_of(object, &|p| p.visible)
            .into_iter()
            .filter(|&k| {
                let p = &e.buffers.centres[k];
                p.lit > 0.05
                    && p.highlight < 0.9
                    && !clipped(&e.student_px(k))
                    && chroma(&e.student_px(k)).is_some()
                    && chroma(&e.px(e.reference, k)).is_some()
            })
            .collect();
        if ks.len() < 20 {
            continue;
        }
        let median = |pic, c: usize| {
            let mut v: Vec<f64> = ks
                .iter()
                .filter_map(|&k| chroma(&e.px(pic, k)))
                .map(|v| v[c])
                .collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let distance = (0..3)
            .map(|c| (median(e.reference, c) - median(e.student, c)).abs())
            .sum::<f64>();
        worst = worst.max(distance);
        shaded += ks.len();
        for &k in &ks {
            map[k] = 1 + u8::from(distance > thresholds.shading);
        }
    }
    verdict(
        Aspect::Shading,
        shaded > 0,
        worst,
        thresholds.shading,
        shaded,
        format!("the colour of lit objects is {worst:.3} from ours (chromaticity)"),
    )
}
