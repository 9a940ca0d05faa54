//! The student's background, fitted once per image: the assignment names
//! none, so the pixels where ours surely sees nothing tell it, and
//! geometry (which pixels show an object) and reflection (whether a
//! mirror may show a coloured background) read it.

use super::fit::{predict, robust_fit};
use crate::compare::Picture;
use raytracer_render::render::probe::Buffers;

/// How far a channel may be from the background colour and still be
/// background.
const TOLERANCE: u8 = 6;

/// The student's background: per channel, a quadratic in the pixel's
/// place on the image with a cubic in its squared distance from the
/// image's centre ([`place`]), fitted robustly on the pixels that surely
/// see nothing (the fit keeps out an object drawn where ours sees none).
/// The assignment names no background: a colour fits it (the terms are
/// then flat), and so does a sky graded by the ray's direction, smooth
/// over a camera's field of view, or a background that changes with the
/// angle from the view's axis alone. Black where no pixel surely sees
/// nothing.
pub(super) struct Background {
    /// Per channel, the fit's intercept and the gains of [`place`]'s
    /// terms (a channel runs from 0 to 1).
    channels: [Vec<f64>; 3],
    /// The pixels it was fitted on: those that surely see nothing.
    fitted: Vec<usize>,
    /// The side of the (square) image.
    size: u32,
}

/// Pixel `k`'s terms in [`Background`]'s fit: its place on the image
/// plane (from −½ to ½ across), their squares and product, and the
/// square and cube of its squared distance `s` from the centre. A
/// direction's angle from the view's axis is a function of `s` alone,
/// and a smooth step of it over the view (a radial gradient that
/// flattens at the centre and the corners) takes powers of `s` up to the
/// third to follow within a background pixel's tolerance.
fn place(size: u32, k: usize) -> [f64; 7] {
    let (x, y) = (k as u32 % size, k as u32 / size);
    let size = f64::from(size);
    let u = (f64::from(x) + 0.5) / size - 0.5;
    let v = (f64::from(y) + 0.5) / size - 0.5;
    let s = u * u + v * v;
    [u, v, u * u, u * v, v * v, s * s, s * s * s]
}

impl Background {
    /// The background of `student`, an image of the scene `buffers`
    /// probes.
    pub fn of(buffers: &Buffers, student: &Picture) -> Self {
        let size = buffers.size;
        let fitted: Vec<usize> = (0..(size * size) as usize)
            .filter(|&k| {
                let (x, y) = (k as u32 % size, k as u32 / size);
                buffers.centre(x, y).object.is_none() && buffers.stable(x, y, |p| p.object)
            })
            .collect();
        let channels = [0, 1, 2].map(|c| {
            let rows: Vec<([f64; 7], f64)> = fitted
                .iter()
                .map(|&k| (place(size, k), f64::from(student.pixel(k)[c]) / 255.0))
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
        Background {
            channels,
            fitted,
            size,
        }
    }

    /// The background's colour at pixel `k`, in 8-bit steps.
    pub fn at(&self, k: usize) -> [f64; 3] {
        let terms = place(self.size, k);
        [0, 1, 2].map(|c| 255.0 * predict(&self.channels[c], &terms))
    }

    /// Whether it is black, as far as the image tells (`false` when no
    /// pixel surely sees nothing).
    pub fn is_black(&self) -> bool {
        !self.fitted.is_empty()
            && (self.fitted.iter()).all(|&k| self.at(k).iter().all(|&c| c <= f64::from(TOLERANCE)))
    }

    /// Whether pixel `k` of `student` (the image it was fitted on) is
    /// not the background.
    pub fn covered(&self, student: &Picture, k: usize) -> bool {
        let p = student.pixel(k);
        let bg = self.at(k);
        (0..3).any(|c| (f64::from(p[c]) - bg[c]).abs() > f64::from(TOLERANCE))
    }
}
