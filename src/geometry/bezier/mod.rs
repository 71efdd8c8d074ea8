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
//! Newton's method on the original two equations. The root search is
//! written once, over where its coefficients live: profiles up to degree
//! [`Bezier::MAX_FIXED_DEGREE`] (16) are solved on fixed-size arrays, one
//! specialisation per degree; higher degrees, up to [`Bezier::MAX_DEGREE`]
//! (64), in a per-thread buffer that grows to the largest size needed and
//! is then reused, so they allocate nothing per ray either.
//!
//! The outward normal is ρ̂·z'(s) − a·|r|'(s), with ρ̂ the unit vector from
//! the axis to the hit point: the profile's tangent in the (radius, height)
//! half-plane turned clockwise. For a profile that runs upward along the
//! wall of a vase this points away from the axis, and a profile that runs
//! counter-clockwise around the region it encloses with the axis gets
//! normals pointing out of that region; the normal field is continuous
//! along the sheet, also where the profile folds back.

//!
//! The files, in the order a ray meets them: `pieces` (the profile cut
//! into monotone pieces and their shells), `axis_ray` (the ray in axis
//! coordinates), `intersect` (which pieces to solve, and how), `poly` and
//! `slice` (the two formulations), `polish`, `surface` (point, normal,
//! texture coordinates) and `bounds`; beneath them the polynomials:
//! `binomials`, `bernstein`, `roots` (the root search) and `store` (where
//! its coefficients live).

mod axis_ray;
mod bernstein;
mod binomials;
mod bounds;
mod intersect;
mod pieces;
mod polish;
mod poly;
mod roots;
mod slice;
mod store;
mod surface;
#[cfg(test)]
mod test_polys;

use super::{Aabb, axis_frame};
use glam::{DVec2, DVec3};
use pieces::{Pieces, min_max};

/// How a hit's texture coordinates are read off the surface.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum BezierUv {
    /// The spec's: u = the curve parameter s, v = the point's angle / 2π.
    #[default]
    Spec,
    /// lazycal's: u = the profile point's angle / 2π (half a turn more
    /// where its radius is negative), v = s.
    Lazycal,
    /// The colon family's: the spec's with u running from `start` to
    /// `start + length` along the profile (a `rotationbody` gives each
    /// curve its share, `ratio:`, of one picture).
    Span {
        /// u where the profile starts.
        start: f64,
        /// u's change along the whole profile.
        length: f64,
    },
}

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
    /// How texture coordinates are read.
    uv: BezierUv,
    /// Profile coefficients on the whole curve (degree + 1 each).
    z: Vec<f64>,
    r: Vec<f64>,
    /// A point on the axis near the surface: rays are restarted from their
    /// closest approach to it so that all arithmetic is at object scale.
    center: DVec3,
    /// The profile cut into pieces (of degree 0, none, for bad input).
    pieces: Pieces,
    bounds: Aabb,
}

impl Bezier {
    /// Highest profile degree that is intersected (65 control points); the
    /// parser rejects more, and a surface built with more is never hit.
    pub const MAX_DEGREE: usize = binomials::MAX_DEGREE;
    /// Highest profile degree solved on fixed-size arrays specialised per
    /// degree (the fastest path); higher degrees use a per-thread buffer.
    pub const MAX_FIXED_DEGREE: usize = 16;

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
            uv: BezierUv::Spec,
            z: Vec::new(),
            r: Vec::new(),
            center: o1,
            pieces: Pieces::default(),
            bounds: Aabb::EMPTY,
            points,
        };
        if !valid {
            shape.bounds = shape.control_bounds();
            return shape;
        }
        shape.z = shape.points.iter().map(|p| p.x).collect();
        shape.r = shape.points.iter().map(|p| p.y).collect();
        let (z_min, z_max) = min_max(&shape.z[..=degree]);
        let r_max = shape.r[..=degree]
            .iter()
            .fold(0.0f64, |m, r| m.max(r.abs()));
        let scale = (z_max - z_min).max(r_max).max(f64::MIN_POSITIVE);
        shape.center = o1 + axis * (0.5 * (z_min + z_max));
        shape.pieces = Pieces::cut(&shape.z, &shape.r, degree, scale);
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

    /// The same surface with its texture coordinates read as `uv` says.
    pub fn with_uv(mut self, uv: BezierUv) -> Self {
        self.uv = uv;
        self
    }

    /// Tight world-space bounds of the surface.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }
}
