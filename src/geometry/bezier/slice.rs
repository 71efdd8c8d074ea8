//! Rays within 10⁻³ of perpendicular to the axis, where the general
//! polynomial degenerates: each half of the ray, split at its closest
//! approach t* to the axis, is solved on its own in a form that stays well
//! conditioned.

use super::axis_ray::AxisRay;
use super::pieces::Pieces;
use super::polish::{ProfileAt, polish};
use super::roots::newton_in_bracket;

/// The nearest hit of `ray` on piece `i` with t_min < t < `t_max`, as
/// (t, s): where g(s) = √A·(z(s) − h*) ∓ da·√(r(s)² − ρ*²) = 0 on each half.
pub fn solve_slice(pieces: &Pieces, i: usize, ray: &AxisRay, t_max: f64) -> Option<(f64, f64)> {
    let n = pieces.degree();
    let (z, r, _) = pieces.coefs(i);
    let pc = &pieces.list()[i];
    let sa = ray.a.sqrt();
    let ts = ray.t_axis;
    let xs = ray.pp + ray.dp * ts;
    let rs2 = xs.length_squared();
    let hs = ray.pa + ray.da * ts;
    let q_tol = 1e-9 * pieces.scale() * pieces.scale();
    for sigma in [-1.0, 1.0] {
        let k = sigma * ray.da;
        let g = |zx: f64, rx: f64| sa * (zx - hs) - k * (rx * rx - rs2).max(0.0).sqrt();
        let g0 = g(z[0], r[0]);
        let g1 = g(z[n], r[n]);
        let same_side = (g0 > 0.0 && g1 > 0.0) || (g0 < 0.0 && g1 < 0.0);
        if same_side || (g0 == 0.0 && g1 == 0.0) || g0.is_nan() || g1.is_nan() {
            continue;
        }
        let x = if g0 == 0.0 {
            0.0
        } else if g1 == 0.0 {
            1.0
        } else {
            let x = (g0 / (g0 - g1)).clamp(0.0, 1.0);
            newton_in_bracket(x, g0 > 0.0, |x| {
                let at = ProfileAt::eval(z, r, x);
                let q = at.r * at.r - rs2;
                let dg = sa * at.dz
                    - if q > 0.0 {
                        k * at.r * at.dr / q.sqrt()
                    } else {
                        0.0
                    };
                (g(at.z, at.r), dg)
            })
        };
        let at = ProfileAt::eval(z, r, x);
        let q = at.r * at.r - rs2;
        if q < -q_tol {
            continue;
        }
        let t = ts + sigma * (q.max(0.0) / ray.a).sqrt();
        let (x, t) = polish(z, r, ray, (x, t), at);
        let tg = ray.t0 + t;
        if tg > ray.t_min && tg < t_max {
            return Some((tg, pc.curve_at(x)));
        }
    }
    None
}
