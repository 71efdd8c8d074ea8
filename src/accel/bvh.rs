//! A bounding volume hierarchy over boxes: binned-SAH build into a flat
//! array of 32-byte nodes, and an ordered, allocation-free traversal from
//! the root or up from a primitive's leaf.

use super::tally::QueryTally;
use crate::geometry::{Aabb, Ray};
use glam::DVec3;
use std::cell::RefCell;

/// Bins per axis for the surface area heuristic.
const BINS: usize = 16;
/// Leaves never hold more primitives than this.
const MAX_LEAF: usize = 8;
// The build's first pass keeps leaf sizes in a byte.
const _: () = assert!(MAX_LEAF <= u8::MAX as usize);
/// Cost of visiting an interior node (two box tests), relative to one
/// primitive test.
const TRAVERSAL_COST: f64 = 1.5;
/// Below this depth splits follow the SAH; deeper ones split at the median,
/// which bounds the depth (and so the traversal stack) for any input.
const SAH_MAX_DEPTH: usize = 48;
/// Traversal stack entries: more than SAH_MAX_DEPTH + 32 median levels (u32
/// indices); a power of two so masked indices need no bounds check.
pub(crate) const STACK_SIZE: usize = 128;
/// Subtrees with at least this many primitives build their halves in parallel.
const PARALLEL_MIN: usize = 4096;
/// Relative slack on the far distance of a box test: absorbs the rounding
/// of the slab arithmetic and of the primitive tests, so no hit is lost.
pub(crate) const FAR_SLACK: f64 = 1.0 + 1.0 / (1u64 << 30) as f64;
/// Relative padding of primitive boxes, of their size plus their distance
/// from the origin (what the rounding errors of the primitive tests scale
/// with), applied before rounding them outward to f32.
const BOX_PAD: f64 = 1.0 / (1u64 << 36) as f64;
/// Boxes with a coordinate beyond this stay out of the tree (f32 range).
const MAX_COORD: f64 = 1e30;

/// One node of the tree: 32 bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub(crate) struct Node {
    /// Lowest corner (x, y, z) then highest corner, rounded outward to f32.
    pub bounds: [f32; 6],
    /// Interior node: id of the first child (even; the second follows it).
    /// Leaf: index of its first entry in [`Bvh::prims`].
    pub start: u32,
    /// Number of primitives of a leaf; 0 for an interior node.
    pub count: u32,
}

/// Two sibling nodes, on one 64-byte cache line. Node id `k` is
/// `pairs[k / 2].0[k % 2]`; the root is id 0 (its sibling slot is unused).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Pair(pub [Node; 2]);

/// A primitive's box and index while the tree is built.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Item {
    /// Box as in [`Node::bounds`].
    bounds: [f32; 6],
    /// Index of the primitive in the caller's list.
    index: u32,
}

impl Item {
    /// The item for primitive `index` with bounds `b`, or `None` when the
    /// box is not finite or too large for f32 (such objects are tested apart).
    pub(crate) fn new(index: u32, b: &Aabb) -> Option<Item> {
        let lo = b.min.to_array();
        let hi = b.max.to_array();
        let mut extent: f64 = 0.0;
        let mut mag: f64 = 0.0;
        for a in 0..3 {
            let ok = lo[a] <= hi[a] && lo[a].abs() <= MAX_COORD && hi[a].abs() <= MAX_COORD;
            if !ok {
                return None;
            }
            extent = extent.max(hi[a] - lo[a]);
            mag = mag.max(lo[a].abs()).max(hi[a].abs());
        }
        let pad = (extent + mag) * BOX_PAD;
        let mut bounds = [0.0; 6];
        for a in 0..3 {
            bounds[a] = f32_down(lo[a] - pad);
            bounds[a + 3] = f32_up(hi[a] + pad);
        }
        Some(Item { bounds, index })
    }

    /// Index of the primitive in the caller's list.
    pub(crate) fn index(&self) -> u32 {
        self.index
    }

    /// Centroid coordinate on `axis` (halves first: no overflow).
    #[inline]
    fn centroid(&self, axis: usize) -> f32 {
        self.bounds[axis] * 0.5 + self.bounds[axis + 3] * 0.5
    }
}

/// The largest f32 not above `x`.
fn f32_down(x: f64) -> f32 {
    let f = x as f32;
    if f as f64 > x { f.next_down() } else { f }
}

/// The smallest f32 not below `x`.
fn f32_up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x { f.next_up() } else { f }
}

/// An empty box for unions.
const EMPTY: [f32; 6] = [
    f32::INFINITY,
    f32::INFINITY,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
];

/// Grows `a` to hold `b` (build boxes are finite: plain comparisons suffice).
#[inline(always)]
fn union(a: &mut [f32; 6], b: &[f32; 6]) {
    for k in 0..3 {
        a[k] = if b[k] < a[k] { b[k] } else { a[k] };
        a[k + 3] = if b[k + 3] > a[k + 3] {
            b[k + 3]
        } else {
            a[k + 3]
        };
    }
}

/// Half the surface area (0 for empty boxes), in f64: no overflow.
#[inline]
fn half_area(b: &[f32; 6]) -> f64 {
    let d = [
        b[3] as f64 - b[0] as f64,
        b[4] as f64 - b[1] as f64,
        b[5] as f64 - b[2] as f64,
    ];
    if d[0] < 0.0 || d[1] < 0.0 || d[2] < 0.0 {
        0.0
    } else {
        d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
    }
}

/// The tree: nodes in sibling pairs (root first) and the primitive indices
/// of the leaves.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh {
    /// Node pairs, in depth-first order. Empty when there are no primitives.
    pub pairs: Vec<Pair>,
    /// Primitive indices, leaf by leaf.
    pub prims: Vec<u32>,
    /// Per pair: the id of the node whose children it holds (0 for pair 0).
    parent: Vec<u32>,
    /// Per primitive index: the id of its leaf, or [`NO_LEAF`].
    leaf_of: Vec<u32>,
}

/// [`Bvh::leaf_of`] for a primitive not in the tree.
const NO_LEAF: u32 = u32::MAX;

impl Bvh {
    /// Builds the tree over `items`; the result does not depend on the
    /// number of threads, and the build needs little beyond the items and
    /// the final arrays.
    pub(crate) fn build(mut items: Vec<Item>, primitives: usize) -> Bvh {
        if items.is_empty() {
            return Bvh::default();
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
        let mut bvh = Bvh {
            pairs,
            prims,
            parent: Vec::new(),
            leaf_of: Vec::new(),
        };
        bvh.link(primitives);
        bvh
    }

    /// Fills the upward links: each pair's parent and each primitive's leaf
    /// (`primitives` bounds the primitive indices).
    fn link(&mut self, primitives: usize) {
        let mut parent = vec![0u32; self.pairs.len()];
        let mut leaf_of = vec![NO_LEAF; primitives];
        // Node ids run over both slots of every pair but the root's unused one.
        for k in (0..2 * self.pairs.len() as u32).filter(|&k| k != 1) {
            let node = self.node(k);
            let s = node.start as usize;
            if node.count == 0 {
                parent[s >> 1] = k;
            } else {
                for &p in &self.prims[s..s + node.count as usize] {
                    if let Some(slot) = leaf_of.get_mut(p as usize) {
                        *slot = k;
                    }
                }
            }
        }
        self.parent = parent;
        self.leaf_of = leaf_of;
    }

    /// The node with id `k`.
    #[inline(always)]
    pub(crate) fn node(&self, k: u32) -> &Node {
        &self.pairs[k as usize >> 1].0[k as usize & 1]
    }

    /// Number of nodes.
    #[cfg(feature = "bench")]
    pub(crate) fn node_count(&self) -> usize {
        (2 * self.pairs.len()).saturating_sub(1)
    }

    /// Bytes held on the heap.
    #[cfg(feature = "bench")]
    pub(crate) fn heap_bytes(&self) -> usize {
        self.pairs.capacity() * size_of::<Pair>()
            + (self.prims.capacity() + self.parent.capacity() + self.leaf_of.capacity())
                * size_of::<u32>()
    }

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

/// Every segment from a point to a point of a box (their convex hull),
/// grown by a margin far above the rounding of a ray's arithmetic: a ray
/// from the point that ends in the box enters only boxes that meet it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hull {
    origin: [f64; 3],
    /// The box's corners relative to the origin, grown by `pad`.
    lo: [f64; 3],
    hi: [f64; 3],
    pad: f64,
}

impl Hull {
    /// The hull of `origin` and the box [`min`, `max`].
    pub(crate) fn new(origin: DVec3, min: DVec3, max: DVec3) -> Hull {
        let scale = origin.abs().max(min.abs()).max(max.abs()).max_element();
        let pad = 1e-6 * (1.0 + scale);
        Hull {
            origin: origin.to_array(),
            lo: (min - origin - pad).to_array(),
            hi: (max - origin + pad).to_array(),
            pad,
        }
    }

    /// Whether box `b`, grown by the margin, meets the hull: whether some
    /// s in [0, 1] puts the box s·(box − origin), on every axis, across b.
    #[inline]
    pub(crate) fn meets(&self, b: &[f32; 6]) -> bool {
        let (mut s0, mut s1) = (0.0f64, 1.0f64);
        for a in 0..3 {
            let bmin = b[a] as f64 - self.pad - self.origin[a];
            let bmax = b[a + 3] as f64 + self.pad - self.origin[a];
            let (lo, hi) = (self.lo[a], self.hi[a]);
            // s·lo <= bmax: the near side of the scaled box not past b's max.
            if lo > 0.0 {
                s1 = s1.min(bmax / lo);
            } else if lo < 0.0 {
                s0 = s0.max(bmax / lo);
            } else if bmax < 0.0 {
                return false;
            }
            // s·hi >= bmin: its far side not short of b's min.
            if hi > 0.0 {
                s0 = s0.max(bmin / hi);
            } else if hi < 0.0 {
                s1 = s1.min(bmin / hi);
            } else if bmin > 0.0 {
                return false;
            }
        }
        s0 <= s1
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

/// What [`RayBox::entry`] returns for a box the ray misses.
pub(crate) const MISS: f64 = f64::INFINITY;

/// A ray prepared for box tests.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayBox {
    origin: [f64; 3],
    inv_dir: [f64; 3],
    /// Per axis: 0 if the ray runs towards +axis (enters at the box's min), else 3.
    near: [usize; 3],
}

impl RayBox {
    /// Precomputes the inverse direction and the entry side per axis.
    #[inline]
    pub(crate) fn new(ray: &Ray) -> Self {
        let inv = [1.0 / ray.dir.x, 1.0 / ray.dir.y, 1.0 / ray.dir.z];
        // A -0 direction gives -inf: the sign, not the comparison, picks the side.
        let side = |v: f64| if v.is_sign_negative() { 3 } else { 0 };
        RayBox {
            origin: ray.origin.to_array(),
            inv_dir: inv,
            near: [side(inv[0]), side(inv[1]), side(inv[2])],
        }
    }

    /// The ray's origin.
    #[inline]
    pub(crate) fn origin(&self) -> [f64; 3] {
        self.origin
    }

    /// The inverse of the ray's direction, per axis.
    #[inline]
    pub(crate) fn inv_dir(&self) -> [f64; 3] {
        self.inv_dir
    }

    /// The distance at which the ray enters the box, clipped to [0, t_best]
    /// (with slack on the far side), or [`MISS`].
    ///
    /// The far distance gets a relative slack far above the rounding error of
    /// the slab arithmetic, so rounding never turns a hit into a miss; the
    /// boxes are already rounded outward. A zero direction component with
    /// the origin on a slab plane makes 0·∞ = NaN; [`max_num`] / [`min_num`]
    /// drop it, which leaves that slab unconstrained: right, since the
    /// (closed) slab holds the whole ray then.
    #[inline(always)]
    pub(crate) fn entry(&self, b: &[f32; 6], t_best: f64) -> f64 {
        // Masks keep the indices provably in 0..6 (no bounds checks).
        let [nx, ny, nz] = self.near.map(|n| n & 3);
        let [fx, fy, fz] = self.near.map(|n| (n ^ 3) & 3);
        let [ox, oy, oz] = self.origin;
        let [ix, iy, iz] = self.inv_dir;
        let tx0 = (b[nx] as f64 - ox) * ix;
        let ty0 = (b[ny + 1] as f64 - oy) * iy;
        let tz0 = (b[nz + 2] as f64 - oz) * iz;
        let tx1 = (b[fx] as f64 - ox) * ix;
        let ty1 = (b[fy + 1] as f64 - oy) * iy;
        let tz1 = (b[fz + 2] as f64 - oz) * iz;
        let t0 = max_num(tz0, max_num(ty0, max_num(tx0, 0.0)));
        let t1 = min_num(tz1, min_num(ty1, min_num(tx1, t_best)));
        if t0 <= t1 * FAR_SLACK { t0 } else { MISS }
    }
}

/// The larger of `t` and `acc`, or `acc` when `t` is NaN (one `maxsd`).
#[inline(always)]
pub(crate) fn max_num(t: f64, acc: f64) -> f64 {
    if t > acc { t } else { acc }
}

/// The smaller of `t` and `acc`, or `acc` when `t` is NaN (one `minsd`).
#[inline(always)]
pub(crate) fn min_num(t: f64, acc: f64) -> f64 {
    if t < acc { t } else { acc }
}

/// Bounds of a set of items' boxes and of their centroids.
#[derive(Clone, Copy, Debug)]
struct Extents {
    bounds: [f32; 6],
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
        let c = [it.centroid(0), it.centroid(1), it.centroid(2)];
        union(&mut self.cent, &[c[0], c[1], c[2], c[0], c[1], c[2]]);
    }

    fn of(items: &[Item]) -> Extents {
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
fn split(items: &mut [Item], ext: &Extents, depth: usize) -> Option<(usize, Extents, Extents)> {
    let n = items.len();
    if n <= 1 {
        return None;
    }
    let cent = &ext.cent;
    if depth < SAH_MAX_DEPTH {
        // Fewer bins for small nodes: binning costs little, evaluating bins does.
        let bins_used = n.clamp(4, BINS);
        // Bin index of a centroid on each axis: ((lo + hi) / 2 - cmin) * bins / width,
        // folded into one multiply-add; usable axes have scale > 0.
        let mut scale = [0f32; 3];
        let mut shift = [0f32; 3];
        for a in 0..3 {
            let width = cent[a + 3] - cent[a];
            if width > 0.0 {
                scale[a] = 0.5 * bins_used as f32 / width;
                shift[a] = cent[a] * (2.0 * scale[a]);
            }
        }
        let bin_of = |it: &Item, a: usize| -> usize {
            let k = (it.bounds[a] + it.bounds[a + 3]) * scale[a] - shift[a];
            // Saturating cast: negatives go to 0; the clamp catches the top edge.
            (k as usize).min(bins_used - 1)
        };
        let mut bins = [[Bin {
            bounds: EMPTY,
            count: 0,
        }; BINS]; 3];
        for it in items.iter() {
            for a in 0..3 {
                if scale[a] > 0.0 {
                    let bin = &mut bins[a][bin_of(it, a)];
                    union(&mut bin.bounds, &it.bounds);
                    bin.count += 1;
                }
            }
        }
        // Cost (half area x count of both sides) of splitting after bin i.
        let mut best: Option<(f64, usize, usize)> = None;
        for a in 0..3 {
            if scale[a] <= 0.0 {
                continue;
            }
            let mut right_cost = [0f64; BINS];
            let mut right_count = [0u32; BINS];
            let mut acc = EMPTY;
            let mut count = 0;
            for i in (1..bins_used).rev() {
                union(&mut acc, &bins[a][i].bounds);
                count += bins[a][i].count;
                right_cost[i] = half_area(&acc) * count as f64;
                right_count[i] = count;
            }
            let mut acc = EMPTY;
            let mut count = 0;
            for i in 0..bins_used - 1 {
                union(&mut acc, &bins[a][i].bounds);
                count += bins[a][i].count;
                if count == 0 || right_count[i + 1] == 0 {
                    continue;
                }
                let cost = half_area(&acc) * count as f64 + right_cost[i + 1];
                if best.is_none_or(|(c, _, _)| cost < c) {
                    best = Some((cost, a, i));
                }
            }
        }
        if let Some((cost, a, i)) = best {
            let area = half_area(&ext.bounds);
            let split_pays = TRAVERSAL_COST * area + cost < n as f64 * area;
            if !split_pays && n <= MAX_LEAF {
                return None;
            }
            // Both sides are non-empty: the counts above came from the same bin_of.
            let mut left = Extents::EMPTY;
            let mut right = Extents::EMPTY;
            let mut lo = 0;
            let mut hi = n;
            while lo < hi {
                let it = items[lo];
                if bin_of(&it, a) <= i {
                    left.grow(&it);
                    lo += 1;
                } else {
                    right.grow(&it);
                    hi -= 1;
                    items.swap(lo, hi);
                }
            }
            return Some((lo, left, right));
        }
    }
    if n <= MAX_LEAF {
        return None;
    }
    // Inseparable centroids or too deep: median split on the widest centroid axis.
    let mut axis = 0;
    for a in 1..3 {
        if cent[a + 3] - cent[a] > cent[axis + 3] - cent[axis] {
            axis = a;
        }
    }
    let mid = n / 2;
    items.select_nth_unstable_by(mid, |p, q| p.centroid(axis).total_cmp(&q.centroid(axis)));
    Some((mid, Extents::of(&items[..mid]), Extents::of(&items[mid..])))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::QueryCost;
    use rand::{Rng, SeedableRng};

    fn unit_box() -> [f32; 6] {
        [0.0, 0.0, 0.0, 1.0, 1.0, 1.0]
    }

    /// A box in f32, rounded outward, around `c` with half sizes `h`.
    fn f32_box(c: DVec3, h: DVec3) -> [f32; 6] {
        let (lo, hi) = (c - h, c + h);
        [
            f32_down(lo.x),
            f32_down(lo.y),
            f32_down(lo.z),
            f32_up(hi.x),
            f32_up(hi.y),
            f32_up(hi.z),
        ]
    }

    #[test]
    fn hull_meets_every_box_a_ray_into_its_box_enters() {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(31);
        fn v(rng: &mut rand_pcg::Pcg64, s: f64) -> DVec3 {
            DVec3::new(
                rng.random_range(-s..s),
                rng.random_range(-s..s),
                rng.random_range(-s..s),
            )
        }
        let (mut culled, mut kept) = (0, 0);
        for k in 0..2000 {
            let scale = [1.0, 1.0 / 1024.0, 1024.0][k % 3];
            // Light boxes: solid, flat on an axis (a square light along the
            // axes, on a plane f32 holds exactly), or a single point.
            let mut centre = v(&mut rng, 5.0 * scale);
            let mut half = v(&mut rng, scale).abs();
            let flat = k / 4 % 3;
            match k % 4 {
                0 => {
                    half[flat] = 0.0;
                    centre[flat] = (centre[flat] / scale).round() * scale;
                }
                1 => half = DVec3::ZERO,
                _ => {}
            }
            // Origins at a corner of the box, inside it (on its plane when
            // it is flat), nearby, or far off.
            let origin = match k % 5 {
                0 => centre + half * DVec3::new(1.0, -1.0, 1.0),
                1 => centre + v(&mut rng, 0.5 * scale) * half.signum().abs(),
                2 => centre + v(&mut rng, scale),
                _ => centre + v(&mut rng, 20.0 * scale),
            };
            let hull = Hull::new(origin, centre - half, centre + half);
            for _ in 0..20 {
                // A sample point of the light: inside, on a corner or an edge.
                let mut u = v(&mut rng, 1.0);
                for a in 0..3 {
                    if rng.random_bool(0.3) {
                        u[a] = u[a].signum();
                    }
                }
                let q = centre + half * u;
                let to = q - origin;
                let dist = to.length();
                if dist == 0.0 {
                    continue;
                }
                let rb = RayBox::new(&Ray::new(origin, to * (1.0 / dist)));
                // Boxes around points of the segment (touching it, beside
                // it, containing the origin or q), and anywhere.
                for _ in 0..10 {
                    let at = match rng.random_range(0..4) {
                        0 => origin + to * rng.random_range(-0.2..1.2),
                        1 => origin,
                        2 => q,
                        _ => centre + v(&mut rng, 10.0 * scale),
                    };
                    let size = [1e-6, 1e-2, 0.3][rng.random_range(0..3)] * scale;
                    let h = v(&mut rng, size).abs();
                    let mut b = f32_box(at + v(&mut rng, scale) * h, h);
                    if k % 4 == 0 && rng.random_bool(0.3) {
                        // Beyond a flat light, touching its plane: rays reach
                        // it at their very end.
                        let (a, side) = (flat, (q[flat] - origin[flat]).signum());
                        let (near, far) = if side > 0.0 { (a, a + 3) } else { (a + 3, a) };
                        b[near] = centre[a] as f32;
                        b[far] = (centre[a] + side * size) as f32;
                    }
                    if rb.entry(&b, dist) != MISS {
                        assert!(hull.meets(&b), "{origin} -> {q}: {b:?}");
                        kept += 1;
                    } else if !hull.meets(&b) {
                        culled += 1;
                    }
                }
            }
        }
        // Both outcomes occur often: the test has teeth.
        assert!(
            culled > 20_000 && kept > 20_000,
            "{culled} culled, {kept} kept"
        );
    }

    #[test]
    fn ray_in_a_face_plane_with_zero_direction_enters() {
        // Origin on the min-x and max-z faces' planes, direction along y only:
        // both 0·∞ cases must leave the slab open.
        for dir in [DVec3::Y, DVec3::NEG_Y] {
            for x in [0.0, 1.0] {
                let o = DVec3::new(x, if dir.y > 0.0 { -2.0 } else { 3.0 }, 1.0);
                let rb = RayBox::new(&Ray::new(o, dir));
                assert_eq!(rb.entry(&unit_box(), f64::INFINITY), 2.0, "{o} {dir}");
            }
        }
        // Negative zero components pick the other side.
        let d = DVec3::new(-0.0, 1.0, -0.0);
        let rb = RayBox::new(&Ray::new(DVec3::new(1.0, -2.0, 0.0), d));
        assert_eq!(rb.entry(&unit_box(), f64::INFINITY), 2.0);
        // Just outside the slab: miss.
        let o = DVec3::new(1.0f64.next_up(), -2.0, 0.5);
        let rb = RayBox::new(&Ray::new(o, DVec3::Y));
        assert_eq!(rb.entry(&unit_box(), f64::INFINITY), MISS);
    }

    #[test]
    fn box_behind_or_beyond_t_best_is_missed() {
        let rb = RayBox::new(&Ray::new(DVec3::new(0.5, 0.5, 5.0), DVec3::Z));
        assert_eq!(rb.entry(&unit_box(), f64::INFINITY), MISS);
        let rb = RayBox::new(&Ray::new(DVec3::new(0.5, 0.5, -5.0), DVec3::Z));
        assert_eq!(rb.entry(&unit_box(), 4.0), MISS);
        assert_eq!(rb.entry(&unit_box(), 5.0), 5.0);
        // Origin inside: entry at 0.
        let rb = RayBox::new(&Ray::new(DVec3::splat(0.5), DVec3::Z));
        assert_eq!(rb.entry(&unit_box(), 1.0), 0.0);
    }

    #[test]
    fn f32_rounding_is_outward() {
        for x in [0.1f64, -0.1, 1e-30, -1e-30, 1e29, -3.3e29, 7.0, 0.0] {
            assert!((f32_down(x) as f64) <= x && (f32_up(x) as f64) >= x, "{x}");
        }
        let b = Aabb::from_points(DVec3::splat(0.1), DVec3::splat(0.3));
        let it = Item::new(0, &b);
        for a in 0..3 {
            assert!(
                it.is_some_and(|it| (it.bounds[a] as f64) < 0.1 && (it.bounds[a + 3] as f64) > 0.3)
            );
        }
        let huge = Aabb::from_points(DVec3::ZERO, DVec3::splat(1e31));
        assert!(Item::new(0, &huge).is_none());
        let nan = Aabb {
            min: DVec3::ZERO,
            max: DVec3::new(f64::NAN, 1.0, 1.0),
        };
        assert!(Item::new(0, &nan).is_none());
    }

    /// Depth of the deepest leaf, and checks every primitive is in exactly one leaf.
    fn depth_and_coverage(bvh: &Bvh, n: usize) -> usize {
        let mut seen = vec![0u32; n];
        let mut max_depth = 0;
        let mut todo = vec![(0u32, 0usize)];
        while let Some((i, d)) = todo.pop() {
            let node = bvh.node(i);
            max_depth = max_depth.max(d);
            if node.count > 0 {
                let s = node.start as usize;
                for &p in &bvh.prims[s..s + node.count as usize] {
                    seen[p as usize] += 1;
                    assert!(node.count as usize <= MAX_LEAF);
                }
            } else {
                for c in [node.start, node.start + 1] {
                    let child = bvh.node(c);
                    for a in 0..3 {
                        assert!(child.bounds[a] >= node.bounds[a]);
                        assert!(child.bounds[a + 3] <= node.bounds[a + 3]);
                    }
                    todo.push((c, d + 1));
                }
            }
        }
        assert!(seen.iter().all(|&k| k == 1));
        max_depth
    }

    /// A walk that no leaf stops or shortens visits exactly the nodes whose
    /// boxes the ray enters (a child's box lies in its parent's), and tests
    /// the primitives of those that are leaves: counted by brute force over
    /// every node.
    #[test]
    fn a_walk_counts_every_node_whose_box_the_ray_enters() {
        let bvh = Bvh::build(sphere_items(3000, 5), 3000);
        let ids: Vec<u32> = (0..2 * bvh.pairs.len() as u32)
            .filter(|&k| k != 1)
            .collect();
        let mut rng = rand_pcg::Pcg64::seed_from_u64(9);
        let mut deep = 0;
        for _ in 0..400 {
            let o = DVec3::new(rng.random(), rng.random(), rng.random()) * 140.0 - 20.0;
            let d = DVec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - 1.0;
            let ray = Ray::new(o, d.normalize());
            let rb = RayBox::new(&ray);
            let entered: Vec<&Node> = ids
                .iter()
                .map(|&k| bvh.node(k))
                .filter(|n| rb.entry(&n.bounds, f64::INFINITY) != MISS)
                .collect();
            let want = QueryCost {
                nodes: entered.len() as u64,
                tests: entered.iter().map(|n| u64::from(n.count)).sum(),
            };
            let mut got = QueryCost::default();
            let mut t = f64::INFINITY;
            bvh.traverse(None, &ray, &mut t, &mut got, |prims, _| {
                (false, prims.len())
            });
            assert_eq!(got, want, "{ray:?}");
            deep += usize::from(want.nodes > 20 && want.tests > 0);
        }
        assert!(deep > 30, "{deep} rays entered many boxes");
    }

    fn sphere_items(n: usize, seed: u64) -> Vec<Item> {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
        (0..n)
            .map(|i| {
                let c = DVec3::new(rng.random(), rng.random(), rng.random()) * 100.0;
                let r = DVec3::splat(rng.random_range(0.01..1.0));
                Item::new(i as u32, &Aabb::from_points(c - r, c + r))
            })
            .collect::<Option<Vec<_>>>()
            .unwrap_or_default()
    }

    #[test]
    fn same_tree_on_one_or_two_threads() -> Result<(), rayon::ThreadPoolBuildError> {
        let items = sphere_items(50_000, 1);
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map(|pool| pool.install(|| Bvh::build(items.clone(), items.len())))
        };
        let (a, b) = (on(1)?, on(2)?);
        assert_eq!(items.len(), 50_000);
        assert_eq!(a.pairs, b.pairs);
        assert_eq!(a.prims, b.prims);
        let depth = depth_and_coverage(&a, items.len());
        assert!(depth < 40, "depth {depth}");
        Ok(())
    }

    /// Centroids at 2^k: each SAH split peels off only the largest few, so
    /// the tree gets deeper than [`SAH_MAX_DEPTH`].
    fn deep_items() -> Vec<Item> {
        (-120..99)
            .flat_map(|k| {
                let x = 2f64.powi(k);
                [DVec3::new(x, 0.0, 0.0), DVec3::new(0.0, -x, 0.0)]
            })
            .enumerate()
            .map(|(i, c)| {
                Item::new(
                    i as u32,
                    &Aabb::from_points(c - c.abs() * 0.25, c + c.abs() * 0.25),
                )
            })
            .collect::<Option<_>>()
            .unwrap_or_default()
    }

    #[test]
    fn upward_links_lead_from_every_leaf_to_the_root() {
        let items = sphere_items(5000, 4);
        let n = items.len();
        // One index left out of the tree: it has no leaf.
        let bvh = Bvh::build(items[1..].to_vec(), n);
        assert_eq!(bvh.leaf_of[items[0].index as usize], NO_LEAF);
        for it in &items[1..] {
            let k = bvh.leaf_of[it.index as usize];
            let leaf = bvh.node(k);
            let s = leaf.start as usize;
            assert!(leaf.count > 0 && bvh.prims[s..s + leaf.count as usize].contains(&it.index));
            // Up the parents: each holds the node as a child, and the root is reached.
            let (mut k, mut steps) = (k, 0);
            while k != 0 {
                let parent = bvh.node(bvh.parent[k as usize >> 1]);
                assert!(parent.count == 0 && parent.start == k & !1);
                k = bvh.parent[k as usize >> 1];
                steps += 1;
                assert!(steps < STACK_SIZE);
            }
        }
    }

    #[test]
    fn depth_stays_within_the_stack() {
        let items = deep_items();
        assert_eq!(items.len(), 2 * 219, "every box is finite");
        let n = items.len();
        let bvh = Bvh::build(items, n);
        let depth = depth_and_coverage(&bvh, n);
        assert!(
            depth > SAH_MAX_DEPTH,
            "the median fallback is not exercised"
        );
        assert!(depth < STACK_SIZE);
    }

    /// The build as it was before the two-pass one (every subtree got its
    /// worst-case 2n − 2 slots, then the used ones were copied out), kept to
    /// check that the tree did not change.
    mod slot_build {
        use super::super::*;

        /// The tree over `items` as the slot build made it.
        pub(super) fn build(mut items: Vec<Item>) -> Bvh {
            let n = items.len();
            if n == 0 {
                return Bvh::default();
            }
            let ext = Extents::of(&items);
            let mut slots = vec![Node::default(); 2 * n - 1];
            let (root, count) = build_node(&mut items, 0, ext, 0, &mut slots[1..], 1);
            let prims = items.iter().map(|it| it.index).collect();
            let pairs = compact(root, &slots, count);
            Bvh {
                pairs,
                prims,
                ..Bvh::default()
            }
        }

        /// Builds the subtree over `items` (the first is primitive `offset` of the
        /// final order, `ext` their extents) and returns its root and node count.
        ///
        /// Its descendants go into `desc`, whose first slot has index `base`: a
        /// subtree over n items has at most 2n − 2 descendants, so each subtree gets
        /// exactly that many slots and the two halves of a split can be built on
        /// different threads without sharing anything.
        fn build_node(
            items: &mut [Item],
            offset: u32,
            ext: Extents,
            depth: usize,
            desc: &mut [Node],
            base: u32,
        ) -> (Node, usize) {
            let n = items.len();
            let Some((mid, left_ext, right_ext)) = split(items, &ext, depth) else {
                let leaf = Node {
                    bounds: ext.bounds,
                    start: offset,
                    count: n as u32,
                };
                return (leaf, 1);
            };
            let (pair, rest) = desc.split_at_mut(2);
            let (left_desc, right_desc) = rest.split_at_mut(2 * mid - 2);
            let (left, right) = items.split_at_mut(mid);
            let left_base = base + 2;
            let right_base = left_base + 2 * mid as u32 - 2;
            let right_offset = offset + mid as u32;
            // Sequential: the tree does not depend on the order halves are built in.
            let (l, nl) = build_node(left, offset, left_ext, depth + 1, left_desc, left_base);
            let (r, nr) = build_node(
                right,
                right_offset,
                right_ext,
                depth + 1,
                right_desc,
                right_base,
            );
            pair[0] = l;
            pair[1] = r;
            let interior = Node {
                bounds: ext.bounds,
                start: base,
                count: 0,
            };
            (interior, 1 + nl + nr)
        }

        /// The nodes reachable from `root` (children in `slots`), without the
        /// unused slots, as sibling pairs in depth-first order.
        fn compact(root: Node, slots: &[Node], count: usize) -> Vec<Pair> {
            let mut out = Vec::with_capacity(count.div_ceil(2));
            out.push(Pair([root, Node::default()]));
            let mut todo = vec![0u32];
            while let Some(k) = todo.pop() {
                let (p, c) = (k as usize >> 1, k as usize & 1);
                if out[p].0[c].count == 0 {
                    let s = out[p].0[c].start as usize;
                    let first = 2 * out.len() as u32;
                    out.push(Pair([slots[s], slots[s + 1]]));
                    out[p].0[c].start = first;
                    todo.push(first + 1);
                    todo.push(first);
                }
            }
            out
        }
    }

    /// Every field of every node, bounds as bits. (The boxes are now unions
    /// taken in another order: equal values, but a zero bound could change
    /// sign; the inputs here have none.)
    fn node_bits(bvh: &Bvh) -> Vec<[u32; 8]> {
        let bits = |n: &Node| {
            let b = n.bounds.map(f32::to_bits);
            [b[0], b[1], b[2], b[3], b[4], b[5], n.start, n.count]
        };
        bvh.pairs
            .iter()
            .flat_map(|p| [bits(&p.0[0]), bits(&p.0[1])])
            .collect()
    }

    /// Equal unit boxes centred on 7 points of a line `spread` apart (all
    /// at one point for 0): centroids the SAH cannot separate.
    fn degenerate_items(n: usize, spread: f64) -> Vec<Item> {
        (0..n)
            .filter_map(|i| {
                let c = DVec3::new(1.0 + spread * (i % 7) as f64, 2.0, 3.0);
                Item::new(i as u32, &Aabb::from_points(c - 0.5, c + 0.5))
            })
            .collect()
    }

    #[test]
    fn same_tree_as_the_slot_build() -> Result<(), rayon::ThreadPoolBuildError> {
        let cases = [
            sphere_items(0, 2),
            sphere_items(1, 2),
            sphere_items(2, 3),
            sphere_items(9, 4),
            sphere_items(1000, 5),
            sphere_items(PARALLEL_MIN - 1, 6),
            sphere_items(PARALLEL_MIN, 7),
            sphere_items(70_000, 8),
            degenerate_items(10_000, 0.0),
            degenerate_items(10_000, 1e-3),
            deep_items(),
        ];
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()?;
            for items in &cases {
                let (new, old) = pool.install(|| {
                    (
                        Bvh::build(items.clone(), items.len()),
                        slot_build::build(items.clone()),
                    )
                });
                let n = items.len();
                assert_eq!(new.pairs, old.pairs, "{n} items, {threads} threads");
                assert_eq!(node_bits(&new), node_bits(&old), "{n} items");
                assert_eq!(new.prims, old.prims, "{n} items");
                // The arrays are allocated at exactly their size.
                assert_eq!(new.pairs.capacity(), new.pairs.len());
                assert_eq!(new.prims.capacity(), n);
                if n > 0 {
                    depth_and_coverage(&new, n);
                }
            }
        }
        Ok(())
    }

    #[test]
    fn node_is_32_bytes() {
        assert_eq!(size_of::<Node>(), 32);
        assert_eq!(size_of::<Pair>(), 64);
    }
}
