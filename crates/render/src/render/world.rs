//! The scene as the tracer holds it: the IR's primitives converted to the
//! chosen precision, with the structure that finds what a ray hits.
//!
//! [`World::closest`] answers "what does this ray hit first" (camera and
//! reflection rays) and [`World::occluded`] "does anything lie on this
//! segment" (shadow rays, which stop at the first hit found). Both either
//! test every primitive or walk a [`Bvh`], as [`Accel`] chooses; the two
//! give the same answers, so the choice is only about speed.
//!
//! Each primitive carries what shading needs (its shape, its object's IR
//! index and its index into the IR's table of distinct materials), laid out in the hierarchy's leaf order: a hit is shaded
//! from the record its test just read, not from the IR's objects, which a
//! large scene's rays would otherwise fetch from memory at random.

use serde::Serialize;

use super::bvh::Bvh;
use super::geometry::{Ray, Rect, Shape, Sphere};
pub use super::prim::{Hit, Prim};
use super::real::{Real, Vector};
use crate::ir;

/// How rays find the primitives they hit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
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

/// Up to this many primitives, every one is tested: when the threshold was
/// chosen, scenes/sample.txt (2) rendered in a quarter less time so, while
/// at 11 the hierarchy was already a little faster and at 101 five times
/// (docs/performance.md, "Brute force").
pub const BRUTE_FORCE_MAX: usize = 4;

/// The primitives of a scene in precision `R`.
pub struct World<R: Real> {
    /// One per IR object: in the IR's order, or in the hierarchy's leaf
    /// order when there is one (so a leaf's primitives lie side by side).
    /// A ray's [`Ray::from`] is a slot of this list.
    pub prims: Vec<Prim<R>>,
    /// The IR's table of distinct materials (most scenes have a handful),
    /// so shading reads a small table rather than the IR object of each
    /// hit.
    pub materials: Vec<ir::Material>,
    /// The hierarchy, when one is used.
    bvh: Option<Bvh>,
}

/// Rays that leave one `origin` (and primitive `from`, or
/// [`Ray::FROM_NO_PRIMITIVE`]) along directions laid out per axis, ray `k`
/// along `(dirs[0][k], dirs[1][k], dirs[2][k])`, with room for what they
/// hit: `distances[k]` holds ray `k`'s `t_max` on entry.
pub struct Fan<'a, R: Real> {
    pub origin: R::Vec,
    pub from: u32,
    pub dirs: [&'a [R]; 3],
    pub distances: &'a mut [R],
    pub slots: &'a mut [u32],
}

impl<R: Real> World<R> {
    /// Convert the IR's objects, build a hierarchy if `accel` asks for one
    /// and lay the primitives out in its leaf order.
    pub fn new(scene: &ir::Scene, accel: Accel) -> World<R> {
        let mut prims: Vec<Prim<R>> = scene
            .objects
            .iter()
            .enumerate()
            .map(|(id, o)| Prim {
                shape: Shape::from(&o.shape),
                id: id as u32,
                material: o.material,
            })
            .collect();
        let hierarchy = match accel {
            Accel::Auto => prims.len() > BRUTE_FORCE_MAX,
            Accel::Bvh => !prims.is_empty(),
            Accel::Brute => false,
        };
        let bvh = if hierarchy {
            Bvh::new(&mut prims)
        } else {
            None
        };
        World {
            prims,
            materials: scene.materials.clone(),
            bvh,
        }
    }

    /// The wide nodes of the hierarchy, or 0 without one.
    pub fn bvh_nodes(&self) -> u64 {
        self.bvh.as_ref().map_or(0, |bvh| bvh.node_count() as u64)
    }

    /// The nearest hit in `(0, t_max)`; among hits at the same `t`, the
    /// primitive that comes first in the IR. Inlined, so that the scan of
    /// a tiny scene sits in the tracer's loops without a call's entry and
    /// exit; the hierarchy's traversal stays out of line.
    #[inline(always)]
    pub fn closest(&self, ray: &Ray<R>, t_max: R) -> Option<Hit<R>> {
        if let Some(bvh) = &self.bvh {
            return self.closest_in(bvh, ray, t_max);
        }
        // Without a hierarchy the slots are in IR order: the first of
        // equal hits is kept.
        let mut best: Option<Hit<R>> = None;
        let mut t_max = t_max;
        for (slot, prim) in self.prims.iter().enumerate() {
            let slot = slot as u32;
            if let Some(t) = prim.hit(slot, ray, t_max) {
                t_max = t;
                best = Some(Hit { t, slot });
            }
        }
        best
    }

    /// [`World::closest`] of every ray of `fan`: where ray `k` hits,
    /// `fan.distances[k]` becomes the hit's `t` and `fan.slots[k]` its
    /// slot; elsewhere neither changes.
    ///
    /// Without a hierarchy the loops run over the rays, one primitive at a
    /// time, each ray a lane of the same branch-free test
    /// ([`super::geometry::SphereApproach::root`], [`Rect::root`]) that
    /// [`Shape::hit`] makes; a lane takes a primitive's hit only when it
    /// is strictly nearer, so the first of equal hits stays, as in the
    /// scan. The compiler vectorises these loops for AVX2 (four `f64`
    /// lanes), chosen at run time; on SSE2 alone it judges two lanes not
    /// worth it and the same loops run a ray at a time.
    pub fn closest_fan(&self, fan: Fan<'_, R>) {
        if let Some(bvh) = &self.bvh {
            let [x, y, z] = fan.dirs;
            let rays = x.iter().zip(y).zip(z);
            let hits = fan.distances.iter_mut().zip(fan.slots);
            for (((&x, &y), &z), (distance, slot)) in rays.zip(hits) {
                let ray = Ray::from_lanes(fan.origin, (x, y, z), fan.from);
                if let Some(hit) = self.closest_in(bvh, &ray, *distance) {
                    (*distance, *slot) = (hit.t, hit.slot);
                }
            }
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2, the one feature it enables.
            unsafe { self.scan_fan_avx2(fan) };
            return;
        }
        self.scan_fan(fan);
    }

    /// [`World::scan_fan`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn scan_fan_avx2(&self, fan: Fan<'_, R>) {
        self.scan_fan(fan);
    }

    /// [`World::closest_fan`] without a hierarchy: every primitive, over
    /// every ray.
    #[inline(always)]
    fn scan_fan(&self, fan: Fan<'_, R>) {
        let Fan {
            origin,
            from,
            dirs: [x, y, z],
            distances,
            slots,
        } = fan;
        let ray = |(&x, &y), &z| Ray::from_lanes(origin, (x, y, z), from);
        for (index, prim) in self.prims.iter().enumerate() {
            let index = index as u32;
            let from_here = from == index;
            let keep = |t: R, distance: &mut R, slot: &mut u32| {
                let nearer = t < *distance;
                *distance = if nearer { t } else { *distance };
                *slot = if nearer { index } else { *slot };
            };
            let rays = x
                .iter()
                .zip(y)
                .zip(z)
                .zip(distances.iter_mut().zip(slots.iter_mut()));
            match &prim.shape {
                // Copied out of the list, so the compiler knows the stores
                // to `distances` and `slots` do not change it.
                &Shape::Sphere(sphere) => {
                    for ((xy, z), (distance, slot)) in rays {
                        let t = sphere.approach(&ray(xy, z)).root(from_here);
                        keep(t, distance, slot);
                    }
                }
                Shape::Rect(rect) if !from_here => {
                    let rect: Rect<R> = **rect;
                    for ((xy, z), (distance, slot)) in rays {
                        keep(rect.root(&ray(xy, z)), distance, slot);
                    }
                }
                Shape::Rect(_) => {}
            }
        }
    }

    /// [`Bvh::closest`] over this world's primitives.
    #[inline(never)]
    fn closest_in(&self, bvh: &Bvh, ray: &Ray<R>, t_max: R) -> Option<Hit<R>> {
        bvh.closest(&self.prims, ray, t_max)
    }

    /// Whether anything lies on the ray in `(0, t_max)`.
    pub fn occluded(&self, ray: &Ray<R>, t_max: R) -> bool {
        if let Some(bvh) = &self.bvh {
            return bvh.occluded(&self.prims, ray, t_max);
        }
        self.prims
            .iter()
            .enumerate()
            .any(|(slot, prim)| prim.hit(slot as u32, ray, t_max).is_some())
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
            } => Shape::Rect(Box::new(Rect {
                center: R::Vec::of(center),
                normal: R::Vec::of(normal),
                right: R::Vec::of(right),
                up: R::Vec::of(up),
                half_width: R::of(width / 2.0),
                half_height: R::of(height / 2.0),
            })),
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::render::fixture::sphere_on_floor;

    /// Directions from `origin` that hit, graze and miss both primitives:
    /// towards points spread over and around them, the sphere's tangent
    /// points among them, and edge-on to the rectangle.
    fn fan_of_directions(origin: DVec3) -> Vec<DVec3> {
        let mut targets = Vec::new();
        for i in 0..=24 {
            for j in 0..=24 {
                let (u, v) = (f64::from(i) / 8.0 - 1.5, f64::from(j) / 8.0 - 1.5);
                targets.push(DVec3::new(u * 2.0, v * 2.0, -5.0));
                targets.push(DVec3::new(u * 2.5, -1.0, -5.0 + v * 2.5));
            }
        }
        // From the eye, the tangent rays along the axes through the
        // sphere's rim, and rays in the rectangle's plane.
        for k in [-1.0, 1.0] {
            targets.push(DVec3::new(k, 0.0, -5.0));
            targets.push(DVec3::new(0.0, k, -5.0));
            targets.push(origin + DVec3::new(k, 0.0, 0.0));
        }
        targets
            .into_iter()
            .map(|target| target - origin)
            .filter(|d| d.length() > 0.0)
            .map(DVec3::normalize)
            .collect()
    }

    /// [`World::closest_fan`] (AVX2 lanes where the processor has them)
    /// and [`World::scan_fan`] (the same loops for SSE2) find bit for bit
    /// what [`World::closest`] finds ray by ray (hits, misses, tangents,
    /// rays leaving either primitive, finite `t_max`), in both
    /// precisions.
    #[test]
    fn the_fan_finds_what_the_scan_finds_ray_by_ray() {
        fn check<R: Real>() {
            let world = World::<R>::new(&sphere_on_floor(0.0), Accel::Brute);
            let starts = [
                (DVec3::ZERO, Ray::<R>::FROM_NO_PRIMITIVE),
                (DVec3::new(0.0, 1.0, -5.0), 0),
                (DVec3::new(0.0, 0.0, -4.0), 0),
                (DVec3::new(0.6, -1.0, -4.5), 1),
                (DVec3::new(3.0, -1.0, -5.0), Ray::<R>::FROM_NO_PRIMITIVE),
            ];
            let mut compared = [0; 2];
            for (origin, from) in starts {
                let dirs: Vec<R::Vec> = fan_of_directions(origin)
                    .into_iter()
                    .map(R::Vec::of)
                    .collect();
                let axes = [0, 1, 2].map(|a| {
                    dirs.iter()
                        .map(|d| [d.x(), d.y(), d.z()][a])
                        .collect::<Vec<R>>()
                });
                let axes = [&axes[0][..], &axes[1][..], &axes[2][..]];
                let origin = R::Vec::of(origin);
                for t_max in [f64::INFINITY, 4.5, 1e-3] {
                    let t_max = R::of(t_max);
                    let expected: Vec<Option<(R, u32)>> = dirs
                        .iter()
                        .map(|&dir| {
                            let ray = Ray { origin, dir, from };
                            world.closest(&ray, t_max).map(|hit| (hit.t, hit.slot))
                        })
                        .collect();
                    type Finder<'a, R> = &'a dyn Fn(Fan<'_, R>);
                    let finders: [Finder<R>; 2] =
                        [&|fan| world.closest_fan(fan), &|fan| world.scan_fan(fan)];
                    for find in finders {
                        let mut distances = vec![t_max; dirs.len()];
                        let mut slots = vec![u32::MAX; dirs.len()];
                        find(Fan {
                            origin,
                            from,
                            dirs: axes,
                            distances: &mut distances,
                            slots: &mut slots,
                        });
                        let found: Vec<Option<(R, u32)>> = distances
                            .iter()
                            .zip(&slots)
                            .map(|(&t, &slot)| (slot != u32::MAX).then_some((t, slot)))
                            .collect();
                        let bits = |v: &[Option<(R, u32)>]| -> Vec<Option<(u64, u32)>> {
                            v.iter()
                                .map(|h| h.map(|(t, s)| (t.wide().to_bits(), s)))
                                .collect()
                        };
                        assert_eq!(bits(&found), bits(&expected), "from {from}");
                        for (hit, &t) in found.iter().zip(&distances) {
                            if hit.is_none() {
                                assert_eq!(t.wide().to_bits(), t_max.wide().to_bits());
                            }
                        }
                    }
                    for hit in &expected {
                        compared[usize::from(hit.is_some())] += 1;
                    }
                }
            }
            // Both hits and misses were compared.
            assert!(compared[0] > 100 && compared[1] > 100, "{compared:?}");
        }
        check::<f64>();
        check::<f32>();
    }
}
