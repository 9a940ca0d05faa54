//! The three measures of a comparison, each on its own: ꟻLIP (NVIDIA's
//! perceptual error for rendered images, computed by its reference code
//! through `nv-flip`), RMSE with PSNR, and coverage, the intersection over
//! union of the pixels that show something: the reference's non-black
//! ones, and the candidate's that differ from its own background colour.

use schemars::JsonSchema;
use serde::Serialize;

use super::Picture;

/// The ꟻLIP error over the pixels of an image, each in `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, JsonSchema)]
pub struct FlipStats {
    pub mean: f32,
    pub median: f32,
    /// 90th percentile.
    pub p90: f32,
    /// 99th percentile.
    pub p99: f32,
    pub max: f32,
}

/// What [`measure`] finds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, JsonSchema)]
pub struct Metrics {
    pub flip: FlipStats,
    /// Root mean square error over every channel, on the `[0, 1]` scale.
    pub rmse: f64,
    /// Peak signal-to-noise ratio in dB; `null` for identical images.
    pub psnr: Option<f64>,
    /// Intersection over union of the non-black masks (1 when both are
    /// wholly black).
    pub coverage_iou: f64,
}

/// Measure `candidate` against `reference` (of the same size), with pixels
/// whose channels are all at most `black_level` counted as black. Returns
/// the metrics and the ꟻLIP error of each pixel.
pub fn measure(reference: &Picture, candidate: &Picture, black_level: u8) -> (Metrics, Vec<f32>) {
    debug_assert_eq!(reference.size(), candidate.size());
    let error_map = flip_map(reference, candidate);
    let rmse = rmse(&reference.rgb, &candidate.rgb);
    let metrics = Metrics {
        flip: flip_stats(&error_map),
        rmse,
        psnr: (rmse > 0.0).then(|| -20.0 * rmse.log10()),
        coverage_iou: coverage_iou(&reference.rgb, &candidate.rgb, black_level),
    };
    (metrics, error_map)
}

/// The ꟻLIP error map at the default viewing conditions (67 pixels per
/// degree: a 0.7 m wide 4K monitor seen from 0.7 m).
fn flip_map(reference: &Picture, candidate: &Picture) -> Vec<f32> {
    let image = |p: &Picture| nv_flip::FlipImageRgb8::with_data(p.width, p.height, &p.rgb);
    nv_flip::flip(
        image(reference),
        image(candidate),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    )
    .to_vec()
}

/// Mean, percentiles (nearest rank) and maximum of the error map.
fn flip_stats(errors: &[f32]) -> FlipStats {
    let mut sorted = errors.to_vec();
    sorted.sort_by(f32::total_cmp);
    let rank = |q: f64| {
        let index = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len()) - 1;
        sorted[index]
    };
    let sum: f64 = errors.iter().map(|&e| f64::from(e)).sum();
    FlipStats {
        mean: (sum / errors.len() as f64) as f32,
        median: rank(0.5),
        p90: rank(0.9),
        p99: rank(0.99),
        max: sorted[sorted.len() - 1],
    }
}

/// RMSE of two equally long channel arrays, on the `[0, 1]` scale.
fn rmse(a: &[u8], b: &[u8]) -> f64 {
    let squares: f64 = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| (f64::from(x) - f64::from(y)).powi(2))
        .sum();
    (squares / a.len() as f64).sqrt() / 255.0
}

/// Intersection over union of the pixels that show something in `a` (the
/// reference, on black) and in `b` (the candidate, on a background of its
/// own): a pixel of `b` shows something when it is more than
/// `black_level` from `b`'s background, its commonest colour where `a` is
/// black. A background colour is the candidate's choice, not
/// a difference in what the pixels see.
fn coverage_iou(a: &[u8], b: &[u8], black_level: u8) -> f64 {
    let lit = |p: &[u8]| p.iter().any(|&c| c > black_level);
    let background: [u8; 3] = {
        let mut counts = std::collections::HashMap::<[u8; 3], u64>::new();
        for (pa, pb) in a.chunks_exact(3).zip(b.chunks_exact(3)) {
            if !lit(pa) {
                *counts.entry([pb[0], pb[1], pb[2]]).or_default() += 1;
            }
        }
        // The commonest colour; of equals, the darkest.
        counts
            .into_iter()
            .max_by_key(|&(p, n)| {
                (
                    n,
                    std::cmp::Reverse(p.iter().map(|&c| u32::from(c)).sum::<u32>()),
                    std::cmp::Reverse(p),
                )
            })
            .map_or([0; 3], |(p, _)| p)
    };
    let shows = |p: &[u8]| (0..3).any(|c| p[c].abs_diff(background[c]) > black_level);
    let (mut both, mut either) = (0u64, 0u64);
    for (pa, pb) in a.chunks_exact(3).zip(b.chunks_exact(3)) {
        let (la, lb) = (lit(pa), shows(pb));
        both += u64::from(la && lb);
        either += u64::from(la || lb);
    }
    if either == 0 {
        1.0
    } else {
        both as f64 / either as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn picture(width: u32, height: u32, rgb: impl Fn(u32, u32) -> [u8; 3]) -> Picture {
        let rgb = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .flat_map(|(x, y)| rgb(x, y))
            .collect();
        Picture { width, height, rgb }
    }

    #[test]
    fn identical_images_have_no_error_and_full_coverage() {
        let a = picture(32, 32, |x, y| [(x * 8) as u8, (y * 8) as u8, 40]);
        let (m, map) = measure(&a, &a, 2);
        assert_eq!(map.len(), 32 * 32);
        assert_eq!(m.flip.max, 0.0);
        assert_eq!(m.rmse, 0.0);
        assert_eq!(m.psnr, None);
        assert_eq!(m.coverage_iou, 1.0);
    }

    #[test]
    fn coverage_counts_lit_pixels_of_either_image() {
        // Left half lit in one, left three quarters in the other: IoU 2/3.
        let a = picture(8, 1, |x, _| if x < 4 { [200, 0, 0] } else { [0, 0, 0] });
        let b = picture(8, 1, |x, _| if x < 6 { [0, 9, 0] } else { [2, 2, 2] });
        assert!((coverage_iou(&a.rgb, &b.rgb, 2) - 2.0 / 3.0).abs() < 1e-12);
        assert_eq!(coverage_iou(&[0; 6], &[1; 6], 2), 1.0);
    }

    #[test]
    fn a_background_of_the_candidates_own_is_no_coverage_difference() {
        let a = picture(8, 8, |x, _| if x < 4 { [200, 90, 40] } else { [0, 0, 0] });
        let b = picture(8, 8, |x, _| if x < 4 { [200, 90, 40] } else { [6, 6, 6] });
        assert_eq!(coverage_iou(&a.rgb, &b.rgb, 2), 1.0);
    }

    #[test]
    fn rmse_and_psnr_of_a_constant_offset() {
        let a = picture(4, 4, |_, _| [100, 100, 100]);
        let b = picture(4, 4, |_, _| [151, 151, 151]);
        let (m, _) = measure(&a, &b, 2);
        assert!((m.rmse - 0.2).abs() < 1e-12);
        assert!((m.psnr.unwrap() - 13.979_400_086_720_377).abs() < 1e-9);
    }

    #[test]
    fn percentiles_are_nearest_rank() {
        let errors: Vec<f32> = (1..=100).map(|i| i as f32 / 100.0).collect();
        let s = flip_stats(&errors);
        assert_eq!((s.median, s.p90, s.p99, s.max), (0.5, 0.9, 0.99, 1.0));
        assert!((s.mean - 0.505).abs() < 1e-6);
    }
}
