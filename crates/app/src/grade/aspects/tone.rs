//! The student's tone curve: how their tracer turns light into 8-bit
//! values (clamping alone, a gamma for the screen, an exposure), which
//! the assignment leaves open. One curve `v = x^(1/γ)` (an exposure's
//! scale is any fit's gain) shared by the three channels is fitted, and
//! every aspect but geometry reads the student's image turned back to
//! linear light, `x = v^γ`, so a gamma changes neither a colour nor a
//! shadow. One curve for all channels: a per-channel fit would turn an
//! ignored light colour back into the right one.
//!
//! The curve is chosen by what it does to shapes, never to colours: on
//! each object that tells (plain objects and mirrors, by their pixels no
//! shadow, highlight lobe or clamping touches), the student's linearised
//! luminance must be a straight function of what ours sees there (the
//! light that reaches the point, and on a mirror what it shows), and the
//! `γ` whose fits leave the least root-mean-square share of the
//! luminance's spread unexplained wins. A `γ` other than 1 is kept only
//! when it leaves at most half of what 1 leaves ([`CLOSE`]): on a scene
//! with little light to tell, every curve fits about as well, and the
//! image is then read as written.

use super::evidence::{clipped, luminance_of, Evidence, HIGHLIGHT_CONE};
use super::fit::{predict, robust_fit};

/// The exponents tried: from 0.8 to 3 in steps of 0.05, which covers
/// clamping (1), the screen gammas of 1.8 to 2.4, and a square root (2).
fn candidates() -> impl Iterator<Item = f64> {
    (16..=60).map(|k| f64::from(k) * 0.05)
}

/// How much more than the least unexplained share a `γ` may leave and
/// still count as no worse: the curve nearest 1 among those is taken, so
/// another curve must explain the image twice as well as clamping alone.
const CLOSE: f64 = 1.0;

/// The pixels of each object that tell the curve, with what ours sees
/// there: its unshadowed pixels away from highlights (out of the
/// cone where any highlight lobe may lie) and clamping,
/// on plain objects and mirrors (whose reflection ours settles, and not
/// of a texture); textured objects only when no other object tells, as
/// what they show depends on the mapping.
fn groups(e: &Evidence) -> Vec<Vec<(usize, [f64; 2])>> {
    let rows = |object: u32, textured: bool| -> Vec<(usize, [f64; 2])> {
        e.pixels_of(object, &|p| {
            p.visible ^ (u64::from(p.reflected.map_or(u32::MAX, |r| r)) << 32)
        })
        .into_iter()
        .filter(|&k| {
            let p = &e.buffers.centres[k];
            let settled = p.reflectivity == 0.0
                || (p.reflection_settled
                    && p.reflected
                        .is_none_or(|r| e.buffers.textured.get(r as usize) != Some(&true)));
            p.unshadowed - p.lit < 1e-9
                && p.highlight <= HIGHLIGHT_CONE
                && settled
                && p.uv.is_some() == textured
                && !clipped(&e.student_px(k))
        })
        .map(|k| {
            let p = &e.buffers.centres[k];
            (k, [p.lit, p.reflected_radiance])
        })
        .collect()
    };
    let enough = |g: &Vec<(usize, [f64; 2])>| g.len() >= 30;
    let untextured: Vec<_> = e
        .objects
        .iter()
        .map(|&o| rows(o, false))
        .filter(enough)
        .collect();
    if !untextured.is_empty() {
        return untextured;
    }
    e.objects
        .iter()
        .map(|&o| rows(o, true))
        .filter(enough)
        .collect()
}

/// The fitted `γ` of the student's image, 1 when no object tells.
pub(super) fn fit_gamma(e: &Evidence) -> f64 {
    let objects = groups(e);
    if objects.is_empty() {
        return 1.0;
    }
    let unexplained = |gamma: f64| -> Option<f64> {
        let (mut residual, mut total) = (0.0, 0.0);
        for group in &objects {
            let rows: Vec<([f64; 2], f64)> = group
                .iter()
                .map(|&(k, x)| {
                    let v = e.student_px(k).map(|c| (f64::from(c) / 255.0).powf(gamma));
                    (x, luminance_of(v))
                })
                .collect();
            let beta = robust_fit(&rows)?;
            // The root mean square residual over the rows' spread: the
            // share of the luminance's spread the line leaves.
            let n = rows.len() as f64;
            let mean = rows.iter().map(|r| r.1).sum::<f64>() / n;
            residual += rows
                .iter()
                .map(|(x, y)| (y - predict(&beta, x)).powi(2))
                .sum::<f64>();
            total += rows.iter().map(|r| (r.1 - mean).powi(2)).sum::<f64>();
        }
        (total > 0.0).then(|| (residual / total).sqrt())
    };
    let scored: Vec<(f64, f64)> = candidates()
        .filter_map(|g| unexplained(g).map(|u| (g, u)))
        .collect();
    let Some(best) = scored.iter().map(|s| s.1).min_by(f64::total_cmp) else {
        return 1.0;
    };
    scored
        .iter()
        .filter(|(_, u)| *u <= best + CLOSE * best.max(0.01))
        .map(|(g, _)| *g)
        .min_by(|a, b| (a - 1.0).abs().total_cmp(&(b - 1.0).abs()))
        .unwrap_or(1.0)
}
