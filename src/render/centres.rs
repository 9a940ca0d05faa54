//! The camera rays through pixel centres, made a frame at a time.
//!
//! [`super::camera_ray`] through the centre of pixel (i, j) aims at
//! `(a, b, −1)` with `a = −0.5 + (i + ½)/N` and `b = 0.5 − (j + ½)/N`, and
//! normalises it as glam does: `r = 1/√((a·a + b·b) + (−1)·(−1))`, then
//! `(a·r, b·r, −1·r)`. Every column shares its `a` and `a·a` across the
//! frame and every row its `b` and `b·b`, so [`PixelCentres`] computes
//! those once (a division each) and a pixel's ray costs one addition, a
//! square root, one division and three products. Each value is the
//! same operation on the same operands as in `camera_ray`, so the rays are
//! the same bits (a unit test compares them in both precisions).

use super::geometry::Ray;
use super::real::{Real, Vector};

/// Where the columns' centres lie on the image plane, in precision `R`.
pub(super) struct PixelCentres<R: Real> {
    size: u32,
    /// Per column `i`: `a` and `a·a`.
    columns: Vec<(R, R)>,
}

/// Where a row's centres lie: `b` and `b·b`.
#[derive(Clone, Copy)]
pub(super) struct RowCentre<R: Real> {
    b: R,
    bb: R,
}

impl<R: Real> PixelCentres<R> {
    /// The columns of a `size × size` frame.
    pub(super) fn new(size: u32) -> Self {
        let n = f64::from(size);
        let columns = (0..size)
            .map(|i| {
                let a = R::of(-0.5 + (f64::from(i) + 0.5) / n);
                (a, a * a)
            })
            .collect();
        PixelCentres { size, columns }
    }

    /// Row `j`'s centre.
    pub(super) fn row(&self, j: u32) -> RowCentre<R> {
        let b = R::of(0.5 - (f64::from(j) + 0.5) / f64::from(self.size));
        RowCentre { b, bb: b * b }
    }

    /// The camera ray through the centre of pixel (i, `row`).
    #[inline(always)]
    pub(super) fn ray(&self, i: usize, row: RowCentre<R>) -> Ray<R> {
        let (a, aa) = self.columns[i];
        let minus_one = -R::one();
        let length = ((aa + row.bb) + minus_one * minus_one).sqrt();
        let r = R::one() / length;
        Ray {
            origin: R::Vec::new(R::zero(), R::zero(), R::zero()),
            dir: R::Vec::new(a * r, row.b * r, minus_one * r),
            from: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::camera_ray;
    use super::*;

    fn same_bits<R: Real>(size: u32) {
        let centres = PixelCentres::<R>::new(size);
        for j in 0..size {
            let row = centres.row(j);
            for i in 0..size {
                let fast = centres.ray(i as usize, row);
                let slow = camera_ray::<R>(size, f64::from(i) + 0.5, f64::from(j) + 0.5);
                let bits = |v: R::Vec| v.wide().to_array().map(f64::to_bits);
                assert_eq!(bits(fast.dir), bits(slow.dir), "{size}: ({i}, {j})");
                assert_eq!(bits(fast.origin), bits(slow.origin));
                assert_eq!(fast.from, slow.from);
            }
        }
    }

    #[test]
    fn centre_rays_are_camera_rays_bit_for_bit() {
        for size in [1, 2, 3, 7, 64, 333, 400] {
            same_bits::<f64>(size);
            same_bits::<f32>(size);
        }
    }
}
