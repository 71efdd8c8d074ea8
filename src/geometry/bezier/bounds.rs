//! The surface's world-space box: tight for a valid profile, the control
//! points swept around the axis for bad input.

use super::super::Aabb;
use super::Bezier;
use super::bernstein::max_on_unit;
use glam::DVec3;

impl Bezier {
    /// Boxes around the control points swept around the axis (for bad input).
    pub(super) fn control_bounds(&self) -> Aabb {
        let rmax = self.points.iter().map(|p| p.y.abs()).fold(0.0, f64::max);
        let r = DVec3::splat(if rmax.is_finite() { rmax } else { 0.0 });
        Aabb::from_points(self.o1 - r, self.o1 + r)
            .union(&Aabb::from_points(self.o2 - r, self.o2 + r))
    }

    /// The tight box: along world axis k the surface reaches
    /// O1ₖ + max over s of (aₖ·z(s) + √(1 − aₖ²)·|r(s)|), and |r| = max(r, −r).
    pub(super) fn exact_bounds(&self) -> Aabb {
        let n = self.pieces.degree();
        let scale = self.pieces.scale();
        let tol = 1e-12 * scale;
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for k in 0..3 {
            let ak = self.axis[k];
            let wk = (1.0 - ak * ak).max(0.0).sqrt();
            let mut extremes = [0.0; 4];
            for (e, (sz, sr)) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)]
                .into_iter()
                .enumerate()
            {
                let c: Vec<f64> = (0..=n)
                    .map(|j| sz * ak * self.z[j] + sr * wk * self.r[j])
                    .collect();
                extremes[e] = max_on_unit(&c, n, tol);
            }
            hi[k] = extremes[0].max(extremes[1]);
            lo[k] = -extremes[2].max(extremes[3]);
        }
        let pad = DVec3::splat(1e-9 * (scale + self.o1.abs().max_element()));
        Aabb {
            min: self.o1 + DVec3::from_array(lo) - pad,
            max: self.o1 + DVec3::from_array(hi) + pad,
        }
    }
}
