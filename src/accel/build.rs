//! The binned-SAH build: a first pass plans the tree's shape (in parallel
//! for large subtrees), binning each node on its centroids' widest axis, a
//! second writes its nodes into an array of exactly their size; the result
//! does not depend on the number of threads.

use super::bvh::Binary;
use super::node::{EMPTY, Item, Node, Pair, half_area, union};
use super::walk::STACK_SIZE;

/// Bins on a node's split axis for the surface area heuristic.
pub(super) const BINS: usize = 16;
/// Leaves never hold more primitives than this.
pub(super) const MAX_LEAF: usize = 8;
// The build's first pass keeps leaf sizes in a byte.
const _: () = assert!(MAX_LEAF <= u8::MAX as usize);
/// Cost of visiting an interior node (two box tests), relative to one
/// primitive test.
pub(super) const TRAVERSAL_COST: f64 = 1.5;
/// Below this depth splits follow the SAH; deeper ones split at the median,
/// which bounds the depth (and so the traversal stack) for any input.
pub(super) const SAH_MAX_DEPTH: usize = 48;
// A traversal pushes at most one node a level.
const _: () = assert!(SAH_MAX_DEPTH + 32 < STACK_SIZE);
/// Subtrees with at least this many primitives build their halves in parallel.
pub(super) const PARALLEL_MIN: usize = 4096;

impl Binary {
    /// Builds the tree over `items`; the result does not depend on the
    /// number of threads, and the build needs little beyond the items and
    /// the final arrays.
    pub(crate) fn build(mut items: Vec<Item>) -> Binary {
        if items.is_empty() {
            return Binary::default();
        }
        // Two passes keep the peak at the items plus the final arrays: the
        // first splits and keeps only the tree's shape (a byte a node), the
        // second writes the nodes, boxes from the items, into an array of
        // exactly their size. (Keeping the leaves' boxes instead, to free the
        // items sooner, peaks higher: freed in small blocks, they stay resident.)
        let ext = Extents::of(&items);
        let plan = plan(&mut items, &ext, 0);
        // Pair 0 holds the root (its sibling slot is unused); its descendants follow.
        let mut pairs = vec![Pair::default(); 1 + plan.pairs()];
        let (head, rest) = pairs.split_at_mut(1);
        head[0].0[0] = lay_out(&plan, &items, 0, rest, 1);
        drop(plan);
        let prims = items.iter().map(|it| it.index).collect();
        drop(items);
        Binary { pairs, prims }
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Extents {
    pub(super) bounds: [f32; 6],
    cent: [f32; 6],
}

impl Extents {
    const EMPTY: Extents = Extents {
        bounds: EMPTY,
        cent: EMPTY,
    };

    #[inline(always)]
    fn grow(&mut self, it: &Item) {
        union(&mut self.bounds, &it.bounds);
        self.grow_centroids(it);
    }

    /// Grows the centroids' extent alone.
    #[inline(always)]
    fn grow_centroids(&mut self, it: &Item) {
        let c = [it.centroid(0), it.centroid(1), it.centroid(2)];
        union(&mut self.cent, &[c[0], c[1], c[2], c[0], c[1], c[2]]);
    }

    pub(super) fn of(items: &[Item]) -> Extents {
        let mut e = Extents::EMPTY;
        for it in items {
            e.grow(it);
        }
        e
    }
}

/// The shape of a subtree, decided by the first pass of the build: which
/// items go where and which nodes are leaves, but no boxes yet.
#[derive(Debug)]
enum BuildPlan {
    /// A subtree planned on one thread.
    Flat(FlatPlan),
    /// An interior node whose halves were planned in parallel.
    Split {
        /// Items of the left half (they come first).
        mid: usize,
        /// The left and right halves.
        halves: Box<(BuildPlan, BuildPlan)>,
        /// Interior nodes, so pairs, of the subtree.
        pairs: usize,
    },
}

/// A subtree planned on one thread, node by node in depth-first order.
#[derive(Debug, Default)]
struct FlatPlan {
    /// Per node: 0 for an interior node, else the leaf's primitive count.
    shape: Vec<u8>,
    /// Interior nodes, so pairs, of the subtree.
    pairs: usize,
}

impl BuildPlan {
    /// Interior nodes of the subtree: the pairs its descendants fill.
    fn pairs(&self) -> usize {
        match self {
            BuildPlan::Flat(flat) => flat.pairs,
            BuildPlan::Split { pairs, .. } => *pairs,
        }
    }
}

/// Plans the subtree over `items` (`ext` their extents), reordering them
/// into their final order; halves of at least [`PARALLEL_MIN`] items are
/// planned in parallel.
fn plan(items: &mut [Item], ext: &Extents, depth: usize) -> BuildPlan {
    if items.len() >= PARALLEL_MIN
        && let Some((mid, left_ext, right_ext)) = split(items, ext, depth)
    {
        let (left, right) = items.split_at_mut(mid);
        let halves = rayon::join(
            || plan(left, &left_ext, depth + 1),
            || plan(right, &right_ext, depth + 1),
        );
        return BuildPlan::Split {
            mid,
            pairs: 1 + halves.0.pairs() + halves.1.pairs(),
            halves: Box::new(halves),
        };
    }
    let mut flat = FlatPlan::default();
    plan_flat(items, ext, depth, &mut flat);
    BuildPlan::Flat(flat)
}

/// Plans the subtree over `items` on this thread, appending its nodes to `flat`.
fn plan_flat(items: &mut [Item], ext: &Extents, depth: usize, flat: &mut FlatPlan) {
    match split(items, ext, depth) {
        // A leaf holds 1 to MAX_LEAF items (split never leaves more in one):
        // the count fits a u8 and is never 0.
        None => flat.shape.push(items.len() as u8),
        Some((mid, left_ext, right_ext)) => {
            flat.shape.push(0);
            flat.pairs += 1;
            let (left, right) = items.split_at_mut(mid);
            plan_flat(left, &left_ext, depth + 1, flat);
            plan_flat(right, &right_ext, depth + 1, flat);
        }
    }
}

/// Writes the subtree planned by `plan` over `items` (the first is primitive
/// `offset` of the final order) and returns its root: the pairs of its
/// interior nodes go, depth-first, into `out`, whose first pair has index `base`.
///
/// A node's box is the union of its items' boxes: the same values the split
/// computed. `out` holds exactly the subtree's pairs, so halves planned in
/// parallel are written in parallel.
fn lay_out(plan: &BuildPlan, items: &[Item], offset: u32, out: &mut [Pair], base: u32) -> Node {
    match plan {
        BuildPlan::Flat(flat) => {
            let mut writer = FlatWriter {
                plan: flat,
                next_node: 0,
                items,
                next_item: 0,
                offset,
                out,
                next_pair: 0,
                base,
            };
            writer.node()
        }
        BuildPlan::Split { mid, halves, .. } => {
            let (left_plan, right_plan) = &**halves;
            let (head, rest) = out.split_at_mut(1);
            let (left_out, right_out) = rest.split_at_mut(left_plan.pairs());
            let (left_items, right_items) = items.split_at(*mid);
            let left_base = base + 1;
            let right_base = left_base + left_plan.pairs() as u32;
            let right_offset = offset + *mid as u32;
            let (l, r) = rayon::join(
                || lay_out(left_plan, left_items, offset, left_out, left_base),
                || lay_out(right_plan, right_items, right_offset, right_out, right_base),
            );
            head[0] = Pair([l, r]);
            interior(&l, &r, base)
        }
    }
}

/// The interior node over children `l` and `r`, whose pair has index `pair`.
#[inline]
fn interior(l: &Node, r: &Node, pair: u32) -> Node {
    let mut bounds = l.bounds;
    union(&mut bounds, &r.bounds);
    Node {
        bounds,
        start: 2 * pair,
        count: 0,
    }
}

/// Writes the nodes of a [`FlatPlan`], depth-first.
struct FlatWriter<'a> {
    /// The plan.
    plan: &'a FlatPlan,
    /// Next entry of the plan's shape.
    next_node: usize,
    /// The subtree's items, in final order.
    items: &'a [Item],
    /// First item of the next leaf.
    next_item: usize,
    /// Index of the subtree's first primitive in the final order.
    offset: u32,
    /// The subtree's pairs.
    out: &'a mut [Pair],
    /// Next unwritten pair of `out`.
    next_pair: usize,
    /// Index of `out[0]` in the whole tree.
    base: u32,
}

impl FlatWriter<'_> {
    /// Writes the next node's subtree and returns the node.
    fn node(&mut self) -> Node {
        let code = self.plan.shape[self.next_node] as usize;
        self.next_node += 1;
        if code > 0 {
            let first = self.next_item;
            self.next_item += code;
            let mut bounds = EMPTY;
            for it in &self.items[first..first + code] {
                union(&mut bounds, &it.bounds);
            }
            return Node {
                bounds,
                start: self.offset + first as u32,
                count: code as u32,
            };
        }
        let p = self.next_pair;
        self.next_pair += 1;
        let l = self.node();
        let r = self.node();
        self.out[p] = Pair([l, r]);
        interior(&l, &r, self.base + p as u32)
    }
}

/// Bin accumulator.
#[derive(Clone, Copy)]
struct Bin {
    bounds: [f32; 6],
    count: u32,
}

/// Decides how to split `items` and reorders them so the first `mid` go
/// left; returns `mid` and both sides' extents, or `None` for a leaf.
pub(super) fn split(
    items: &mut [Item],
    ext: &Extents,
    depth: usize,
) -> Option<(usize, Extents, Extents)> {
    let n = items.len();
    if n <= 1 {
        return None;
    }
    let cent = &ext.cent;
    // The widest axis of the centroids (the first of equals): bins on it
    // alone, as pbrt does, cost a third of binning all three.
    let mut axis = 0;
    for a in 1..3 {
        if cent[a + 3] - cent[a] > cent[axis + 3] - cent[axis] {
            axis = a;
        }
    }
    let width = cent[axis + 3] - cent[axis];
    if depth < SAH_MAX_DEPTH && width > 0.0 {
        // Fewer bins for small nodes: binning costs little, evaluating bins does.
        let bins_used = n.clamp(4, BINS);
        // Bin index of a centroid: ((lo + hi) / 2 - cmin) * bins / width,
        // folded into one multiply-add.
        let scale = 0.5 * bins_used as f32 / width;
        let shift = cent[axis] * (2.0 * scale);
        let bin_of = |it: &Item| -> usize {
            let k = (it.bounds[axis] + it.bounds[axis + 3]) * scale - shift;
            // Saturating cast (to i32: fewer instructions than to usize):
            // negatives and NaN go to 0; the clamp catches the top edge.
            (k as i32).clamp(0, bins_used as i32 - 1) as usize
        };
        let mut bins = [Bin {
            bounds: EMPTY,
            count: 0,
        }; BINS];
        for it in items.iter() {
            let bin = &mut bins[bin_of(it)];
            union(&mut bin.bounds, &it.bounds);
            bin.count += 1;
        }
        // The bins that hold items, in order. A split after an empty bin
        // parts the items as the split after the last bin before it that
        // holds some, at the same cost, and is weighed after it; a split
        // before the first or after the last leaves a side empty. Only
        // splits after a bin that holds items, before another, are weighed.
        let mut held = [0u8; BINS];
        let mut m = 0;
        for (i, bin) in bins[..bins_used].iter().enumerate() {
            held[m] = i as u8;
            m += usize::from(bin.count > 0);
        }
        // Cost (half area x count of both sides) of splitting after held
        // bin r (a side's box: the union of its bins', so of its items').
        let mut right_cost = [0f64; BINS];
        let mut acc = EMPTY;
        let mut count = 0;
        for r in (1..m).rev() {
            let bin = &bins[held[r] as usize];
            union(&mut acc, &bin.bounds);
            count += bin.count;
            right_cost[r] = half_area(&acc) * count as f64;
        }
        let mut best: Option<(f64, usize, [f32; 6])> = None;
        let mut acc = EMPTY;
        let mut count = 0;
        for r in 0..m.saturating_sub(1) {
            let bin = &bins[held[r] as usize];
            union(&mut acc, &bin.bounds);
            count += bin.count;
            let cost = half_area(&acc) * count as f64 + right_cost[r + 1];
            if best.is_none_or(|(c, _, _)| cost < c) {
                best = Some((cost, r, acc));
            }
        }
        if let Some((cost, r, left_bounds)) = best {
            let area = half_area(&ext.bounds);
            let split_pays = TRAVERSAL_COST * area + cost < n as f64 * area;
            if !split_pays && n <= MAX_LEAF {
                return None;
            }
            let i = held[r] as usize;
            // The right side's box, its bins in the sweep's order: `union`
            // keeps the first of 0 and −0, and the tree's bits are kept.
            let mut right_bounds = EMPTY;
            for &j in held[r + 1..m].iter().rev() {
                union(&mut right_bounds, &bins[j as usize].bounds);
            }
            // Both sides hold items: bins `held[r]` and `held[r + 1]` do
            // (by the same `bin_of` as the partition's).
            let mut left = Extents {
                bounds: left_bounds,
                cent: EMPTY,
            };
            let mut right = Extents {
                bounds: right_bounds,
                cent: EMPTY,
            };
            // Hoare's partition: each item is read once, and only pairs on
            // the wrong sides move.
            let (mut lo, mut hi) = (0, n);
            loop {
                while lo < hi && bin_of(&items[lo]) <= i {
                    left.grow_centroids(&items[lo]);
                    lo += 1;
                }
                while lo < hi && bin_of(&items[hi - 1]) > i {
                    right.grow_centroids(&items[hi - 1]);
                    hi -= 1;
                }
                if lo == hi {
                    return Some((lo, left, right));
                }
                // items[lo] goes right and items[hi - 1] left.
                items.swap(lo, hi - 1);
                left.grow_centroids(&items[lo]);
                right.grow_centroids(&items[hi - 1]);
                lo += 1;
                hi -= 1;
            }
        }
    }
    if n <= MAX_LEAF {
        return None;
    }
    // Inseparable centroids or too deep: median split on the widest centroid axis.
    let mid = n / 2;
    items.select_nth_unstable_by(mid, |p, q| p.centroid(axis).total_cmp(&q.centroid(axis)));
    Some((mid, Extents::of(&items[..mid]), Extents::of(&items[mid..])))
}
