//! A bounding volume hierarchy over a scene's primitives, in the tracer's
//! precision.
//!
//! Built top-down as a binary tree with the surface area heuristic, on
//! binned centroids (Wald 2007) for large nodes and over every split of
//! the sorted centroids for nodes of up to 16 primitives, then collapsed into a 4-wide tree (each
//! node the boxes of up to four children, tested at once, one SIMD slab
//! test per axis over four lanes; which binary nodes become wide nodes is
//! chosen by expected cost in [`collapse`]), so a ray visits fewer
//! nodes.
//! Building reorders the world's primitives into leaf order, so a leaf
//! names a run of slots and its primitives lie side by side in memory.
//!
//! The hierarchy must find exactly what testing every primitive finds, so
//! the image is the same byte for byte:
//! - boxes are `f32` in both precisions and tested in `f32`, four at once
//!   with glam's SIMD `Vec4` (a scene reaching beyond [`MAX_SCALE`] gets
//!   no hierarchy); collapsing keeps every binary node's box;
//!   every primitive's box is padded by many
//!   rounding steps of `R` at its own scale (for the primitive test's
//!   rounding) plus many `f32` steps at the whole scene's scale (for the
//!   box test's: ray origins lie on primitives or at the camera, inside
//!   that scale) and rounded outwards, so no ray a primitive test accepts
//!   misses the box around it;
//! - [`Bvh::closest`] breaks ties in `t` towards the lower IR index, as a
//!   front-to-back scan of the primitives does;
//! - each primitive is tested with the very [`Shape::hit`] the scan uses.
//!
//! [`Bvh::closest`] visits the nearer children first and skips boxes
//! beyond the nearest hit so far; [`Bvh::occluded`] stops at the first hit (shadow
//! rays need any hit, not the nearest).

mod collapse;

use arrayvec::ArrayVec;
use glam::{DVec3, Vec3A, Vec4};
use rayon::prelude::*;

use super::geometry::Ray;
use super::prim::{Hit, Prim};
use super::real::{Real, Vector};

/// Primitives in a leaf at most (unless they cannot be told apart).
const MAX_LEAF: usize = 4;
/// Centroid bins per axis for the surface area heuristic.
const BINS: usize = 16;
/// The relative cost of testing a primitive against visiting a node, as
/// the surface area heuristic weighs them (docs/performance.md has how it
/// was chosen).
const PRIMITIVE_COST: f64 = 0.3;
/// Scenes whose coordinates reach beyond this are left to brute force:
/// far inside `f32`'s range, so box tests never meet an infinity.
pub const MAX_SCALE: f64 = 1e30;
/// Deeper than this, a node becomes a leaf, so traversal's stack is fixed.
const MAX_DEPTH: usize = 60;
/// Boxes grow by this many epsilons of `R` at the primitive's scale...
const PAD_EPSILONS: f64 = 256.0;
/// ...and this many `f32` epsilons at the scene's scale.
const PAD_F32_EPSILONS: f64 = 64.0;

/// A node of the binary tree while building, in depth-first order (an
/// interior node's first child is the next node, its second at its
/// index), 32 bytes: its box, then in the fourth lanes the node's two
/// integers as bit patterns.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    /// Min x, y, z; then, as bits, interior: the second child's node
    /// index, leaf: the first primitive.
    lo: [f32; 4],
    /// Max x, y, z; then, as bits, the primitives in a leaf (0: interior).
    hi: [f32; 4],
}

impl Node {
    fn leaf(b: Aabb, first: u32, count: u32) -> Node {
        Node {
            lo: b.lo.extend(f32::from_bits(first)).to_array(),
            hi: b.hi.extend(f32::from_bits(count)).to_array(),
        }
    }

    fn make_interior(&mut self, second: u32) {
        self.lo[3] = f32::from_bits(second);
        self.hi[3] = f32::from_bits(0);
    }

    /// Interior: the second child; leaf: the first primitive.
    #[inline]
    fn index(&self) -> usize {
        self.lo[3].to_bits() as usize
    }

    /// Primitives in a leaf; 0 for an interior node.
    #[inline]
    fn count(&self) -> usize {
        self.hi[3].to_bits() as usize
    }

    /// The node's box.
    fn bounds(&self) -> Aabb {
        Aabb {
            lo: Vec3A::from_slice(&self.lo),
            hi: Vec3A::from_slice(&self.hi),
        }
    }
}

/// A node of the 4-wide hierarchy the binary one is collapsed into: four
/// children's boxes, lane `i` for child `i`, so one SIMD slab test per
/// axis tests all four; an unused lane's box lies at +∞ and is never
/// entered. 128 bytes, two cache lines.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Wide {
    /// The children's bounding planes: per axis x, y, z their minimum
    /// coordinates, then per axis their maximum ones.
    planes: [[f32; 4]; 6],
    /// An interior child's wide node; a leaf's first primitive.
    index: [u32; 4],
    /// A leaf's primitives; 0 for an interior child (or an unused lane).
    count: [u32; 4],
}

impl Wide {
    const EMPTY: Wide = Wide {
        planes: [[f32::INFINITY; 4]; 6],
        index: [0; 4],
        count: [0; 4],
    };
}

/// The hierarchy over one scene's primitives, which it lays out in leaf
/// order: a leaf is a run of slots of the world's list.
pub struct Bvh {
    /// The 4-wide tree, root first.
    nodes: Vec<Wide>,
}

/// A primitive while building: its padded box, rounded outwards to `f32`
/// (so every node's box, their union, is the union's rounding: `f32`
/// arithmetic while building loses nothing), in 32 bytes: binning reads
/// every item once per level, so at 10⁶ primitives the build streams
/// this list some twenty times.
#[derive(Clone, Copy)]
struct Item {
    /// The minimum corner, and in the fourth lane the item's slot before
    /// reordering, as the bits of a float (see [`SLOT_BITS`]).
    lo: Vec4,
    /// The maximum corner (fourth lane 0).
    hi: Vec4,
}

/// What an item's slot is XORed with to become the bits of its fourth
/// lane: every SIMD operation on the item's corners and centroid also
/// computes that lane, and a slot's plain bits (below 2²³) are a
/// subnormal float, which the processor handles by a slow microcode
/// assist in every addition and multiplication. With bit 30 flipped the
/// exponent is at least 128 for any slot below 2³⁰, so the lane is a
/// normal number, an infinity or a NaN, which cost nothing extra
/// (docs/performance.md has what binning lost to the assists).
const SLOT_BITS: u32 = 1 << 30;

impl Item {
    fn new(lo: Vec3A, hi: Vec3A, slot: u32) -> Item {
        Item {
            lo: lo.extend(f32::from_bits(slot ^ SLOT_BITS)),
            hi: hi.extend(0.0),
        }
    }

    #[inline(always)]
    fn lo(&self) -> Vec3A {
        Vec3A::from_vec4(self.lo)
    }

    #[inline(always)]
    fn hi(&self) -> Vec3A {
        Vec3A::from_vec4(self.hi)
    }

    /// Twice the centroid, `lo + hi`: binning only compares centroids
    /// with each other, so the factor ½ is left out.
    #[inline(always)]
    fn centroid(&self) -> Vec3A {
        self.lo() + self.hi()
    }

    /// [`Item::centroid`]'s coordinate on one axis, the same sum read
    /// from memory: indexing the SIMD value by a variable axis stores it
    /// to the stack first.
    #[inline(always)]
    fn centroid_along(&self, axis: usize) -> f32 {
        let (lo, hi): (&[f32; 4], &[f32; 4]) = (self.lo.as_ref(), self.hi.as_ref());
        lo[axis] + hi[axis]
    }

    fn slot(&self) -> u32 {
        self.lo.w.to_bits() ^ SLOT_BITS
    }
}

/// A box while building, in `f32` (SIMD lanes).
#[derive(Clone, Copy)]
struct Aabb {
    lo: Vec3A,
    hi: Vec3A,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        lo: Vec3A::INFINITY,
        hi: Vec3A::NEG_INFINITY,
    };

    fn grow(&mut self, lo: Vec3A, hi: Vec3A) {
        self.lo = self.lo.min(lo);
        self.hi = self.hi.max(hi);
    }

    /// The surface area, in `f64` (the extents of a scene of scale
    /// [`MAX_SCALE`] would overflow a product in `f32`).
    fn area(&self) -> f64 {
        let e = (self.hi - self.lo).max(Vec3A::ZERO).as_dvec3();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
}

impl Bvh {
    /// The hierarchy over `prims`, reordered into its leaf order; `None`
    /// (and `prims` untouched) for a scene larger than [`MAX_SCALE`],
    /// whose ray origins `f32` box tests could not hold.
    pub fn new<R: Real>(prims: &mut Vec<Prim<R>>) -> Option<Bvh> {
        let bounds = |prim: &Prim<R>| {
            let (lo, hi) = prim.shape.bounds();
            (lo.wide(), hi.wide())
        };
        let scale_of = |(lo, hi): (DVec3, DVec3)| {
            (lo.abs().max(hi.abs()).max_element() + (hi - lo).max_element()).max(1.0)
        };
        let scene_scale = prims
            .par_iter()
            .map(|prim| scale_of(bounds(prim)))
            .reduce(|| 1.0, f64::max);
        if scene_scale > MAX_SCALE {
            return None;
        }
        let scene_pad = f64::from(f32::EPSILON) * PAD_F32_EPSILONS * scene_scale;
        let mut items: Vec<Item> = prims
            .par_iter()
            .enumerate()
            .map(|(slot, prim)| {
                let (lo, hi) = bounds(prim);
                let own_pad = R::epsilon().wide() * PAD_EPSILONS * scale_of((lo, hi));
                let pad = DVec3::splat(scene_pad + own_pad);
                let (lo, hi) = to_f32_box(lo - pad, hi + pad);
                Item::new(lo, hi, slot as u32)
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * items.len().div_ceil(2).max(1));
        build(&mut items, 0, 0, &mut nodes);
        let mut wide = Vec::with_capacity(nodes.len() / 2 + 1);
        collapse::Plan::new(&nodes, items.len()).collapse(&nodes, 0, &mut wide);
        drop(nodes);
        // Gathered in leaf order: independent reads, unlike moving the
        // primitives along the permutation's cycles in place, whose cache
        // misses each wait for the one before.
        let order: Vec<u32> = items.iter().map(Item::slot).collect();
        drop(items);
        *prims = order
            .par_iter()
            .map(|&slot| prims[slot as usize].clone())
            .collect();
        Some(Bvh { nodes: wide })
    }

    /// How many wide nodes the tree has (at least 1).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// The nearest hit in `(0, t_max)` among `prims` (the list the
    /// hierarchy was built over); among hits at the same `t`, the primitive
    /// with the lowest IR index. Marked `inline`, so that
    /// `World::closest_in` holds the traversal without a second call per
    /// ray whichever codegen unit each lands in.
    #[inline]
    pub fn closest<R: Real>(&self, prims: &[Prim<R>], ray: &Ray<R>, t_max: R) -> Option<Hit<R>> {
        let slab = Slab::new(ray);
        let mut best: Option<Hit<R>> = None;
        let mut reach = reach_f32(t_max);
        // Children still to visit, the nearest on top.
        let mut stack = ArrayVec::<Child, STACK>::new();
        let mut node = 0usize;
        // A primitive's `t` does not depend on the limit it is given (only
        // whether it is returned), so testing against `t_max` and keeping
        // the nearest, the lower index on a tie, is what a scan finds.
        let mut test_leaf = |child: Child, reach: &mut f32| {
            for slot in child.slots() {
                let prim = &prims[slot as usize];
                if let Some(t) = prim.hit(slot, ray, t_max) {
                    if best.is_none_or(|hit| {
                        t < hit.t || (t == hit.t && prim.id < prims[hit.slot as usize].id)
                    }) {
                        best = Some(Hit { t, slot });
                        *reach = reach_f32(t);
                    }
                }
            }
        };
        loop {
            let w = &self.nodes[node];
            let (near, mut mask) = slab.enter(w, reach);
            // One child entered (the common case deep in the tree): no
            // ordering to do.
            if mask.is_power_of_two() {
                let lane = mask.trailing_zeros() as usize;
                let child = Child::of(w, lane, near[lane]);
                if child.is_interior() {
                    node = child.index as usize;
                    continue;
                }
                test_leaf(child, &mut reach);
                mask = 0;
            }
            // The entered children, nearest first.
            let mut order = [(0f32, 0usize); 4];
            let mut hits = 0;
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let entry = near[lane];
                let mut at = hits;
                while at > 0 && order[at - 1].0 > entry {
                    order[at] = order[at - 1];
                    at -= 1;
                }
                order[at] = (entry, lane);
                hits += 1;
            }
            // Leaves nearer than every interior child are tested at once;
            // the nearest interior child is visited next and the children
            // beyond it are pushed, farthest first.
            let mut next = None;
            for (k, &(entry, lane)) in order[..hits].iter().enumerate() {
                if entry > reach {
                    break;
                }
                let child = Child::of(w, lane, entry);
                if !child.is_interior() {
                    test_leaf(child, &mut reach);
                    continue;
                }
                next = Some(child.index as usize);
                for &(entry, lane) in order[k + 1..hits].iter().rev() {
                    stack.push(Child::of(w, lane, entry));
                }
                break;
            }
            if let Some(next) = next {
                node = next;
                continue;
            }
            // Pop the next child the ray enters before the nearest hit:
            // leaves are tested here, an interior child is visited next.
            loop {
                let Some(child) = stack.pop() else {
                    return best;
                };
                if child.entry > reach {
                    continue;
                }
                if child.is_interior() {
                    node = child.index as usize;
                    break;
                }
                test_leaf(child, &mut reach);
            }
        }
    }

    /// Whether any of `prims` lies on the ray in `(0, t_max)`. Marked
    /// `inline`: the tracer's path loop, which makes the shadow rays,
    /// then holds the traversal without a call per ray.
    #[inline]
    pub fn occluded<R: Real>(&self, prims: &[Prim<R>], ray: &Ray<R>, t_max: R) -> bool {
        let slab = Slab::new(ray);
        let reach = reach_f32(t_max);
        let mut stack = ArrayVec::<u32, STACK>::new();
        let mut node = 0u32;
        loop {
            let w = &self.nodes[node as usize];
            let (_, mut mask) = slab.enter(w, reach);
            // Leaves are tested as they are met, interior children pushed.
            while mask != 0 {
                let lane = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let child = Child::of(w, lane, 0.0);
                if child.is_interior() {
                    stack.push(child.index);
                    continue;
                }
                for slot in child.slots() {
                    if prims[slot as usize].hit(slot, ray, t_max).is_some() {
                        return true;
                    }
                }
            }
            let Some(next) = stack.pop() else {
                return false;
            };
            node = next;
        }
    }
}

/// A child of a wide node met in traversal.
#[derive(Clone, Copy, Debug)]
struct Child {
    /// An interior child's wide node; a leaf's first primitive.
    index: u32,
    /// A leaf's primitives; 0 for an interior child.
    count: u32,
    /// Where the ray enters its box.
    entry: f32,
}

impl Child {
    #[inline(always)]
    fn of(w: &Wide, lane: usize, entry: f32) -> Child {
        Child {
            index: w.index[lane],
            count: w.count[lane],
            entry,
        }
    }

    #[inline(always)]
    fn is_interior(&self) -> bool {
        self.count == 0
    }

    /// A leaf's slots.
    #[inline(always)]
    fn slots(&self) -> std::ops::Range<u32> {
        self.index..self.index + self.count
    }
}

/// Traversal stacks: a wide node pushes at most three children and
/// visits one, and the binary hierarchy is at most [`MAX_DEPTH`] deep.
const STACK: usize = 3 * (MAX_DEPTH + 2);

/// `t` as an `f32` no smaller than it (a few steps up covers rounding),
/// and finite: an unused lane's box, at +∞, is then never entered.
#[inline]
fn reach_f32<R: Real>(t: R) -> f32 {
    let t = t.wide() as f32;
    (t + t * (4.0 * f32::EPSILON)).min(f32::MAX)
}

/// A ray prepared for `f32` box tests: origin and reciprocal direction,
/// each component in all four lanes, and per axis whether the ray runs
/// backwards along it (so it enters a box by its maximum plane).
struct Slab {
    origin: [Vec4; 3],
    inverse: [Vec4; 3],
    backwards: [bool; 3],
}

impl Slab {
    fn new<R: Real>(ray: &Ray<R>) -> Slab {
        let (o, d) = (ray.origin.wide(), ray.dir.wide());
        // A component too small for a finite reciprocal (zero included)
        // becomes the smallest normal value of its sign: no slab distance
        // is `0 · ∞ = NaN`, and the ray moves less than any padding.
        let component = |c: f64| {
            let c = c as f32;
            if c.abs() < f32::MIN_POSITIVE {
                f32::MIN_POSITIVE.copysign(c)
            } else {
                c
            }
        };
        let inverse = [d.x, d.y, d.z].map(|c| component(c).recip());
        Slab {
            origin: [o.x, o.y, o.z].map(|c| Vec4::splat(c as f32)),
            inverse: inverse.map(Vec4::splat),
            backwards: inverse.map(|c| c < 0.0),
        }
    }

    /// Where the ray enters each child box of `node`, and a bit mask of
    /// those it enters within `[0, reach]`. Along each axis the ray meets
    /// a box's minimum plane first if it runs forwards and its maximum
    /// plane first if backwards: rounding is monotone and the reciprocal is
    /// never zero, so the plane chosen by the direction's sign is exactly
    /// the smaller of the two distances and no per-lane minimum is needed.
    /// An unused lane's box lies at +∞ on every axis: along an axis the ray
    /// follows forwards it is entered at +∞, beyond the finite `reach`, and
    /// along one it follows backwards it is left at −∞, before 0.
    #[inline(always)]
    fn enter(&self, node: &Wide, reach: f32) -> ([f32; 4], u32) {
        let mut near = Vec4::ZERO;
        let mut far = Vec4::splat(reach);
        for axis in 0..3 {
            let backwards = usize::from(self.backwards[axis]);
            let distance = |plane: usize| {
                (Vec4::from_array(node.planes[plane]) - self.origin[axis]) * self.inverse[axis]
            };
            near = near.max(distance(axis + 3 * backwards));
            far = far.min(distance(axis + 3 * (1 - backwards)));
        }
        (near.to_array(), near.cmple(far).bitmask())
    }
}

/// Build the subtree over `items` (which start at leaf slot `offset`) into
/// `nodes`, reordering `items` into leaf order; returns the root's index.
/// With more than one thread in the current rayon pool, the two halves of
/// a node over [`PARALLEL_MIN`] items or more near the root are built at
/// once, each into its own list, appended in order: the tree is the same
/// for any number of threads.
fn build(items: &mut [Item], offset: usize, depth: usize, nodes: &mut Vec<Node>) -> usize {
    let mut bounds = Aabb::EMPTY;
    let mut centroids = Aabb::EMPTY;
    for item in items.iter() {
        bounds.grow(item.lo(), item.hi());
        let centroid = item.centroid();
        centroids.grow(centroid, centroid);
    }
    let index = nodes.len();
    nodes.push(Node::leaf(bounds, offset as u32, items.len() as u32));
    if items.len() <= 1 || depth >= MAX_DEPTH {
        return index;
    }
    let Some(split) = best_split(items, &bounds, &centroids) else {
        return index;
    };
    // Enough subtrees to keep every thread busy, each large enough to pay
    // for its own list (which is copied once more per parallel level).
    let threads = rayon::current_num_threads();
    let parallel = threads > 1 && items.len() >= PARALLEL_MIN && (1 << depth) < 4 * threads;
    let (left, right) = items.split_at_mut(split);
    let second = if parallel {
        let subtree = |items: &mut [Item], offset| {
            let mut nodes = Vec::new();
            build(items, offset, depth + 1, &mut nodes);
            nodes
        };
        let (left, right) =
            rayon::join(|| subtree(left, offset), || subtree(right, offset + split));
        append(nodes, left);
        let second = nodes.len();
        append(nodes, right);
        second
    } else {
        build(left, offset, depth + 1, nodes);
        build(right, offset + split, depth + 1, nodes)
    };
    nodes[index].make_interior(second as u32);
    index
}

/// Nodes over at least this many primitives build their halves in
/// parallel: below it a half takes well under a millisecond.
const PARALLEL_MIN: usize = 4096;

/// Append a subtree built into its own list, moving its interior nodes'
/// child indices to where it lands.
fn append(nodes: &mut Vec<Node>, subtree: Vec<Node>) {
    let base = nodes.len();
    nodes.extend(subtree.into_iter().map(|mut node| {
        if node.count() == 0 {
            node.make_interior((node.index() + base) as u32);
        }
        node
    }));
}

/// Partition `items` along the cheapest SAH split and return the size of
/// the first part, or `None` when a leaf is cheaper: by sweeping every
/// split of the items sorted along each axis for a node of at most
/// [`SWEEP_MAX`] items (most nodes are small, and sixteen bins per axis
/// cost more to fill and sweep than their few items), else on binned
/// centroids.
fn best_split(items: &mut [Item], bounds: &Aabb, centroids: &Aabb) -> Option<usize> {
    let n = items.len();
    // Costs relative to the parent's area, in units of a node visit.
    let worth_splitting = |cost: f64| {
        let split_cost = 1.0 + PRIMITIVE_COST * cost / bounds.area();
        n > MAX_LEAF || split_cost < PRIMITIVE_COST * n as f64
    };
    // A split costs at least the visit itself (or NaN, for a box of no
    // area, which is no split either), so a leaf that tests fewer
    // primitives than that costs needs no sweep.
    if n <= MAX_LEAF && PRIMITIVE_COST * n as f64 <= 1.0 {
        return None;
    }
    if n <= SWEEP_MAX {
        let (cost, order, split) = sweep_split(items)?;
        worth_splitting(cost).then(|| {
            let sorted: ArrayVec<Item, SWEEP_MAX> =
                order[..n].iter().map(|&k| items[k as usize]).collect();
            items.copy_from_slice(&sorted);
            split
        })
    } else {
        let bins = Bins::over(centroids);
        let (cost, axis, bin) = bins.best_split(items)?;
        worth_splitting(cost).then(|| {
            let mut split = 0;
            for i in 0..n {
                if (bins.along(&items[i], axis) as usize) < bin {
                    items.swap(i, split);
                    split += 1;
                }
            }
            split
        })
    }
}

/// Nodes of at most this many items try every split along each axis.
const SWEEP_MAX: usize = 16;

/// The cheapest split of at most [`SWEEP_MAX`] items sorted by centroid
/// along some axis (equal centroids in their order in `items`, so the
/// tree is the same on every run): its SAH cost (`area · count` summed
/// over both sides), that order as indices into `items`, and the first
/// side's size.
fn sweep_split(items: &[Item]) -> Option<(f64, [u8; SWEEP_MAX], usize)> {
    let n = items.len();
    let centroids: ArrayVec<Vec3A, SWEEP_MAX> = items.iter().map(Item::centroid).collect();
    let mut best: Option<(f64, [u8; SWEEP_MAX], usize)> = None;
    for axis in 0..3 {
        // Sorted as integers: the centroid's bits in `total_cmp`'s order
        // above the item's index, so ties keep the items' order and an
        // integer sort (a sorting network for so few) does the work.
        let mut keys: ArrayVec<u64, SWEEP_MAX> = centroids
            .iter()
            .enumerate()
            .map(|(k, c)| u64::from(total_order_bits(c[axis])) << 32 | k as u64)
            .collect();
        keys.sort_unstable();
        let mut order = [0u8; SWEEP_MAX];
        for (at, key) in order.iter_mut().zip(&keys) {
            *at = *key as u8;
        }
        let mut right_area = [0.0; SWEEP_MAX];
        let mut right = Aabb::EMPTY;
        for k in (1..n).rev() {
            let item = &items[order[k] as usize];
            right.grow(item.lo(), item.hi());
            right_area[k] = right.area();
        }
        let mut left = Aabb::EMPTY;
        let mut cheapest: Option<(f64, usize)> = None;
        for k in 1..n {
            let item = &items[order[k - 1] as usize];
            left.grow(item.lo(), item.hi());
            let cost = left.area() * k as f64 + right_area[k] * (n - k) as f64;
            if cheapest.is_none_or(|(c, _)| cost < c) {
                cheapest = Some((cost, k));
            }
        }
        if let Some((cost, k)) = cheapest {
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, order, k));
            }
        }
    }
    best
}

/// [`BINS`] equal bins per axis over a node's centroids.
struct Bins {
    origin: Vec3A,
    scale: Vec3A,
    extent: Vec3A,
}

impl Bins {
    fn over(centroids: &Aabb) -> Bins {
        let extent = centroids.hi - centroids.lo;
        Bins {
            origin: centroids.lo,
            scale: Vec3A::splat(BINS as f32) / extent,
            extent,
        }
    }

    /// The item's bin along each axis at once: its scaled centroid
    /// clamped to `[0, BINS - 1]` (a NaN, from an axis of zero extent,
    /// becomes 0: the maximum takes the second operand when one is NaN,
    /// in SSE and in `f32::max` alike) and truncated, the bin
    /// [`Bins::along`] finds one axis at a time.
    #[inline(always)]
    fn of(&self, item: &Item) -> [u32; 3] {
        let scaled = ((item.centroid() - self.origin) * self.scale)
            .max(Vec3A::ZERO)
            .min(Vec3A::splat((BINS - 1) as f32));
        truncate(scaled)
    }

    /// The item's bin along one axis (`as` saturates: a NaN or negative
    /// is bin 0).
    #[inline(always)]
    fn along(&self, item: &Item, axis: usize) -> u32 {
        let scaled = (item.centroid_along(axis) - self.origin[axis]) * self.scale[axis];
        (scaled as u32).min(BINS as u32 - 1)
    }

    /// The cheapest split between two bins: its SAH cost, the axis and
    /// the first bin of the second side. An axis along which all
    /// centroids share one coordinate has nothing to split and is skipped.
    fn best_split(&self, items: &[Item]) -> Option<(f64, usize, usize)> {
        // Two sets of bins, filled by alternate items and then merged (a
        // union and a sum, exact in any order): neighbouring items mostly
        // share a bin, and with one set each item's update would wait for
        // the store of the one before.
        let mut sets = [[[(Aabb::EMPTY, 0usize); BINS]; 3]; 2];
        let mut add = |set: usize, item: &Item| {
            for (axis_bins, bin) in sets[set].iter_mut().zip(self.of(item)) {
                let bin = &mut axis_bins[bin as usize];
                bin.0.grow(item.lo(), item.hi());
                bin.1 += 1;
            }
        };
        let mut pairs = items.chunks_exact(2);
        for pair in &mut pairs {
            add(0, &pair[0]);
            add(1, &pair[1]);
        }
        for item in pairs.remainder() {
            add(0, item);
        }
        let [mut bins, odd] = sets;
        for (axis_bins, odd_bins) in bins.iter_mut().zip(&odd) {
            for (bin, odd_bin) in axis_bins.iter_mut().zip(odd_bins) {
                bin.0.grow(odd_bin.0.lo, odd_bin.0.hi);
                bin.1 += odd_bin.1;
            }
        }
        let mut best: Option<(f64, usize, usize)> = None;
        for (axis, bins) in bins.iter().enumerate() {
            if self.extent[axis] <= 0.0 {
                continue;
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
        best
    }
}

/// The first three lanes of `v`, each in `[0, 2²³)`, truncated to
/// integers in SIMD lanes, where three `as` conversions are three scalar
/// ones with saturation checks: adding 2²³ leaves a lane's integer part in
/// the low bits of the sum's significand, rounded to nearest, so one is
/// taken off where the sum rounded up.
#[inline(always)]
fn truncate(v: Vec3A) -> [u32; 3] {
    let shift = Vec3A::splat(8_388_608.0);
    let rounded = v + shift;
    let rounded_up = (rounded - shift).cmpgt(v);
    let floor = rounded - Vec3A::select(rounded_up, Vec3A::ONE, Vec3A::ZERO);
    floor.to_array().map(|lane| lane.to_bits() & 0x7F_FFFF)
}

/// `x`'s bits as an unsigned integer whose order is [`f32::total_cmp`]'s.
#[inline(always)]
fn total_order_bits(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits >> 31 == 1 {
        !bits
    } else {
        bits | 1 << 31
    }
}

/// A box in `f32`, rounded outwards: min and max corners.
fn to_f32_box(lo: DVec3, hi: DVec3) -> (Vec3A, Vec3A) {
    let down = |x: f64| {
        let r = x as f32;
        if f64::from(r) > x {
            next_toward_neg_infinity(r)
        } else {
            r
        }
    };
    let up = |x: f64| {
        let r = x as f32;
        if f64::from(r) < x {
            -next_toward_neg_infinity(-r)
        } else {
            r
        }
    };
    (
        Vec3A::new(down(lo.x), down(lo.y), down(lo.z)),
        Vec3A::new(up(hi.x), up(hi.y), up(hi.z)),
    )
}

/// The largest `f32` below finite `r`.
fn next_toward_neg_infinity(r: f32) -> f32 {
    if r == 0.0 {
        -f32::from_bits(1)
    } else if r > 0.0 {
        f32::from_bits(r.to_bits() - 1)
    } else {
        f32::from_bits(r.to_bits() + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::geometry::{Shape, Sphere};

    /// Spheres of radius `radius` at the given `x`, in IR order.
    fn spheres(xs: &[f64], radius: f64) -> Vec<Prim<f64>> {
        xs.iter()
            .enumerate()
            .map(|(id, &x)| Prim {
                shape: Shape::Sphere(Sphere {
                    center: DVec3::new(x, 0.0, -5.0),
                    radius,
                }),
                id: id as u32,
                material: 0,
            })
            .collect()
    }

    #[test]
    fn boxes_are_rounded_outwards() {
        let (lo64, hi64) = (DVec3::new(0.1, -0.1, -1e-50), DVec3::new(0.3, -0.3, 1e-50));
        let (lo, hi) = to_f32_box(lo64, hi64);
        for axis in 0..3 {
            assert!(f64::from(lo[axis]) <= lo64[axis], "{axis}");
            assert!(f64::from(hi[axis]) >= hi64[axis], "{axis}");
        }
    }

    #[test]
    fn an_items_slot_survives_and_its_lane_is_never_subnormal() {
        for slot in [
            0,
            1,
            12_345,
            (1 << 23) - 1,
            1 << 23,
            (1 << 30) - 1,
            1 << 30,
            u32::MAX,
        ] {
            let item = Item::new(Vec3A::ZERO, Vec3A::ONE, slot);
            assert_eq!(item.slot(), slot);
            if slot < 1 << 30 {
                assert!(!item.lo.w.is_subnormal() && item.lo.w != 0.0, "{slot}");
                assert!(!(item.lo + item.hi).w.is_subnormal(), "{slot}");
            }
        }
    }

    #[test]
    fn binning_in_lanes_agrees_with_one_axis_at_a_time() {
        // Bins over centroids spread along x, none along y (a scale of
        // ∞, so `0 · ∞ = NaN`), and along z over a narrower range than the
        // items' (some fall below it, some beyond).
        let bins = Bins::over(&Aabb {
            lo: Vec3A::new(-1.0, 2.0, 0.5),
            hi: Vec3A::new(3.0, 2.0, 0.75),
        });
        let mut seen = [[false; BINS]; 3];
        for k in 0..=4000 {
            let x = -1.5 + k as f32 * 1e-3;
            let c = Vec3A::new(x, 1.0, x);
            let item = Item::new(c, c, 0);
            let lanes = bins.of(&item);
            for axis in 0..3 {
                assert_eq!(lanes[axis], bins.along(&item, axis), "{x} {axis}");
                seen[axis][lanes[axis] as usize] = true;
            }
        }
        assert!(seen[0].iter().all(|&s| s), "every bin along x is used");
        assert!(seen[1][0] && seen[2][0] && seen[2][BINS - 1]);
    }

    #[test]
    fn total_order_bits_sort_as_total_cmp_does() {
        let mut xs = [
            f32::NAN,
            1.5,
            -0.0,
            f32::INFINITY,
            0.0,
            -f32::NAN,
            f32::MIN_POSITIVE,
            -1.5,
            f32::NEG_INFINITY,
            -f32::from_bits(1),
            f32::from_bits(1),
        ];
        let mut by_bits = xs;
        xs.sort_by(f32::total_cmp);
        by_bits.sort_by_key(|&x| total_order_bits(x));
        assert_eq!(xs.map(f32::to_bits), by_bits.map(f32::to_bits));
    }

    #[test]
    fn the_tree_is_the_same_built_on_one_thread_or_several() {
        // Enough spheres for parallel levels; a hash spreads them out.
        let xs: Vec<f64> = (0..3 * PARALLEL_MIN as u64)
            .map(|i| (i.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40) as f64 / 1e3)
            .collect();
        let built = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a thread pool");
            let mut prims = spheres(&xs, 0.25);
            let bvh = pool
                .install(|| Bvh::new(&mut prims))
                .expect("a small scene");
            let ids: Vec<u32> = prims.iter().map(|p| p.id).collect();
            (format!("{:?}", bvh.nodes), ids)
        };
        let (nodes, ids) = built(1);
        assert!(nodes.len() > 1000 && ids.len() == xs.len());
        assert!(built(4) == (nodes, ids), "a parallel build differs");
    }

    #[test]
    fn a_scene_beyond_f32_range_gets_no_hierarchy() {
        assert!(Bvh::new(&mut spheres(&[0.0, 1e31], 1.0)).is_none());
        assert!(Bvh::new(&mut spheres(&[0.0, 1e6], 1.0)).is_some());
    }

    #[test]
    fn rays_along_an_axis_through_box_faces_still_hit() {
        // Direction components exactly zero, origin on the spheres' plane.
        let xs: Vec<f64> = (0..9).map(f64::from).collect();
        let mut prims = spheres(&xs, 0.25);
        let bvh = Bvh::new(&mut prims).expect("a small scene");
        let ray = Ray {
            origin: DVec3::new(-3.0, 0.0, -5.0),
            dir: DVec3::X,
            from: Ray::<f64>::FROM_NO_PRIMITIVE,
        };
        let hit = bvh.closest(&prims, &ray, f64::INFINITY).expect("a hit");
        assert_eq!((prims[hit.slot as usize].id, hit.t), (0, 2.75));
        assert!(bvh.occluded(&prims, &ray, 2.8));
        assert!(!bvh.occluded(&prims, &ray, 2.7));
    }

    /// Rays from inside and outside a cloud of spheres of varied sizes
    /// (overlapping; twelve coincident, which every fifth ray aims at) in
    /// precision `R`: the hierarchy finds what a scan of every primitive
    /// finds, the tie rule included, and shadow rays see a hit exactly
    /// when the scan does.
    fn the_hierarchy_finds_what_a_scan_finds<R: Real>() {
        let mut random = crate::render::fixture::uniform(0x2545_F491_4F6C_DD1D);
        let coincident = DVec3::new(0.5, 0.5, 0.5);
        let mut prims: Vec<Prim<R>> = (0..600)
            .map(|id| {
                let (center, radius) = if id % 50 == 49 {
                    (coincident, 0.15)
                } else {
                    let center = DVec3::new(random(), random(), random()) * 4.0 - 2.0;
                    (center, 0.02 + 0.2 * random())
                };
                Prim {
                    shape: Shape::Sphere(Sphere {
                        center: R::Vec::of(center),
                        radius: R::of(radius),
                    }),
                    id,
                    material: 0,
                }
            })
            .collect();
        let bvh = Bvh::new(&mut prims).expect("a small scene");
        let (mut hits, mut ties) = (0, 0);
        for k in 0..4000 {
            let origin = DVec3::new(random(), random(), random()) * 6.0 - 3.0;
            let dir = if k % 5 == 0 {
                (coincident - origin).normalize()
            } else {
                (DVec3::new(random(), random(), random()) - 0.5).normalize()
            };
            let from = if k % 3 == 0 {
                (k % prims.len()) as u32
            } else {
                Ray::<R>::FROM_NO_PRIMITIVE
            };
            let ray = Ray {
                origin: R::Vec::of(origin),
                dir: R::Vec::of(dir),
                from,
            };
            let t_max = if k % 2 == 0 {
                R::infinity()
            } else {
                R::of(2.0)
            };
            let mut scan: Option<(R, u32)> = None;
            for (slot, prim) in prims.iter().enumerate() {
                if let Some(t) = prim.hit(slot as u32, &ray, t_max) {
                    if scan.is_none_or(|(best, id)| t < best || (t == best && prim.id < id)) {
                        scan = Some((t, prim.id));
                    }
                }
            }
            hits += usize::from(scan.is_some());
            // The first of the coincident spheres wins their ties.
            ties += usize::from(scan.is_some_and(|(_, id)| id == 49));
            let found = bvh
                .closest(&prims, &ray, t_max)
                .map(|hit| (hit.t, prims[hit.slot as usize].id));
            assert_eq!(found, scan, "ray {k}");
            assert_eq!(bvh.occluded(&prims, &ray, t_max), scan.is_some(), "ray {k}");
        }
        assert!(hits > 1000, "{hits} of 4000 rays hit: too few to compare");
        assert!(
            ties > 100,
            "{ties} rays met the coincident spheres: too few"
        );
    }

    #[test]
    fn the_hierarchy_finds_what_a_scan_finds_in_f64() {
        the_hierarchy_finds_what_a_scan_finds::<f64>();
    }

    #[test]
    fn the_hierarchy_finds_what_a_scan_finds_in_f32() {
        the_hierarchy_finds_what_a_scan_finds::<f32>();
    }
}
