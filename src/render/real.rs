//! The two precisions the tracer runs in, behind one trait.
//!
//! [`Real`] is `f32` or `f64`; its [`Real::Vec`] is glam's `Vec3` or
//! `DVec3`. Every ray computation (camera rays, intersections, hit points,
//! spawned rays) is generic over it, so `--precision f32|f64` runs the same
//! code. Colours stay `f64` in both: precision is about geometry.
//!
//! It also carries what robust ray spawning needs of the number format:
//! stepping a value a number of representable floats away from zero, and
//! the constants of Wächter & Binder's offset (Ray Tracing Gems ch. 6).

use std::fmt::Debug;
use std::ops::{Add, Mul, Neg, Sub};

use glam::{DVec3, Vec3};
use num_traits::{Float, FloatConst};

/// A floating-point type the tracer can run in.
pub trait Real: Float + FloatConst + Debug + Default + Send + Sync + 'static {
    /// The 3-vector of this precision.
    type Vec: Vector<Self>;

    /// Points closer to the origin than this (in every component) are
    /// offset by [`Real::FLOAT_SCALE`] in absolute terms, not in ulps.
    const ORIGIN: Self;
    /// The absolute offset near the origin, along the normal.
    const FLOAT_SCALE: Self;
    /// How many representable values a spawned ray's origin is moved along
    /// the normal, per unit of the normal's component.
    const INT_SCALE: Self;
    /// Shadow rays end this fraction of the way to the light, so a surface
    /// the light sits on does not shadow it.
    const SHADOW_REACH: Self;

    /// Round an `f64` to this precision.
    fn of(x: f64) -> Self;

    /// Widen to `f64`.
    fn wide(self) -> f64;

    /// `self` moved `ulps` representable values: away from zero for
    /// positive `ulps` when `self` is positive, towards it when negative.
    fn step_ulps(self, ulps: i32) -> Self;
}

/// The vector operations the tracer uses, on glam's `Vec3` and `DVec3`.
pub trait Vector<R>:
    Copy
    + Debug
    + Send
    + Sync
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<R, Output = Self>
    + Neg<Output = Self>
{
    fn new(x: R, y: R, z: R) -> Self;
    fn of(v: DVec3) -> Self;
    fn wide(self) -> DVec3;
    fn x(self) -> R;
    fn y(self) -> R;
    fn z(self) -> R;
    fn dot(self, other: Self) -> R;
    fn cross(self, other: Self) -> Self;
    fn length(self) -> R;
    fn normalize(self) -> Self;
    fn min(self, other: Self) -> Self;
    fn max(self, other: Self) -> Self;
    fn is_finite(self) -> bool;
}

macro_rules! vector {
    ($vec:ty, $real:ty) => {
        impl Vector<$real> for $vec {
            fn new(x: $real, y: $real, z: $real) -> Self {
                <$vec>::new(x, y, z)
            }
            fn of(v: DVec3) -> Self {
                <$vec>::new(<$real>::of(v.x), <$real>::of(v.y), <$real>::of(v.z))
            }
            fn wide(self) -> DVec3 {
                DVec3::new(self.x.wide(), self.y.wide(), self.z.wide())
            }
            fn x(self) -> $real {
                self.x
            }
            fn y(self) -> $real {
                self.y
            }
            fn z(self) -> $real {
                self.z
            }
            fn dot(self, other: Self) -> $real {
                <$vec>::dot(self, other)
            }
            fn cross(self, other: Self) -> Self {
                <$vec>::cross(self, other)
            }
            fn length(self) -> $real {
                <$vec>::length(self)
            }
            fn normalize(self) -> Self {
                <$vec>::normalize(self)
            }
            fn min(self, other: Self) -> Self {
                <$vec>::min(self, other)
            }
            fn max(self, other: Self) -> Self {
                <$vec>::max(self, other)
            }
            fn is_finite(self) -> bool {
                <$vec>::is_finite(self)
            }
        }
    };
}

vector!(Vec3, f32);
vector!(DVec3, f64);

impl Real for f32 {
    type Vec = Vec3;
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    const SHADOW_REACH: f32 = 1.0 - 512.0 * f32::EPSILON;

    fn of(x: f64) -> f32 {
        x as f32
    }
    fn wide(self) -> f64 {
        f64::from(self)
    }
    fn step_ulps(self, ulps: i32) -> f32 {
        // Adjacent floats of one sign have adjacent bit patterns.
        f32::from_bits((self.to_bits() as i32).wrapping_add(ulps) as u32)
    }
}

impl Real for f64 {
    type Vec = DVec3;
    const ORIGIN: f64 = 1.0 / 32.0;
    // The same 2^12 ulps of ORIGIN as f32's 1/65536 is in its format.
    const FLOAT_SCALE: f64 = 1.0 / 35_184_372_088_832.0; // 2^-45
    const INT_SCALE: f64 = 256.0;
    const SHADOW_REACH: f64 = 1.0 - 512.0 * f64::EPSILON;

    fn of(x: f64) -> f64 {
        x
    }
    fn wide(self) -> f64 {
        self
    }
    fn step_ulps(self, ulps: i32) -> f64 {
        f64::from_bits((self.to_bits() as i64).wrapping_add(i64::from(ulps)) as u64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_ulps_moves_by_representable_values() {
        assert_eq!(1.0f32.step_ulps(1), 1.0 + f32::EPSILON);
        assert_eq!(1.0f64.step_ulps(1), 1.0 + f64::EPSILON);
        assert_eq!((-1.0f64).step_ulps(1), -1.0 - f64::EPSILON);
        assert_eq!(2.0f32.step_ulps(-1), 2.0 - f32::EPSILON);
    }

    #[test]
    fn float_scale_is_the_same_share_of_origin_in_both() {
        let ulps32 = f32::FLOAT_SCALE / (f32::ORIGIN * f32::EPSILON);
        let ulps64 = f64::FLOAT_SCALE / (f64::ORIGIN * f64::EPSILON);
        assert_eq!(f64::from(ulps32), ulps64);
    }
}
