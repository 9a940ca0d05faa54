//! The two precisions the tracer runs in, behind one trait.
//!
//! [`Real`] is `f32` or `f64`; its [`Real::Vec`] is glam's `Vec3` or
//! `DVec3`. Every ray computation (camera rays, intersections, hit points,
//! spawned rays) is generic over it, so `--precision f32|f64` runs the same
//! code. Colours stay `f64` in both: precision is about geometry.
//!
//! It also carries how far short of a light a shadow ray stops, which
//! depends on the number format.

use std::fmt::Debug;
use std::ops::{Add, Mul, Neg, Sub};

use glam::{DVec3, Vec3};
use num_traits::{Float, FloatConst};

/// A floating-point type the tracer can run in.
pub trait Real: Float + FloatConst + Debug + Default + Send + Sync + 'static {
    /// The 3-vector of this precision.
    type Vec: Vector<Self>;

    /// Shadow rays end this fraction of the way to the light, so a surface
    /// the light sits on does not shadow it.
    const SHADOW_REACH: Self;

    /// Round an `f64` to this precision.
    fn of(x: f64) -> Self;

    /// Widen to `f64`.
    fn wide(self) -> f64;
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
    fn length(self) -> R;
    fn normalize(self) -> Self;
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
            fn length(self) -> $real {
                <$vec>::length(self)
            }
            fn normalize(self) -> Self {
                <$vec>::normalize(self)
            }
        }
    };
}

vector!(Vec3, f32);
vector!(DVec3, f64);

impl Real for f32 {
    type Vec = Vec3;
    const SHADOW_REACH: f32 = 1.0 - 512.0 * f32::EPSILON;

    fn of(x: f64) -> f32 {
        x as f32
    }
    fn wide(self) -> f64 {
        f64::from(self)
    }
}

impl Real for f64 {
    type Vec = DVec3;
    const SHADOW_REACH: f64 = 1.0 - 512.0 * f64::EPSILON;

    fn of(x: f64) -> f64 {
        x
    }
    fn wide(self) -> f64 {
        self
    }
}
