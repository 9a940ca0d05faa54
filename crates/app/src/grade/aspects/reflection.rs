//! Reflection: what mirrors show, on mirrors without a texture. The
//! student's brightness is fitted per mirror as `a + b·lit + c·(what ours
//! sees in the mirror)`; a pixel the fit does not explain differs, and a
//! mirror whose gain `c` on what ours shows is below a share of its
//! reflectivity does not show it at all. What a mirror shows of a texture
//! (the mapping is open) or of another mirror (added or blended) is not
//! judged, nor where a highlight may brighten it.

use super::evidence::{clipped, luminance, Evidence, HIGHLIGHT_CONE};
use super::fit::{predict, robust_fit, spread};
use super::{ratio, verdict, Aspect, AspectResult, AspectThresholds};

/// Judge reflection, marking `map`.
pub(super) fn judge(e: &Evidence, thresholds: &AspectThresholds, map: &mut [u8]) -> AspectResult {
    let (mut showing, mut mirror_bad, mut mirror_judged) = (0usize, 0usize, 0usize);
    let mut weakest_gain = f64::INFINITY;
    for &object in &e.objects {
        let first = e.first_probe(object);
        if first.reflectivity == 0.0 || first.uv.is_some() {
            continue;
        }
        let ks: Vec<usize> = e
            .pixels_of(object, &|p| {
                p.visible ^ (u64::from(p.reflected.map_or(u32::MAX, |r| r)) << 32)
            })
            .into_iter()
            .filter(|&k| {
                let p = &e.buffers.centres[k];
                let indirect = p.reflected.is_some_and(|r| {
                    e.buffers.textured.get(r as usize) == Some(&true)
                        || e.buffers.reflective.get(r as usize) == Some(&true)
                });
                !clipped(&e.student_px(k)) && p.highlight < 0.95 && !indirect
            })
            .collect();
        let rows: Vec<([f64; 2], f64)> = ks
            .iter()
            .map(|&k| {
                let p = &e.buffers.centres[k];
                ([p.lit, p.reflected_radiance], luminance(&e.student_px(k)))
            })
            .collect();
        let Some(beta) = robust_fit(&rows) else {
            continue;
        };
        // Whether the student's mirror shows what ours shows at all: the
        // fit's gain on it against the mirror's reflectivity, told only
        // where what ours shows varies enough over the mirror to tell a
        // gain from the intercept.
        let shown: Vec<f64> = rows.iter().map(|(x, _)| x[1]).collect();
        let gain = (spread(&shown) >= 0.03).then(|| beta[2] / first.reflectivity);
        if let Some(gain) = gain {
            weakest_gain = weakest_gain.min(gain);
        }
        let missing = gain.is_some_and(|g| g < thresholds.reflection_gain);
        for (&k, (x, s)) in ks.iter().zip(&rows) {
            let r = s - predict(&beta, x);
            // A highlight only brightens: not a reflection's error.
            let highlight = r > 0.0 && e.buffers.centres[k].highlight > HIGHLIGHT_CONE;
            let shows = x[1] > 0.03;
            let bad = (r.abs() > 0.06 && !highlight) || (missing && shows);
            showing += usize::from(shows);
            mirror_judged += 1;
            mirror_bad += usize::from(bad);
            map[k] = 1 + u8::from(bad);
        }
    }
    let measure = ratio(mirror_bad, showing).min(1.0);
    verdict(
        Aspect::Reflection,
        showing >= 20,
        measure,
        thresholds.reflection,
        mirror_judged,
        format!(
            "{mirror_bad} of {mirror_judged} mirror pixels are not what ours shows, against {showing} that show something ({:.1} %){}",
            100.0 * measure,
            if weakest_gain.is_finite() {
                format!(
                    "; the mirror shows {:.0} % of what ours shows (at least {:.0} %)",
                    100.0 * weakest_gain,
                    100.0 * thresholds.reflection_gain
                )
            } else {
                String::new()
            }
        ),
    )
}
