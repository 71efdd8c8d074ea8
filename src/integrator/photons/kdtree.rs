//! PM's photon map: a balanced k-d tree stored flat, its leaves ranges of
//! the photons' order and its splits in breadth-first arrays (Jensen's
//! photon map, with buckets), searched for the K nearest photons on one
//! side of a surface.

use super::trace::Photon;
use glam::DVec3;

/// Photons a leaf holds at most: a leaf is scanned whole.
const LEAF: usize = 32;

/// Subtrees larger than this are built on two threads.
const PARALLEL: usize = 1 << 15;

/// A photon's place in the tree: its position and its index among the
/// photons it was built from.
#[derive(Clone, Copy, Debug)]
struct Entry {
    pos: [f64; 3],
    index: u32,
}

/// Positions and directions in tree order, and the splits.
///
/// Node 0 is the range of every photon; node `i`, the range `[lo, hi)`, is
/// a leaf when it holds at most [`LEAF`] photons; otherwise with
/// `mid = lo + (hi − lo)/2` it splits along `axis[i]` at `split[i]`
/// (the coordinate of the photon at `mid`) into node `2i + 1`, `[lo, mid)`,
/// at or below the split, and node `2i + 2`, `[mid, hi)`, at or above.
/// Siblings' splits share a cache line, and the top levels a few.
pub(crate) struct KdTree {
    pos: Vec<[f64; 3]>,
    dir: Vec<[f64; 3]>,
    index: Vec<u32>,
    split: Vec<f64>,
    axis: Vec<u8>,
}

/// A photon found: (d², its index among the photons the tree was built
/// from) orders it (ties go to the lower index).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Found {
    /// Its d² (never −0).
    pub d2: f64,
    /// Its place in the tree's order.
    pub slot: u32,
}

/// One K-nearest search's results: candidates within the bound, cut to
/// the K least by (d², index) whenever they reach 2K (one selection
/// per K candidates instead of a heap's sift per candidate).
#[derive(Default)]
pub(crate) struct Nearest {
    /// The candidates in `buf[..len]`; the rest is room for one leaf.
    buf: Vec<Found>,
    len: usize,
    k: usize,
    /// The largest d² a photon may have to enter.
    bound: f64,
}

impl Nearest {
    /// The photons found (the K least, or all when fewer), in no order.
    pub fn found(&self) -> &[Found] {
        &self.buf[..self.len]
    }

    /// Whether K photons were found.
    pub fn full(&self) -> bool {
        self.len >= self.k
    }

    /// The farthest found photon's d².
    pub fn farthest(&self) -> f64 {
        self.found().iter().map(|f| f.d2).fold(0.0, f64::max)
    }

    fn reset(&mut self, k: usize, r2: f64) {
        let room = 2 * k + LEAF;
        if self.buf.len() < room {
            self.buf.resize(room, Found { d2: 0.0, slot: 0 });
        }
        self.len = 0;
        self.k = k;
        self.bound = r2;
    }

    /// Tightens the bound after a scan that took the candidates from
    /// `before` to `len` (`index`: the tree's, for ties).
    #[inline]
    fn settle(&mut self, before: usize, index: &[u32]) {
        if self.len >= 2 * self.k {
            self.cut(index);
        } else if before < self.k && self.len >= self.k {
            // The first K: none nearer can be missed beyond the farthest.
            self.bound = self.bound.min(self.farthest());
        }
    }

    /// Keeps the K least; the bound becomes the K-th one's d² (a photon
    /// as far that sorts before it by index may still enter).
    fn cut(&mut self, index: &[u32]) {
        let k = self.k;
        if self.len > k {
            let found = &mut self.buf[..self.len];
            // By d² alone (its bits order as it does); ties across the K-th
            // d² are rare and settled by the whole key.
            found.select_nth_unstable_by_key(k - 1, |f| f.d2.to_bits());
            let kth = found[k - 1].d2;
            if found[k..].iter().any(|f| f.d2 == kth) {
                found.select_nth_unstable_by_key(k - 1, |f| {
                    (f.d2.to_bits(), index[f.slot as usize])
                });
            }
            self.len = k;
        }
        if self.len == k {
            self.bound = self.buf[k - 1].d2;
        }
    }
}

impl KdTree {
    /// The tree over `photons`.
    pub fn new(photons: &[Photon]) -> Self {
        let mut entries: Vec<Entry> = photons
            .iter()
            .enumerate()
            .map(|(i, p)| Entry {
                pos: p.pos.to_array(),
                index: i as u32,
            })
            .collect();
        // Each range's split at its middle slot while the halves are built
        // apart, then moved into the breadth-first arrays.
        let mut split_at = vec![(0u8, 0.0); entries.len()];
        build(&mut entries, &mut split_at);
        let mut nodes = 1;
        let mut n = entries.len();
        while n > LEAF {
            n = n.div_ceil(2);
            nodes *= 2;
        }
        let mut tree = KdTree {
            pos: entries.iter().map(|e| e.pos).collect(),
            dir: entries
                .iter()
                .map(|e| photons[e.index as usize].dir.to_array())
                .collect(),
            index: entries.iter().map(|e| e.index).collect(),
            split: vec![0.0; nodes],
            axis: vec![0; nodes],
        };
        tree.place_splits(0, 0, entries.len(), &split_at);
        tree
    }

    /// Fills node `node`'s split, the range `[lo, hi)`, and its subtree's,
    /// from the (axis, coordinate) `build` left at each range's middle slot.
    fn place_splits(&mut self, node: usize, lo: usize, hi: usize, split_at: &[(u8, f64)]) {
        if hi - lo <= LEAF {
            return;
        }
        let mid = lo + (hi - lo) / 2;
        (self.axis[node], self.split[node]) = split_at[mid];
        self.place_splits(2 * node + 1, lo, mid, split_at);
        self.place_splits(2 * node + 2, mid, hi, split_at);
    }

    /// The index of the photon at `slot` among those the tree was built from.
    pub fn index(&self, slot: u32) -> u32 {
        self.index[slot as usize]
    }

    /// The K nearest photons within √`r2` of `x` that arrived on the side
    /// `side` faces (d·side < 0), into `out`.
    pub fn nearest(&self, x: DVec3, side: DVec3, k: usize, r2: f64, out: &mut Nearest) {
        out.reset(k, r2);
        if self.pos.is_empty() || k == 0 {
            return;
        }
        let (q, side) = (x.to_array(), side.to_array());
        self.visit((0, 0, self.pos.len()), q, side, [0.0; 3], out);
        out.cut(&self.index);
    }

    /// Searches node `node`, the range `[lo, hi)`, whose box is `off` away
    /// from `q` along each axis (at least: the splits met on the way down).
    fn visit(
        &self,
        (node, lo, hi): (usize, usize, usize),
        q: [f64; 3],
        side: [f64; 3],
        off: [f64; 3],
        out: &mut Nearest,
    ) {
        if hi - lo <= LEAF {
            self.scan(lo, hi, q, side, out);
            return;
        }
        let mid = lo + (hi - lo) / 2;
        let a = self.axis[node] as usize;
        let d = q[a] - self.split[node];
        let (near, far) = if d < 0.0 {
            ((2 * node + 1, lo, mid), (2 * node + 2, mid, hi))
        } else {
            ((2 * node + 2, mid, hi), (2 * node + 1, lo, mid))
        };
        self.visit(near, q, side, off, out);
        // Every photon across the split is at least |d| away along the
        // axis, and `off` away along the others: a lower bound of their d²,
        // kept a hair below it (1e-9) so that rounding never prunes a photon
        // whose own d² reaches the bound.
        let mut far_off = off;
        far_off[a] = d;
        let box_d2 = far_off[0] * far_off[0] + far_off[1] * far_off[1] + far_off[2] * far_off[2];
        if box_d2 <= out.bound * (1.0 + 1e-9) {
            self.visit(far, q, side, far_off, out);
        }
    }

    /// Offers the photons of `[lo, hi)` within the bound on the side
    /// `side` faces, without a branch a photon.
    #[inline]
    fn scan(&self, lo: usize, hi: usize, q: [f64; 3], side: [f64; 3], out: &mut Nearest) {
        let (before, bound) = (out.len, out.bound);
        let mut len = before;
        for s in lo..hi {
            let p = self.pos[s];
            let (dx, dy, dz) = (q[0] - p[0], q[1] - p[1], q[2] - p[2]);
            let d2 = dx * dx + dy * dy + dz * dz;
            let d = self.dir[s];
            let facing = d[0] * side[0] + d[1] * side[1] + d[2] * side[2] < 0.0;
            out.buf[len] = Found { d2, slot: s as u32 };
            len += ((d2 <= bound) & facing) as usize;
        }
        out.len = len;
        out.settle(before, &self.index);
    }
}

/// Orders `entries` into a tree, writing each split's axis and coordinate
/// into `split` (the same length, at the range's middle).
fn build(entries: &mut [Entry], split: &mut [(u8, f64)]) {
    let n = entries.len();
    if n <= LEAF {
        return;
    }
    let a = split_axis(entries);
    let mid = n / 2;
    entries.select_nth_unstable_by(mid, |p, q| {
        p.pos[a].total_cmp(&q.pos[a]).then(p.index.cmp(&q.index))
    });
    split[mid] = (a as u8, entries[mid].pos[a]);
    let (el, er) = entries.split_at_mut(mid);
    let (al, ar) = split.split_at_mut(mid);
    if n > PARALLEL {
        rayon::join(|| build(el, al), || build(er, ar));
    } else {
        build(el, al);
        build(er, ar);
    }
}

/// The axis to split `entries` along: the widest spread of their middle
/// half, estimated from at most 64 of them taken evenly (an infinite floor's
/// few far photons would make the whole extent choose an axis along which
/// most photons lie at one value), then the widest extent.
fn split_axis(entries: &[Entry]) -> usize {
    const SAMPLE: usize = 64;
    let step = entries.len().div_ceil(SAMPLE).max(1);
    let mut best = (0, (f64::NEG_INFINITY, f64::NEG_INFINITY));
    for a in 0..3 {
        let mut v = [0.0; SAMPLE];
        let mut m = 0;
        for e in entries.iter().step_by(step) {
            v[m] = e.pos[a];
            m += 1;
        }
        let v = &mut v[..m];
        v.sort_unstable_by(f64::total_cmp);
        let spread = v[3 * m / 4] - v[m / 4];
        let (lo, hi) = entries
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), e| {
                (lo.min(e.pos[a]), hi.max(e.pos[a]))
            });
        let score = (spread, hi - lo);
        if score > best.1 {
            best = (a, score);
        }
    }
    best.0
}
