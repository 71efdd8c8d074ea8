//! The ray–box slab test in f64 against f32 boxes, with slack on the far
//! side so rounding never turns a hit into a miss.

use super::node::{WIDTH, Wide};
use crate::geometry::Ray;

/// Relative slack on the far distance of a box test: absorbs the rounding
/// of the slab arithmetic and of the primitive tests, so no hit is lost.
pub(crate) const FAR_SLACK: f64 = 1.0 + 1.0 / (1u64 << 30) as f64;

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

    /// Per axis: 0 if the ray enters a box at its min, 3 at its max.
    #[inline]
    pub(crate) fn near(&self) -> [usize; 3] {
        self.near
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
        let (mut t0, mut t1) = (0.0, t_best);
        for a in 0..3 {
            // The mask keeps the indices provably in 0..6 (no bounds checks).
            let near = self.near[a] & 3;
            self.slab(a, b[near + a], b[(near ^ 3) + a], &mut t0, &mut t1);
        }
        clip(t0, t1)
    }

    /// [`RayBox::entry`] of each child box of `node` at once: lane k is
    /// exactly what `entry` gives for child k's box (the same operations in
    /// the same order), [`MISS`] for an unused slot.
    #[inline(always)]
    pub(crate) fn entries(&self, node: &Wide, t_best: f64) -> [f64; WIDTH] {
        let mut t0 = [0.0; WIDTH];
        let mut t1 = [t_best; WIDTH];
        for a in 0..3 {
            let (near, far) = if self.near[a] == 0 {
                (&node.lo[a], &node.hi[a])
            } else {
                (&node.hi[a], &node.lo[a])
            };
            for k in 0..WIDTH {
                self.slab(a, near[k], far[k], &mut t0[k], &mut t1[k]);
            }
        }
        std::array::from_fn(|k| clip(t0[k], t1[k]))
    }

    /// One axis of the slab test: the distances at which the ray crosses
    /// axis `a`'s planes `near` and `far`, folded into the entry `t0` and
    /// the exit `t1` found so far.
    #[inline(always)]
    fn slab(&self, a: usize, near: f32, far: f32, t0: &mut f64, t1: &mut f64) {
        let o = self.origin[a];
        fold_slab(near as f64 - o, far as f64 - o, self.inv_dir[a], t0, t1);
    }
}

/// One axis of a ray's slab test from its planes' offsets from the origin,
/// `dn` = near − o and `df` = far − o: the crossings dn·inv and df·inv
/// folded into the entry `t0` and the exit `t1` found so far. A ray's
/// tests of one box, of a node's boxes and of a packet's lanes all fold
/// through here, so their answers agree to the bit.
#[inline(always)]
pub(crate) fn fold_slab(dn: f64, df: f64, inv: f64, t0: &mut f64, t1: &mut f64) {
    *t0 = max_num(dn * inv, *t0);
    *t1 = min_num(df * inv, *t1);
}

/// The entry distance `t0`, or [`MISS`] when the exit `t1` (with slack)
/// lies before it.
#[inline(always)]
pub(crate) fn clip(t0: f64, t1: f64) -> f64 {
    if t0 <= t1 * FAR_SLACK { t0 } else { MISS }
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
