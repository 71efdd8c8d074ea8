//! Shadow rays towards one point: the directions around it, as cells on the
//! six faces of a cube, each listing the objects whose boxes it sees,
//! nearest first (Haines and Greenberg's light buffer). A shadow ray tests
//! its direction's cell in that order and stops at the first object that
//! blocks it or lies farther from the light than the point it leaves.

use super::Accel;
use super::bvh::{f32_down, padded};
use crate::geometry::Ray;
use glam::DVec3;
use rayon::prelude::*;
use std::sync::atomic::Ordering::Relaxed;
use std::sync::atomic::{AtomicU32, AtomicU64};

/// Relative margin on projected face coordinates and on distances: far
/// above their rounding and that of the primitive tests (1e-16), so a cell
/// never leaves out an object that a ray through it meets.
const MARGIN: f64 = 1e-9;
/// Cells per face at most, per object projected on it.
const CELLS_PER_OBJECT: f64 = 2.0;
/// Cells span this many times the median object's projection (so each
/// object lands in about 2.25 of them).
const CELL_OVER_MEDIAN: f64 = 2.0;
/// Cells along a face's side at most.
const MAX_SIDE: usize = 4096;
/// An object over more cells than this is listed once for its whole face.
const MAX_CELLS_PER_OBJECT: usize = 256;
/// Buckets of the histogram of projected sizes: an f32's exponent and
/// three bits of its mantissa (an eighth of an octave).
const SIZE_BUCKETS: usize = 1 << 11;
/// Objects per task of the parallel first pass.
const CHUNK: usize = 1 << 14;

/// The objects of an [`Accel`] seen in each direction from one point.
pub struct LightBuffer {
    center: DVec3,
    faces: [Face; 6],
}

/// An object as a cell lists it: its distance from the centre (an f32
/// rounded down) in the high half, its index in the low half, so entries
/// sort nearest first, ties in index order.
type Entry = u64;

/// The entry of object `index` at distance `near` (rounded down) from the centre.
fn entry(near: f64, index: u32) -> Entry {
    // Non-negative, so the f32's bits order as the number does.
    (u64::from(f32_down(near * (1.0 - MARGIN)).to_bits()) << 32) | u64::from(index)
}

/// One face of the cube around the centre: a grid over the part of its
/// coordinates (u, v) ∈ [−1, 1]² that objects cover.
#[derive(Debug, Default)]
struct Face {
    cells: Grid,
    /// Where each cell's run starts in `entries` (one more than the cells).
    start: Vec<u32>,
    entries: Vec<Entry>,
    /// Objects tested for every direction of the face: those reaching the
    /// centre's plane (their projection is unbounded), and the largest.
    whole: Vec<Entry>,
}

/// Where an object's box lies on one face, seen from the centre.
enum Seen {
    /// Not in the face's directions.
    Not,
    /// In directions of the face without bound (the box reaches the plane
    /// through the centre parallel to the face).
    Unbounded,
    /// Within [u0, u1] × [v0, v1], given as (u0, v0, u1, v1), widened by the margin.
    Within([f64; 4]),
}

/// The face a nonzero direction `d` falls on (2·axis, +1 if negative) and
/// its coordinates there, each in [−1, 1].
#[inline(always)]
fn face_of(d: DVec3) -> (usize, f64, f64) {
    let a = d.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    let w = a[axis];
    let face = axis * 2 + (d[axis] < 0.0) as usize;
    (face, d[(axis + 1) % 3] / w, d[(axis + 2) % 3] / w)
}

/// How box `b` (relative to the centre) lies on `face`.
fn seen(b: &[f64; 6], face: usize) -> Seen {
    let axis = face / 2;
    // Depth along the face's axis, nearest and farthest.
    let (w0, w1) = if face % 2 == 1 {
        (-b[axis + 3], -b[axis])
    } else {
        (b[axis], b[axis + 3])
    };
    if w1 <= 0.0 {
        return Seen::Not;
    }
    if w0 <= 0.0 {
        return Seen::Unbounded;
    }
    // Outside the face's pyramid |x| ≤ w on another axis, with room for the
    // margin: no division needed to tell.
    let (p, q) = ((axis + 1) % 3, (axis + 2) % 3);
    let reach = w1 * (1.0 + 4.0 * MARGIN) + 2.0 * MARGIN;
    if b[p] > reach || b[p + 3] < -reach || b[q] > reach || b[q + 3] < -reach {
        return Seen::Not;
    }
    // With the depth positive over the box, a coordinate x/w is extreme at
    // a corner: at one of the four pairs of extremes.
    let (r0, r1) = (1.0 / w0, 1.0 / w1);
    let range = |k: usize| {
        let (x0, x1) = (b[k], b[k + 3]);
        let q = [x0 * r0, x0 * r1, x1 * r0, x1 * r1];
        let lo = q.into_iter().fold(f64::INFINITY, f64::min);
        let hi = q.into_iter().fold(f64::NEG_INFINITY, f64::max);
        (
            lo - MARGIN * (1.0 + lo.abs()),
            hi + MARGIN * (1.0 + hi.abs()),
        )
    };
    let (u0, u1) = range(p);
    let (v0, v1) = range(q);
    if u1 < -1.0 || u0 > 1.0 || v1 < -1.0 || v0 > 1.0 {
        return Seen::Not;
    }
    Seen::Within([u0.max(-1.0), v0.max(-1.0), u1.min(1.0), v1.min(1.0)])
}

/// What the first pass learns of one face.
#[derive(Clone)]
struct Survey {
    lo: [f64; 2],
    hi: [f64; 2],
    /// Objects within the face, by size bucket.
    sizes: Vec<u32>,
    within: usize,
    unbounded: Vec<Entry>,
}

impl Default for Survey {
    fn default() -> Self {
        Survey {
            lo: [f64::INFINITY; 2],
            hi: [f64::NEG_INFINITY; 2],
            sizes: vec![0; SIZE_BUCKETS],
            within: 0,
            unbounded: Vec::new(),
        }
    }
}

impl Survey {
    fn add(&mut self, s: &Seen, e: Entry) {
        match s {
            Seen::Not => {}
            Seen::Unbounded => self.unbounded.push(e),
            Seen::Within(r) => {
                for k in 0..2 {
                    self.lo[k] = self.lo[k].min(r[k]);
                    self.hi[k] = self.hi[k].max(r[k + 2]);
                }
                let size = (r[2] - r[0]).max(r[3] - r[1]) as f32;
                let bucket = (size.max(f32::MIN_POSITIVE).to_bits() >> 20) as usize;
                self.sizes[bucket.min(SIZE_BUCKETS - 1)] += 1;
                self.within += 1;
            }
        }
    }

    fn merge(mut self, o: Survey) -> Survey {
        for k in 0..2 {
            self.lo[k] = self.lo[k].min(o.lo[k]);
            self.hi[k] = self.hi[k].max(o.hi[k]);
        }
        for (a, b) in self.sizes.iter_mut().zip(&o.sizes) {
            *a += b;
        }
        self.within += o.within;
        self.unbounded.extend(o.unbounded);
        self
    }

    /// The size below which half the objects lie (a bucket's top).
    fn median(&self) -> f64 {
        let mut below = 0;
        let bucket = self
            .sizes
            .iter()
            .position(|&k| {
                below += k as usize;
                below * 2 >= self.within
            })
            .unwrap_or(SIZE_BUCKETS - 1);
        f32::from_bits(((bucket as u32 + 1) << 20) - 1) as f64
    }
}

impl LightBuffer {
    /// The buffer of `accel`'s bounded objects around `center`.
    pub(crate) fn build(accel: &Accel, center: DVec3) -> LightBuffer {
        let objects = accel.objects();
        // Object i's box relative to the centre, and its entry.
        let boxed = |i: usize| {
            let mut b = padded(&objects[i].shape.bounds()?)?;
            let mut q = 0.0;
            for a in 0..3 {
                b[a] -= center[a];
                b[a + 3] -= center[a];
                let gap = b[a].max(-b[a + 3]).max(0.0);
                q += gap * gap;
            }
            Some((b, entry(q.sqrt(), i as u32)))
        };
        let surveys = (0..objects.len().div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let mut s: [Survey; 6] = Default::default();
                for (b, e) in (c * CHUNK..objects.len().min((c + 1) * CHUNK)).filter_map(boxed) {
                    for (f, s) in s.iter_mut().enumerate() {
                        s.add(&seen(&b, f), e);
                    }
                }
                s
            })
            .reduce(Default::default, |a, b| {
                let [a0, a1, a2, a3, a4, a5] = a;
                let [b0, b1, b2, b3, b4, b5] = b;
                [
                    a0.merge(b0),
                    a1.merge(b1),
                    a2.merge(b2),
                    a3.merge(b3),
                    a4.merge(b4),
                    a5.merge(b5),
                ]
            });
        let grids = surveys.map(Counting::new);
        // Count each cell's run, then fill the runs, both in parallel: a
        // run's order is then arbitrary, and sorting it fixes it.
        let chunks = || (0..objects.len().div_ceil(CHUNK)).into_par_iter();
        let in_chunk = |c: usize| (c * CHUNK..objects.len().min((c + 1) * CHUNK)).filter_map(boxed);
        let large: Vec<(usize, Entry)> = chunks()
            .flat_map_iter(|c| {
                let mut large = Vec::new();
                for (b, e) in in_chunk(c) {
                    for (f, g) in grids.iter().enumerate() {
                        if let Seen::Within(r) = seen(&b, f) {
                            match g.span(&r) {
                                Some(cells) => cells.for_each(|k| {
                                    g.count[k + 1].fetch_add(1, Relaxed);
                                }),
                                None => large.push((f, e)),
                            }
                        }
                    }
                }
                large
            })
            .collect();
        let slots: [Vec<AtomicU64>; 6] = grids.each_ref().map(|g| {
            let mut sum = 0;
            for n in &g.count {
                sum += n.load(Relaxed);
                n.store(sum, Relaxed);
            }
            (0..sum).map(|_| AtomicU64::new(0)).collect()
        });
        let next: [Vec<AtomicU32>; 6] = grids.each_ref().map(|g| {
            g.count
                .iter()
                .map(|n| AtomicU32::new(n.load(Relaxed)))
                .collect()
        });
        chunks().for_each(|c| {
            for (b, e) in in_chunk(c) {
                for (f, g) in grids.iter().enumerate() {
                    if let Seen::Within(r) = seen(&b, f)
                        && let Some(cells) = g.span(&r)
                    {
                        for k in cells {
                            slots[f][next[f][k].fetch_add(1, Relaxed) as usize].store(e, Relaxed);
                        }
                    }
                }
            }
        });
        drop(next);
        let mut faces: [Face; 6] = grids.map(Counting::into_face);
        for (face, slots) in faces.iter_mut().zip(slots) {
            face.entries = slots.into_iter().map(AtomicU64::into_inner).collect();
        }
        for (f, e) in large {
            faces[f].whole.push(e);
        }
        faces.par_iter_mut().for_each(Face::sort);
        LightBuffer { center, faces }
    }

    /// The point the buffer is around.
    pub(crate) fn center(&self) -> DVec3 {
        self.center
    }

    /// Whether any of the bounded objects blocks `ray`, which runs from its
    /// origin straight to the centre, with `ray.t_min` < t < `t_max`
    /// (`blocks` decides one object); `hint` gets the blocker.
    #[inline]
    pub(crate) fn occluded(
        &self,
        ray: &Ray,
        t_max: f64,
        mut blocks: impl FnMut(u32) -> bool,
        hint: &mut Option<u32>,
    ) -> bool {
        let d = ray.origin - self.center;
        if d == DVec3::ZERO {
            return false;
        }
        let (f, u, v) = face_of(d);
        let face = &self.faces[f];
        // An object that meets the ray lies nearer the centre than t_max:
        // the runs are sorted, so the first one beyond ends them.
        for list in [face.whole.as_slice(), face.cell(u, v)] {
            for &e in list {
                if f32::from_bits((e >> 32) as u32) as f64 >= t_max {
                    break;
                }
                let i = e as u32;
                if blocks(i) {
                    *hint = Some(i);
                    return true;
                }
            }
        }
        false
    }
}

impl Face {
    /// Sorts each cell's run and the whole face's list, nearest first.
    fn sort(&mut self) {
        for k in 1..self.start.len() {
            self.entries[self.start[k - 1] as usize..self.start[k] as usize].sort_unstable();
        }
        self.whole.sort_unstable();
    }

    /// The run of the cell of (u, v).
    #[inline(always)]
    fn cell(&self, u: f64, v: f64) -> &[Entry] {
        let k = self.cells.cell(u, v);
        &self.entries[self.start[k] as usize..self.start[k + 1] as usize]
    }
}

/// The cells of a face: a grid over the range [lo, lo + side / scale) of
/// (u, v), with what the build counts per cell.
#[derive(Debug, Default)]
struct Grid {
    lo: [f64; 2],
    scale: [f64; 2],
    side: [usize; 2],
}

/// A face's grid while its runs are counted: count[k + 1] for cell k
/// (then, summed, where each run starts), and the objects of the whole face.
struct Counting {
    cells: Grid,
    count: Vec<AtomicU32>,
    whole: Vec<Entry>,
}

impl Counting {
    /// The grid over what `survey` found, no run counted yet.
    fn new(mut survey: Survey) -> Counting {
        let mut cells = Grid {
            side: [1, 1],
            ..Grid::default()
        };
        if survey.within > 0 {
            // Cells about twice the median object, at most twice as many as the objects.
            let cell = (survey.median() * CELL_OVER_MEDIAN).max(f64::MIN_POSITIVE);
            let span = [survey.hi[0] - survey.lo[0], survey.hi[1] - survey.lo[1]];
            let wanted = (span[0] / cell) * (span[1] / cell);
            let grow = (wanted / (CELLS_PER_OBJECT * survey.within as f64 + 16.0))
                .sqrt()
                .max(1.0);
            for (k, span) in span.into_iter().enumerate() {
                cells.side[k] = ((span / (cell * grow)).ceil() as usize).clamp(1, MAX_SIDE);
                cells.scale[k] = cells.side[k] as f64 / span.max(f64::MIN_POSITIVE);
            }
            cells.lo = survey.lo;
        }
        let n = cells.side[0] * cells.side[1] + 1;
        Counting {
            cells,
            count: (0..n).map(|_| AtomicU32::new(0)).collect(),
            whole: std::mem::take(&mut survey.unbounded),
        }
    }

    /// The cells of the face range `r` (as in [`Seen::Within`]), or `None`
    /// when they are more than [`MAX_CELLS_PER_OBJECT`].
    fn span(&self, r: &[f64; 4]) -> Option<impl Iterator<Item = usize> + use<>> {
        let g = &self.cells;
        let (i0, j0) = g.index(r[0], r[1]);
        let (i1, j1) = g.index(r[2], r[3]);
        let w = g.side[0];
        ((i1 - i0 + 1) * (j1 - j0 + 1) <= MAX_CELLS_PER_OBJECT)
            .then(|| (j0..=j1).flat_map(move |j| (i0..=i1).map(move |i| j * w + i)))
    }

    /// The face, its runs starting where the sums of `count` say (entries still to come).
    fn into_face(self) -> Face {
        Face {
            cells: self.cells,
            start: self.count.into_iter().map(AtomicU32::into_inner).collect(),
            entries: Vec::new(),
            whole: self.whole,
        }
    }
}

impl Grid {
    /// The cell of face coordinates (u, v), clamped to the grid: monotone
    /// in each, so a range's end cells bound those of the points inside it.
    #[inline(always)]
    fn index(&self, u: f64, v: f64) -> (usize, usize) {
        let i = ((u - self.lo[0]) * self.scale[0]).max(0.0) as usize;
        let j = ((v - self.lo[1]) * self.scale[1]).max(0.0) as usize;
        (i.min(self.side[0] - 1), j.min(self.side[1] - 1))
    }

    /// The index of the cell of (u, v).
    #[inline(always)]
    fn cell(&self, u: f64, v: f64) -> usize {
        let (i, j) = self.index(u, v);
        j * self.side[0] + i
    }
}
