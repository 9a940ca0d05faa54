//! Geometry: the camera and the intersections, judged by which pixels
//! show an object. Background where ours sees nothing, an object where
//! ours sees a lit one; the student's background is theirs to choose: a
//! colour, or a sky that changes with the ray's direction
//! ([`super::background`]). Only pixels stable for the object they see are
//! judged, so rays through pixel centres or corners both pass; which of
//! the two the image fits is told as the image's pixel reading.

use super::evidence::Evidence;
use super::unlit::{self, Mirrors};
use super::{ratio, verdict, Aspect, AspectResult, AspectThresholds};
use raytracer_render::render::probe::{Buffers, Probe};

/// Whether ours surely shows an object at a probe (`Some(true)`), surely
/// shows nothing (`Some(false)`), or shows too dark an object to tell.
/// A mirror counts by its own light alone, at its weight when blended,
/// `1 − k`, the least either reading gives it: what it shows is
/// reflection's to judge, so a mirror that shows the wrong thing (or, in
/// a tracer that does not recurse, a black mirror's own black) costs
/// reflection, not geometry. A mirror of `unlit` counts only where it
/// also shows something ([`Mirrors`]).
fn expect(probe: &Probe, buffers: &Buffers, unlit: &Mirrors) -> Option<bool> {
    let own = (1.0 - probe.reflectivity) * probe.lit > 0.01;
    match probe.object {
        None => Some(false),
        Some(object) if own && (!unlit.holds(object) || unlit::shows(probe, buffers)) => Some(true),
        Some(_) => None,
    }
}

/// Whether ours surely shows an object at pixel `k`'s centre and corner,
/// where both tell.
fn expected(e: &Evidence, unlit: &Mirrors, k: usize) -> (Option<bool>, Option<bool>) {
    let (x, y) = e.xy(k);
    (
        expect(e.buffers.centre(x, y), e.buffers, unlit),
        expect(e.buffers.corner(x, y), e.buffers, unlit),
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
    let background = e.background();
    let unlit = e.unlit_mirrors();
    let (mut centre_miss, mut corner_miss, mut total) = (0usize, 0usize, 0usize);
    for k in 0..e.n {
        let seen = background.covered(e.student, k);
        if let (Some(a), Some(b)) = expected(e, unlit, k) {
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
    let background = e.background();
    let unlit = e.unlit_mirrors();
    let (mut judged, mut differ) = (0usize, 0usize);
    for (k, state) in map.iter_mut().enumerate() {
        let (x, y) = e.xy(k);
        if !e.buffers.stable(x, y, |p| p.object) {
            continue;
        }
        if let (Some(want), _) = expected(e, unlit, k) {
            judged += 1;
            let bad = want != background.covered(e.student, k);
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
