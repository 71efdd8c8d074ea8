//! PM's photon map: a balanced k-d tree stored flat, its nodes implicit in
//! the photons' order (Jensen's photon map, with buckets), searched for the
//! K nearest photons on one side of a surface into a fixed-size heap.

use glam::DVec3;

/// Photons a leaf holds at most: a leaf is scanned whole.
const LEAF: usize = 8;

/// Subtrees larger than this are built on two threads.
const PARALLEL: usize = 1 << 15;

/// A photon's place in the tree: its position and its index among the
/// photons it was built from.
#[derive(Clone, Copy, Debug)]
struct Entry {
    pos: [f64; 3],
    index: u32,
}

/// Positions and directions in tree order.
///
/// The range `[lo, hi)` is a leaf when it holds at most [`LEAF`] photons;
/// otherwise with `mid = lo + (hi − lo)/2` it is a node: the photon at `mid`
/// splits it along `axis[mid]`, `[lo, mid)` lying at or below that photon on
/// the axis and `(mid, hi)` at or above.
pub(crate) struct KdTree {
    pos: Vec<[f64; 3]>,
    dir: Vec<[f64; 3]>,
    index: Vec<u32>,
    axis: Vec<u8>,
}

/// A photon found: (d², index) orders it (ties go to the lower index).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Found {
    /// Its d² (never −0).
    pub d2: f64,
    /// Its index among the photons the tree was built from.
    pub index: u32,
    /// Its place in the tree's order.
    pub slot: u32,
}

impl Found {
    /// (d², index) as one ordered key: d² ≥ 0 orders as its bits do.
    #[inline]
    pub fn key(&self) -> (u64, u32) {
        (self.d2.to_bits(), self.index)
    }
}

/// One K-nearest search's results: candidates within the bound, cut to
/// the K least by [`Found::key`] whenever they reach 2K (one selection
/// per K candidates instead of a heap's sift per candidate).
#[derive(Default)]
pub(crate) struct Nearest {
    found: Vec<Found>,
    k: usize,
    /// The largest d² a photon may have to enter.
    bound: f64,
}

impl Nearest {
    /// The photons found (the K least, or all when fewer), in no order.
    pub fn found(&self) -> &[Found] {
        &self.found
    }

    /// Whether K photons were found.
    pub fn full(&self) -> bool {
        self.found.len() >= self.k
    }

    /// The farthest found photon's d².
    pub fn farthest(&self) -> f64 {
        self.found.iter().map(|f| f.d2).fold(0.0, f64::max)
    }

    fn reset(&mut self, k: usize, r2: f64) {
        self.found.clear();
        if self.found.capacity() < 2 * k {
            self.found.reserve(2 * k);
        }
        self.k = k;
        self.bound = r2;
    }

    /// Offers `f`; the caller has checked that its d² is at most the bound.
    #[inline]
    fn offer(&mut self, f: Found) {
        self.found.push(f);
        if self.found.len() == self.k {
            // The first K: none nearer can be missed beyond the farthest.
            self.bound = self.bound.min(self.farthest());
        } else if self.found.len() >= 2 * self.k {
            self.cut();
        }
    }

    /// Keeps the K least; the bound becomes the K-th one's d² (a photon
    /// as far that sorts before it by index may still enter).
    fn cut(&mut self) {
        let k = self.k;
        if self.found.len() > k {
            self.found.select_nth_unstable_by_key(k - 1, Found::key);
            self.found.truncate(k);
        }
        if self.found.len() == k {
            self.bound = self.found[k - 1].d2;
        }
    }
}

impl KdTree {
    /// The tree over the photons at `positions` with directions `dirs`.
    pub fn new(positions: &[DVec3], dirs: &[DVec3]) -> Self {
        let mut entries: Vec<Entry> = positions
            .iter()
            .enumerate()
            .map(|(i, p)| Entry {
                pos: p.to_array(),
                index: i as u32,
            })
            .collect();
        let mut axis = vec![0u8; entries.len()];
        build(&mut entries, &mut axis);
        KdTree {
            pos: entries.iter().map(|e| e.pos).collect(),
            dir: entries
                .iter()
                .map(|e| dirs[e.index as usize].to_array())
                .collect(),
            index: entries.iter().map(|e| e.index).collect(),
            axis,
        }
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
        self.visit(0, self.pos.len(), q, side, [0.0; 3], out);
        out.cut();
    }

    /// Searches `[lo, hi)`, whose box is `off` away from `q` along each axis
    /// (at least: the splits met on the way down).
    fn visit(
        &self,
        lo: usize,
        hi: usize,
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
        let a = self.axis[mid] as usize;
        let d = q[a] - self.pos[mid][a];
        let (near, far) = if d < 0.0 {
            ((lo, mid), (mid + 1, hi))
        } else {
            ((mid + 1, hi), (lo, mid))
        };
        self.visit(near.0, near.1, q, side, off, out);
        // The split photon and every one across it are at least |d| away
        // along the axis, and `off` away along the others: a lower bound
        // of their d², kept a hair below it (1e-9) so that rounding never
        // prunes a photon whose own d² reaches the bound.
        let mut far_off = off;
        far_off[a] = d;
        let box_d2 = far_off[0] * far_off[0] + far_off[1] * far_off[1] + far_off[2] * far_off[2];
        if box_d2 <= out.bound * (1.0 + 1e-9) {
            self.scan(mid, mid + 1, q, side, out);
            self.visit(far.0, far.1, q, side, far_off, out);
        }
    }

    #[inline]
    fn scan(&self, lo: usize, hi: usize, q: [f64; 3], side: [f64; 3], out: &mut Nearest) {
        for s in lo..hi {
            let p = self.pos[s];
            let (dx, dy, dz) = (q[0] - p[0], q[1] - p[1], q[2] - p[2]);
            let d2 = dx * dx + dy * dy + dz * dz;
            if d2 > out.bound {
                continue;
            }
            let d = self.dir[s];
            if d[0] * side[0] + d[1] * side[1] + d[2] * side[2] >= 0.0 {
                continue;
            }
            out.offer(Found {
                d2,
                index: self.index[s],
                slot: s as u32,
            });
        }
    }
}

/// Orders `entries` into a tree, writing each split's axis into `axis`
/// (the same length, at the split's middle).
fn build(entries: &mut [Entry], axis: &mut [u8]) {
    let n = entries.len();
    if n <= LEAF {
        return;
    }
    let a = split_axis(entries);
    let mid = n / 2;
    entries.select_nth_unstable_by(mid, |p, q| {
        p.pos[a].total_cmp(&q.pos[a]).then(p.index.cmp(&q.index))
    });
    axis[mid] = a as u8;
    // The split photon stays at the middle, its own node.
    let (el, er) = entries.split_at_mut(mid);
    let (al, ar) = axis.split_at_mut(mid);
    let (er, ar) = (&mut er[1..], &mut ar[1..]);
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
