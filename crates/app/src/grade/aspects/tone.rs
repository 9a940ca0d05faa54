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
//! light that reaches the point, and on a mirror the colour and light of
//! what it shows), and the `γ` whose fits leave the least
//! root-mean-square share of the image's spread unexplained (residuals
//! taken back to 8-bit values, where every curve rounds alike) wins. It
//! is kept only when it leaves less than nine tenths of what 1 leaves
//! ([`KEEP_CLAMPING`]): on a scene with little light to tell, every curve
//! fits about as well, and the image is then read as written.

use super::fit::{predict, robust_fit};

/// The exponents tried: from 0.8 to 3 in steps of 0.05, which covers
/// clamping (1), the screen gammas of 1.8 to 2.4, and a square root (2).
fn candidates() -> impl Iterator<Item = f64> {
    (16..=60).map(|k| f64::from(k) * 0.05)
}

/// The share of what clamping alone (`γ` = 1) leaves unexplained that
/// another curve must leave less than to be read into the image: a
/// curve's gain over clamping is small where the light varies little
/// (tests/students/tune's gamma 2.2 left 0.77 of what 1 leaves on
/// field/texture.scene, whose only lit object is a mirror), and its
/// correct readings' best curves left 0.94 and more.
const KEEP_CLAMPING: f64 = 0.9;

/// The darkest linear luminance at which a curve's slope is taken: below
/// it (the first few 8-bit steps), a steep curve's slope would count a
/// rounding as a large error.
const DARKEST: f64 = 0.0001;

/// The luminance of a colour in linear light, each channel in [0, 1].
pub(super) fn luminance_of(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// One pixel that tells the curve: the student's 8-bit colour there, and
/// what ours sees (the light that reaches the point, and on a mirror the
/// colour and the light of what it shows, [`Probe::shown`]).
///
/// [`Probe::shown`]: raytracer_render::render::probe::Probe::shown
pub(super) type Row = ([u8; 3], [f64; 3]);

/// The fitted `γ` of the student's image from the rows of each object
/// that tells, by kind ([`super::evidence::Evidence::tone_rows`]): the
/// plain objects' alone when they tell a screen's curve from clamping
/// (a mirror's brightness also holds what it shows, which a bug of the
/// tracer's reflection changes), else with the mirrors', else the
/// textured objects'; 1 when none tells.
pub(super) fn fit_gamma(plain: &[Vec<Row>], mirrors: &[Vec<Row>], textured: &[Vec<Row>]) -> Fitted {
    let alone = scores(plain);
    if tells(&alone) {
        return decide(&alone);
    }
    let lit: Vec<Vec<Row>> = plain.iter().chain(mirrors).cloned().collect();
    if lit.is_empty() {
        decide(&scores(textured))
    } else {
        decide(&scores(&lit))
    }
}

/// Whether `scored` tells clamping alone (`γ` = 1) from a screen's
/// curve (`γ` = 2.2): one leaves less than [`KEEP_CLAMPING`] of what the
/// other leaves.
fn tells(scored: &[(f64, f64)]) -> bool {
    match (score_at(scored, 1.0), score_at(scored, 2.2)) {
        (Some(a), Some(b)) => a.min(b) < KEEP_CLAMPING * a.max(b),
        _ => false,
    }
}

/// The unexplained share `scored` gives `gamma`, when it was scored.
fn score_at(scored: &[(f64, f64)], gamma: f64) -> Option<f64> {
    scored
        .iter()
        .find(|(g, _)| (g - gamma).abs() < 1e-9)
        .map(|s| s.1)
}

/// Each candidate `γ` with the share of the image's spread the fits of
/// `objects` leave unexplained under it.
fn scores(objects: &[Vec<Row>]) -> Vec<(f64, f64)> {
    let unexplained = |gamma: f64| -> Option<f64> {
        let (mut residuals, mut spreads) = (Vec::new(), Vec::new());
        for group in objects {
            let rows: Vec<([f64; 3], f64)> = group
                .iter()
                .map(|&(p, x)| {
                    let v = p.map(|c| (f64::from(c) / 255.0).powf(gamma));
                    (x, luminance_of(v))
                })
                .collect();
            let beta = robust_fit(&rows)?;
            // Each residual taken back to the student's 8-bit scale (over
            // the curve's slope there), where every curve's rounding is
            // the same; and each value as written from its object's median.
            residuals.extend(rows.iter().map(|(x, y)| {
                let slope = gamma * y.max(DARKEST).powf((gamma - 1.0) / gamma);
                ((y - predict(&beta, x)) / slope).abs()
            }));
            let written: Vec<f64> = group
                .iter()
                .map(|(p, _)| luminance_of(p.map(|c| f64::from(c) / 255.0)))
                .collect();
            let mean = written.iter().sum::<f64>() / written.len() as f64;
            spreads.extend(written.iter().map(|w| (w - mean).abs()));
        }
        // The root mean square residual over the values' spread: the
        // share of the image's spread the curve and lines leave.
        let spread = root_mean_square(&spreads);
        (spread > 0.0).then(|| root_mean_square(&residuals) / spread)
    };
    candidates()
        .filter_map(|g| unexplained(g).map(|u| (g, u)))
        .collect()
}

/// The curve `scored` chooses: the best, unless clamping alone leaves
/// less than [`KEEP_CLAMPING`] more.
fn decide(scored: &[(f64, f64)]) -> Fitted {
    let Some(&(best_gamma, best)) = scored.iter().min_by(|a, b| a.1.total_cmp(&b.1)) else {
        return Fitted {
            gamma: 1.0,
            unexplained: None,
        };
    };
    let gamma = match score_at(scored, 1.0) {
        Some(u) if best >= KEEP_CLAMPING * u => 1.0,
        _ => best_gamma,
    };
    Fitted {
        gamma,
        unexplained: Some(best),
    }
}

/// The fitted curve, and the least share of the image's spread a curve
/// leaves unexplained: how well what ours sees explains the image at all.
pub(super) struct Fitted {
    pub gamma: f64,
    pub unexplained: Option<f64>,
}

/// The root mean square of `values`; 0 for none.
fn root_mean_square(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    (values.iter().map(|v| v * v).sum::<f64>() / values.len() as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::{fit_gamma, Row};

    /// An object whose light runs from 0.05 to 0.85, written through the
    /// curve `v = x^(1/γ)` after `0.05 + 0.8·x`.
    fn object(gamma: f64) -> Vec<Row> {
        (0..200)
            .map(|i| {
                let lit = 0.05 + 0.8 * f64::from(i) / 200.0;
                let x = 0.05 + 0.8 * lit;
                let v = (255.0 * x.powf(1.0 / gamma)).round() as u8;
                ([v, v, v], [lit, 0.0, 0.0])
            })
            .collect()
    }

    #[test]
    fn a_screen_gamma_is_read_and_clamping_alone_is_kept() {
        let screen = fit_gamma(&[object(2.2)], &[], &[]);
        assert!((screen.gamma - 2.2).abs() <= 0.1, "{}", screen.gamma);
        assert_eq!(fit_gamma(&[object(1.0)], &[], &[]).gamma, 1.0);
    }

    #[test]
    fn plain_objects_that_tell_outvote_a_mirror() {
        // A mirror whose brightness bends (a bug of what it shows, say)
        // does not move the curve the plain objects tell.
        let fitted = fit_gamma(&[object(1.0)], &[object(2.2), object(2.2)], &[]);
        assert_eq!(fitted.gamma, 1.0);
        // With no plain object, the mirrors tell it.
        let fitted = fit_gamma(&[], &[object(2.2)], &[]);
        assert!((fitted.gamma - 2.2).abs() <= 0.1, "{}", fitted.gamma);
    }
}
