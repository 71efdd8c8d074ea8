//! Primitives: one file per kind, each answering the same questions
//! (intersect, surface point at a hit, bounds).
//!
//! Conventions shared by every kind:
//! - a [`Ray`] has a unit direction, so `t` is a distance;
//! - `intersect(ray, t_min, t_max)` returns the nearest hit with
//!   `t_min < t < t_max`, or `None`;
//! - [`SurfacePoint::normal`] is the unit *outward* geometric normal (for
//!   two-sided flat shapes: the normal the spec defines, e.g. unit(Dx × Dy));
//!   whether the ray hit the front is decided by its sign against the ray.

mod aabb;
mod bezier;
mod cube;
mod cylinder;
mod plane;
mod sphere;
mod square;
mod triangle;

pub use aabb::Aabb;
pub use bezier::Bezier;
pub use cube::Cube;
pub use cylinder::Cylinder;
pub use plane::Plane;
pub use sphere::Sphere;
pub use square::Square;
pub use triangle::Triangle;

use glam::{DVec2, DVec3};

/// A ray with a unit-length direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
    /// Hits at distances up to this are not reported (0 for a free ray).
    pub t_min: f64,
}

impl Ray {
    /// A ray from `origin` along `dir`, which must already be unit length.
    #[inline]
    pub fn new(origin: DVec3, dir: DVec3) -> Self {
        Ray {
            origin,
            dir,
            t_min: 0.0,
        }
    }

    /// A ray from `origin`, a point nudged off a surface by [`offset_origin`],
    /// that ignores hits within a sliver of it: where two surfaces meet (a
    /// box's edge, a cylinder's rim) the origin lies on the other surface up
    /// to rounding, which must not count as a fresh hit at t ≈ 1e-16.
    #[inline]
    pub fn off_surface(origin: DVec3, dir: DVec3) -> Self {
        Ray {
            origin,
            dir,
            t_min: SLIVER_REL * (1.0 + origin.abs().max_element()),
        }
    }

    /// The point at distance `t` along the ray.
    #[inline]
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.dir * t
    }
}

/// What an intersection test found: the distance plus the few numbers the
/// shape needs to finish the hit later in [`Shape::surface`] (only for the
/// nearest hit, so the costly parts are not paid for discarded candidates).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f64,
    /// Shape-specific sub-part (cube face, cylinder side or cap, ...).
    pub part: u32,
    /// Shape-specific parameters (barycentrics, curve parameter, ...).
    pub u: f64,
    /// Shape-specific parameters (barycentrics, curve parameter, ...).
    pub v: f64,
}

impl Hit {
    /// A hit at distance `t` with no extra data.
    #[inline]
    pub fn at(t: f64) -> Self {
        Hit {
            t,
            ..Hit::default()
        }
    }
}

/// The stretch of a ray inside a convex solid, with the sub-part (face,
/// cap, side) that bounds it at each end: narrowed piece by piece, as in a
/// slab test, then the nearest usable end is the hit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Span {
    near: f64,
    far: f64,
    near_part: u32,
    far_part: u32,
}

impl Span {
    /// The span [near, far] bounded by the parts given.
    #[inline]
    pub(crate) fn new(near: f64, far: f64, near_part: u32, far_part: u32) -> Self {
        Span {
            near,
            far,
            near_part,
            far_part,
        }
    }

    /// The whole ray, before any piece is clipped.
    #[inline]
    pub(crate) fn all() -> Self {
        Span::new(f64::NEG_INFINITY, f64::INFINITY, 0, 0)
    }

    /// Narrows the span to [near, far], whose ends belong to the given parts.
    #[inline]
    pub(crate) fn clip(&mut self, near: f64, far: f64, near_part: u32, far_part: u32) {
        if near > self.near {
            self.near = near;
            self.near_part = near_part;
        }
        if far < self.far {
            self.far = far;
            self.far_part = far_part;
        }
    }

    /// The nearest end with `t_min < t < t_max`: the entry from outside, the
    /// exit from inside; `None` when the span is empty.
    #[inline]
    pub(crate) fn hit(&self, t_min: f64, t_max: f64) -> Option<Hit> {
        if self.near > self.far {
            return None;
        }
        let (t, part) = if self.near > t_min && self.near < t_max {
            (self.near, self.near_part)
        } else if self.far > t_min && self.far < t_max {
            (self.far, self.far_part)
        } else {
            return None;
        };
        Some(Hit {
            t,
            part,
            ..Hit::default()
        })
    }
}

/// Everything shading needs to know about a hit point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The hit point.
    pub point: DVec3,
    /// Unit outward geometric normal.
    pub normal: DVec3,
    /// Unit outward shading normal (interpolated on smooth meshes, else `normal`).
    pub shading_normal: DVec3,
    /// Texture coordinates as the spec defines them (u selects the row).
    pub uv: DVec2,
}

/// Every kind of primitive, as one enum so the hot path branches instead of
/// calling through pointers. Large kinds are boxed to keep the enum small.
#[derive(Clone, Debug)]
pub enum Shape {
    /// A sphere.
    Sphere(Sphere),
    /// An infinite plane.
    Plane(Box<Plane>),
    /// A parallelogram.
    Square(Box<Square>),
    /// An oriented box.
    Cube(Box<Cube>),
    /// A closed cylinder.
    Cylinder(Box<Cylinder>),
    /// A Bézier surface of revolution.
    Bezier(Box<Bezier>),
    /// A triangle (alone or from a mesh).
    Triangle(Box<Triangle>),
}

impl Shape {
    /// The nearest hit with `t_min < t < t_max`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        match self {
            Shape::Sphere(s) => s.intersect(ray, t_min, t_max),
            Shape::Plane(s) => s.intersect(ray, t_min, t_max),
            Shape::Square(s) => s.intersect(ray, t_min, t_max),
            Shape::Cube(s) => s.intersect(ray, t_min, t_max),
            Shape::Cylinder(s) => s.intersect(ray, t_min, t_max),
            Shape::Bezier(s) => s.intersect(ray, t_min, t_max),
            Shape::Triangle(s) => s.intersect(ray, t_min, t_max),
        }
    }

    /// Finishes a hit returned by [`Shape::intersect`] for the same ray.
    #[inline]
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        match self {
            Shape::Sphere(s) => s.surface(ray, hit),
            Shape::Plane(s) => s.surface(ray, hit),
            Shape::Square(s) => s.surface(ray, hit),
            Shape::Cube(s) => s.surface(ray, hit),
            Shape::Cylinder(s) => s.surface(ray, hit),
            Shape::Bezier(s) => s.surface(ray, hit),
            Shape::Triangle(s) => s.surface(ray, hit),
        }
    }

    /// [`Shape::surface`] without the texture coordinates (left at zero), for
    /// untextured materials: spares spheres their trigonometry.
    #[inline]
    pub fn surface_untextured(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        match self {
            Shape::Sphere(s) => s.surface_untextured(ray, hit),
            _ => self.surface(ray, hit),
        }
    }

    /// World-space bounds, or `None` for unbounded shapes (planes).
    pub fn bounds(&self) -> Option<Aabb> {
        match self {
            Shape::Sphere(s) => Some(s.bounds()),
            Shape::Plane(_) => None,
            Shape::Square(s) => Some(s.bounds()),
            Shape::Cube(s) => Some(s.bounds()),
            Shape::Cylinder(s) => Some(s.bounds()),
            Shape::Bezier(s) => Some(s.bounds()),
            Shape::Triangle(s) => Some(s.bounds()),
        }
    }
}

/// The reference direction e1 ⟂ `axis` used by the spec's angular texture
/// mappings (cylinder, Bézier): unit(axis × z), or x when axis ∥ z.
/// Returns (e1, e2 = axis × e1); `axis` must be unit length.
pub fn axis_frame(axis: DVec3) -> (DVec3, DVec3) {
    let c = axis.cross(DVec3::Z);
    let e1 = if c.length_squared() < 1e-24 {
        DVec3::X
    } else {
        c.normalize()
    };
    (e1, axis.cross(e1))
}

/// Two unit vectors perpendicular to the unit vector `w` and to each other.
pub fn perpendiculars(w: DVec3) -> (DVec3, DVec3) {
    let a = if w.x.abs() > 0.9 { DVec3::Y } else { DVec3::X };
    let u = w.cross(a).normalize();
    (u, w.cross(u))
}

/// The angle of `q` around an axis with frame (e1, e2), in [0, 2π).
pub fn angle_around(q: DVec3, e1: DVec3, e2: DVec3) -> f64 {
    let a = q.dot(e2).atan2(q.dot(e1));
    if a < 0.0 {
        a + std::f64::consts::TAU
    } else {
        a
    }
}

/// The origin for a ray leaving `point` on the side `side` (a unit normal
/// pointing where the new ray goes): nudged off the surface by a distance
/// relative to the coordinates' magnitude, so it cannot re-hit the surface
/// it starts on through rounding error.
#[inline]
pub fn offset_origin(point: DVec3, side: DVec3) -> DVec3 {
    point + side * (OFFSET_REL * (1.0 + point.abs().max_element()))
}

/// Relative size of the nudge in [`offset_origin`].
pub const OFFSET_REL: f64 = 1e-9;

/// Relative size of the sliver that [`Ray::off_surface`] ignores: far above
/// rounding (1e-16), far below the nudge, so a surface the ray really leaves
/// towards is never skipped.
pub const SLIVER_REL: f64 = 1e-10;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perpendiculars_are_orthonormal() {
        for w in [
            DVec3::X,
            DVec3::Y,
            -DVec3::Z,
            DVec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let (u, v) = perpendiculars(w);
            assert!(u.dot(w).abs() < 1e-15 && v.dot(w).abs() < 1e-15 && u.dot(v).abs() < 1e-15);
            assert!((u.length() - 1.0).abs() < 1e-15 && (v.length() - 1.0).abs() < 1e-15);
        }
    }

    /// A million-sphere scene keeps its objects small: the enum stays at the
    /// sphere's size because the larger kinds are boxed.
    #[test]
    fn shape_stays_small() {
        assert!(
            std::mem::size_of::<Shape>() <= 48,
            "{}",
            std::mem::size_of::<Shape>()
        );
    }
}
