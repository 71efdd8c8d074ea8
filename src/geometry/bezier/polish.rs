//! Newton's method on the two equations of a hit, z(x) = pa + t·da and
//! r(x)² = |p⊥ + t·d⊥|², for where a solver's formula for t loses digits.

use super::axis_ray::AxisRay;
use super::bernstein::eval_d;

/// The profile's z, z', r and r' at one curve parameter.
#[derive(Clone, Copy)]
pub struct ProfileAt {
    /// z(x).
    pub z: f64,
    /// z'(x).
    pub dz: f64,
    /// r(x).
    pub r: f64,
    /// r'(x).
    pub dr: f64,
}

impl ProfileAt {
    /// The profile `z`, `r` (coefficients of one degree) at `x`.
    #[inline(always)]
    pub fn eval(z: &[f64], r: &[f64], x: f64) -> Self {
        let n = z.len() - 1;
        let (zx, dz) = eval_d(z, n, x);
        let (rx, dr) = eval_d(r, n, x);
        ProfileAt {
            z: zx,
            dz,
            r: rx,
            dr,
        }
    }
}

/// The hit (x, t) of `ray` on the profile `z`, `r` polished from (x, t),
/// where the profile is `at`: keeps the best point by residual.
pub fn polish(
    z: &[f64],
    r: &[f64],
    ray: &AxisRay,
    (mut x, mut t): (f64, f64),
    mut at: ProfileAt,
) -> (f64, f64) {
    let mut best = (x, t);
    let mut best_err = f64::INFINITY;
    for _ in 0..4 {
        let p = ray.pp + ray.dp * t;
        let rho = p.length();
        let f1 = at.z - ray.pa - t * ray.da;
        let f2 = at.r * at.r - rho * rho;
        // Residual in length units: |r| − ρ ≈ (r² − ρ²)/(|r| + ρ).
        let err = f1.abs() + f2.abs() / (at.r.abs() + rho).max(f64::MIN_POSITIVE);
        if err.partial_cmp(&best_err) != Some(std::cmp::Ordering::Less) {
            break;
        }
        best = (x, t);
        best_err = err;
        if err == 0.0 {
            break;
        }
        let j22 = -2.0 * p.dot(ray.dp);
        let j21 = 2.0 * at.r * at.dr;
        let det = at.dz * j22 + ray.da * j21;
        if det == 0.0 || !det.is_finite() {
            break;
        }
        x -= (f1 * j22 + ray.da * f2) / det;
        t -= (at.dz * f2 - j21 * f1) / det;
        at = ProfileAt::eval(z, r, x);
    }
    best
}
