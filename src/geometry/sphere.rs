//! Spheres: `primitive sphere` (`O= R= De= Dc=`) and sphere lights.

use super::{Aabb, Hit, Ray, SurfacePoint};
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// A sphere with a texture orientation (De: the pole, Dc: the seam).
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: DVec3,
    /// Radius (> 0).
    pub radius: f64,
    /// Unit (De, Dc) when not the default (z, y): boxed, as a million
    /// spheres rarely carry one, to keep the sphere at 40 bytes.
    orientation: Option<Box<[DVec3; 2]>>,
}

impl Sphere {
    /// A sphere with the default texture orientation (De = z, Dc = y).
    pub fn new(center: DVec3, radius: f64) -> Self {
        Sphere {
            center,
            radius,
            orientation: None,
        }
    }

    /// A sphere whose texture has its pole along `de` and its seam along `dc` (both unit).
    pub fn with_orientation(center: DVec3, radius: f64, de: DVec3, dc: DVec3) -> Self {
        let default = de == DVec3::Z && dc == DVec3::Y;
        Sphere {
            center,
            radius,
            orientation: (!default).then(|| Box::new([de, dc])),
        }
    }

    /// Unit pole direction of the texture mapping (De).
    pub fn de(&self) -> DVec3 {
        self.orientation.as_ref().map_or(DVec3::Z, |o| o[0])
    }

    /// Unit seam direction of the texture mapping (Dc).
    pub fn dc(&self) -> DVec3 {
        self.orientation.as_ref().map_or(DVec3::Y, |o| o[1])
    }

    /// Both roots of the ray/sphere quadratic (t0 ≤ t1), or `None` on a miss.
    /// Uses the form of Ray Tracing Gems ch. 7 that stays exact for huge
    /// spheres seen from close by (the framework's Cornell box walls).
    #[inline]
    pub fn roots(&self, ray: &Ray) -> Option<(f64, f64)> {
        let f = ray.origin - self.center;
        let b = f.dot(ray.dir);
        let perp = f - ray.dir * b;
        let r2 = self.radius * self.radius;
        let disc = r2 - perp.length_squared();
        if disc < 0.0 {
            return None;
        }
        let c = f.length_squared() - r2;
        let q = -b - disc.sqrt().copysign(b);
        if q == 0.0 {
            return Some((0.0, 0.0));
        }
        let (t0, t1) = (c / q, q);
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }

    /// The nearest hit with `t_min < t < t_max`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let (t0, t1) = self.roots(ray)?;
        if t0 > t_min && t0 < t_max {
            Some(Hit::at(t0))
        } else if t1 > t_min && t1 < t_max {
            Some(Hit::at(t1))
        } else {
            None
        }
    }

    /// Point, outward normal and texture coordinates at a hit.
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        let s = self.surface_untextured(ray, hit);
        SurfacePoint {
            uv: self.uv(s.normal),
            ..s
        }
    }

    /// Point and outward normal at a hit, texture coordinates left at zero.
    #[inline]
    pub fn surface_untextured(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        let point = ray.at(hit.t);
        let normal = ((point - self.center) / self.radius).normalize();
        SurfacePoint {
            point,
            normal,
            shading_normal: normal,
            uv: DVec2::ZERO,
        }
    }

    /// The spec's sphere mapping for the unit direction `i` from the centre.
    pub fn uv(&self, i: DVec3) -> DVec2 {
        let (de, dc) = (self.de(), self.dc());
        let a = (-i.dot(de)).clamp(-1.0, 1.0).acos();
        let sin_a = a.sin();
        let b = if sin_a > 0.0 {
            (i.dot(dc) / sin_a).clamp(-1.0, 1.0).acos()
        } else {
            0.0
        };
        let mut v = b / (2.0 * PI);
        if i.dot(dc.cross(de)) < 0.0 {
            v = 1.0 - v;
        }
        DVec2::new(a / PI, v)
    }

    /// Bounds.
    pub fn bounds(&self) -> Aabb {
        let r = DVec3::splat(self.radius);
        Aabb::from_points(self.center - r, self.center + r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_unit_sphere_at_closed_form_distance() {
        let s = Sphere::new(DVec3::new(0.0, 5.0, 0.0), 1.0);
        let r = Ray::new(DVec3::ZERO, DVec3::Y);
        assert_eq!(s.intersect(&r, 0.0, f64::INFINITY).map(|h| h.t), Some(4.0));
        // From inside: the far root.
        let r = Ray::new(DVec3::new(0.0, 5.0, 0.0), DVec3::Y);
        assert_eq!(s.intersect(&r, 0.0, f64::INFINITY).map(|h| h.t), Some(1.0));
        // Offset ray at height h: t = 5 - sqrt(1 - h²).
        let h = 0.6;
        let r = Ray::new(DVec3::new(h, 0.0, 0.0), DVec3::Y);
        let t = s.intersect(&r, 0.0, f64::INFINITY).map(|h| h.t);
        assert!(t.is_some_and(|t| (t - (5.0 - (1.0f64 - h * h).sqrt())).abs() < 1e-14));
        let r = Ray::new(DVec3::new(1.01, 0.0, 0.0), DVec3::Y);
        assert!(s.intersect(&r, 0.0, f64::INFINITY).is_none());
    }

    #[test]
    fn huge_sphere_seen_from_near_is_exact() {
        // The framework's Cornell box wall: R = 1e5, the eye 100 units away.
        let s = Sphere::new(DVec3::new(100_001.0, 0.0, 0.0), 100_000.0);
        let r = Ray::new(DVec3::new(-50.0, 0.0, 0.0), DVec3::X);
        let t = s.intersect(&r, 0.0, f64::INFINITY).map(|h| h.t);
        assert!(t.is_some_and(|t| (t - 51.0).abs() < 1e-9 * 51.0), "{t:?}");
    }

    #[test]
    fn uv_follows_spec_at_poles_and_equator() {
        let s = Sphere::new(DVec3::ZERO, 1.0);
        // -De (bottom pole): a = 0 -> u = 0; +De: u = 1.
        assert!(s.uv(-DVec3::Z).x.abs() < 1e-12);
        assert!((s.uv(DVec3::Z).x - 1.0).abs() < 1e-12);
        // On the equator along Dc: b = 0 -> v = 0 (or 1 on the other side).
        let uv = s.uv(DVec3::Y);
        assert!((uv.x - 0.5).abs() < 1e-12 && uv.y.abs() < 1e-12);
        // Along -Dc: b = pi -> v = 1/2 either way.
        assert!((s.uv(-DVec3::Y).y - 0.5).abs() < 1e-12);
        // Dc x De = y x z = x: +x has v = 1/4, -x has v = 3/4.
        assert!((s.uv(DVec3::X).y - 0.25).abs() < 1e-12);
        assert!((s.uv(-DVec3::X).y - 0.75).abs() < 1e-12);
    }
}
