//! The scene as the tracer holds it: the IR's primitives converted to the
//! chosen precision, with the structure that finds what a ray hits.
//!
//! [`World::closest`] answers "what does this ray hit first" (camera and
//! reflection rays) and [`World::occluded`] "does anything lie on this
//! segment" (shadow rays, which stop at the first hit found). Both either
//! test every primitive or walk a [`Bvh`], as [`Accel`] chooses; the two
//! give the same answers, so the choice is only about speed.

use serde::Serialize;

use super::bvh::Bvh;
use super::geometry::{Ray, Rect, Shape, Sphere};
use super::real::{Real, Vector};
use crate::ir;

/// The nearest hit of a ray.
#[derive(Clone, Copy, Debug)]
pub struct Hit<R: Real> {
    pub t: R,
    /// Index of the primitive (and of its object in the IR).
    pub prim: u32,
}

/// How rays find the primitives they hit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Accel {
    /// A hierarchy when the scene has more than [`BRUTE_FORCE_MAX`]
    /// primitives, else testing them all.
    #[default]
    Auto,
    /// Always a bounding volume hierarchy.
    Bvh,
    /// Always test every primitive.
    Brute,
}

/// Up to this many primitives, every one is tested: scenes/sample.txt (2)
/// renders a third faster so, while at 11 the hierarchy was already a
/// little faster and at 101 five times (docs/performance.md).
pub const BRUTE_FORCE_MAX: usize = 4;

/// The primitives of a scene in precision `R`.
pub struct World<R: Real> {
    /// One shape per IR object, in the IR's order.
    pub shapes: Vec<Shape<R>>,
    /// The hierarchy, when one is used.
    bvh: Option<Bvh<R>>,
}

impl<R: Real> World<R> {
    /// Convert the IR's objects, keeping their order (a primitive's index
    /// is its object's index), and build a hierarchy if `accel` asks for one.
    pub fn new(scene: &ir::Scene, accel: Accel) -> World<R> {
        let shapes: Vec<Shape<R>> = scene
            .objects
            .iter()
            .map(|o| Shape::from(&o.shape))
            .collect();
        let hierarchy = match accel {
            Accel::Auto => shapes.len() > BRUTE_FORCE_MAX,
            Accel::Bvh => !shapes.is_empty(),
            Accel::Brute => false,
        };
        let bvh = hierarchy.then(|| Bvh::new(&shapes)).flatten();
        World { shapes, bvh }
    }

    /// The nearest hit in `(0, t_max)`; among hits at the same `t`, the
    /// primitive that comes first in the IR.
    pub fn closest(&self, ray: &Ray<R>, t_max: R) -> Option<Hit<R>> {
        if let Some(bvh) = &self.bvh {
            return bvh.closest(&self.shapes, ray, t_max);
        }
        let mut best: Option<Hit<R>> = None;
        let mut t_max = t_max;
        for (index, shape) in self.shapes.iter().enumerate() {
            let index = index as u32;
            if let Some(t) = shape.hit(ray, t_max, ray.from == Some(index)) {
                t_max = t;
                best = Some(Hit { t, prim: index });
            }
        }
        best
    }

    /// Whether anything lies on the ray in `(0, t_max)`.
    pub fn occluded(&self, ray: &Ray<R>, t_max: R) -> bool {
        if let Some(bvh) = &self.bvh {
            return bvh.occluded(&self.shapes, ray, t_max);
        }
        self.shapes.iter().enumerate().any(|(index, shape)| {
            shape
                .hit(ray, t_max, ray.from == Some(index as u32))
                .is_some()
        })
    }
}

impl<R: Real> From<&ir::Shape> for Shape<R> {
    /// The IR's shape in precision `R`.
    fn from(shape: &ir::Shape) -> Shape<R> {
        match *shape {
            ir::Shape::Sphere { center, radius } => Shape::Sphere(Sphere {
                center: R::Vec::of(center),
                radius: R::of(radius),
            }),
            ir::Shape::Rect {
                center,
                normal,
                right,
                up,
                width,
                height,
            } => Shape::Rect(Rect {
                center: R::Vec::of(center),
                normal: R::Vec::of(normal),
                right: R::Vec::of(right),
                up: R::Vec::of(up),
                half_width: R::of(width / 2.0),
                half_height: R::of(height / 2.0),
            }),
        }
    }
}
