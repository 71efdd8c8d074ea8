//! Bézier surfaces of revolution: `primitive bezier` (`O1= O2= P= z r` ...).
//!
//! The surface is S(s, φ) = O1 + a·z(s) + r(s)·(cos φ·e1 + sin φ·e2) for
//! s ∈ [0, 1], with z(s), r(s) the Bernstein polynomials of the profile and
//! a = unit(O2 − O1). Only r² matters for the shape, so a negative r draws
//! the same surface as |r|.
//!
//! Intersection is exact (no tessellation). The constructor cuts the profile
//! into pieces on which z and |r| are monotone (at the roots of z', r' and r),
//! each bounded by a cylindrical shell in axis space. A ray that reaches a
//! piece's shell is solved on that piece in one of two ways:
//! - in general, substituting t = (z(s) − pa)/da turns the two equations
//!   z(s) = pa + t·da, r(s)² = |p⊥ + t·d⊥|² into one polynomial in s of
//!   degree 2n whose roots are isolated by Bernstein subdivision (Descartes'
//!   rule) and refined by bracketed Newton; as z is monotone on a piece, t is
//!   monotone in s and the first root in the ray's direction is the nearest;
//! - for rays within 10⁻³ of perpendicular to the axis that polynomial
//!   degenerates (its roots pair up into double roots), so each half of the
//!   ray, split at its closest approach t* to the axis (|d⊥|² = A), is
//!   solved as √A·(z(s) − h*) = ±da·√(r(s)² − ρ*²), which stays well
//!   conditioned; it only misses slivers of relative size ~slope² (10⁻⁶)
//!   where a ray grazes the surface, and the polynomial resolves its root
//!   pairs down to slopes ~10⁻⁵, so the two hand over without a gap.
//!
//! Where either formula for t is ill-conditioned the hit is polished by
//! Newton's method on the original two equations. Profiles up to degree
//! [`Bezier::MAX_FIXED_DEGREE`] (16) are solved on fixed-size arrays, one
//! specialisation per degree. Higher degrees, up to [`Bezier::MAX_DEGREE`]
//! (64), run the same algorithm on slices: the polynomial and its
//! subdivisions live in a per-thread buffer that grows to the largest size
//! needed and is then reused, so they allocate nothing per ray either.
//!
//! The outward normal is ρ̂·z'(s) − a·|r|'(s), with ρ̂ the unit vector from
//! the axis to the hit point: the profile's tangent in the (radius, height)
//! half-plane turned clockwise. For a profile that runs upward along the
//! wall of a vase this points away from the axis, and a profile that runs
//! counter-clockwise around the region it encloses with the axis gets
//! normals pointing out of that region; the normal field is continuous
//! along the sheet, also where the profile folds back.

mod bernstein;

use super::{Aabb, Hit, Ray, SurfacePoint, angle_around, axis_frame};
use bernstein::{
    BINOM, Flow, INV_BINOM, binom_row, converged, derivative, eval_d, eval_d_any, inv_binom_row,
    max_on_unit, restrict, roots_in_open_unit, visit_roots, visit_roots_any,
};
use glam::{DVec2, DVec3};
use std::cell::RefCell;
use std::f64::consts::TAU;

/// The surface swept by rotating a Bézier profile (z along the axis from
/// `o1`, r the radius) about the axis `o1` → `o2`.
#[derive(Clone, Debug, PartialEq)]
pub struct Bezier {
    /// Start of the axis.
    pub o1: DVec3,
    /// A second point on the axis (gives its direction).
    pub o2: DVec3,
    /// Profile control points (z, r), at least two.
    pub points: Vec<DVec2>,
    /// Unit axis direction.
    axis: DVec3,
    /// Texture frame around the axis.
    e1: DVec3,
    e2: DVec3,
    /// Profile degree; 0 marks a surface that is never hit (bad input).
    degree: usize,
    /// Profile coefficients on the whole curve (degree + 1 each).
    z: Vec<f64>,
    r: Vec<f64>,
    /// A point on the axis near the surface: rays are restarted from their
    /// closest approach to it so that all arithmetic is at object scale.
    center: DVec3,
    /// Size of the profile (for tolerances).
    scale: f64,
    pieces: Vec<Piece>,
    /// Per piece: z (n+1), r (n+1) and r² (2n+1) coefficients, back to back.
    coefs: Vec<f64>,
    bounds: Aabb,
}

/// A stretch of the profile on which z and |r| are monotone, with its
/// bounding shell in axis space (padded).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Piece {
    s0: f64,
    s1: f64,
    z_lo: f64,
    z_hi: f64,
    rho_lo2: f64,
    rho_hi2: f64,
    /// Whether z grows with s on the piece (t then grows with s when da > 0).
    z_up: bool,
}

/// The ray in axis coordinates, restarted at `t0`.
struct Frame {
    t0: f64,
    /// Axial coordinate of the origin relative to O1, and of the direction.
    pa: f64,
    da: f64,
    /// Perpendicular parts of origin and direction.
    pp: DVec3,
    dp: DVec3,
    /// |d⊥|², p⊥·d⊥, |p⊥|²: the squared distance from the axis is
    /// a·t² + 2b·t + c.
    a: f64,
    b: f64,
    c: f64,
    /// 1/da, and where the ray comes closest to the axis (0 if parallel).
    inv_da: f64,
    t_axis: f64,
    /// Valid window in global t.
    t_min: f64,
}

/// Rays with |da| < SLICE_SLOPE·|d⊥| use the per-half formulation.
const SLICE_SLOPE: f64 = 1e-3;
/// Pieces the constructor aims for (more: tighter shells, more tests per ray).
const TARGET_PIECES: usize = 4;
/// Pieces sorted by entry distance before solving; more are solved unsorted.
const SORTED: usize = 16;

/// The value and derivative of a degree-m Bernstein polynomial at x: either
/// [`eval_d`] (degrees whose binomials are in the fixed tables) or
/// [`eval_d_any`].
trait Eval: Fn(&[f64], usize, f64) -> (f64, f64) + Copy {}
impl<E: Fn(&[f64], usize, f64) -> (f64, f64) + Copy> Eval for E {}

impl Bezier {
    /// Highest profile degree that is intersected (65 control points); the
    /// parser rejects more, and a surface built with more is never hit.
    pub const MAX_DEGREE: usize = bernstein::LARGEST_DEGREE;
    /// Highest profile degree solved on fixed-size arrays specialised per
    /// degree (the fastest path); higher degrees use a per-thread buffer.
    pub const MAX_FIXED_DEGREE: usize = bernstein::MAX_DEGREE;

    /// A surface from the spec's keys (O1 ≠ O2, at least two control points).
    pub fn new(o1: DVec3, o2: DVec3, points: Vec<DVec2>) -> Self {
        let axis = (o2 - o1).normalize_or_zero();
        let (e1, e2) = axis_frame(axis);
        let degree = points.len().wrapping_sub(1);
        let valid = axis != DVec3::ZERO
            && (1..=Self::MAX_DEGREE).contains(&degree)
            && o1.is_finite()
            && points.iter().all(|p| p.is_finite());
        let mut shape = Bezier {
            o1,
            o2,
            axis,
            e1,
            e2,
            degree: 0,
            z: Vec::new(),
            r: Vec::new(),
            center: o1,
            scale: 1.0,
            pieces: Vec::new(),
            coefs: Vec::new(),
            bounds: Aabb::EMPTY,
            points,
        };
        if !valid {
            shape.bounds = shape.control_bounds();
            return shape;
        }
        shape.degree = degree;
        shape.z = shape.points.iter().map(|p| p.x).collect();
        shape.r = shape.points.iter().map(|p| p.y).collect();
        let (z_min, z_max) = min_max(&shape.z[..=degree]);
        let r_max = shape.r[..=degree]
            .iter()
            .fold(0.0f64, |m, r| m.max(r.abs()));
        shape.scale = (z_max - z_min).max(r_max).max(f64::MIN_POSITIVE);
        shape.center = o1 + axis * (0.5 * (z_min + z_max));
        shape.build_pieces();
        shape.bounds = shape.exact_bounds();
        shape
    }

    /// The same surface with its texture angle measured from the unit vector
    /// `e1` towards `e2` (both perpendicular to the axis and to each other)
    /// instead of the spec's frame: V's `Bezier` measures it
    /// counter-clockwise about +z from +x.
    pub fn with_angle_frame(mut self, e1: DVec3, e2: DVec3) -> Self {
        (self.e1, self.e2) = (e1, e2);
        self
    }

    /// Cuts the profile where z', r' or r vanish, then halves the largest
    /// pieces until there are [`TARGET_PIECES`].
    fn build_pieces(&mut self) {
        let n = self.degree;
        let mut cuts = roots_in_open_unit(&derivative(&self.z, n), n - 1);
        cuts.extend(roots_in_open_unit(&derivative(&self.r, n), n - 1));
        cuts.extend(roots_in_open_unit(&self.r, n));
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
        let area = |s: &(f64, f64), this: &Self| {
            let z = restrict(&this.z, n, s.0, s.1);
            let r = restrict(&this.r, n, s.0, s.1);
            let (zl, zh) = min_max(&z[..=n]);
            let (rl, rh) = min_max(&r[..=n]);
            (zh - zl) * (rh - rl)
        };
        while spans.len() < TARGET_PIECES {
            let (i, largest) = spans
                .iter()
                .enumerate()
                .map(|(i, s)| (i, area(s, self)))
                .fold((0, 0.0), |b, c| if c.1 > b.1 { c } else { b });
            if largest <= 0.0 {
                break;
            }
            let (a, b) = spans[i];
            let mid = 0.5 * (a + b);
            spans[i] = (a, mid);
            spans.insert(i + 1, (mid, b));
        }
        let pad = 1e-9 * self.scale;
        for &(s0, s1) in &spans {
            let z = restrict(&self.z, n, s0, s1);
            let mut r = restrict(&self.r, n, s0, s1);
            // Where the profile meets the axis make r exactly 0, so that a ray
            // through the apex sees f ≥ 0 at the piece's end (see solve_poly).
            for k in [0, n] {
                if r[k].abs() <= 1e-12 * self.scale {
                    r[k] = 0.0;
                }
            }
            let rr = bernstein::product(&r, &r, n);
            let (z_lo, z_hi) = min_max(&z[..=n]);
            let (r_lo, r_hi) = min_max(&r[..=n]);
            let (rho_lo, rho_hi) = if r_lo >= 0.0 {
                (r_lo, r_hi)
            } else if r_hi <= 0.0 {
                (-r_hi, -r_lo)
            } else {
                (0.0, r_hi.max(-r_lo))
            };
            self.pieces.push(Piece {
                s0,
                s1,
                z_lo: z_lo - pad,
                z_hi: z_hi + pad,
                rho_lo2: (rho_lo - pad).max(0.0).powi(2),
                rho_hi2: (rho_hi + pad).powi(2),
                z_up: z[n] >= z[0],
            });
            self.coefs.extend_from_slice(&z[..=n]);
            self.coefs.extend_from_slice(&r[..=n]);
            self.coefs.extend_from_slice(&rr[..=2 * n]);
        }
    }

    /// Boxes around the control points swept around the axis (for bad input).
    fn control_bounds(&self) -> Aabb {
        let rmax = self.points.iter().map(|p| p.y.abs()).fold(0.0, f64::max);
        let r = DVec3::splat(if rmax.is_finite() { rmax } else { 0.0 });
        Aabb::from_points(self.o1 - r, self.o1 + r)
            .union(&Aabb::from_points(self.o2 - r, self.o2 + r))
    }

    /// The tight box: along world axis k the surface reaches
    /// O1ₖ + max over s of (aₖ·z(s) + √(1 − aₖ²)·|r(s)|), and |r| = max(r, −r).
    fn exact_bounds(&self) -> Aabb {
        let n = self.degree;
        let tol = 1e-12 * self.scale;
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
        let pad = DVec3::splat(1e-9 * (self.scale + self.o1.abs().max_element()));
        Aabb {
            min: self.o1 + DVec3::from_array(lo) - pad,
            max: self.o1 + DVec3::from_array(hi) + pad,
        }
    }

    /// The z, r and r² coefficients of piece `i`.
    #[inline]
    fn piece_coefs(&self, i: usize) -> (&[f64], &[f64], &[f64]) {
        let n = self.degree;
        let stride = 4 * n + 3;
        let c = &self.coefs[i * stride..(i + 1) * stride];
        let (z, rest) = c.split_at(n + 1);
        let (r, rr) = rest.split_at(n + 1);
        (z, r, rr)
    }

    /// The nearest hit with `t_min < t < t_max`; `Hit::u` is the curve
    /// parameter s of the hit.
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        if self.degree == 0 {
            return None;
        }
        let t0 = (self.center - ray.origin).dot(ray.dir);
        let p = ray.origin + ray.dir * t0 - self.o1;
        let d = ray.dir;
        let pa = p.dot(self.axis);
        let da = d.dot(self.axis);
        let pp = p - self.axis * pa;
        let dp = d - self.axis * da;
        let fr = Frame {
            t0,
            pa,
            da,
            pp,
            dp,
            a: dp.length_squared(),
            b: pp.dot(dp),
            c: pp.length_squared(),
            inv_da: 1.0 / da,
            t_axis: if dp == DVec3::ZERO {
                0.0
            } else {
                -pp.dot(dp) / dp.length_squared()
            },
            t_min,
        };
        let slice = da.abs() < SLICE_SLOPE * fr.a.sqrt();
        // Culling is done in local t with some slack; hits are checked exactly.
        let slack = 1e-9 * (self.scale + t0.abs());
        let lo = t_min - t0 - slack;
        let mut best_t = t_max;
        let mut best_s = f64::NAN;
        let mut order = [(0.0f64, 0u16); SORTED];
        let mut sorted = 0;
        for (i, pc) in self.pieces.iter().enumerate() {
            let Some(entry) = cull(pc, &fr, lo, best_t - t0 + slack) else {
                continue;
            };
            if sorted < SORTED {
                let mut j = sorted;
                while j > 0 && order[j - 1].0 > entry {
                    order[j] = order[j - 1];
                    j -= 1;
                }
                order[j] = (entry, i as u16);
                sorted += 1;
            } else if let Some((t, s)) = self.solve_piece(i, &fr, slice, best_t) {
                best_t = t;
                best_s = s;
            }
        }
        for &(entry, i) in &order[..sorted] {
            if entry > best_t - t0 + slack {
                break;
            }
            if let Some((t, s)) = self.solve_piece(i as usize, &fr, slice, best_t) {
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

    /// The nearest hit on piece `i` with t_min < t < t_max, as (t, s).
    fn solve_piece(&self, i: usize, fr: &Frame, slice: bool, t_max: f64) -> Option<(f64, f64)> {
        if slice {
            return if self.degree <= Self::MAX_FIXED_DEGREE {
                self.solve_slice(i, fr, t_max, eval_d)
            } else {
                self.solve_slice(i, fr, t_max, eval_d_any)
            };
        }
        macro_rules! by_degree {
            ($($n:literal => ($n1:literal, $l:literal)),*) => {
                match self.degree {
                    $($n => self.solve_poly::<$n1, $l>(i, fr, t_max),)*
                    _ => self.solve_poly_any(i, fr, t_max),
                }
            };
        }
        by_degree!(1 => (2, 3), 2 => (3, 5), 3 => (4, 7), 4 => (5, 9), 5 => (6, 11),
            6 => (7, 13), 7 => (8, 15), 8 => (9, 17), 9 => (10, 19), 10 => (11, 21),
            11 => (12, 23), 12 => (13, 25), 13 => (14, 27), 14 => (15, 29),
            15 => (16, 31), 16 => (17, 33))
    }

    /// General rays: roots of r(s)²·da² = |p⊥·da + (z(s) − pa)·d⊥|², for
    /// profiles of degree N1 − 1 (the polynomial has L = 2·N1 − 1 coefficients).
    fn solve_poly<const N1: usize, const L: usize>(
        &self,
        i: usize,
        fr: &Frame,
        t_max: f64,
    ) -> Option<(f64, f64)> {
        let n = N1 - 1;
        let (zs, rs, rrs) = self.piece_coefs(i);
        let z: [f64; N1] = std::array::from_fn(|j| zs[j]);
        let r: [f64; N1] = std::array::from_fn(|j| rs[j]);
        let pc = &self.pieces[i];
        let (pa, da) = (fr.pa, fr.da);
        // f = w·(A·w + 2B·da) + da²·(C − r²) with w = z − pa, as one product
        // of scaled coefficients (C(n,j)·w_j) to skip the weights.
        let c = fr.c;
        let bn = &BINOM[n];
        let two_b_da = 2.0 * fr.b * da;
        let mut wh = [0.0; N1];
        let mut vh = [0.0; N1];
        for j in 0..N1 {
            let w = z[j] - pa;
            wh[j] = bn[j] * w;
            vh[j] = bn[j] * (fr.a * w + two_b_da);
        }
        let mut f = [0.0; L];
        for j in 0..N1 {
            for k in 0..N1 {
                f[j + k] += wh[j] * vh[k];
            }
        }
        let dd = da * da;
        let inv = &INV_BINOM[2 * n];
        for k in 0..L {
            f[k] = f[k] * inv[k] + dd * (c - rrs[k]);
        }
        // The end values are da²·(ρ² − r²) at the piece's ends: as a norm
        // they keep their sign when r = 0 there and the ray passes through
        // the apex (a double root in s, a plain crossing in space).
        f[0] = (fr.dp * (z[0] - pa) + fr.pp * da).length_squared() - dd * r[0] * r[0];
        f[L - 1] = (fr.dp * (z[n] - pa) + fr.pp * da).length_squared() - dd * r[n] * r[n];
        let forward = pc.z_up == (da > 0.0);
        let mut found = None;
        visit_roots(&f, forward, &mut |x| {
            self.take_root(eval_d, &z, &r, pc, fr, t_max, x, &mut found)
        });
        found
    }

    /// What the search for roots of the ray's polynomial does with the root
    /// `x` (curve parameter within piece `pc`): its distance, polished where
    /// t = w/da loses digits; a hit before the window is passed over, one in
    /// it is kept in `found`, and either way the search stops past the window.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn take_root(
        &self,
        eval: impl Eval,
        z: &[f64],
        r: &[f64],
        pc: &Piece,
        fr: &Frame,
        t_max: f64,
        x: f64,
        found: &mut Option<(f64, f64)>,
    ) -> Flow {
        let n = z.len() - 1;
        let (zx, dz) = eval(z, n, x);
        let (mut x, mut t) = (x, (zx - fr.pa) / fr.da);
        if (dz / fr.da).abs() > 1e2 * self.scale {
            let (rx, dr) = eval(r, n, x);
            (x, t) = polish(eval, z, r, n, fr, x, t, zx, dz, rx, dr);
        }
        let tg = fr.t0 + t;
        if tg <= fr.t_min {
            return Flow::Continue;
        }
        if tg < t_max {
            *found = Some((tg, pc.s0 + x.clamp(0.0, 1.0) * (pc.s1 - pc.s0)));
        }
        Flow::Stop
    }

    /// [`Self::solve_poly`] for profiles of any degree, on the calling
    /// thread's scratch buffer (a fresh one if that is in use).
    fn solve_poly_any(&self, i: usize, fr: &Frame, t_max: f64) -> Option<(f64, f64)> {
        thread_local! {
            static SCRATCH: RefCell<Vec<f64>> = const { RefCell::new(Vec::new()) };
        }
        SCRATCH.with(|cell| match cell.try_borrow_mut() {
            Ok(mut buf) => self.solve_poly_in(i, fr, t_max, &mut buf),
            Err(_) => self.solve_poly_in(i, fr, t_max, &mut Vec::new()),
        })
    }

    /// The body of [`Self::solve_poly_any`]: the same polynomial, built in
    /// `buf` and searched there.
    fn solve_poly_in(
        &self,
        i: usize,
        fr: &Frame,
        t_max: f64,
        buf: &mut Vec<f64>,
    ) -> Option<(f64, f64)> {
        let n = self.degree;
        let l = 2 * n + 1;
        let (z, r, rrs) = self.piece_coefs(i);
        let pc = &self.pieces[i];
        let (pa, da) = (fr.pa, fr.da);
        let c = fr.c;
        let bn = binom_row(n);
        let two_b_da = 2.0 * fr.b * da;
        buf.clear();
        buf.resize(l + 2 * (n + 1), 0.0);
        let (f, rest) = buf.split_at_mut(l);
        let (wh, vh) = rest.split_at_mut(n + 1);
        for j in 0..=n {
            let w = z[j] - pa;
            wh[j] = bn[j] * w;
            vh[j] = bn[j] * (fr.a * w + two_b_da);
        }
        for j in 0..=n {
            for k in 0..=n {
                f[j + k] += wh[j] * vh[k];
            }
        }
        let dd = da * da;
        let inv = inv_binom_row(2 * n);
        for k in 0..l {
            f[k] = f[k] * inv[k] + dd * (c - rrs[k]);
        }
        f[0] = (fr.dp * (z[0] - pa) + fr.pp * da).length_squared() - dd * r[0] * r[0];
        f[l - 1] = (fr.dp * (z[n] - pa) + fr.pp * da).length_squared() - dd * r[n] * r[n];
        buf.truncate(l);
        let forward = pc.z_up == (da > 0.0);
        let mut found = None;
        visit_roots_any(buf, l - 1, forward, &mut |x| {
            self.take_root(eval_d_any, z, r, pc, fr, t_max, x, &mut found)
        });
        found
    }

    /// Rays nearly perpendicular to the axis: each half of the ray, split at
    /// its closest approach t* to the axis, meets the piece where
    /// g(s) = √A·(z(s) − h*) ∓ da·√(r(s)² − ρ*²) = 0.
    /// `eval` evaluates the profile polynomials.
    fn solve_slice(&self, i: usize, fr: &Frame, t_max: f64, eval: impl Eval) -> Option<(f64, f64)> {
        let n = self.degree;
        let (z, r, _) = self.piece_coefs(i);
        let pc = &self.pieces[i];
        let sa = fr.a.sqrt();
        let ts = fr.t_axis;
        let xs = fr.pp + fr.dp * ts;
        let rs2 = xs.length_squared();
        let hs = fr.pa + fr.da * ts;
        let q_tol = 1e-9 * self.scale * self.scale;
        for sigma in [-1.0, 1.0] {
            let k = sigma * fr.da;
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
                let positive_at_0 = g0 > 0.0;
                let (mut a, mut b) = (0.0, 1.0);
                let mut x = (g0 / (g0 - g1)).clamp(0.0, 1.0);
                let mut last_step = 1.0f64;
                for _ in 0..200 {
                    let (zx, dz) = eval(z, n, x);
                    let (rx, dr) = eval(r, n, x);
                    let q = rx * rx - rs2;
                    let gx = g(zx, rx);
                    if gx == 0.0 {
                        break;
                    }
                    if (gx > 0.0) == positive_at_0 {
                        a = x;
                    } else {
                        b = x;
                    }
                    let dg = sa * dz - if q > 0.0 { k * rx * dr / q.sqrt() } else { 0.0 };
                    let step = gx / dg;
                    if converged(step, last_step) {
                        x = (x - step).clamp(a, b);
                        break;
                    }
                    last_step = step;
                    let mut next = x - step;
                    if !(next > a && next < b) {
                        next = 0.5 * (a + b);
                    }
                    x = next;
                    if b - a <= 1e-15 {
                        break;
                    }
                }
                x
            };
            let (zx, dz) = eval(z, n, x);
            let (rx, dr) = eval(r, n, x);
            let q = rx * rx - rs2;
            if q < -q_tol {
                continue;
            }
            let t = ts + sigma * (q.max(0.0) / fr.a).sqrt();
            let (x, t) = polish(eval, z, r, n, fr, x, t, zx, dz, rx, dr);
            let tg = fr.t0 + t;
            if tg > fr.t_min && tg < t_max {
                return Some((tg, pc.s0 + x.clamp(0.0, 1.0) * (pc.s1 - pc.s0)));
            }
        }
        None
    }

    /// Point, outward normal (see the module docs for which side that is)
    /// and texture coordinates (u = s, v = angle around the axis / 2π) at a hit.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        let point = ray.at(hit.t);
        let q = point - self.o1;
        let uv = DVec2::new(
            if hit.u.is_finite() { hit.u } else { 0.0 },
            angle_around(q, self.e1, self.e2) / TAU,
        );
        let normal = self.normal_at(hit.u, q);
        SurfacePoint {
            point,
            normal,
            shading_normal: normal,
            uv,
        }
    }

    /// Unit outward normal at curve parameter `s` for the point `q` − O1.
    fn normal_at(&self, s: f64, q: DVec3) -> DVec3 {
        let n = self.degree;
        if n == 0 || !s.is_finite() {
            return self.axis;
        }
        let s = s.clamp(0.0, 1.0);
        // Step inward from the ends, where the derivative or r may vanish.
        let inward = if s < 0.5 { 1e-7 } else { -1e-7 };
        let (mut rs, mut dr) = eval_d_any(&self.r, n, s);
        let (_, mut dz) = eval_d_any(&self.z, n, s);
        if dz.hypot(dr) <= 1e-12 * self.scale {
            (rs, dr) = eval_d_any(&self.r, n, s + inward);
            dz = eval_d_any(&self.z, n, s + inward).1;
        }
        if rs == 0.0 {
            rs = eval_d_any(&self.r, n, s + inward).0;
        }
        let d_rho = if rs < 0.0 { -dr } else { dr };
        let radial = q - self.axis * q.dot(self.axis);
        let rho = radial.length();
        let normal = if rho > 1e-12 * self.scale {
            radial / rho * dz - self.axis * d_rho
        } else if d_rho != 0.0 {
            // On the axis: the profile meets it, the normal is along it.
            -self.axis * d_rho.signum()
        } else {
            self.axis * dz.signum()
        };
        normal.try_normalize().unwrap_or(self.axis)
    }

    /// Tight world-space bounds of the surface.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }
}

/// Where the ray (local t) enters the shell of `pc` within (lo, hi), or
/// `None` if it cannot meet it there.
#[inline]
fn cull(pc: &Piece, fr: &Frame, lo: f64, hi: f64) -> Option<f64> {
    let (ta, tb) = if fr.da != 0.0 {
        let t1 = (pc.z_lo - fr.pa) * fr.inv_da;
        let t2 = (pc.z_hi - fr.pa) * fr.inv_da;
        (t1.min(t2).max(lo), t1.max(t2).min(hi))
    } else if fr.pa >= pc.z_lo && fr.pa <= pc.z_hi {
        (lo, hi)
    } else {
        return None;
    };
    // (Also rejects NaN from a degenerate ray.)
    if ta.partial_cmp(&tb).is_none_or(|o| o.is_gt()) {
        return None;
    }
    // Squared distance from the axis; the shells are padded for its rounding.
    let rho2 = |t: f64| fr.c + t * (2.0 * fr.b + fr.a * t);
    let closest = fr.t_axis.clamp(ta, tb);
    if closest.is_finite() && rho2(closest) > pc.rho_hi2 {
        return None;
    }
    if ta.is_finite() && tb.is_finite() && rho2(ta).max(rho2(tb)) < pc.rho_lo2 {
        return None;
    }
    Some(ta)
}

/// Newton's method on z(x) = pa + t·da, r(x)² = |p⊥ + t·d⊥|² from (x, t),
/// given z, z', r, r' at x (`eval` evaluates z and r); keeps the best point
/// by residual.
#[allow(clippy::too_many_arguments)]
fn polish(
    eval: impl Eval,
    z: &[f64],
    r: &[f64],
    n: usize,
    fr: &Frame,
    mut x: f64,
    mut t: f64,
    mut zx: f64,
    mut dz: f64,
    mut rx: f64,
    mut dr: f64,
) -> (f64, f64) {
    let mut best = (x, t);
    let mut best_err = f64::INFINITY;
    for _ in 0..4 {
        let p = fr.pp + fr.dp * t;
        let rho = p.length();
        let f1 = zx - fr.pa - t * fr.da;
        let f2 = rx * rx - rho * rho;
        // Residual in length units: |r| − ρ ≈ (r² − ρ²)/(|r| + ρ).
        let err = f1.abs() + f2.abs() / (rx.abs() + rho).max(f64::MIN_POSITIVE);
        if err.partial_cmp(&best_err) != Some(std::cmp::Ordering::Less) {
            break;
        }
        best = (x, t);
        best_err = err;
        if err == 0.0 {
            break;
        }
        let j22 = -2.0 * p.dot(fr.dp);
        let j21 = 2.0 * rx * dr;
        let det = dz * j22 + fr.da * j21;
        if det == 0.0 || !det.is_finite() {
            break;
        }
        x -= (f1 * j22 + fr.da * f2) / det;
        t -= (dz * f2 - j21 * f1) / det;
        (zx, dz) = eval(z, n, x);
        (rx, dr) = eval(r, n, x);
    }
    best
}

fn min_max(v: &[f64]) -> (f64, f64) {
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        })
}
