//! Rays, the hits a shape reports and the surface point it finishes them
//! into, and the nudge that keeps a new ray off the surface it leaves.

use glam::{DVec2, DVec3};

/// A ray with a unit-length direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point.
    pub origin: DVec3,
    /// Unit direction.
    pub dir: DVec3,
    /// Hits at distances up to this are not reported (0 for a free ray);
    /// never negative, so every hit's distance is positive.
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
/// shape needs to finish the hit later in
/// [`Shape::surface`](super::Shape::surface) (only for the
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

    /// Whether the span ends at or before `t_min` or starts at or past
    /// `t_max`: then, narrowed in any way, it gives no [`Span::hit`]
    /// between them.
    #[inline]
    pub(crate) fn outside(&self, t_min: f64, t_max: f64) -> bool {
        self.far <= t_min || self.near >= t_max
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
