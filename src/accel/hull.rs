//! The hull of a point and a box: which subtrees the shadow rays from one
//! point towards one area light can enter.

use glam::DVec3;

/// Every segment from a point to a point of a box (their convex hull),
/// grown by a margin far above the rounding of a ray's arithmetic: a ray
/// from the point that ends in the box enters only boxes that meet it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hull {
    origin: [f64; 3],
    /// The box's corners relative to the origin, grown by `pad`.
    lo: [f64; 3],
    hi: [f64; 3],
    pad: f64,
}

impl Hull {
    /// The hull of `origin` and the box [`min`, `max`].
    pub(crate) fn new(origin: DVec3, min: DVec3, max: DVec3) -> Hull {
        let scale = origin.abs().max(min.abs()).max(max.abs()).max_element();
        let pad = 1e-6 * (1.0 + scale);
        Hull {
            origin: origin.to_array(),
            lo: (min - origin - pad).to_array(),
            hi: (max - origin + pad).to_array(),
            pad,
        }
    }

    /// Whether box `b`, grown by the margin, meets the hull: whether some
    /// s in [0, 1] puts the box s·(box − origin), on every axis, across b.
    #[inline]
    pub(crate) fn meets(&self, b: &[f32; 6]) -> bool {
        let (mut s0, mut s1) = (0.0f64, 1.0f64);
        for a in 0..3 {
            let bmin = b[a] as f64 - self.pad - self.origin[a];
            let bmax = b[a + 3] as f64 + self.pad - self.origin[a];
            let (lo, hi) = (self.lo[a], self.hi[a]);
            // s·lo <= bmax: the near side of the scaled box not past b's max.
            if lo > 0.0 {
                s1 = s1.min(bmax / lo);
            } else if lo < 0.0 {
                s0 = s0.max(bmax / lo);
            } else if bmax < 0.0 {
                return false;
            }
            // s·hi >= bmin: its far side not short of b's min.
            if hi > 0.0 {
                s0 = s0.max(bmin / hi);
            } else if hi < 0.0 {
                s1 = s1.min(bmin / hi);
            } else if bmin > 0.0 {
                return false;
            }
        }
        s0 <= s1
    }
}
