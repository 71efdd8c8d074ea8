//! Single-ray walks of the tree: ordered, allocation-free, from the root,
//! up from a primitive's leaf, or within subtrees found once for a hull.

use super::bvh::{Bvh, NO_LEAF};
use super::hull::Hull;
use super::node::{Node, Pair};
use super::ray_box::{FAR_SLACK, MISS, RayBox, max_num};
use super::tally::QueryTally;
use crate::geometry::Ray;
use std::cell::RefCell;

/// Traversal stack entries: more than SAH_MAX_DEPTH + 32 median levels (u32
/// indices); a power of two so masked indices need no bounds check.
pub(crate) const STACK_SIZE: usize = 128;

impl Bvh {
    /// Visits, nearest box first, the leaves whose boxes the ray enters at a
    /// distance in [0, `t_best`] (up to the slack); `leaf` gets the leaf's
    /// primitives and may lower `t_best`, and returns whether to stop the
    /// walk and how many primitives it tested. Every node visited and every
    /// test is counted into `tally`.
    ///
    /// For a ray leaving the surface of primitive `from`, the walk starts at
    /// its leaf and goes up, visiting at each level the subtree beside the
    /// path. Those subtrees and the leaf make up the whole tree, so the same
    /// leaves are visited, but the primitives near the origin come first and
    /// the descent from the root is skipped: a shadow ray mostly meets its
    /// blocker a level or two up. Otherwise (`None`, or a primitive not in
    /// the tree) the walk is the root's subtree alone.
    #[inline]
    pub(crate) fn traverse(
        &self,
        from: Option<u32>,
        ray: &Ray,
        t_best: &mut f64,
        tally: &mut impl QueryTally,
        mut leaf: impl FnMut(&[u32], &mut f64) -> (bool, usize),
    ) {
        let Some(Pair([root, _])) = self.pairs.first() else {
            return;
        };
        let rb = RayBox::new(ray);
        // A ray that misses the whole tree needs no stack.
        if rb.entry(&root.bounds, *t_best) == MISS {
            return;
        }
        let start = from
            .and_then(|p| self.leaf_of.get(p as usize).copied())
            .filter(|&k| k != NO_LEAF)
            .unwrap_or(0);
        let up = |stack: &mut Stack| {
            // Subtree roots in order: the start node, then each sibling up the path.
            let mut k = start;
            let mut sub = start;
            loop {
                let node = self.node(sub);
                // The root's box was tested above.
                if (sub == 0 || rb.entry(&node.bounds, *t_best) != MISS)
                    && self.walk(&rb, node, t_best, stack, tally, &mut leaf)
                {
                    return;
                }
                if k == 0 {
                    return;
                }
                // Node k is not the root, so it has a sibling (ids 2p, 2p + 1
                // of pair p ≥ 1) and a parent.
                sub = k ^ 1;
                k = self.parent[k as usize >> 1];
            }
        };
        with_stack(up);
    }

    /// The walk of [`Bvh::traverse`] from `root`, with a stack to use; true
    /// when `leaf` stopped it.
    #[inline(always)]
    fn walk(
        &self,
        rb: &RayBox,
        root: &Node,
        t_best: &mut f64,
        stack: &mut Stack,
        tally: &mut impl QueryTally,
        mut leaf: impl FnMut(&[u32], &mut f64) -> (bool, usize),
    ) -> bool {
        let Stack {
            node: stack_node,
            t: stack_t,
        } = stack;
        let mut sp = 0;
        let mut node = root;
        loop {
            tally.node();
            if node.count > 0 {
                let s = node.start as usize;
                let (stop, tested) = leaf(&self.prims[s..s + node.count as usize], t_best);
                tally.tests(tested);
                if stop {
                    return true;
                }
            } else {
                let pair = &self.pairs[node.start as usize >> 1].0;
                let ta = rb.entry(&pair[0].bounds, *t_best);
                let tb = rb.entry(&pair[1].bounds, *t_best);
                let (hit_a, hit_b) = (ta != MISS, tb != MISS);
                if hit_a || hit_b {
                    // Go to the nearer child, push the other if hit. The order
                    // is a coin toss for the branch predictor, so it is chosen
                    // by arithmetic; a missed child has entry MISS = ∞, so it
                    // is never the nearer one.
                    let a_first = ta <= tb;
                    // The mask only spares a bounds check: sp <= depth <=
                    // SAH_MAX_DEPTH + 32 < STACK_SIZE (one push per level).
                    stack_node[sp & (STACK_SIZE - 1)] = node.start + a_first as u32;
                    stack_t[sp & (STACK_SIZE - 1)] = max_num(ta, tb);
                    sp += (hit_a && hit_b) as usize;
                    node = &pair[!a_first as usize];
                    continue;
                }
            }
            // Pop the nearest pending node that may still hold a nearer hit.
            loop {
                if sp == 0 {
                    return false;
                }
                sp -= 1;
                if stack_t[sp & (STACK_SIZE - 1)] <= *t_best * FAR_SLACK {
                    node = self.node(stack_node[sp & (STACK_SIZE - 1)]);
                    break;
                }
            }
        }
    }

    /// Up to `out.len()` subtrees (node ids) that together hold every leaf
    /// whose box meets `hull`, each meeting it, leaves whose primitives
    /// `skip` accepts left out: the tree is searched breadth first, a node
    /// giving way to those of its children that meet the hull while they
    /// fit. Returns their number.
    pub(crate) fn reach(
        &self,
        hull: &Hull,
        out: &mut [u32],
        skip: impl Fn(&[u32]) -> bool,
    ) -> usize {
        let Some(Pair([root, _])) = self.pairs.first() else {
            return 0;
        };
        let room = out.len().min(STACK_SIZE);
        if room == 0 || !hull.meets(&root.bounds) {
            return 0;
        }
        // Pending nodes, first in first out; the pending and the found
        // together never exceed the room.
        let mut queue = [0u32; STACK_SIZE];
        let (mut head, mut tail, mut len) = (0, 1, 0);
        while head < tail {
            let id = queue[head & (STACK_SIZE - 1)];
            head += 1;
            let node = self.node(id);
            let s = node.start as usize;
            if node.count > 0 {
                if !skip(&self.prims[s..s + node.count as usize]) {
                    out[len] = id;
                    len += 1;
                }
                continue;
            }
            let pair = &self.pairs[s >> 1].0;
            let meets = [hull.meets(&pair[0].bounds), hull.meets(&pair[1].bounds)];
            let kids = meets.iter().filter(|&&m| m).count();
            if len + (tail - head) + kids <= room {
                for (k, _) in meets.iter().enumerate().filter(|(_, m)| **m) {
                    queue[tail & (STACK_SIZE - 1)] = node.start + k as u32;
                    tail += 1;
                }
            } else {
                out[len] = id;
                len += 1;
            }
        }
        len
    }

    /// [`Bvh::traverse`] over the subtrees `roots` alone, in that order.
    #[inline]
    pub(crate) fn traverse_within(
        &self,
        roots: &[u32],
        ray: &Ray,
        t_best: &mut f64,
        tally: &mut impl QueryTally,
        mut leaf: impl FnMut(&[u32], &mut f64) -> (bool, usize),
    ) {
        let rb = RayBox::new(ray);
        for &id in roots {
            let node = self.node(id);
            if rb.entry(&node.bounds, *t_best) == MISS {
                continue;
            }
            // A leaf needs no stack.
            let s = node.start as usize;
            let stop = if node.count > 0 {
                tally.node();
                let (stop, tested) = leaf(&self.prims[s..s + node.count as usize], t_best);
                tally.tests(tested);
                stop
            } else {
                let mut stop = false;
                with_stack(|stack| stop = self.walk(&rb, node, t_best, stack, tally, &mut leaf));
                stop
            };
            if stop {
                return;
            }
        }
    }
}

/// A traversal stack: pending node ids and their entry distances.
#[derive(Debug)]
struct Stack {
    node: [u32; STACK_SIZE],
    t: [f64; STACK_SIZE],
}

impl Stack {
    const EMPTY: Stack = Stack {
        node: [0; STACK_SIZE],
        t: [0.0; STACK_SIZE],
    };
}

thread_local! {
    /// Each thread's traversal stack, reused by every query on that thread.
    static STACK: RefCell<Stack> = const { RefCell::new(Stack::EMPTY) };
}

/// Runs `f` with this thread's traversal stack. The stack lives in the
/// thread, not in the caller's frame: a fresh one would be zeroed (1.5 KiB)
/// on every query, a large part of a shadow ray's cost.
#[inline(always)]
fn with_stack(f: impl FnOnce(&mut Stack)) {
    STACK.with(|cell| match cell.try_borrow_mut() {
        Ok(mut stack) => f(&mut stack),
        // Only a query made from inside another query's leaf gets here.
        Err(_) => {
            let mut fresh = Stack::EMPTY;
            f(&mut fresh)
        }
    });
}
