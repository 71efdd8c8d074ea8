//! General rays: substituting t = (z(s) − pa)/da turns the two equations
//! of a hit into one polynomial in s of degree 2n, whose roots are visited
//! nearest first. One function for every degree and storage.

use super::axis_ray::AxisRay;
use super::bernstein::eval_d;
use super::binomials::{binom_row, inv_binom_row};
use super::pieces::Pieces;
use super::polish::{ProfileAt, polish};
use super::roots::{Flow, visit_roots};
use super::store::Store;

/// The nearest hit of `ray` on piece `i` with t_min < t < `t_max`, as
/// (t, s): the roots of |p⊥·da + (z(s) − pa)·d⊥|² − da²·r(s)², built and
/// searched in `store` (whose degree is twice the profile's).
pub fn solve_poly<S: Store>(
    pieces: &Pieces,
    i: usize,
    ray: &AxisRay,
    t_max: f64,
    store: &mut S,
) -> Option<(f64, f64)> {
    let n = store.degree() / 2;
    debug_assert_eq!(n, pieces.degree());
    let (z, r, rr) = pieces.coefs(i);
    let (z, r, rr) = (&z[..=n], &r[..=n], &rr[..=2 * n]);
    let pc = &pieces.list()[i];
    let f = store.build(|f, spare| ray_polynomial(z, r, rr, ray, f, &mut spare[..=n]));
    let forward = pc.z_up == (ray.da > 0.0);
    let mut found = None;
    visit_roots(store, &f, forward, &mut |x| {
        // The root's distance, polished where t = w/da loses digits; a hit
        // before the window is passed over, one in it is kept, and either
        // way the search stops past the window. (The visitor is compiled
        // apart from the search: the degree comes from the type where it can.)
        let n = S::FIXED_DEGREE.map_or(n, |m| m / 2);
        let (zx, dz) = eval_d(z, n, x);
        let (mut x, mut t) = (x, (zx - ray.pa) / ray.da);
        if (dz / ray.da).abs() > 1e2 * pieces.scale() {
            let (rx, dr) = eval_d(r, n, x);
            let at = ProfileAt {
                z: zx,
                dz,
                r: rx,
                dr,
            };
            (x, t) = polish(z, r, ray, (x, t), at);
        }
        let tg = ray.t0 + t;
        if tg <= ray.t_min {
            return Flow::Continue;
        }
        if tg < t_max {
            found = Some((tg, pc.curve_at(x)));
        }
        Flow::Stop
    });
    found
}

/// Writes into `f` (2n + 1 zeros) the coefficients of the ray's polynomial
/// on a piece with profile `z`, `r` (degree n) and r² `rr` (2n + 1
/// coefficients); `vh` (n + 1 values) is scratch.
#[inline(always)]
fn ray_polynomial(z: &[f64], r: &[f64], rr: &[f64], ray: &AxisRay, f: &mut [f64], vh: &mut [f64]) {
    let n = z.len() - 1;
    let (pa, da) = (ray.pa, ray.da);
    // f = w·(A·w + 2B·da) + da²·(C − r²) with w = z − pa, as one product
    // of scaled coefficients (C(n,j)·w_j) to skip the weights.
    let bn = binom_row(n);
    let two_b_da = 2.0 * ray.b * da;
    // (Loops over zipped slices of exact lengths: no bounds checks.)
    for ((v, b), zj) in vh.iter_mut().zip(bn).zip(z) {
        *v = b * (ray.a * (zj - pa) + two_b_da);
    }
    for (j, (b, zj)) in bn.iter().zip(z).enumerate() {
        let wh = b * (zj - pa);
        for (fk, v) in f[j..].iter_mut().zip(&*vh) {
            *fk += wh * v;
        }
    }
    let dd = da * da;
    let inv = inv_binom_row(2 * n);
    for ((fk, ik), rk) in f.iter_mut().zip(inv).zip(rr) {
        *fk = *fk * ik + dd * (ray.c - rk);
    }
    // The end values are da²·(ρ² − r²) at the piece's ends: as a norm
    // they keep their sign when r = 0 there and the ray passes through
    // the apex (a double root in s, a plain crossing in space).
    f[0] = (ray.dp * (z[0] - pa) + ray.pp * da).length_squared() - dd * r[0] * r[0];
    f[2 * n] = (ray.dp * (z[n] - pa) + ray.pp * da).length_squared() - dd * r[n] * r[n];
}
