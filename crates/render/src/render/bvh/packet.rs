//! Coherent rays through the hierarchy together: a packet of up to
//! [`PACKET`] rays (neighbouring camera rays of a row) walks the 4-wide
//! tree once, each node fetched once for all of them, with a bit mask of
//! the rays still inside each subtree.
//!
//! Every ray keeps its own reach and its own nearest hit, and at a node
//! each active ray makes the very slab test [`Bvh::closest`] makes
//! ([`Slab::enter`]) against its own reach, so a ray tests every primitive
//! whose padded box it enters before its nearest hit so far, and perhaps
//! some more (a leaf is tested for every ray the packet brought to it).
//! Testing more primitives cannot change the nearest hit, and the same
//! [`Prim::hit`] and tie rule (the lower IR index at equal `t`) pick it,
//! so each ray finds bit for bit what [`Bvh::closest`] finds.

use arrayvec::ArrayVec;

use super::{reach_f32, Bvh, Child, Slab, STACK};
use crate::render::geometry::Ray;
use crate::render::prim::{Hit, Prim};
use crate::render::real::Real;

/// Rays in a packet at most.
pub const PACKET: usize = 8;

impl Bvh {
    /// [`Bvh::closest`] of every ray of `rays` (at most [`PACKET`]):
    /// where ray `k` hits something in `(0, t_max[k])`, `t_max[k]` becomes
    /// the hit's `t` and `slots[k]` its slot; elsewhere neither changes.
    pub fn closest_packet<R: Real>(
        &self,
        prims: &[Prim<R>],
        rays: &[Ray<R>],
        t_max: &mut [R],
        slots: &mut [u32],
    ) {
        let n = rays.len();
        debug_assert!(n <= PACKET && t_max.len() == n && slots.len() == n);
        let slabs: ArrayVec<Slab, PACKET> = rays.iter().map(Slab::new).collect();
        let limits: ArrayVec<R, PACKET> = t_max.iter().copied().collect();
        let mut reach: ArrayVec<f32, PACKET> = limits.iter().map(|&t| reach_f32(t)).collect();
        let mut best: [Option<Hit<R>>; PACKET] = [None; PACKET];
        // Children still to visit with the rays that entered them.
        let mut stack = ArrayVec::<(u32, u32), STACK>::new();
        let mut test_leaf = |child: Child, mut mask: u32, reach: &mut [f32]| {
            while mask != 0 {
                let k = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                for slot in child.slots() {
                    let prim = &prims[slot as usize];
                    if let Some(t) = prim.hit(slot, &rays[k], limits[k]) {
                        if best[k].is_none_or(|hit| {
                            t < hit.t || (t == hit.t && prim.id < prims[hit.slot as usize].id)
                        }) {
                            best[k] = Some(Hit { t, slot });
                            reach[k] = reach_f32(t);
                        }
                    }
                }
            }
        };
        let mut node = 0u32;
        let mut active = (1u32 << n) - 1;
        loop {
            let w = &self.nodes[node as usize];
            // Per child: the rays that enter it, and the nearest entry.
            let mut entered = [0u32; 4];
            let mut nearest = [f32::INFINITY; 4];
            let mut rays_left = active;
            while rays_left != 0 {
                let k = rays_left.trailing_zeros() as usize;
                rays_left &= rays_left - 1;
                let (near, mut lanes) = slabs[k].enter(w, reach[k]);
                while lanes != 0 {
                    let lane = lanes.trailing_zeros() as usize;
                    lanes &= lanes - 1;
                    entered[lane] |= 1 << k;
                    nearest[lane] = nearest[lane].min(near[lane]);
                }
            }
            // Leaves are tested now; interior children are visited
            // nearest first: the nearest next, the others pushed farthest
            // first.
            let mut order = ArrayVec::<(f32, usize), 4>::new();
            for lane in 0..4 {
                if entered[lane] == 0 {
                    continue;
                }
                let child = Child::of(w, lane, nearest[lane]);
                if child.is_interior() {
                    let at = order.iter().position(|&(e, _)| e > nearest[lane]);
                    order.insert(at.unwrap_or(order.len()), (nearest[lane], lane));
                } else {
                    test_leaf(child, entered[lane], &mut reach);
                }
            }
            if let Some(&(_, first)) = order.first() {
                for &(_, lane) in order[1..].iter().rev() {
                    stack.push((w.index[lane], entered[lane]));
                }
                node = w.index[first];
                active = entered[first];
                continue;
            }
            let Some((next, mask)) = stack.pop() else {
                break;
            };
            node = next;
            active = mask;
        }
        for k in 0..n {
            if let Some(hit) = best[k] {
                (t_max[k], slots[k]) = (hit.t, hit.slot);
            }
        }
    }
}
