//! A bounding volume hierarchy over a scene's primitives, in the tracer's
//! precision.
//!
//! Built top-down with the surface area heuristic on binned centroids
//! (Wald 2007), then stored flat in depth-first order: an interior node's
//! first child is the next node, its second child is at `second`; a leaf
//! names a run of primitives, kept in leaf order with the IR index of each:
//! spheres inline (so a leaf is one cache line or two), other shapes by
//! their index into the world's list.
//!
//! The hierarchy must find exactly what testing every primitive finds, so
//! the image is the same byte for byte:
//! - every box is padded by many rounding steps of the scene's scale before
//!   it is rounded to `R`, so no ray a primitive test accepts (with its own
//!   rounding) misses the box around it;
//! - [`Bvh::closest`] breaks ties in `t` towards the lower IR index, as a
//!   front-to-back scan of the primitives does;
//! - each primitive is tested with the very [`Shape::hit`] the scan uses.
//!
//! [`Bvh::closest`] visits the nearer child first and skips boxes beyond
//! the nearest hit so far; [`Bvh::occluded`] stops at the first hit (shadow
//! rays need any hit, not the nearest).

use glam::DVec3;

use super::geometry::{Ray, Shape, Sphere};
use super::real::{Real, Vector};
use super::world::Hit;

/// Primitives in a leaf at most (unless they cannot be told apart).
const MAX_LEAF: usize = 4;
/// Centroid bins per axis for the surface area heuristic.
const BINS: usize = 16;
/// The relative cost of testing a primitive against visiting a node.
const PRIMITIVE_COST: f64 = 0.6;
/// Deeper than this, a node becomes a leaf, so traversal's stack is fixed.
const MAX_DEPTH: usize = 60;
/// Boxes grow by this many machine epsilons of the scene's scale.
const PAD_EPSILONS: f64 = 256.0;

/// An axis-aligned box in precision `R`, per axis.
#[derive(Clone, Copy, Debug)]
struct Bounds<R: Real> {
    /// The min corner, then the max corner.
    corners: [[R; 3]; 2],
}

/// A node of the flat hierarchy.
#[derive(Clone, Copy, Debug)]
struct Node<R: Real> {
    bounds: Bounds<R>,
    /// Interior: the second child's node index. Leaf: the first primitive.
    index: u32,
    /// Primitives in a leaf; 0 for an interior node.
    count: u32,
}

/// The hierarchy over one scene's primitives.
pub struct Bvh<R: Real> {
    nodes: Vec<Node<R>>,
    /// The primitives in leaf order.
    prims: Vec<Prim<R>>,
    /// The IR index of each of `prims`.
    ids: Vec<u32>,
}

/// A primitive in leaf order.
#[derive(Clone, Copy, Debug)]
enum Prim<R: Real> {
    Sphere(Sphere<R>),
    /// Any other shape: look it up in the world's list by IR index.
    Other,
}

impl<R: Real> Prim<R> {
    /// [`Shape::hit`] of the primitive with IR index `id`.
    #[inline]
    fn hit(&self, shapes: &[Shape<R>], id: u32, ray: &Ray<R>, t_max: R) -> Option<R> {
        let from_here = ray.from == Some(id);
        match self {
            Prim::Sphere(s) => s.hit(ray, t_max, from_here),
            Prim::Other => shapes[id as usize].hit(ray, t_max, from_here),
        }
    }
}

/// A primitive while building: its padded box (in `f64`) and centroid.
#[derive(Clone, Copy)]
struct Item {
    lo: DVec3,
    hi: DVec3,
    id: u32,
}

impl Item {
    fn centroid(&self) -> DVec3 {
        (self.lo + self.hi) * 0.5
    }
}

/// A box in `f64` while building.
#[derive(Clone, Copy)]
struct Aabb {
    lo: DVec3,
    hi: DVec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        lo: DVec3::INFINITY,
        hi: DVec3::NEG_INFINITY,
    };

    fn grow(&mut self, lo: DVec3, hi: DVec3) {
        self.lo = self.lo.min(lo);
        self.hi = self.hi.max(hi);
    }

    fn area(&self) -> f64 {
        let e = (self.hi - self.lo).max(DVec3::ZERO);
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
}

impl<R: Real> Bvh<R> {
    /// The hierarchy over `shapes`, whose positions are their IR indices.
    pub fn new(shapes: &[Shape<R>]) -> Bvh<R> {
        let pad_scale = R::epsilon().wide() * PAD_EPSILONS;
        let mut items: Vec<Item> = shapes
            .iter()
            .enumerate()
            .map(|(id, shape)| {
                let (lo, hi) = shape.bounds();
                let (lo, hi) = (lo.wide(), hi.wide());
                let scale = lo.abs().max(hi.abs()).max_element() + (hi - lo).max_element();
                let pad = DVec3::splat(pad_scale * scale.max(1.0));
                Item {
                    lo: lo - pad,
                    hi: hi + pad,
                    id: id as u32,
                }
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * items.len().div_ceil(2).max(1));
        build(&mut items, 0, 0, &mut nodes);
        let ids: Vec<u32> = items.iter().map(|item| item.id).collect();
        let prims = ids
            .iter()
            .map(|&id| match shapes[id as usize] {
                Shape::Sphere(s) => Prim::Sphere(s),
                Shape::Rect(_) => Prim::Other,
            })
            .collect();
        Bvh { nodes, prims, ids }
    }

    /// The nearest hit in `(0, t_max)` among `shapes` (the list the
    /// hierarchy was built over); among hits at the same `t`, the primitive
    /// with the lowest IR index.
    pub fn closest(&self, shapes: &[Shape<R>], ray: &Ray<R>, t_max: R) -> Option<Hit<R>> {
        let slab = Slab::new(ray);
        let mut best: Option<Hit<R>> = None;
        let mut reach = t_max;
        // Nodes still to visit, with where the ray enters them.
        let mut stack = [(0u32, R::zero()); MAX_DEPTH + 2];
        let mut top = 0;
        slab.enter(&self.nodes[0].bounds, reach)?;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if n.count > 0 {
                let first = n.index as usize;
                for slot in first..first + n.count as usize {
                    let id = self.ids[slot];
                    // With a hit in hand, also accept one at the same `t`
                    // (the lower index wins it, as in a scan).
                    let limit = match best {
                        Some(hit) => hit.t.step_ulps(1),
                        None => t_max,
                    };
                    if let Some(t) = self.prims[slot].hit(shapes, id, ray, limit) {
                        let better = match best {
                            Some(hit) => t < hit.t || id < hit.prim,
                            None => true,
                        };
                        if better {
                            best = Some(Hit { t, prim: id });
                            reach = t;
                        }
                    }
                }
            } else {
                let (a, b) = (node + 1, n.index as usize);
                let ta = slab.enter(&self.nodes[a].bounds, reach);
                let tb = slab.enter(&self.nodes[b].bounds, reach);
                match (ta, tb) {
                    (Some(ta), Some(tb)) => {
                        let (near, far) = if tb < ta { (b, (a, ta)) } else { (a, (b, tb)) };
                        stack[top] = (far.0 as u32, far.1);
                        top += 1;
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = b;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            // Pop the next node the ray enters before the nearest hit.
            loop {
                if top == 0 {
                    return best;
                }
                top -= 1;
                let (candidate, entry) = stack[top];
                if entry <= reach {
                    node = candidate as usize;
                    break;
                }
            }
        }
    }

    /// Whether any of `shapes` lies on the ray in `(0, t_max)`.
    pub fn occluded(&self, shapes: &[Shape<R>], ray: &Ray<R>, t_max: R) -> bool {
        let slab = Slab::new(ray);
        let mut stack = [0u32; MAX_DEPTH + 2];
        let mut top = 0;
        let mut node = 0usize;
        if slab.enter(&self.nodes[0].bounds, t_max).is_none() {
            return false;
        }
        loop {
            let n = &self.nodes[node];
            if n.count > 0 {
                let first = n.index as usize;
                for slot in first..first + n.count as usize {
                    let id = self.ids[slot];
                    if self.prims[slot].hit(shapes, id, ray, t_max).is_some() {
                        return true;
                    }
                }
            } else {
                let (a, b) = (node + 1, n.index as usize);
                let hit_a = slab.enter(&self.nodes[a].bounds, t_max).is_some();
                let hit_b = slab.enter(&self.nodes[b].bounds, t_max).is_some();
                if hit_a && hit_b {
                    stack[top] = b as u32;
                    top += 1;
                }
                if hit_a || hit_b {
                    node = if hit_a { a } else { b };
                    continue;
                }
            }
            if top == 0 {
                return false;
            }
            top -= 1;
            node = stack[top] as usize;
        }
    }
}

/// A ray prepared for box tests: origin, reciprocal direction and, per
/// axis, which corner of a box the ray meets first.
struct Slab<R: Real> {
    origin: [R; 3],
    inverse: [R; 3],
    /// 1 where the direction is negative: the ray enters at the max side.
    first: [usize; 3],
}

impl<R: Real> Slab<R> {
    fn new(ray: &Ray<R>) -> Slab<R> {
        let (o, d) = (ray.origin, ray.dir);
        let inverse = [d.x().recip(), d.y().recip(), d.z().recip()];
        Slab {
            origin: [o.x(), o.y(), o.z()],
            inverse,
            first: inverse.map(|i| usize::from(i < R::zero())),
        }
    }

    /// Where the ray enters `bounds`, if it does within `[0, reach]`.
    /// Zero direction components give infinite slab distances; a `NaN`
    /// (origin exactly on a slab plane parallel to the ray) is ignored by
    /// `min`/`max`, which pick the other operand.
    #[inline]
    fn enter(&self, bounds: &Bounds<R>, reach: R) -> Option<R> {
        let mut near = R::zero();
        let mut far = reach;
        for axis in 0..3 {
            let first = self.first[axis];
            let a = (bounds.corners[first][axis] - self.origin[axis]) * self.inverse[axis];
            let b = (bounds.corners[1 - first][axis] - self.origin[axis]) * self.inverse[axis];
            near = near.max(a);
            far = far.min(b);
        }
        (near <= far).then_some(near)
    }
}

/// Build the subtree over `items` (which start at leaf slot `offset`) into
/// `nodes`, reordering `items` into leaf order; returns the root's index.
fn build<R: Real>(
    items: &mut [Item],
    offset: usize,
    depth: usize,
    nodes: &mut Vec<Node<R>>,
) -> usize {
    let mut bounds = Aabb::EMPTY;
    let mut centroids = Aabb::EMPTY;
    for item in items.iter() {
        bounds.grow(item.lo, item.hi);
        let c = item.centroid();
        centroids.grow(c, c);
    }
    let index = nodes.len();
    nodes.push(Node {
        bounds: to_bounds(bounds),
        index: offset as u32,
        count: items.len() as u32,
    });
    if items.len() <= 1 || depth >= MAX_DEPTH {
        return index;
    }
    let Some(split) = best_split(items, &bounds, &centroids) else {
        return index;
    };
    let (left, right) = items.split_at_mut(split);
    build(left, offset, depth + 1, nodes);
    let second = build(right, offset + split, depth + 1, nodes);
    nodes[index].index = second as u32;
    nodes[index].count = 0;
    index
}

/// Partition `items` along the cheapest binned SAH split and return the
/// size of the first part, or `None` when a leaf is cheaper.
fn best_split(items: &mut [Item], bounds: &Aabb, centroids: &Aabb) -> Option<usize> {
    let n = items.len();
    let extent = centroids.hi - centroids.lo;
    let mut best: Option<(f64, usize, usize)> = None; // (cost, axis, bin)
    for axis in 0..3 {
        // All centroids share this coordinate: nothing to split along it.
        if extent[axis] <= 0.0 {
            continue;
        }
        let scale = BINS as f64 / extent[axis];
        let bin_of = |item: &Item| {
            (((item.centroid()[axis] - centroids.lo[axis]) * scale) as usize).min(BINS - 1)
        };
        let mut bins = [(Aabb::EMPTY, 0usize); BINS];
        for item in items.iter() {
            let bin = &mut bins[bin_of(item)];
            bin.0.grow(item.lo, item.hi);
            bin.1 += 1;
        }
        // Areas and counts of everything right of each boundary.
        let mut right = [(0.0, 0usize); BINS];
        let mut acc = (Aabb::EMPTY, 0usize);
        for bin in (1..BINS).rev() {
            acc.0.grow(bins[bin].0.lo, bins[bin].0.hi);
            acc.1 += bins[bin].1;
            right[bin] = (acc.0.area(), acc.1);
        }
        let mut left = (Aabb::EMPTY, 0usize);
        for bin in 1..BINS {
            left.0.grow(bins[bin - 1].0.lo, bins[bin - 1].0.hi);
            left.1 += bins[bin - 1].1;
            let (right_area, right_count) = right[bin];
            if left.1 == 0 || right_count == 0 {
                continue;
            }
            let cost = left.0.area() * left.1 as f64 + right_area * right_count as f64;
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, axis, bin));
            }
        }
    }
    let (cost, axis, bin) = best?;
    // Costs relative to the parent's area, in units of a node visit.
    let area = bounds.area();
    let split_cost = 1.0 + PRIMITIVE_COST * cost / area;
    let leaf_cost = PRIMITIVE_COST * n as f64;
    if n <= MAX_LEAF && split_cost >= leaf_cost {
        return None;
    }
    let scale = BINS as f64 / extent[axis];
    let goes_left = |item: &Item| {
        (((item.centroid()[axis] - centroids.lo[axis]) * scale) as usize).min(BINS - 1) < bin
    };
    let mut split = 0;
    for i in 0..n {
        if goes_left(&items[i]) {
            items.swap(i, split);
            split += 1;
        }
    }
    Some(split)
}

/// A building box in precision `R`. Rounding to nearest moves a corner by
/// at most half a unit in the last place of the scene's scale, far less
/// than the padding every primitive's box already has.
fn to_bounds<R: Real>(b: Aabb) -> Bounds<R> {
    Bounds {
        corners: [
            [R::of(b.lo.x), R::of(b.lo.y), R::of(b.lo.z)],
            [R::of(b.hi.x), R::of(b.hi.y), R::of(b.hi.z)],
        ],
    }
}
