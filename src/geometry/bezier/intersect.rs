//! The nearest hit of a ray: the pieces whose shells the ray reaches,
//! nearest entry first (or, for shadow rays, any hit: the pieces in list
//! order), each solved by the formulation that suits the ray on storage
//! that suits the degree.

use super::super::{Hit, Ray};
use super::Bezier;
use super::axis_ray::AxisRay;
use super::pieces::Pieces;
use super::poly::solve_poly;
use super::slice::solve_slice;
use super::store::{Fixed, Scratch};

/// Rays with |da| < SLICE_SLOPE·|d⊥| use the per-half formulation.
const SLICE_SLOPE: f64 = 1e-3;
/// Pieces sorted by entry distance before solving; more are solved unsorted.
const SORTED: usize = 16;

impl Bezier {
    /// The nearest hit with `t_min < t < t_max`; `Hit::u` is the curve
    /// parameter s of the hit.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        self.find::<false>(ray, t_min, t_max)
    }

    /// Whether [`Bezier::intersect`] finds a hit, for an any-hit query: the
    /// pieces are solved in list order up to the first with a hit. (Until
    /// its first hit the nearest search tests the shells and solves the
    /// pieces with the bound `t_max` and passes over no piece the ray
    /// enters, so both find a hit exactly when some piece the ray enters
    /// has one below `t_max`.)
    pub fn blocks(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.find::<true>(ray, t_min, t_max).is_some()
    }

    /// The nearest hit, or with `ANY` the first found, not necessarily the
    /// nearest.
    #[inline(always)]
    fn find<const ANY: bool>(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let pieces = &self.pieces;
        if pieces.degree() == 0 {
            return None;
        }
        let ar = AxisRay::new(ray, self.o1, self.axis, self.center, t_min);
        let t0 = ar.t0;
        let slice = ar.da.abs() < SLICE_SLOPE * ar.a.sqrt();
        // Culling is done in local t with some slack; hits are checked exactly.
        let slack = 1e-9 * (pieces.scale() + t0.abs());
        let lo = t_min - t0 - slack;
        pieces.shell().entry(&ar, lo, t_max - t0 + slack)?;
        let mut best_t = t_max;
        let mut best_s = f64::NAN;
        let mut order = [(0.0f64, 0u16); SORTED];
        let mut sorted = 0;
        for (i, pc) in pieces.list().iter().enumerate() {
            let Some(entry) = pc.shell.entry(&ar, lo, best_t - t0 + slack) else {
                continue;
            };
            if ANY {
                // Pieces the ray enters, solved in list order; the first
                // hit ends the search.
                if let Some((t, s)) = solve_piece(pieces, i, &ar, slice, best_t) {
                    (best_t, best_s) = (t, s);
                    break;
                }
                continue;
            }
            if sorted < SORTED {
                let mut j = sorted;
                while j > 0 && order[j - 1].0 > entry {
                    order[j] = order[j - 1];
                    j -= 1;
                }
                order[j] = (entry, i as u16);
                sorted += 1;
            } else if let Some((t, s)) = solve_piece(pieces, i, &ar, slice, best_t) {
                best_t = t;
                best_s = s;
            }
        }
        for &(entry, i) in &order[..sorted] {
            if entry > best_t - t0 + slack {
                break;
            }
            if let Some((t, s)) = solve_piece(pieces, i as usize, &ar, slice, best_t) {
                best_t = t;
                best_s = s;
            }
        }
        (best_t < t_max).then_some(Hit {
            t: best_t,
            part: 0,
            u: best_s,
            v: 0.0,
        })
    }
}

/// The nearest hit on piece `i` with t_min < t < t_max, as (t, s): nearly
/// perpendicular rays (`slice`) by [`solve_slice`], others by [`solve_poly`]
/// on fixed-size arrays up to degree [`Bezier::MAX_FIXED_DEGREE`] and on the
/// thread's scratch buffer above.
fn solve_piece(
    pieces: &Pieces,
    i: usize,
    ray: &AxisRay,
    slice: bool,
    t_max: f64,
) -> Option<(f64, f64)> {
    if slice {
        return solve_slice(pieces, i, ray, t_max);
    }
    const { assert!(Bezier::MAX_FIXED_DEGREE == 16) };
    match pieces.degree() {
        1 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<3>),
        2 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<5>),
        3 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<7>),
        4 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<9>),
        5 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<11>),
        6 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<13>),
        7 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<15>),
        8 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<17>),
        9 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<19>),
        10 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<21>),
        11 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<23>),
        12 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<25>),
        13 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<27>),
        14 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<29>),
        15 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<31>),
        16 => solve_poly(pieces, i, ray, t_max, &mut Fixed::<33>),
        n => Scratch::with(2 * n, |store| solve_poly(pieces, i, ray, t_max, store)),
    }
}
