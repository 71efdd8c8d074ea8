//! Parallelograms: `primitive square` (`O= Dx= Dy=`, half-edge vectors) and square lights.

use super::plane::behind;
use super::{Aabb, Hit, Ray, SurfacePoint};
use glam::{DVec2, DVec3};

/// How far past its edges (in units of the half-edge vectors) a square still
/// counts as hit: squares that share an edge, each rounding its own hit
/// point, could otherwise both miss a ray through that edge (a crack).
const SQUARE_EDGE_SLACK: f64 = 1e-9;

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
    /// A square from the spec's keys; Dx and Dy must not be parallel (a
    /// degenerate square is never hit).
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
    /// parallelogram coordinates (a, b) with P = O + a·Dx + b·Dy, |a|, |b| ≤ 1
    /// up to a slack of 1e-9 that keeps shared edges crack-free.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let s = self.center - ray.origin;
        let (num, denom) = (s.dot(self.normal), self.normal.dot(ray.dir));
        if behind(num, denom, t_min) {
            return None;
        }
        // A ray parallel to the plane gives ±∞ or NaN here, which the range test rejects.
        let t = num / denom;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let q = ray.dir * t - s;
        let (a, b) = (q.dot(self.ax), q.dot(self.ay));
        const LIMIT: f64 = 1.0 + SQUARE_EDGE_SLACK;
        (a.abs() <= LIMIT && b.abs() <= LIMIT).then_some(Hit {
            t,
            part: 0,
            u: a,
            v: b,
        })
    }

    /// Point (on the closed parallelogram), normal and texture coordinates at a hit.
    pub fn surface(&self, _ray: &Ray, hit: &Hit) -> SurfacePoint {
        let (a, b) = (hit.u.clamp(-1.0, 1.0), hit.v.clamp(-1.0, 1.0));
        let q = self.dx * a + self.dy * b;
        SurfacePoint {
            point: self.center + q,
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
