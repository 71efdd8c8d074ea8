//! The independent reference for the convex solids (cube, cylinder): a
//! golden-section search for the minimum of their implicit function along
//! the ray, then bisection for its roots.

use crate::geometry::Ray;
use glam::DVec3;

/// What an independent search on a convex implicit function f (f < 0 inside)
/// says the nearest hit in (t_lo, t_hi) is.
#[derive(Debug)]
pub(super) enum Expect {
    /// No hit in the window.
    Miss,
    /// Distance and how far a correct answer may be from it (1e-9 of the
    /// scene's scale, divided by how steeply f changes along the ray there).
    Hit(f64, f64),
    /// Tangent rays, origins on the surface, hits at a window bound.
    Unsure,
}

/// The nearest hit of `r` in (t_lo, t_hi) on the convex solid f < 0, searched
/// for on [0, t_far]; `scale` sizes the tolerances.
pub(super) fn convex_reference(
    f: &dyn Fn(DVec3) -> f64,
    r: &Ray,
    t_lo: f64,
    t_hi: f64,
    t_far: f64,
    scale: f64,
) -> Expect {
    let g = |t: f64| f(r.at(t));
    let band = 1e-9 * scale;
    let bisect = |mut a: f64, mut b: f64| {
        // g(a) and g(b) of opposite signs.
        let sa = g(a) < 0.0;
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if (g(m) < 0.0) == sa {
                a = m;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    };
    // Golden-section search for the minimum of the convex g on [0, t_far].
    let (mut a, mut b) = (0.0, t_far);
    let k = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..300 {
        let (m1, m2) = (b - k * (b - a), a + k * (b - a));
        if g(m1) < g(m2) {
            b = m2;
        } else {
            a = m1;
        }
    }
    let t_star = 0.5 * (a + b);
    let (g0, g_star) = (g(0.0), g(t_star));
    if g0.abs() <= band || g(t_far) <= band {
        return Expect::Unsure;
    }
    let mut roots = Vec::new();
    if g0 > 0.0 {
        if g_star > band {
            return Expect::Miss;
        }
        if g_star >= -band {
            return Expect::Unsure;
        }
        roots.push(bisect(0.0, t_star));
    }
    roots.push(bisect(if g0 < 0.0 { 0.0 } else { t_star }, t_far));
    for t in roots {
        // How fast f changes along the ray at the root: rounding moves any
        // computed root by about (error in f) / slope.
        let step = 1e-6 * scale;
        let slope = ((g(t + step) - g(t - step)) / (2.0 * step)).abs();
        if slope < 1e-4 {
            return Expect::Unsure;
        }
        let tol = 1e-9 * scale / slope;
        if (t - t_lo).abs() <= tol || (t - t_hi).abs() <= tol {
            return Expect::Unsure;
        }
        if t > t_lo && t < t_hi {
            return Expect::Hit(t, tol);
        }
    }
    Expect::Miss
}
