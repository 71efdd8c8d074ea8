//! Bézier surfaces of revolution: `primitive bezier` (`O1= O2= P= z r` ...).

use super::{Aabb, Hit, Ray, SurfacePoint};
use glam::{DVec2, DVec3};

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
}

impl Bezier {
    /// A surface from the spec's keys (O1 ≠ O2, at least two control points).
    pub fn new(o1: DVec3, o2: DVec3, points: Vec<DVec2>) -> Self {
        Bezier { o1, o2, points }
    }

    /// The nearest hit with `t_min < t < t_max`.
    pub fn intersect(&self, _ray: &Ray, _t_min: f64, _t_max: f64) -> Option<Hit> {
        None
    }

    /// Point, outward normal and texture coordinates at a hit.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        SurfacePoint {
            point: ray.at(hit.t),
            normal: DVec3::Z,
            shading_normal: DVec3::Z,
            uv: DVec2::ZERO,
        }
    }

    /// Bounds.
    pub fn bounds(&self) -> Aabb {
        let rmax = self.points.iter().map(|p| p.y.abs()).fold(0.0, f64::max);
        let r = DVec3::splat(rmax);
        Aabb::from_points(self.o1 - r, self.o1 + r)
            .union(&Aabb::from_points(self.o2 - r, self.o2 + r))
    }
}
