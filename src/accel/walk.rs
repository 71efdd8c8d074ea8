//! Single-ray walks of the wide tree: ordered, allocation-free, from the
//! root, up from a primitive's leaf, or within subtrees found once for a hull.

use super::bvh::{Bvh, NO_LEAF, ROOT, split_slot};
use super::hull::Hull;
use super::isa::Isa;
use super::node::{NO_CHILD, WIDTH};
use super::ray_box::{FAR_SLACK, MISS, RayBox};
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
    /// walk and how many primitives it tested. Every node and leaf visited
    /// and every test is counted into `tally`.
    ///
    /// For a ray leaving the surface of primitive `from`, the walk starts at
    /// its leaf and goes up, visiting at each level the node's other
    /// children. Those subtrees and the leaf make up the whole tree, so the
    /// same leaves are visited, but the primitives near the origin come
    /// first and the descent from the root is skipped: a shadow ray mostly
    /// meets its blocker a level or two up. Otherwise (`None`, or a
    /// primitive not in the tree) the walk is the root's subtree alone.
    ///
    /// `NEAREST`: a node's children entered are visited nearest first, for
    /// a nearest-hit query (a near hit lowers `t_best` and prunes the
    /// rest); otherwise in slot order, for an any-hit one, which any
    /// blocker ends: sorting would only delay the next node's load.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn traverse<const NEAREST: bool>(
        &self,
        from: Option<u32>,
        ray: &Ray,
        t_best: &mut f64,
        isa: Isa,
        tally: &mut impl QueryTally,
        mut leaf: impl FnMut(&[u32], &mut f64) -> (bool, usize),
    ) {
        if self.wide.is_empty() {
            return;
        }
        let rb = RayBox::new(ray);
        // A ray that misses the whole tree needs no stack.
        if rb.entry(&self.root, *t_best) == MISS {
            return;
        }
        if let [node] = &self.wide[..] {
            // One node, its children leaves (a scene of a few objects):
            // each entered in turn, none ordered, no stack; compiled for
            // `isa` like the deeper walks.
            isa.run(
                #[inline(always)]
                || {
                    tally.node();
                    let t = rb.entries(node, *t_best);
                    for k in (0..WIDTH).filter(|&k| node.count[k] > 0) {
                        let entered = t[k] != MISS && t[k] <= *t_best * FAR_SLACK;
                        if entered
                            && self.visit(node.child[k], node.count[k], t_best, tally, &mut leaf)
                        {
                            return;
                        }
                    }
                },
            );
            return;
        }
        let start = from
            .and_then(|p| self.leaf_of.get(p as usize).copied())
            .filter(|&k| k != NO_LEAF);
        // The start leaf's node (the leaf among its children; the root
        // without one), then each node up the path without the child just
        // come from.
        let (mut n, mut k) = (start.map_or(0, |slot| split_slot(slot).0), WIDTH);
        with_stack(
            isa,
            #[inline(always)]
            |stack| loop {
                if self.walk::<NEAREST>(&rb, n, k, t_best, stack, tally, &mut leaf) {
                    return;
                }
                match self.parent[n] {
                    ROOT => return,
                    up => (n, k) = split_slot(up),
                }
            },
        );
    }

    /// Visits the leaf of `count` primitives from `start`: `leaf` tests
    /// them, counted into `tally`. True when it stops the walk.
    #[inline(always)]
    fn visit(
        &self,
        start: u32,
        count: u32,
        t_best: &mut f64,
        tally: &mut impl QueryTally,
        leaf: &mut impl FnMut(&[u32], &mut f64) -> (bool, usize),
    ) -> bool {
        tally.node();
        let s = start as usize;
        let (stop, tested) = leaf(&self.prims[s..s + count as usize], t_best);
        tally.tests(tested);
        stop
    }

    /// Walks the subtree of `slot` if the ray enters its box: a leaf at
    /// once, a node with `walk`. True when `leaf` stopped it.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn enter_slot<const NEAREST: bool>(
        &self,
        rb: &RayBox,
        slot: u32,
        t_best: &mut f64,
        isa: Isa,
        tally: &mut impl QueryTally,
        leaf: &mut impl FnMut(&[u32], &mut f64) -> (bool, usize),
    ) -> bool {
        let (n, k) = split_slot(slot);
        let node = &self.wide[n];
        if rb.entry(&node.bounds(k), *t_best) == MISS {
            return false;
        }
        let (child, count) = (node.child[k], node.count[k]);
        if count > 0 {
            self.visit(child, count, t_best, tally, leaf)
        } else {
            with_stack(
                isa,
                #[inline(always)]
                |stack| self.walk::<NEAREST>(rb, child as usize, WIDTH, t_best, stack, tally, leaf),
            )
        }
    }

    /// The walk of [`Bvh::traverse`] from wide node `root`, leaving out its
    /// child `skip` (none if `skip` ≥ [`WIDTH`]), with a stack to use; true
    /// when `leaf` stopped it.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn walk<const NEAREST: bool>(
        &self,
        rb: &RayBox,
        root: usize,
        skip: usize,
        t_best: &mut f64,
        stack: &mut Stack,
        tally: &mut impl QueryTally,
        leaf: &mut impl FnMut(&[u32], &mut f64) -> (bool, usize),
    ) -> bool {
        let Stack { entry, t: stack_t } = stack;
        let mut sp = 0;
        // The current child: a node's index (count 0) or a leaf.
        let (mut child, mut count) = (root as u32, 0);
        let mut skip = skip;
        loop {
            if count > 0 {
                if self.visit(child, count, t_best, tally, leaf) {
                    return true;
                }
            } else {
                tally.node();
                let node = &self.wide[child as usize];
                let mut t = rb.entries(node, *t_best);
                if skip < WIDTH {
                    t[skip] = MISS;
                    skip = WIDTH;
                }
                let mut hit = 0u32;
                for (k, &t) in t.iter().enumerate() {
                    hit |= u32::from(t != MISS) << k;
                }
                // The mask only spares a bounds check: WIDTH − 1 pushes a
                // level, and the depth is below STACK_SIZE.
                let mut push = |k: usize| {
                    entry[sp & (WIDE_STACK - 1)] = (node.child[k], node.count[k]);
                    stack_t[sp & (WIDE_STACK - 1)] = t[k];
                    sp += 1;
                };
                if hit != 0 && NEAREST {
                    // The children entered, nearest first: push the others
                    // farthest first, go to the nearest.
                    let (order, n) = in_order(&t, hit);
                    order[1..n].iter().rev().for_each(|&k| push(k));
                    (child, count) = (node.child[order[0]], node.count[order[0]]);
                    continue;
                }
                if hit != 0 {
                    // In slot order: push all but the first, last first;
                    // go to the first.
                    let first = hit.trailing_zeros() as usize;
                    let mut rest = hit & (hit - 1);
                    while rest != 0 {
                        let k = (u32::BITS - 1 - rest.leading_zeros()) as usize;
                        push(k);
                        rest &= !(1 << k);
                    }
                    (child, count) = (node.child[first], node.count[first]);
                    continue;
                }
            }
            // Pop the last child pushed that may still hold a nearer hit.
            loop {
                if sp == 0 {
                    return false;
                }
                sp -= 1;
                if stack_t[sp & (WIDE_STACK - 1)] <= *t_best * FAR_SLACK {
                    (child, count) = entry[sp & (WIDE_STACK - 1)];
                    break;
                }
            }
        }
    }

    /// Up to `out.len()` subtrees (slots, or [`ROOT`] for the whole tree)
    /// that together hold every leaf whose box meets `hull`, each meeting
    /// it, leaves whose primitives `skip` accepts left out: the tree is
    /// searched breadth first, a subtree giving way to those of its
    /// children that meet the hull while they fit. Returns their number.
    pub(crate) fn reach(
        &self,
        hull: &Hull,
        out: &mut [u32],
        skip: impl Fn(&[u32]) -> bool,
    ) -> usize {
        let room = out.len().min(STACK_SIZE);
        if self.wide.is_empty() || room == 0 {
            return 0;
        }
        // Pending subtrees, first in first out; the pending and the found
        // together never exceed the room.
        let mut queue = [0u32; STACK_SIZE];
        queue[0] = ROOT;
        let (mut head, mut tail, mut len) = (0, 1, 0);
        while head < tail {
            let slot = queue[head & (STACK_SIZE - 1)];
            head += 1;
            let n = if slot == ROOT {
                0
            } else {
                let (n, k) = split_slot(slot);
                let (child, count) = (self.wide[n].child[k], self.wide[n].count[k]);
                if count > 0 {
                    let s = child as usize;
                    if !skip(&self.prims[s..s + count as usize]) {
                        out[len] = slot;
                        len += 1;
                    }
                    continue;
                }
                child as usize
            };
            let node = &self.wide[n];
            let meets: [bool; WIDTH] =
                std::array::from_fn(|k| node.child[k] != NO_CHILD && hull.meets(&node.bounds(k)));
            let kids = meets.iter().filter(|&&m| m).count();
            if len + (tail - head) + kids <= room {
                for (k, _) in meets.iter().enumerate().filter(|(_, m)| **m) {
                    queue[tail & (STACK_SIZE - 1)] = (n * WIDTH + k) as u32;
                    tail += 1;
                }
            } else {
                out[len] = slot;
                len += 1;
            }
        }
        len
    }

    /// [`Bvh::traverse`] over the subtrees `roots` (as [`Bvh::reach`] gives
    /// them) alone, in that order.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn traverse_within<const NEAREST: bool>(
        &self,
        roots: &[u32],
        ray: &Ray,
        t_best: &mut f64,
        isa: Isa,
        tally: &mut impl QueryTally,
        mut leaf: impl FnMut(&[u32], &mut f64) -> (bool, usize),
    ) {
        let rb = RayBox::new(ray);
        for &slot in roots {
            let stop = if slot == ROOT {
                with_stack(
                    isa,
                    #[inline(always)]
                    |stack| self.walk::<NEAREST>(&rb, 0, WIDTH, t_best, stack, tally, &mut leaf),
                )
            } else {
                self.enter_slot::<NEAREST>(&rb, slot, t_best, isa, tally, &mut leaf)
            };
            if stop {
                return;
            }
        }
    }
}

/// The lanes set in `mask` (bit k for lane k) in increasing order of
/// `key`, the lower lane first of equal keys, and their number.
#[inline(always)]
pub(super) fn in_order(key: &[f64; WIDTH], mut mask: u32) -> ([usize; WIDTH], usize) {
    let mut order = [0; WIDTH];
    let mut n = 0;
    while mask != 0 {
        let k = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let mut j = n;
        while j > 0 && key[order[j - 1]] > key[k] {
            order[j] = order[j - 1];
            j -= 1;
        }
        order[j] = k;
        n += 1;
    }
    (order, n)
}

/// Entries of a single ray's traversal stack: up to WIDTH − 1 pushes a
/// level of a tree shallower than [`STACK_SIZE`]; a power of two.
const WIDE_STACK: usize = WIDTH * STACK_SIZE;

/// A traversal stack: pending children (as in [`Wide`](super::node::Wide)) and their entry distances.
#[derive(Debug)]
struct Stack {
    entry: [(u32, u32); WIDE_STACK],
    t: [f64; WIDE_STACK],
}

impl Stack {
    const EMPTY: Stack = Stack {
        entry: [(0, 0); WIDE_STACK],
        t: [0.0; WIDE_STACK],
    };
}

thread_local! {
    /// Each thread's traversal stack, reused by every query on that thread.
    static STACK: RefCell<Stack> = const { RefCell::new(Stack::EMPTY) };
}

/// Runs `f` with this thread's traversal stack, compiled for `isa` (what
/// it inlines: the walk and its leaves' tests), and returns its result.
/// The stack lives in the thread, not in the caller's frame: a fresh one
/// would be zeroed (8 KiB) on every query, a large part of a shadow ray's cost.
#[inline(always)]
fn with_stack<R>(isa: Isa, f: impl FnOnce(&mut Stack) -> R) -> R {
    STACK.with(|cell| match cell.try_borrow_mut() {
        Ok(mut stack) => isa.run(
            #[inline(always)]
            || f(&mut stack),
        ),
        // Only a query made from inside another query's leaf finds it
        // borrowed.
        Err(_) => with_fresh_stack(isa, f),
    })
}

/// [`with_stack`] with a fresh stack, out of line: the 8 KiB stays out of
/// the frame of every query that does not need it.
#[cold]
#[inline(never)]
fn with_fresh_stack<R>(isa: Isa, f: impl FnOnce(&mut Stack) -> R) -> R {
    let mut stack = Stack::EMPTY;
    isa.run(
        #[inline(always)]
        || f(&mut stack),
    )
}
