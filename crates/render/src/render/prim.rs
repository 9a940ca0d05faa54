//! What the hit-finding structures hold and return: a primitive with the
//! indices shading needs, and the nearest hit of a ray. Below both
//! [`super::world`] and [`super::bvh`], so neither imports the other's
//! internals.

use super::geometry::{Ray, Shape};
use super::real::Real;

/// The nearest hit of a ray.
#[derive(Clone, Copy, Debug)]
pub struct Hit<R: Real> {
    pub t: R,
    /// The primitive's slot in [`super::world::World::prims`].
    pub slot: u32,
}

/// A primitive as the tracer holds it: 48 bytes in `f64`, so a leaf of
/// four spheres is three cache lines and shading reads nothing else.
#[derive(Clone, Debug)]
pub struct Prim<R: Real> {
    pub shape: Shape<R>,
    /// Its object's index in the IR: ties between hits go to the lower.
    pub id: u32,
    /// Its material's index in [`super::world::World::materials`].
    pub material: u32,
}

impl<R: Real> Prim<R> {
    /// [`Shape::hit`] of this primitive, which lies in `slot`: inlined, so
    /// the sphere test sits in the traversal loops.
    #[inline(always)]
    pub fn hit(&self, slot: u32, ray: &Ray<R>, t_max: R) -> Option<R> {
        self.shape.hit(ray, t_max, ray.from == slot)
    }
}
