//! Geometry: the camera and the intersections, judged by which pixels
//! show an object. Background where ours sees nothing, an object where
//! ours sees a lit one; the student's background is theirs to choose: a
//! colour, or a sky that changes with the ray's direction
//! ([`Background`]). Only pixels stable for the object they see are
//! judged, so rays through pixel centres or corners both pass; which of
//! the two the image fits is told as the image's pixel reading.

use super::evidence::Evidence;
use super::fit::{predict, robust_fit};
use super::{ratio, verdict, Aspect, AspectResult, AspectThresholds};
use raytracer_render::render::probe::Probe;

/// How far a channel may be from the background colour and still be
/// background.
const BACKGROUND_TOLERANCE: u8 = 6;

/// Whether ours surely shows an object at a probe (`Some(true)`), surely
/// shows nothing (`Some(false)`), or shows too dark an object to tell.
/// A mirror counts by its own light alone, at its weight when blended,
/// `1 − k`, the least either reading gives it: what it shows is
/// reflection's to judge, so a mirror that shows the wrong thing (or, in
/// a tracer that does not recurse, a black mirror's own black) costs
/// reflection, not geometry.
fn expect(probe: &Probe) -> Option<bool> {
    match probe.object {
        None => Some(false),
        Some(_) if (1.0 - probe.reflectivity) * probe.lit > 0.01 => Some(true),
        Some(_) => None,
    }
}

/// Whether the student's background is black, as far as the image tells
/// (`false` when no pixel surely sees nothing).
pub(super) fn black_background(e: &Evidence) -> bool {
    let background = Background::of(e);
    !background.fitted.is_empty()
        && background
            .fitted
            .iter()
            .all(|&k| (0..3).all(|c| background.at(e, k)[c] <= f64::from(BACKGROUND_TOLERANCE)))
}

/// The student's background: per channel, a quadratic in the pixel's
/// place on the image with a cubic in its squared distance from the
/// image's centre ([`place`]), fitted robustly on the pixels that surely
/// see nothing (the fit keeps out an object drawn where ours sees none).
/// The assignment names no background: a colour fits it (the terms are
/// then flat), and so does a sky graded by the ray's direction, smooth
/// over a camera's field of view, or a background that changes with the
/// angle from the view's axis alone. Black where no pixel surely sees
/// nothing.
struct Background {
    /// Per channel, the fit's intercept and the gains of [`place`]'s
    /// terms (a channel runs from 0 to 1).
    channels: [Vec<f64>; 3],
    /// The pixels it was fitted on: those that surely see nothing.
    fitted: Vec<usize>,
}

/// Pixel `k`'s terms in [`Background`]'s fit: its place on the image
/// plane (from −½ to ½ across), their squares and product, and the
/// square and cube of its squared distance `s` from the centre. A
/// direction's angle from the view's axis is a function of `s` alone,
/// and a smooth step of it over the view (a radial gradient that
/// flattens at the centre and the corners) takes powers of `s` up to the
/// third to follow within a background pixel's tolerance.
fn place(e: &Evidence, k: usize) -> [f64; 7] {
    let (x, y) = e.xy(k);
    let size = f64::from(e.size);
    let u = (f64::from(x) + 0.5) / size - 0.5;
    let v = (f64::from(y) + 0.5) / size - 0.5;
    let s = u * u + v * v;
    [u, v, u * u, u * v, v * v, s * s, s * s * s]
}

impl Background {
    fn of(e: &Evidence) -> Self {
        let fitted: Vec<usize> = (0..e.n)
            .filter(|&k| {
                let (x, y) = e.xy(k);
                e.buffers.centre(x, y).object.is_none() && e.buffers.stable(x, y, |p| p.object)
            })
            .collect();
        let channels = [0, 1, 2].map(|c| {
            let rows: Vec<([f64; 7], f64)> = fitted
                .iter()
                .map(|&k| (place(e, k), f64::from(e.student_px(k)[c]) / 255.0))
                .collect();
            robust_fit(&rows).unwrap_or_else(|| {
                // Too few pixels for the fit: their median.
                let mut values: Vec<f64> = rows.iter().map(|r| r.1).collect();
                values.sort_unstable_by(f64::total_cmp);
                let median = values.get(values.len() / 2).copied().unwrap_or(0.0);
                let mut flat = vec![0.0; 8];
                flat[0] = median;
                flat
            })
        });
        Background { channels, fitted }
    }

    /// The background's colour at pixel `k`, in 8-bit steps.
    fn at(&self, e: &Evidence, k: usize) -> [f64; 3] {
        let terms = place(e, k);
        [0, 1, 2].map(|c| 255.0 * predict(&self.channels[c], &terms))
    }

    /// Whether pixel `k` of the student's image is not the background.
    fn covered(&self, e: &Evidence, k: usize) -> bool {
        let p = e.student_px(k);
        let bg = self.at(e, k);
        (0..3).any(|c| (f64::from(p[c]) - bg[c]).abs() > f64::from(BACKGROUND_TOLERANCE))
    }
}

/// Whether ours surely shows an object at pixel `k`'s centre and corner,
/// where both tell.
fn expected(e: &Evidence, k: usize) -> (Option<bool>, Option<bool>) {
    let (x, y) = e.xy(k);
    (
        expect(e.buffers.centre(x, y)),
        expect(e.buffers.corner(x, y)),
    )
}

/// Which pixel the student's rays go through, when the image tells,
/// from the image judged on the probes of each (`centres`, `corners`):
/// the one whose light explains the image twice as well (what ours sees
/// half a pixel away is another brightness, over every lit object), or
/// else the one that misses markedly fewer of the pixels ours surely
/// covers or surely leaves empty.
pub(super) fn pixel_reading(centres: &Evidence, corners: &Evidence) -> Option<Reading> {
    let e = centres;
    let background = Background::of(e);
    let (mut centre_miss, mut corner_miss, mut total) = (0usize, 0usize, 0usize);
    for k in 0..e.n {
        let seen = background.covered(e, k);
        if let (Some(a), Some(b)) = expected(e, k) {
            total += 1;
            centre_miss += usize::from(a != seen);
            corner_miss += usize::from(b != seen);
        }
    }
    let pick = |corners_better: bool| {
        if corners_better {
            Reading::Corners
        } else {
            Reading::Centres
        }
    };
    // How well each reading's light explains the image, where it tells
    // twice as well; else which pixels each covers.
    let light = match (centres.tone.unexplained, corners.tone.unexplained) {
        (Some(a), Some(b)) if a.min(b) < 0.5 * a.max(b) => Some(pick(b < a)),
        _ => None,
    };
    light.or_else(|| {
        (total > 0 && centre_miss.abs_diff(corner_miss) * 500 >= total)
            .then_some(pick(corner_miss < centre_miss))
    })
}

/// Where a student's rays go through each pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Reading {
    Centres,
    /// Its top-left corner.
    Corners,
}

impl Reading {
    pub fn words(self) -> &'static str {
        match self {
            Reading::Centres => "your image fits rays through pixel centres",
            Reading::Corners => "your image fits rays through pixel corners (the assignment's \"usually the centre\" allows it)",
        }
    }
}

/// Judge geometry, marking `map`.
pub(super) fn judge(
    e: &Evidence,
    thresholds: &AspectThresholds,
    _earlier: &[AspectResult],
    map: &mut [u8],
) -> AspectResult {
    let background = Background::of(e);
    let (mut judged, mut differ) = (0usize, 0usize);
    for (k, state) in map.iter_mut().enumerate() {
        let (x, y) = e.xy(k);
        if !e.buffers.stable(x, y, |p| p.object) {
            continue;
        }
        if let (Some(want), _) = expected(e, k) {
            judged += 1;
            let bad = want != background.covered(e, k);
            differ += usize::from(bad);
            *state = 1 + u8::from(bad);
        }
    }
    let fraction = ratio(differ, judged);
    verdict(
        Aspect::Geometry,
        judged >= 100,
        fraction,
        thresholds.geometry,
        judged,
        if judged >= 100 {
            format!(
                "{differ} of {judged} pixels that are surely background or a lit object differ ({:.2} %)",
                100.0 * fraction
            )
        } else {
            format!("only {judged} pixels are surely background or a lit object (100 needed)")
        },
    )
}
