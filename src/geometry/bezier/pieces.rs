//! The profile cut into pieces on which z and |r| are monotone, each with
//! its coefficients and a cylindrical shell in axis space that a ray must
//! reach before the piece is solved.

use super::axis_ray::AxisRay;
use super::bernstein::{derivative, product, restrict};
use super::roots::roots_in_open_unit;

/// Pieces the constructor aims for (more: tighter shells, more tests per ray).
const TARGET_PIECES: usize = 4;

/// A stretch of the profile on which z and |r| are monotone, with its
/// bounding shell in axis space (padded).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// Where the piece starts and ends on the curve.
    s0: f64,
    s1: f64,
    z_lo: f64,
    z_hi: f64,
    rho_lo2: f64,
    rho_hi2: f64,
    /// Whether z grows with s on the piece (t then grows with s when da > 0).
    pub z_up: bool,
}

/// The pieces of a profile of one degree, and their coefficients (none,
/// of degree 0, for a surface that is never hit).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pieces {
    /// Degree of the profile; 0 marks a surface that is never hit.
    degree: usize,
    /// Size of the profile (for tolerances).
    scale: f64,
    list: Vec<Piece>,
    /// Per piece: z (n+1), r (n+1) and r² (2n+1) coefficients, back to back.
    coefs: Vec<f64>,
}

/// Smallest and largest of `v`.
pub fn min_max(v: &[f64]) -> (f64, f64) {
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        })
}

impl Pieces {
    /// Cuts the profile z, r (degree `n` ≥ 1, size `scale`) where z', r' or
    /// r vanish, then halves the largest pieces until there are
    /// [`TARGET_PIECES`].
    pub fn cut(z: &[f64], r: &[f64], n: usize, scale: f64) -> Self {
        let mut cuts = roots_in_open_unit(&derivative(z, n), n - 1);
        cuts.extend(roots_in_open_unit(&derivative(r, n), n - 1));
        cuts.extend(roots_in_open_unit(r, n));
        cuts.retain(|&c| c > 1e-9 && c < 1.0 - 1e-9);
        cuts.sort_by(f64::total_cmp);
        let mut spans: Vec<(f64, f64)> = Vec::new();
        let mut start = 0.0;
        for c in cuts.into_iter().chain([1.0]) {
            if c - start > 1e-9 || c == 1.0 {
                spans.push((start, c));
                start = c;
            }
        }
        // The area of a piece's shell in the (z, ρ) half-plane: what a
        // split can save (none for a cylinder's wall).
        let area = |s: &(f64, f64)| {
            let zs = restrict(z, n, s.0, s.1);
            let rs = restrict(r, n, s.0, s.1);
            let (zl, zh) = min_max(&zs[..=n]);
            let (rl, rh) = min_max(&rs[..=n]);
            (zh - zl) * (rh - rl)
        };
        while spans.len() < TARGET_PIECES {
            let (i, largest) = spans
                .iter()
                .enumerate()
                .map(|(i, s)| (i, area(s)))
                .fold((0, 0.0), |b, c| if c.1 > b.1 { c } else { b });
            if largest <= 0.0 {
                break;
            }
            let (a, b) = spans[i];
            let mid = 0.5 * (a + b);
            spans[i] = (a, mid);
            spans.insert(i + 1, (mid, b));
        }
        let mut pieces = Pieces {
            degree: n,
            scale,
            list: Vec::new(),
            coefs: Vec::new(),
        };
        let pad = 1e-9 * scale;
        for &(s0, s1) in &spans {
            let zp = restrict(z, n, s0, s1);
            let mut rp = restrict(r, n, s0, s1);
            // Where the profile meets the axis make r exactly 0, so that a ray
            // through the apex sees f ≥ 0 at the piece's end (see the
            // polynomial's end values in `poly`).
            for k in [0, n] {
                if rp[k].abs() <= 1e-12 * scale {
                    rp[k] = 0.0;
                }
            }
            let rr = product(&rp, &rp, n);
            let (z_lo, z_hi) = min_max(&zp[..=n]);
            let (r_lo, r_hi) = min_max(&rp[..=n]);
            let (rho_lo, rho_hi) = if r_lo >= 0.0 {
                (r_lo, r_hi)
            } else if r_hi <= 0.0 {
                (-r_hi, -r_lo)
            } else {
                (0.0, r_hi.max(-r_lo))
            };
            pieces.list.push(Piece {
                s0,
                s1,
                z_lo: z_lo - pad,
                z_hi: z_hi + pad,
                rho_lo2: (rho_lo - pad).max(0.0).powi(2),
                rho_hi2: (rho_hi + pad).powi(2),
                z_up: zp[n] >= zp[0],
            });
            pieces.coefs.extend_from_slice(&zp[..=n]);
            pieces.coefs.extend_from_slice(&rp[..=n]);
            pieces.coefs.extend_from_slice(&rr[..=2 * n]);
        }
        pieces
    }

    /// Degree of the profile.
    #[inline]
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Size of the profile (for tolerances).
    #[inline]
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The pieces in curve order.
    #[inline]
    pub fn list(&self) -> &[Piece] {
        &self.list
    }

    /// The z, r and r² coefficients of piece `i`.
    #[inline]
    pub fn coefs(&self, i: usize) -> (&[f64], &[f64], &[f64]) {
        let n = self.degree;
        let stride = 4 * n + 3;
        let c = &self.coefs[i * stride..(i + 1) * stride];
        let (z, rest) = c.split_at(n + 1);
        let (r, rr) = rest.split_at(n + 1);
        (z, r, rr)
    }
}

impl Piece {
    /// Where `ray` (local t) enters the shell within (lo, hi), or `None` if
    /// it cannot meet it there.
    #[inline]
    pub fn entry(&self, ray: &AxisRay, lo: f64, hi: f64) -> Option<f64> {
        let (ta, tb) = if ray.da != 0.0 {
            let t1 = (self.z_lo - ray.pa) * ray.inv_da;
            let t2 = (self.z_hi - ray.pa) * ray.inv_da;
            (t1.min(t2).max(lo), t1.max(t2).min(hi))
        } else if ray.pa >= self.z_lo && ray.pa <= self.z_hi {
            (lo, hi)
        } else {
            return None;
        };
        // (Also rejects NaN from a degenerate ray.)
        if ta.partial_cmp(&tb).is_none_or(|o| o.is_gt()) {
            return None;
        }
        // Squared distance from the axis; the shells are padded for its rounding.
        let rho2 = |t: f64| ray.c + t * (2.0 * ray.b + ray.a * t);
        let closest = ray.t_axis.clamp(ta, tb);
        if closest.is_finite() && rho2(closest) > self.rho_hi2 {
            return None;
        }
        if ta.is_finite() && tb.is_finite() && rho2(ta).max(rho2(tb)) < self.rho_lo2 {
            return None;
        }
        Some(ta)
    }

    /// The curve parameter at `x` ∈ [0, 1] within the piece (clamped).
    #[inline]
    pub fn curve_at(&self, x: f64) -> f64 {
        self.s0 + x.clamp(0.0, 1.0) * (self.s1 - self.s0)
    }
}
