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
    /// Its bounding shell.
    pub shell: Shell,
    /// Whether z grows with s on the piece (t then grows with s when da > 0).
    pub z_up: bool,
}

/// The solid between two heights and two distances from the axis (squared).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Shell {
    z_lo: f64,
    z_hi: f64,
    rho_lo2: f64,
    rho_hi2: f64,
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
    /// A shell around all the pieces' shells (unused at degree 0).
    shell: Shell,
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
            shell: Shell::default(),
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
                shell: Shell {
                    z_lo: z_lo - pad,
                    z_hi: z_hi + pad,
                    rho_lo2: (rho_lo - pad).max(0.0).powi(2),
                    rho_hi2: (rho_hi + pad).powi(2),
                },
                z_up: zp[n] >= zp[0],
            });
            pieces.coefs.extend_from_slice(&zp[..=n]);
            pieces.coefs.extend_from_slice(&rp[..=n]);
            pieces.coefs.extend_from_slice(&rr[..=2 * n]);
        }
        pieces.shell = around(pieces.list.iter().map(|p| &p.shell), scale);
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

    /// A shell around every piece's: a ray it turns away enters none
    /// (see [`around`]).
    #[inline]
    pub fn shell(&self) -> &Shell {
        &self.shell
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

impl Shell {
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
}

/// A shell holding every shell of `shells` (at least one), widened by
/// 1e-6 of `scale`² (the profile's size) on the axis distances: its test
/// evaluates the same quadratic at the same or nearer points than a
/// piece's, and the widening covers their rounding, so it never turns
/// away a ray that some piece's shell lets in. Tested first, it spares a
/// ray that misses the surface the test of each piece.
fn around<'s>(shells: impl Iterator<Item = &'s Shell>, scale: f64) -> Shell {
    let mut all = Shell {
        z_lo: f64::INFINITY,
        z_hi: f64::NEG_INFINITY,
        rho_lo2: f64::INFINITY,
        rho_hi2: 0.0,
    };
    for s in shells {
        all.z_lo = all.z_lo.min(s.z_lo);
        all.z_hi = all.z_hi.max(s.z_hi);
        all.rho_lo2 = all.rho_lo2.min(s.rho_lo2);
        all.rho_hi2 = all.rho_hi2.max(s.rho_hi2);
    }
    let widen = 1e-6 * scale * scale;
    all.rho_lo2 = (all.rho_lo2 - widen).max(0.0);
    all.rho_hi2 += widen;
    all
}

impl Piece {
    /// The curve parameter at `x` ∈ [0, 1] within the piece (clamped).
    #[inline]
    pub fn curve_at(&self, x: f64) -> f64 {
        self.s0 + x.clamp(0.0, 1.0) * (self.s1 - self.s0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use glam::DVec3;
    use rand::{Rng, SeedableRng};
    use std::f64::consts::TAU;

    /// The shell around a profile's pieces lets in every ray that one of
    /// their shells lets in: random profiles, rays at random points by
    /// the shells' heights and radii (inside the inner ones too, and from
    /// inside), over the whole ray, from its start, and in slivers.
    #[test]
    fn the_shell_around_the_pieces_lets_in_what_any_piece_does() {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(5);
        let (mut entered, mut turned_away) = (0, 0);
        for _ in 0..300 {
            let n = rng.random_range(1..=6);
            let z: Vec<f64> = (0..=n).map(|_| rng.random_range(-1.0..1.0)).collect();
            let r: Vec<f64> = (0..=n).map(|_| rng.random_range(-0.2..1.0)).collect();
            let pieces = Pieces::cut(&z, &r, n, 2.0);
            for _ in 0..300 {
                let near = |rng: &mut rand_pcg::Pcg64, reach: f64| {
                    let (a, rho) = (rng.random_range(0.0..TAU), rng.random_range(0.0..reach));
                    DVec3::new(rho * a.cos(), rho * a.sin(), rng.random_range(-1.2..1.2))
                };
                let origin = if rng.random_bool(0.3) {
                    near(&mut rng, 1.0)
                } else {
                    near(&mut rng, 6.0) * DVec3::new(1.0, 1.0, 4.0)
                };
                let dir = (near(&mut rng, 1.1) - origin).normalize_or_zero();
                if dir == DVec3::ZERO {
                    continue;
                }
                let ray = AxisRay::new(
                    &Ray::new(origin, dir),
                    DVec3::ZERO,
                    DVec3::Z,
                    DVec3::ZERO,
                    0.0,
                );
                let a = rng.random_range(-8.0..8.0);
                for (lo, hi) in [
                    (f64::NEG_INFINITY, f64::INFINITY),
                    (-ray.t0, f64::INFINITY),
                    (a, a + 1e-3),
                ] {
                    if pieces
                        .list()
                        .iter()
                        .any(|p| p.shell.entry(&ray, lo, hi).is_some())
                    {
                        entered += 1;
                        assert!(
                            pieces.shell().entry(&ray, lo, hi).is_some(),
                            "z {z:?} r {r:?}: the ray from {origin} along {dir} in ({lo}, {hi})"
                        );
                    } else if pieces.shell().entry(&ray, lo, hi).is_none() {
                        turned_away += 1;
                    }
                }
            }
        }
        // Both cases are common: the test is not vacuous, nor the shell.
        assert!(
            entered > 30_000 && turned_away > 30_000,
            "{entered} entered, {turned_away} turned away"
        );
    }
}
