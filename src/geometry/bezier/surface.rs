//! What a hit looks like: the point, the outward normal and the texture
//! coordinates.

use super::super::{Hit, Ray, SurfacePoint, angle_around};
use super::bernstein::eval_d;
use super::{Bezier, BezierUv};
use glam::{DVec2, DVec3};
use std::f64::consts::TAU;

impl Bezier {
    /// Point, outward normal (see the module docs for which side that is)
    /// and texture coordinates (u = s, v = angle around the axis / 2π; or
    /// as [`BezierUv`] says) at a hit.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        let point = ray.at(hit.t);
        let q = point - self.o1;
        let s = if hit.u.is_finite() { hit.u } else { 0.0 };
        let angle = angle_around(q, self.e1, self.e2) / TAU;
        let uv = match self.uv {
            BezierUv::Spec => DVec2::new(s, angle),
            BezierUv::Lazycal => {
                let n = self.pieces.degree();
                let negative = n > 0 && eval_d(&self.r, n, s.clamp(0.0, 1.0)).0 < 0.0;
                DVec2::new(if negative { angle + 0.5 } else { angle }, s)
            }
            BezierUv::Span { start, length } => DVec2::new(start + length * s, angle),
        };
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
        let n = self.pieces.degree();
        if n == 0 || !s.is_finite() {
            return self.axis;
        }
        let scale = self.pieces.scale();
        let s = s.clamp(0.0, 1.0);
        // Step inward from the ends, where the derivative or r may vanish.
        let inward = if s < 0.5 { 1e-7 } else { -1e-7 };
        let (mut rs, mut dr) = eval_d(&self.r, n, s);
        let (_, mut dz) = eval_d(&self.z, n, s);
        if dz.hypot(dr) <= 1e-12 * scale {
            (rs, dr) = eval_d(&self.r, n, s + inward);
            dz = eval_d(&self.z, n, s + inward).1;
        }
        if rs == 0.0 {
            rs = eval_d(&self.r, n, s + inward).0;
        }
        let d_rho = if rs < 0.0 { -dr } else { dr };
        let radial = q - self.axis * q.dot(self.axis);
        let rho = radial.length();
        let normal = if rho > 1e-12 * scale {
            radial / rho * dz - self.axis * d_rho
        } else if d_rho != 0.0 {
            // On the axis: the profile meets it, the normal is along it.
            -self.axis * d_rho.signum()
        } else {
            self.axis * dz.signum()
        };
        normal.try_normalize().unwrap_or(self.axis)
    }
}
