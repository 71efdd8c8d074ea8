//! Closed cylinders: `primitive cylinder` (`O1= O2= R=`).

use super::{Aabb, Hit, Ray, SurfacePoint};
use glam::{DVec2, DVec3};

/// A closed cylinder: side surface plus discs at both ends.
#[derive(Clone, Debug, PartialEq)]
pub struct Cylinder {
    /// Centre of the first cap.
    pub o1: DVec3,
    /// Centre of the second cap.
    pub o2: DVec3,
    /// Radius (> 0).
    pub radius: f64,
}

impl Cylinder {
    /// A cylinder from the spec's keys (O1 ≠ O2, R > 0).
    pub fn new(o1: DVec3, o2: DVec3, radius: f64) -> Self {
        Cylinder { o1, o2, radius }
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
        let r = DVec3::splat(self.radius);
        Aabb::from_points(self.o1 - r, self.o1 + r)
            .union(&Aabb::from_points(self.o2 - r, self.o2 + r))
    }
}
