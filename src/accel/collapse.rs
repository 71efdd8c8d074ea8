//! The wide tree the queries walk, made from the binary one the build
//! makes: each wide node takes the binary descendants reached by opening,
//! largest box first, up to [`WIDTH`] of them; the leaves, and so the order
//! of [`Bvh::prims`], stay as they are. Then the upward links.

use super::bvh::{Binary, Bvh, NO_LEAF, ROOT};
use super::node::{Item, Node, Pair, WIDTH, Wide, half_area};

impl Bvh {
    /// Builds the tree over `items` (`primitives` bounds their indices):
    /// the binary tree, then its collapse.
    pub(crate) fn build(items: Vec<Item>, primitives: usize) -> Bvh {
        let binary = Binary::build(items);
        let Some(Pair([root, _])) = binary.pairs.first() else {
            return Bvh::default();
        };
        // At most one wide node per interior binary node (one per pair but
        // the root's); untouched room costs nothing and is given back.
        let mut bvh = Bvh {
            wide: Vec::with_capacity(binary.pairs.len()),
            parent: Vec::with_capacity(binary.pairs.len()),
            ..Bvh::default()
        };
        bvh.root = root.bounds;
        bvh.leaf_of = vec![NO_LEAF; primitives];
        bvh.wide.push(Wide::EMPTY);
        bvh.parent.push(ROOT);
        if root.count > 0 {
            // The whole tree is one leaf: the root's only child.
            bvh.set_leaf(&binary, 0, 0, root);
        } else {
            bvh.fill(&binary, 0, 0);
        }
        bvh.wide.shrink_to_fit();
        bvh.parent.shrink_to_fit();
        bvh.prims = binary.prims;
        bvh
    }

    /// Makes child `k` of wide node `w` binary leaf `leaf`, and that leaf
    /// the home of its primitives.
    fn set_leaf(&mut self, bin: &Binary, w: usize, k: usize, leaf: &Node) {
        let node = &mut self.wide[w];
        node.set_bounds(k, &leaf.bounds);
        node.child[k] = leaf.start;
        node.count[k] = leaf.count;
        let s = leaf.start as usize;
        for &p in &bin.prims[s..s + leaf.count as usize] {
            if let Some(home) = self.leaf_of.get_mut(p as usize) {
                *home = (w * WIDTH + k) as u32;
            }
        }
    }

    /// Fills wide node `w` with the descendants of interior binary node `b`,
    /// making wide nodes for those that are interior, depth first.
    fn fill(&mut self, bin: &Binary, w: usize, b: u32) {
        // Each child's id, and its area if it is interior (else -1).
        let area = |id: u32| {
            let node = bin.node(id);
            if node.count == 0 {
                half_area(&node.bounds)
            } else {
                -1.0
            }
        };
        let first = bin.node(b).start;
        let mut kids = [(first, area(first)); WIDTH];
        kids[1] = (first + 1, area(first + 1));
        let mut n = 2;
        // Open the interior child of largest area (the first of equal ones)
        // while there is room.
        while n < WIDTH {
            let mut k = 0;
            for j in 1..n {
                if kids[j].1 > kids[k].1 {
                    k = j;
                }
            }
            if kids[k].1 < 0.0 {
                break;
            }
            let s = bin.node(kids[k].0).start;
            kids.copy_within(k + 1..n, k + 2);
            kids[k] = (s, area(s));
            kids[k + 1] = (s + 1, area(s + 1));
            n += 1;
        }
        for (k, &(id, _)) in kids[..n].iter().enumerate() {
            let node = bin.node(id);
            if node.count > 0 {
                self.set_leaf(bin, w, k, node);
            } else {
                self.wide[w].set_bounds(k, &node.bounds);
                let c = self.wide.len();
                self.wide.push(Wide::EMPTY);
                self.parent.push((w * WIDTH + k) as u32);
                self.wide[w].child[k] = c as u32;
                self.fill(bin, c, id);
            }
        }
    }
}
