//! Collapsing the binary hierarchy into the 4-wide one the tracer walks,
//! choosing which binary nodes become wide nodes by their expected cost.
//!
//! Every wide node is a binary node whose subtree is cut into at most four
//! children; the leaves are the binary tree's, and every leaf is a child
//! of exactly one wide node whatever the cut, so the primitive tests a ray
//! makes do not depend on it: the cut only decides how many wide nodes a
//! ray visits. A wide node is visited
//! - by a ray from outside that enters its box: in proportion to the
//!   box's surface area, as in the surface area heuristic;
//! - by every ray that starts on a primitive under it (reflection and
//!   shadow rays, which in a dense scene are most rays): in proportion to
//!   the primitives it holds. Area alone misses these, and it favours
//!   deep chains of wide nodes over small primitives.
//!
//! The expected visits of a wide node are the sum of its two shares, each
//! relative to the root's, and the cut that minimises their total over the
//! tree is found exactly by dynamic programming over the binary nodes,
//! children before parents (Ylitie, Karras and Laine 2017 do the same for
//! area alone): for each node and each number of slots from one to four,
//! the least cost of its subtree given that many children's lanes of the
//! wide node above, either the node whole (becoming a wide node itself) or
//! its slots shared between its two children.

use arrayvec::ArrayVec;

use super::{Node, Wide};

/// What the dynamic programme found for one binary node, for each number
/// of lanes `s` (index `s - 1`) its subtree may fill in the wide node
/// above.
#[derive(Clone, Copy)]
struct Cut {
    /// The least expected number of wide-node visits in the subtree.
    cost: [f64; 4],
    /// Lanes given to the first child when sharing `s` lanes between the
    /// two children is the cheapest; 0 when the node stays whole.
    first_lanes: [u8; 4],
    /// The primitives under the node.
    under: u32,
}

/// Cuts of every binary node, so a node made wide knows how to share its
/// four lanes between its children.
pub(super) struct Plan {
    cuts: Vec<Cut>,
    /// Per node, the first child's lanes when it is made a wide node.
    wide_first_lanes: Vec<u8>,
}

impl Plan {
    /// The cheapest cut of the binary tree `nodes` over `primitives`
    /// (depth-first order: an interior node's first child is the next
    /// node, so children come after their parents and a reverse pass sees
    /// them first).
    pub(super) fn new(nodes: &[Node], primitives: usize) -> Plan {
        let area = |n: &Node| n.bounds().area();
        let root_area = area(&nodes[0]);
        let root_count = primitives.max(1) as f64;
        // A root box of no area (coincident primitives) weighs by count
        // alone: no 0 / 0.
        let area_share = |n: &Node| {
            if root_area > 0.0 {
                area(n) / root_area
            } else {
                0.0
            }
        };
        let leaf = Cut {
            cost: [0.0; 4],
            first_lanes: [0; 4],
            under: 0,
        };
        let mut cuts = vec![leaf; nodes.len()];
        let mut wide_first_lanes = vec![0u8; nodes.len()];
        for (i, n) in nodes.iter().enumerate().rev() {
            if n.count() > 0 {
                cuts[i].under = n.count() as u32;
                continue;
            }
            let (first, second) = (&cuts[i + 1], &cuts[n.index()]);
            let under = first.under + second.under;
            // The cheapest sharing of 2, 3 and 4 lanes between the two
            // children: its cost and the first child's lanes.
            let mut shared = [(f64::INFINITY, 0u8); 3];
            for (lanes, cheapest) in (2..=4).zip(&mut shared) {
                for k in 1..lanes {
                    let cost = first.cost[k - 1] + second.cost[lanes - k - 1];
                    if cost < cheapest.0 {
                        *cheapest = (cost, k as u8);
                    }
                }
            }
            let (below, wide_first) = shared[2];
            wide_first_lanes[i] = wide_first;
            let whole = area_share(n) + f64::from(under) / root_count + below;
            let mut cut = Cut {
                cost: [whole; 4],
                first_lanes: [0; 4],
                under,
            };
            for (lanes, &(cost, first_lanes)) in (2..=4).zip(&shared) {
                if cost < whole {
                    cut.cost[lanes - 1] = cost;
                    cut.first_lanes[lanes - 1] = first_lanes;
                }
            }
            cuts[i] = cut;
        }
        Plan {
            cuts,
            wide_first_lanes,
        }
    }

    /// Collapse the binary subtree at `root` into wide nodes appended to
    /// `wide`, by the plan's cut; returns the index of the wide node made.
    /// Children keep their depth-first order (the first child's first).
    pub(super) fn collapse(&self, nodes: &[Node], root: usize, wide: &mut Vec<Wide>) -> usize {
        let mut children = ArrayVec::<usize, 4>::new();
        if nodes[root].count() > 0 {
            children.push(root);
        } else {
            let first_lanes = usize::from(self.wide_first_lanes[root]);
            self.lanes_of(nodes, root + 1, first_lanes, &mut children);
            self.lanes_of(nodes, nodes[root].index(), 4 - first_lanes, &mut children);
        }
        let at = wide.len();
        wide.push(Wide::EMPTY);
        let mut made = Wide::EMPTY;
        for (lane, &c) in children.iter().enumerate() {
            let n = &nodes[c];
            for axis in 0..3 {
                made.planes[axis][lane] = n.lo[axis];
                made.planes[3 + axis][lane] = n.hi[axis];
            }
            if n.count() > 0 {
                made.index[lane] = n.index() as u32;
                made.count[lane] = n.count() as u32;
            } else {
                made.index[lane] = self.collapse(nodes, c, wide) as u32;
            }
        }
        wide[at] = made;
        at
    }

    /// The children filling at most `lanes` lanes for the subtree at `n`:
    /// `n` itself, or its children's shares.
    fn lanes_of(&self, nodes: &[Node], n: usize, lanes: usize, children: &mut ArrayVec<usize, 4>) {
        let first_lanes = usize::from(self.cuts[n].first_lanes[lanes - 1]);
        if first_lanes == 0 {
            children.push(n);
        } else {
            self.lanes_of(nodes, n + 1, first_lanes, children);
            self.lanes_of(nodes, nodes[n].index(), lanes - first_lanes, children);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::bvh::{build, Aabb, Item};
    use glam::Vec3A;

    /// Sphere-like boxes of varied sizes at random places.
    fn items(count: usize) -> Vec<Item> {
        let mut random = crate::render::fixture::uniform(0x9E37_79B9_7F4A_7C15);
        (0..count)
            .map(|slot| {
                let centre = Vec3A::new(random() as f32, random() as f32, random() as f32) * 10.0;
                let radius = 0.05 + 0.5 * random() as f32;
                Item::new(centre - radius, centre + radius, slot as u32)
            })
            .collect()
    }

    fn area(lo: [f32; 3], hi: [f32; 3]) -> f64 {
        let (lo, hi) = (lo.into(), hi.into());
        Aabb { lo, hi }.area()
    }

    /// The expected visits of the wide subtree at `node`, whose box is
    /// `lo`–`hi`, by the plan's measure, and the primitives under it.
    fn realised(
        wide: &[Wide],
        node: usize,
        lo: [f32; 3],
        hi: [f32; 3],
        root: (f64, f64),
    ) -> (f64, u32) {
        let w = &wide[node];
        let (mut cost, mut under) = (0.0, 0);
        for lane in 0..4 {
            if w.planes[0][lane] == f32::INFINITY {
                continue;
            }
            if w.count[lane] > 0 {
                under += w.count[lane];
                continue;
            }
            let lo = [0, 1, 2].map(|axis| w.planes[axis][lane]);
            let hi = [0, 1, 2].map(|axis| w.planes[3 + axis][lane]);
            let (c, u) = realised(wide, w.index[lane] as usize, lo, hi, root);
            cost += c;
            under += u;
        }
        (
            cost + area(lo, hi) / root.0 + f64::from(under) / root.1,
            under,
        )
    }

    #[test]
    fn the_wide_tree_costs_what_the_plan_says_and_less_than_binary_lanes() {
        let mut items = items(500);
        let mut nodes = Vec::new();
        build(&mut items, 0, 0, &mut nodes);
        let plan = Plan::new(&nodes, items.len());
        let mut wide = Vec::new();
        plan.collapse(&nodes, 0, &mut wide);
        let root = &nodes[0];
        let (lo, hi) = (
            [root.lo[0], root.lo[1], root.lo[2]],
            [root.hi[0], root.hi[1], root.hi[2]],
        );
        let root_area = area(lo, hi);
        let (cost, under) = realised(&wide, 0, lo, hi, (root_area, items.len() as f64));
        assert_eq!(under as usize, items.len(), "every primitive once");
        let planned = plan.cuts[0].cost[0];
        assert!(
            (cost - planned).abs() <= 1e-9 * planned,
            "{cost} against {planned}"
        );
        // Every binary interior node a wide node of two lanes: a valid cut,
        // and a dearer one.
        let mut under_node = vec![0u32; nodes.len()];
        let mut binary = 0.0;
        for (i, n) in nodes.iter().enumerate().rev() {
            if n.count() > 0 {
                under_node[i] = n.count() as u32;
            } else {
                under_node[i] = under_node[i + 1] + under_node[n.index()];
                let (lo, hi) = ([n.lo[0], n.lo[1], n.lo[2]], [n.hi[0], n.hi[1], n.hi[2]]);
                binary += area(lo, hi) / root_area + f64::from(under_node[i]) / items.len() as f64;
            }
        }
        assert!(
            wide.len() > 20 && planned < 0.75 * binary,
            "{planned} against {binary}"
        );
    }
}
