//! The tree's node layout: 32-byte nodes in 64-byte sibling pairs, and the
//! f32 boxes of primitives, rounded outward so no hit is lost.

use crate::geometry::Aabb;

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
    /// Leaf: index of its first entry in [`Bvh::prims`](super::bvh::Bvh::prims).
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
    pub(super) bounds: [f32; 6],
    /// Index of the primitive in the caller's list.
    pub(super) index: u32,
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

    /// A placeholder for an object kept out of the tree.
    pub(crate) const LEFT_OUT: Item = Item {
        bounds: EMPTY,
        index: u32::MAX,
    };

    /// Whether this is [`Item::LEFT_OUT`].
    pub(crate) fn left_out(&self) -> bool {
        self.index == u32::MAX
    }

    /// Index of the primitive in the caller's list.
    pub(crate) fn index(&self) -> u32 {
        self.index
    }

    /// Centroid coordinate on `axis` (halves first: no overflow).
    #[inline]
    pub(super) fn centroid(&self, axis: usize) -> f32 {
        self.bounds[axis] * 0.5 + self.bounds[axis + 3] * 0.5
    }
}

/// The largest f32 not above `x`.
pub(super) fn f32_down(x: f64) -> f32 {
    let f = x as f32;
    if f as f64 > x { f.next_down() } else { f }
}

/// The smallest f32 not below `x`.
pub(super) fn f32_up(x: f64) -> f32 {
    let f = x as f32;
    if (f as f64) < x { f.next_up() } else { f }
}

/// An empty box for unions.
pub(super) const EMPTY: [f32; 6] = [
    f32::INFINITY,
    f32::INFINITY,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
    f32::NEG_INFINITY,
];

/// Grows `a` to hold `b` (build boxes are finite: plain comparisons suffice).
#[inline(always)]
pub(super) fn union(a: &mut [f32; 6], b: &[f32; 6]) {
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
pub(super) fn half_area(b: &[f32; 6]) -> f64 {
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

/// Children of a node of the wide tree, the width of its box tests.
pub(crate) const WIDTH: usize = 4;

/// [`Wide::child`] of an unused slot.
pub(crate) const NO_CHILD: u32 = u32::MAX;

/// A node of the wide tree single rays walk: its children's boxes axis by
/// axis (lane k is child k), so one pass tests them all. A child is a leaf
/// (`count` > 0 primitives from `child` in [`Bvh::prims`](super::bvh::Bvh::prims)), another node
/// (`count` 0, `child` its index), or unused ([`NO_CHILD`], an empty box).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Wide {
    /// Per axis, the children's lowest coordinates (f32, rounded outward).
    pub lo: [[f32; WIDTH]; 3],
    /// Per axis, the children's highest coordinates.
    pub hi: [[f32; WIDTH]; 3],
    /// Per child: a node's index, a leaf's first entry, or [`NO_CHILD`].
    pub child: [u32; WIDTH],
    /// Per child: a leaf's primitive count, else 0.
    pub count: [u32; WIDTH],
}

impl Wide {
    /// A node with every slot unused.
    pub(crate) const EMPTY: Wide = Wide {
        lo: [[f32::INFINITY; WIDTH]; 3],
        hi: [[f32::NEG_INFINITY; WIDTH]; 3],
        child: [NO_CHILD; WIDTH],
        count: [0; WIDTH],
    };

    /// The box of child `k`, as in [`Node::bounds`].
    #[inline(always)]
    pub(crate) fn bounds(&self, k: usize) -> [f32; 6] {
        let (lo, hi) = (&self.lo, &self.hi);
        [lo[0][k], lo[1][k], lo[2][k], hi[0][k], hi[1][k], hi[2][k]]
    }

    /// Sets child `k`: its box, and its node index (`count` 0) or leaf.
    pub(crate) fn set_child(&mut self, k: usize, b: &[f32; 6], child: u32, count: u32) {
        for a in 0..3 {
            self.lo[a][k] = b[a];
            self.hi[a][k] = b[a + 3];
        }
        self.child[k] = child;
        self.count[k] = count;
    }
}
