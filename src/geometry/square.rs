//! Parallelograms: `primitive square` (`O= Dx= Dy=`, half-edge vectors) and square lights.

use super::{Aabb, Hit, Ray, SurfacePoint};
use glam::{DVec2, DVec3};

/// The parallelogram O ± Dx ± Dy, two-sided, normal unit(Dx × Dy).
#[derive(Clone, Debug, PartialEq)]
pub struct Square {
    /// Centre.
    pub center: DVec3,
    /// Half-edge vector.
    pub dx: DVec3,
    /// Half-edge vector.
    pub dy: DVec3,
    /// Unit normal, unit(Dx × Dy).
    pub normal: DVec3,
    /// Dual vectors: (P − O)·ax = a, (P − O)·ay = b for P = O + a·Dx + b·Dy.
    ax: DVec3,
    ay: DVec3,
}

impl Square {
    /// A square from the spec's keys; Dx and Dy must not be parallel.
    pub fn new(center: DVec3, dx: DVec3, dy: DVec3) -> Self {
        let n = dx.cross(dy);
        let normal = n.normalize();
        let ax = dy.cross(n) / dx.dot(dy.cross(n));
        let ay = n.cross(dx) / dy.dot(n.cross(dx));
        Square {
            center,
            dx,
            dy,
            normal,
            ax,
            ay,
        }
    }

    /// The hit with `t_min < t < t_max`, if any; `u`, `v` hold the
    /// parallelogram coordinates in [−1, 1].
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let denom = self.normal.dot(ray.dir);
        if denom == 0.0 {
            return None;
        }
        let t = (self.center - ray.origin).dot(self.normal) / denom;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let q = ray.at(t) - self.center;
        let (a, b) = (q.dot(self.ax), q.dot(self.ay));
        (a.abs() <= 1.0 && b.abs() <= 1.0).then_some(Hit {
            t,
            part: 0,
            u: a,
            v: b,
        })
    }

    /// Point, normal and texture coordinates at a hit.
    pub fn surface(&self, _ray: &Ray, hit: &Hit) -> SurfacePoint {
        let point = self.center + self.dx * hit.u + self.dy * hit.v;
        let q = point - self.center;
        SurfacePoint {
            point,
            normal: self.normal,
            shading_normal: self.normal,
            uv: DVec2::new(
                q.dot(self.dx) / self.dx.length_squared() / 2.0 + 0.5,
                q.dot(self.dy) / self.dy.length_squared() / 2.0 + 0.5,
            ),
        }
    }

    /// Bounds.
    pub fn bounds(&self) -> Aabb {
        let e = self.dx.abs() + self.dy.abs();
        Aabb::from_points(self.center - e, self.center + e)
    }
}
