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

impl RayBox {
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
            let (o, inv) = (self.origin[a], self.inv_dir[a]);
            for k in 0..WIDTH {
                t0[k] = max_num((near[k] as f64 - o) * inv, t0[k]);
                t1[k] = min_num((far[k] as f64 - o) * inv, t1[k]);
            }
        }
        let mut t = [MISS; WIDTH];
        for k in 0..WIDTH {
            t[k] = if t0[k] <= t1[k] * FAR_SLACK {
                t0[k]
            } else {
                MISS
            };
        }
        t
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
