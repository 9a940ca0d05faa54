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

/// The luminance of a colour in linear light, each channel in [0, 1].
pub(super) fn luminance_of(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// One pixel that tells the curve: the student's 8-bit colour there, and
/// what ours sees (the light that reaches the point, and on a mirror what
/// it shows).
pub(super) type Row = ([u8; 3], [f64; 2]);

/// The fitted `γ` of the student's image from the rows of each object
/// that tells ([`super::evidence::Evidence::tone_rows`]); 1 when none
/// does.
pub(super) fn fit_gamma(objects: &[Vec<Row>]) -> f64 {
    if objects.is_empty() {
        return 1.0;
    }
    let unexplained = |gamma: f64| -> Option<f64> {
        let (mut residual, mut total) = (0.0, 0.0);
        for group in objects {
            let rows: Vec<([f64; 2], f64)> = group
                .iter()
                .map(|&(p, x)| {
                    let v = p.map(|c| (f64::from(c) / 255.0).powf(gamma));
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
