//! A bounding volume hierarchy over boxes: a flat array of node pairs and
//! the primitive indices of its leaves, with upward links for walks that
//! start at a primitive's leaf (built in `build`, walked in `walk`).

use super::node::{Node, Pair};

/// The tree: nodes in sibling pairs (root first) and the primitive indices
/// of the leaves.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh {
    /// Node pairs, in depth-first order. Empty when there are no primitives.
    pub pairs: Vec<Pair>,
    /// Primitive indices, leaf by leaf.
    pub prims: Vec<u32>,
    /// Per pair: the id of the node whose children it holds (0 for pair 0).
    pub(super) parent: Vec<u32>,
    /// Per primitive index: the id of its leaf, or [`NO_LEAF`].
    pub(super) leaf_of: Vec<u32>,
}

/// [`Bvh::leaf_of`] for a primitive not in the tree.
pub(super) const NO_LEAF: u32 = u32::MAX;

impl Bvh {
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
}
