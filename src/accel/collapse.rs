//! The wide tree the queries walk, made from the binary one the build
//! makes: each wide node takes the binary descendants reached by opening,
//! largest box first, up to [`WIDTH`] of them; the leaves, and so the order
//! of [`Bvh::prims`], stay as they are. A first pass counts the nodes of
//! each subtree, so that the second writes them, depth first, into an
//! array of exactly their number, the top levels' subtrees in parallel;
//! the result does not depend on the number of threads. Then the upward
//! links.

use super::bvh::{Binary, Bvh, NO_LEAF, ROOT};
use super::node::{Item, Pair, WIDTH, Wide, half_area};
use rayon::prelude::*;

/// Wide levels whose subtrees are counted and written in parallel.
const PARALLEL_LEVELS: usize = 3;

/// The node counts of a wide subtree: in all, and, in the top levels, of
/// each of its root's node children (in order).
struct Sizes {
    total: usize,
    kids: Vec<Sizes>,
}

impl Bvh {
    /// Builds the tree over `items` (`primitives` bounds their indices):
    /// the binary tree, then its collapse.
    pub(crate) fn build(items: Vec<Item>, primitives: usize) -> Bvh {
        let binary = Binary::build(items);
        let Some(Pair([root, _])) = binary.pairs.first() else {
            return Bvh::default();
        };
        let mut wide = Vec::new();
        let mut parent = Vec::new();
        if root.count > 0 {
            // The whole tree is one leaf: the root's only child.
            let mut node = Wide::EMPTY;
            node.set_child(0, &root.bounds, root.start, root.count);
            wide.push(node);
            parent.push(ROOT);
        } else {
            let sizes = sizes(&binary, 0, 0);
            // Made in parallel: the pages are first touched on both threads.
            (0..sizes.total)
                .into_par_iter()
                .map(|_| Wide::EMPTY)
                .collect_into_vec(&mut wide);
            parent = vec![ROOT; sizes.total];
            write(&binary, 0, Some(&sizes), 0, &mut wide, &mut parent);
        }
        // Each primitive's leaf.
        let mut leaf_of = vec![NO_LEAF; primitives];
        for (n, node) in wide.iter().enumerate() {
            for k in (0..WIDTH).filter(|&k| node.count[k] > 0) {
                let s = node.child[k] as usize;
                for &p in &binary.prims[s..s + node.count[k] as usize] {
                    if let Some(home) = leaf_of.get_mut(p as usize) {
                        *home = (n * WIDTH + k) as u32;
                    }
                }
            }
        }
        Bvh {
            root: root.bounds,
            prims: binary.prims,
            wide,
            parent,
            leaf_of,
        }
    }
}

/// The children of the wide node made from interior binary node `b`: its
/// children, then, while there is room, the interior one of largest area
/// (the first of equal ones) replaced by its two. Their ids and number.
fn kids(bin: &Binary, b: u32) -> ([u32; WIDTH], usize) {
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
    (kids.map(|(id, _)| id), n)
}

/// The interior ones of `b`'s wide children.
fn inner_kids(bin: &Binary, b: u32) -> impl Iterator<Item = u32> {
    let (kids, n) = kids(bin, b);
    (0..n)
        .map(move |k| kids[k])
        .filter(|&id| bin.node(id).count == 0)
}

/// The node counts of the wide subtree made from interior binary node `b`
/// at wide level `level`.
fn sizes(bin: &Binary, b: u32, level: usize) -> Sizes {
    if level >= PARALLEL_LEVELS {
        return Sizes {
            total: count(bin, b),
            kids: Vec::new(),
        };
    }
    let inner: Vec<u32> = inner_kids(bin, b).collect();
    let kids: Vec<Sizes> = inner
        .into_par_iter()
        .map(|id| sizes(bin, id, level + 1))
        .collect();
    Sizes {
        total: 1 + kids.iter().map(|s| s.total).sum::<usize>(),
        kids,
    }
}

/// The number of nodes of the wide subtree made from interior binary node `b`.
fn count(bin: &Binary, b: u32) -> usize {
    1 + inner_kids(bin, b).map(|id| count(bin, id)).sum::<usize>()
}

/// Writes the wide subtree made from interior binary node `b`, depth
/// first, into `out` (its root first, as node `base`) and its nodes'
/// parents into `up`; `sizes` are its counts when known (the top levels,
/// written in parallel). Returns the number of nodes written.
fn write(
    bin: &Binary,
    b: u32,
    sizes: Option<&Sizes>,
    base: usize,
    out: &mut [Wide],
    up: &mut [u32],
) -> usize {
    let (kids, n) = kids(bin, b);
    let (head, mut rest) = out.split_at_mut(1);
    let (_, mut up_rest) = up.split_at_mut(1);
    let node = &mut head[0];
    let mut next = base + 1;
    // The node children left to write, in parallel, with their slices.
    let mut jobs = Vec::new();
    let mut inner = 0;
    for (k, &id) in kids[..n].iter().enumerate() {
        let child = bin.node(id);
        if child.count > 0 {
            node.set_child(k, &child.bounds, child.start, child.count);
            continue;
        }
        node.set_child(k, &child.bounds, next as u32, 0);
        let slot = (base * WIDTH + k) as u32;
        if let Some(sizes) = sizes {
            let size = &sizes.kids[inner];
            inner += 1;
            let (mine, others) = std::mem::take(&mut rest).split_at_mut(size.total);
            let (my_up, other_up) = std::mem::take(&mut up_rest).split_at_mut(size.total);
            my_up[0] = slot;
            jobs.push((id, size, next, mine, my_up));
            (rest, up_rest) = (others, other_up);
            next += size.total;
        } else {
            let at = next - base - 1;
            up_rest[at] = slot;
            next += write(bin, id, None, next, &mut rest[at..], &mut up_rest[at..]);
        }
    }
    jobs.into_par_iter().for_each(|(id, size, base, out, up)| {
        let sizes = (!size.kids.is_empty()).then_some(size);
        write(bin, id, sizes, base, out, up);
    });
    next - base
}
