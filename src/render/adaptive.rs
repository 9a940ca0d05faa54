//! Adaptive antialiasing: spend up to `spp` samples only where the image
//! has contrast.
//!
//! A first pass takes sample 0 of every pixel's stratified grid (the
//! centre at one sample per pixel). A pixel is refined when the first
//! sample of one of its eight neighbours differs from its own by at least
//! the threshold in some channel (clamped linear radiance, in steps of
//! 1/255); a refined pixel takes the rest of its grid, samples 1 to
//! spp − 1, and averages all of them in the order uniform sampling does.
//! So a pixel never takes more than `spp` samples, a flat region takes
//! one, and a refined pixel equals the uniform render's pixel bit for bit
//! (threshold 0 refines every pixel, and the image is uniform `spp`).
//!
//! Every decision reads first samples only, and each first sample is a
//! function of its own pixel: the image is the same for any number of
//! threads. A part of the frame decides its pixels the way the whole
//! frame does when its first pass covers a one-pixel border around it,
//! which [`FirstPass::rows`] computes.

use glam::DVec3;
use rayon::prelude::*;

use super::real::Real;
use super::sampling::Sampler;
use super::trace::{Counters, Tracer};

/// The default contrast that refines a pixel, in steps of 1/255: a
/// neighbour whose first sample is 2/255 brighter or darker in some
/// channel. Measured with `raytracer accuracy --aa-threshold` over
/// scenes/ (docs/accuracy.md): at 4 the textured scene's grain, dimmed to
/// a tenth by ambient-only light, is missed (RMSE ×2.8 uniform 16 spp's);
/// at 1 the sample scene refines a quarter of its pixels and takes over
/// half uniform 16's time; 2 is between them.
pub const DEFAULT_THRESHOLD: u8 = 2;

/// The first samples of a band of rows, with the rows either side of it.
pub(super) struct FirstPass {
    size: u32,
    /// The first row held.
    top: u32,
    values: Vec<DVec3>,
}

impl FirstPass {
    /// Sample 0 of every pixel of rows `band`, and of the row above and
    /// the row below it where the image has them.
    pub(super) fn rows<R: Real>(
        sampler: &Sampler,
        tracer: &Tracer<'_, R>,
        size: u32,
        band: std::ops::Range<u32>,
    ) -> (Self, Counters) {
        let top = band.start.saturating_sub(1);
        let bottom = (band.end + 1).min(size);
        let mut values = vec![DVec3::ZERO; (bottom - top) as usize * size as usize];
        let counters = values
            .par_chunks_mut(size as usize)
            .zip(top..bottom)
            .map(|(row, j)| {
                let mut counters = Counters::default();
                for (i, value) in (0..size).zip(row.iter_mut()) {
                    *value = sampler.sample(tracer, (i, j), 0, &mut counters);
                }
                counters
            })
            .reduce(Counters::default, |mut a, b| {
                a += b;
                a
            });
        (FirstPass { size, top, values }, counters)
    }

    /// Sample 0 of pixel (i, j).
    pub(super) fn get(&self, (i, j): (u32, u32)) -> DVec3 {
        self.values[(j - self.top) as usize * self.size as usize + i as usize]
    }

    /// Whether pixel (i, j) differs from a neighbour by at least
    /// `threshold`/255 in some channel (always, for threshold 0).
    pub(super) fn needs_refining(&self, (i, j): (u32, u32), threshold: u8) -> bool {
        let limit = f64::from(threshold) / 255.0;
        let own = self.get((i, j));
        let last_row = self.top + (self.values.len() / self.size as usize) as u32 - 1;
        let rows = j.saturating_sub(1).max(self.top)..=(j + 1).min(last_row);
        let columns = i.saturating_sub(1)..=(i + 1).min(self.size - 1);
        rows.flat_map(|y| columns.clone().map(move |x| (x, y)))
            .any(|neighbour| (self.get(neighbour) - own).abs().max_element() >= limit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pass(size: u32, values: Vec<DVec3>) -> FirstPass {
        FirstPass {
            size,
            top: 0,
            values,
        }
    }

    #[test]
    fn contrast_with_any_neighbour_refines() {
        // A 3×3 image, bright in the top-left corner only.
        let mut values = vec![DVec3::ZERO; 9];
        values[0] = DVec3::new(0.0, 4.0 / 255.0, 0.0);
        let first = pass(3, values);
        assert!(first.needs_refining((0, 0), 4));
        assert!(first.needs_refining((1, 1), 4), "diagonal neighbour");
        assert!(!first.needs_refining((2, 2), 4), "not a neighbour");
        assert!(!first.needs_refining((1, 1), 5), "below the threshold");
        assert!(first.needs_refining((2, 2), 0), "0 refines everything");
    }
}
