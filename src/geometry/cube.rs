//! Oriented boxes: `primitive cube` (`O= Dx= Dy= x= y= z=`).

use super::{Aabb, Hit, Ray, SurfacePoint};
use glam::{DVec2, DVec3};

/// A box centred at `center` with orthonormal axes and half-lengths.
#[derive(Clone, Debug, PartialEq)]
pub struct Cube {
    /// Centre.
    pub center: DVec3,
    /// Orthonormal axes Dx, Dy, Dz = Dx × Dy.
    pub axes: [DVec3; 3],
    /// Half-lengths along the axes.
    pub half: DVec3,
}

impl Cube {
    /// A box from orthonormal `dx`, `dy` (the caller orthonormalises) and half-lengths.
    pub fn new(center: DVec3, dx: DVec3, dy: DVec3, half: DVec3) -> Self {
        Cube {
            center,
            axes: [dx, dy, dx.cross(dy)],
            half,
        }
    }

    /// The nearest hit with `t_min < t < t_max`.
    pub fn intersect(&self, _ray: &Ray, _t_min: f64, _t_max: f64) -> Option<Hit> {
        None
    }

    /// Point, outward normal and texture coordinates at a hit.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        SurfacePoint {
            point: ray.at(hit.t),
            normal: self.axes[2],
            shading_normal: self.axes[2],
            uv: DVec2::ZERO,
        }
    }

    /// Bounds.
    pub fn bounds(&self) -> Aabb {
        let e = (self.axes[0] * self.half.x).abs()
            + (self.axes[1] * self.half.y).abs()
            + (self.axes[2] * self.half.z).abs();
        Aabb::from_points(self.center - e, self.center + e)
    }
}
