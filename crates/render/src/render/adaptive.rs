//! Adaptive antialiasing: spend up to `spp` samples only where the image
//! has detail a cheap estimate would get wrong, in three levels.
//!
//! 1. **Corners.** A first pass takes one sample at every pixel corner
//!    (Whitted's 1980 scheme): `(size + 1)²` samples, each shared by the
//!    four pixels that meet there, so about one per pixel. A pixel is the
//!    mean of its four corners when they agree within the threshold in
//!    every channel (clamped linear radiance, in steps of 1/255), or when
//!    it does not bend ([`Corners::bends`]): its corners' steps continue
//!    its neighbours' within the threshold, so the image is a gradient
//!    across it, whose mean its corners' mean is.
//! 2. **Four samples.** Otherwise it takes four samples of its stratified
//!    grid, one in each quadrant ([`Sampler::quadrants`]). If each lies
//!    within the threshold of the bilinear interpolation of the corners
//!    (the pixel is smooth inside, not only at its corners), the pixel is
//!    the mean of the four.
//! 3. **All of them.** Otherwise it takes the rest of its grid and is the
//!    mean of all `spp` samples in the order uniform sampling averages
//!    them: bit for bit the uniform render's pixel.
//!
//! The corners see an edge or a texture step that crosses the pixel
//! itself, so an edge refines the one or two pixels it crosses; the bend
//! test keeps smooth shading (a lit plane changes by several 1/255 a
//! pixel) from being refined at all; and the middle level stops where an
//! edge only clips a corner. What no level sees is detail between samples
//! whose contrast is under the threshold (a faint texture grain under
//! ambient-only light), which is why the default threshold is a fraction
//! of a step ([`DEFAULT_THRESHOLD`]). docs/accuracy.md measures what each
//! setting costs and buys.
//!
//! With threshold 0 every pixel takes all its samples and the image is
//! uniform `spp`'s (the corners are then spent for nothing). A pixel takes
//! at most `spp` samples of its own; the corners add `(size + 1)²` to the
//! frame. With `spp` < 9 there is no middle level, and with `spp` = 1 no
//! corner pass: the image is the uniform one.
//!
//! Every decision reads the corners around the pixel and its own samples,
//! each a function of its position alone: the image is the same for any
//! number of threads, and a band of rows decides its pixels as the whole
//! frame does when its corner pass covers one corner row beyond the band
//! above and below, which [`Corners::rows`] takes. Those rows belong to
//! the neighbouring bands, which count them: a band counts the rays of
//! its own corner rows only, so the counters of the bands that cut a frame
//! add up to the whole frame's.

use glam::DVec3;
use rayon::prelude::*;

use super::real::Real;
use super::sampling::{mean, Sampler};
use super::trace::{Counters, Tracer};

/// The default contrast that refines a pixel, in steps of 1/255: one
/// step. `make accuracy` chooses it among candidates on a tuning set of
/// scenes by a rule fixed before the run (`accuracy::summary`: the most
/// scene and sample-count pairs meeting adaptive sampling's target) and
/// judges it on scenes held out from the choice; docs/accuracy.md has the
/// candidates, the choice, each miss and the held-out verdicts. A smaller
/// threshold keeps more of a faint texture's grain at more cost
/// (`--aa-threshold`).
pub const DEFAULT_THRESHOLD: f64 = 1.0;

/// The corner samples of a band of rows and of the corner rows either
/// side of it, each row `size + 1` corners wide.
pub(super) struct Corners {
    width: usize,
    /// The first corner row held.
    top: u32,
    values: Vec<DVec3>,
}

impl Corners {
    /// The samples at the corners of every pixel of rows `band`, and at
    /// the corner row above and below them where the frame has one. The
    /// counters count only the corner rows the band owns (see
    /// [`owns_corner_row`]), so a frame's bands together count each corner
    /// once, as the whole frame does, though each traces its neighbours'.
    pub(super) fn rows<R: Real>(
        sampler: &Sampler,
        tracer: &Tracer<'_, R>,
        size: u32,
        band: std::ops::Range<u32>,
    ) -> (Self, Counters) {
        let width = size as usize + 1;
        let top = band.start.saturating_sub(1);
        let bottom = (band.end + 1).min(size);
        let mut values = vec![DVec3::ZERO; (bottom - top + 1) as usize * width];
        let counters = values
            .par_chunks_mut(width)
            .zip(top..bottom + 1)
            .map(|(row, y)| {
                let mut counters = Counters::default();
                for (x, value) in (0..=size).zip(row.iter_mut()) {
                    *value = sampler.corner(tracer, (x, y), &mut counters);
                }
                if owns_corner_row(&band, size, y) {
                    counters
                } else {
                    Counters::default()
                }
            })
            .reduce(Counters::default, |mut a, b| {
                a += b;
                a
            });
        (Corners { width, top, values }, counters)
    }

    /// The four corners of pixel (i, j): top left, top right, bottom
    /// left, bottom right.
    fn of(&self, (i, j): (u32, u32)) -> [DVec3; 4] {
        let at = |x, y| self.at(x, y).expect("a pixel's corners are held");
        let (x, y) = (i64::from(i), i64::from(j));
        [at(x, y), at(x + 1, y), at(x, y + 1), at(x + 1, y + 1)]
    }

    /// The corner sample at (x, y), if the frame has that corner.
    fn at(&self, x: i64, y: i64) -> Option<DVec3> {
        let x = usize::try_from(x).ok().filter(|&x| x < self.width)?;
        let row = usize::try_from(y - i64::from(self.top)).ok()?;
        self.values.get(row * self.width + x).copied()
    }

    /// Whether pixel (i, j) bends: whether, along some edge of it, the
    /// step between its corners differs by at least `threshold`/255 in
    /// some channel from the steps of the neighbours on both sides (on
    /// the one side the frame has, at its border). A pixel where the
    /// image is linear, across it and its neighbours, does not bend,
    /// however steep: the mean of its corners is its mean. An edge
    /// inside it bends it and not its neighbours, whose own steps are
    /// flat on one side.
    fn bends(&self, (i, j): (u32, u32), threshold: f64) -> bool {
        let (x, y) = (i64::from(i), i64::from(j));
        let limit = threshold / 255.0;
        // Along rows y and y + 1, then along columns x and x + 1: the
        // corner before, the pixel's two, and the corner after.
        let lines = [0, 1].into_iter().flat_map(|k| {
            [
                [(x - 1, y + k), (x, y + k), (x + 1, y + k), (x + 2, y + k)],
                [(x + k, y - 1), (x + k, y), (x + k, y + 1), (x + k, y + 2)],
            ]
        });
        lines.into_iter().any(|line| {
            let [before, first, second, after] = line.map(|(x, y)| self.at(x, y));
            let (first, second) = (first.expect("held"), second.expect("held"));
            let step = second - first;
            let sides = [before.map(|b| first - b), after.map(|a| a - second)];
            let bend = sides
                .into_iter()
                .flatten()
                .map(|side| (step - side).abs())
                .reduce(DVec3::min)
                .unwrap_or(step.abs());
            bend.max_element() >= limit
        })
    }
}

/// Whether the band of pixel rows `band` of a `size`-row frame owns
/// corner row `y`: the top corners of its own rows, and the frame's bottom
/// corner row when the band is the last. Every corner row has exactly one
/// owner among the bands that cut a frame.
fn owns_corner_row(band: &std::ops::Range<u32>, size: u32, y: u32) -> bool {
    band.contains(&y) || (y == size && band.end == size)
}

/// Pixel (i, j) sampled as the module header describes; `counters` hears
/// the samples it took and which level it reached.
pub(super) fn pixel<R: Real>(
    sampler: &Sampler,
    tracer: &Tracer<'_, R>,
    corners: &Corners,
    pixel: (u32, u32),
    threshold: f64,
    counters: &mut Counters,
) -> DVec3 {
    let (four_corners, bends) = (corners.of(pixel), || corners.bends(pixel, threshold));
    if !disagree(&four_corners, threshold) || !bends() {
        return mean(four_corners.into_iter());
    }
    let corners = four_corners;
    let mut known = None;
    if let Some(quadrants) = sampler.quadrants() {
        let four = quadrants.map(|s| sampler.sample(tracer, pixel, s, counters));
        let linear = quadrants.iter().zip(&four).all(|(&s, &value)| {
            let expected = bilinear(&corners, sampler.offset(pixel, s));
            !disagree(&[expected, value], threshold)
        });
        if linear {
            counters.pixels_partly_refined += 1;
            return mean(four.into_iter());
        }
        known = Some((quadrants, four));
    }
    counters.pixels_refined += 1;
    let all = (0..sampler.count()).map(|s| {
        let taken = known.and_then(|(quadrants, four)| {
            let k = quadrants.iter().position(|&q| q == s)?;
            Some(four[k])
        });
        taken.unwrap_or_else(|| sampler.sample(tracer, pixel, s, counters))
    });
    mean(all)
}

/// The bilinear interpolation of `corners` (top left, top right, bottom
/// left, bottom right) at (u, v) in the pixel.
fn bilinear([tl, tr, bl, br]: &[DVec3; 4], (u, v): (f64, f64)) -> DVec3 {
    let top = tl.lerp(*tr, u);
    let bottom = bl.lerp(*br, u);
    top.lerp(bottom, v)
}

/// Whether some channel of `samples` spans at least `threshold`/255
/// (always, for threshold 0).
fn disagree(samples: &[DVec3], threshold: f64) -> bool {
    let (low, high) = samples
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(low, high), &s| {
            (low.min(s), high.max(s))
        });
    (high - low).max_element() >= threshold / 255.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_channel_spanning_the_threshold_disagrees() {
        let dark = DVec3::ZERO;
        let green = DVec3::new(0.0, 4.0 / 255.0, 0.0);
        assert!(disagree(&[dark, green, dark, dark], 4.0));
        assert!(
            !disagree(&[dark, green, dark, dark], 5.0),
            "below the threshold"
        );
        assert!(!disagree(&[green; 4], 1.0), "equal samples agree");
        assert!(
            disagree(&[dark, green / 8.0, dark, dark], 0.5),
            "half a step is a threshold of its own"
        );
        assert!(!disagree(&[dark, green / 8.0, dark, dark], 0.51));
        assert!(disagree(&[green; 4], 0.0), "0 refines everything");
    }

    /// Corners `size + 1` a side, all rows held, valued `f(x, y)`.
    fn frame(size: u32, f: impl Fn(u32, u32) -> f64) -> Corners {
        let values = (0..=size)
            .flat_map(|y| (0..=size).map(move |x| (x, y)))
            .map(|(x, y)| DVec3::splat(f(x, y)))
            .collect();
        Corners {
            width: size as usize + 1,
            top: 0,
            values,
        }
    }

    #[test]
    fn a_gradient_does_not_bend_and_an_edge_bends_only_its_pixels() {
        let step = 3.0 / 255.0;
        let ramp = frame(6, |x, y| f64::from(x + y) * step);
        assert!((0..6).all(|i| !ramp.bends((i, 2), 2.0)), "a ramp is linear");
        // A vertical edge between corner columns 3 and 4: in pixel 3.
        let edge = frame(6, |x, _| if x >= 4 { 1.0 } else { 0.0 });
        let bent: Vec<u32> = (0..6).filter(|&i| edge.bends((i, 2), 2.0)).collect();
        assert_eq!(bent, [3]);
        assert!(ramp.bends((2, 2), 0.0), "0 refines everything");
    }

    #[test]
    fn every_corner_row_has_one_owner_among_the_bands() {
        let size = 7;
        for cuts in [vec![0, 7], vec![0, 3, 7], vec![0, 1, 2, 5, 6, 7]] {
            let bands: Vec<_> = cuts.windows(2).map(|w| w[0]..w[1]).collect();
            for y in 0..=size {
                let owners = bands
                    .iter()
                    .filter(|band| owns_corner_row(band, size, y))
                    .count();
                assert_eq!(owners, 1, "corner row {y} of bands {bands:?}");
            }
        }
    }

    #[test]
    fn a_pixel_reads_its_own_corners() {
        // Corner rows 1..=2 of a 2-pixel-wide frame: values x + 10·y.
        let values = (1..=2)
            .flat_map(|y| (0..=2).map(move |x| DVec3::splat(f64::from(x + 10 * y))))
            .collect();
        let corners = Corners {
            width: 3,
            top: 1,
            values,
        };
        let xs = corners.of((1, 1)).map(|c| c.x);
        assert_eq!(xs, [11.0, 12.0, 21.0, 22.0]);
    }
}
