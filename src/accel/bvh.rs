//! A bounding volume hierarchy over boxes: the binary tree in a flat array
//! of node pairs that the build makes (in `build`), and the wide tree the
//! queries walk (made from it in `collapse`, walked in `walk` and
//! `packet`), with upward links for walks that start at a primitive's leaf.

use super::node::{Node, Pair, WIDTH, Wide};

/// The binary tree the build makes: nodes in sibling pairs (root first)
/// and the primitive indices of the leaves.
#[derive(Clone, Debug, Default)]
pub(crate) struct Binary {
    /// Node pairs, in depth-first order. Empty when there are no primitives.
    pub pairs: Vec<Pair>,
    /// Primitive indices, leaf by leaf.
    pub prims: Vec<u32>,
}

impl Binary {
    /// The node with id `k`.
    #[inline(always)]
    pub(crate) fn node(&self, k: u32) -> &Node {
        &self.pairs[k as usize >> 1].0[k as usize & 1]
    }
}

/// The tree the queries walk: wide nodes (root first), the primitive
/// indices of the leaves, and the upward links.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh {
    /// Primitive indices, leaf by leaf.
    pub prims: Vec<u32>,
    /// The wide nodes, in depth-first order. Empty when there are no primitives.
    pub(super) wide: Vec<Wide>,
    /// The root's box (of the whole tree).
    pub(super) root: [f32; 6],
    /// Per wide node: the slot (node · [`WIDTH`] + child) that holds it, or
    /// [`ROOT`] for the root.
    pub(super) parent: Vec<u32>,
    /// Per primitive index: the slot of its leaf, or [`NO_LEAF`].
    pub(super) leaf_of: Vec<u32>,
}

/// [`Bvh::leaf_of`] for a primitive not in the tree.
pub(super) const NO_LEAF: u32 = u32::MAX;

/// [`Bvh::parent`] of the root; as a subtree, the whole tree.
pub(super) const ROOT: u32 = u32::MAX;

/// Wide node and child of a slot.
#[inline(always)]
pub(super) fn split_slot(slot: u32) -> (usize, usize) {
    (slot as usize / WIDTH, slot as usize % WIDTH)
}

impl Bvh {
    /// Number of wide nodes.
    #[cfg(feature = "bench")]
    pub(crate) fn node_count(&self) -> usize {
        self.wide.len()
    }

    /// Bytes held on the heap.
    #[cfg(feature = "bench")]
    pub(crate) fn heap_bytes(&self) -> usize {
        self.wide.capacity() * size_of::<Wide>()
            + (self.prims.capacity() + self.parent.capacity() + self.leaf_of.capacity())
                * size_of::<u32>()
    }
}
