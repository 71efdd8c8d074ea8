//! Triangles: `primitive triangle` (`O1= O2= O3=`) and OBJ meshes (`primitive mesh`).

use super::{Aabb, Hit, Ray, SurfacePoint};
use glam::{DVec2, DVec3};
use std::path::Path;

/// A triangle, with per-vertex normals when it comes from a smooth mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Triangle {
    /// First vertex.
    pub p0: DVec3,
    /// Edge p1 − p0.
    pub e1: DVec3,
    /// Edge p2 − p0.
    pub e2: DVec3,
    /// Unit vertex normals, when the mesh has them.
    pub normals: Option<[DVec3; 3]>,
}

impl Triangle {
    /// A triangle from three vertices (not collinear).
    pub fn new(a: DVec3, b: DVec3, c: DVec3, normals: Option<[DVec3; 3]>) -> Self {
        Triangle {
            p0: a,
            e1: b - a,
            e2: c - a,
            normals,
        }
    }

    /// The hit with `t_min < t < t_max` (Möller–Trumbore); `u`, `v` are the
    /// barycentric weights of the second and third vertex.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let p = ray.dir.cross(self.e2);
        let det = self.e1.dot(p);
        if det == 0.0 {
            return None;
        }
        let inv = 1.0 / det;
        let s = ray.origin - self.p0;
        let u = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(self.e1);
        let v = ray.dir.dot(q) * inv;
        if v < 0.0 || u + v > 1.0 {
            return None;
        }
        let t = self.e2.dot(q) * inv;
        (t > t_min && t < t_max).then_some(Hit { t, part: 0, u, v })
    }

    /// Point, normals and barycentric texture coordinates at a hit.
    pub fn surface(&self, _ray: &Ray, hit: &Hit) -> SurfacePoint {
        let point = self.p0 + self.e1 * hit.u + self.e2 * hit.v;
        let normal = self.e1.cross(self.e2).normalize();
        let shading_normal = match self.normals {
            Some([a, b, c]) => {
                let n = (a * (1.0 - hit.u - hit.v) + b * hit.u + c * hit.v).normalize_or_zero();
                if n == DVec3::ZERO { normal } else { n }
            }
            None => normal,
        };
        SurfacePoint {
            point,
            normal,
            shading_normal,
            uv: DVec2::new(hit.u, hit.v),
        }
    }

    /// Bounds.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.p0, self.p0 + self.e1).grow(self.p0 + self.e2)
    }
}

/// Loads an OBJ file as triangles, scaled, rotated (Euler angles in radians
/// about x, then y, then z) and translated.
pub fn load_obj(
    _path: &Path,
    _origin: DVec3,
    _scale: DVec3,
    _rotation: DVec3,
) -> Result<Vec<Triangle>, String> {
    Err("meshes are not supported yet".to_string())
}
