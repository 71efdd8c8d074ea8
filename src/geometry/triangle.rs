//! Triangles: `primitive triangle` (`O1= O2= O3=`) and OBJ meshes (`primitive mesh`).

use super::{Aabb, Hit, Ray, SurfacePoint};
use glam::{DVec2, DVec3};

/// A triangle, with per-vertex normals when it comes from a smooth mesh and
/// per-vertex texture coordinates when its OBJ file has them.
///
/// The vertices are kept as given (not as edge vectors) so that triangles
/// sharing a vertex see bit-identical coordinates: with the watertight test
/// in [`Triangle::intersect`] a mesh then has no cracks along its edges.
#[derive(Clone, Debug, PartialEq)]
pub struct Triangle {
    /// The three vertices; the outward normal is unit((v1 − v0) × (v2 − v0)).
    pub vertices: [DVec3; 3],
    /// Vertex normals and texture coordinates, when there are any (boxed:
    /// most triangles have none, and meshes hold up to millions of triangles).
    attributes: Option<Box<Attributes>>,
}

/// What a mesh's vertices may carry besides their position.
#[derive(Clone, Debug, PartialEq)]
struct Attributes {
    /// Unit vertex normals.
    normals: Option<[DVec3; 3]>,
    /// Texture coordinates (an OBJ file's `vt`, for `primitive polyhedron`).
    uvs: Option<[DVec2; 3]>,
}

impl Triangle {
    /// A triangle from three vertices (not collinear: a degenerate triangle is
    /// never hit) and optional unit vertex normals.
    pub fn new(a: DVec3, b: DVec3, c: DVec3, normals: Option<[DVec3; 3]>) -> Self {
        Triangle {
            vertices: [a, b, c],
            attributes: normals.map(|n| {
                Box::new(Attributes {
                    normals: Some(n),
                    uvs: None,
                })
            }),
        }
    }

    /// The same triangle with texture coordinates at its vertices: a hit's
    /// are then theirs, interpolated, instead of its barycentrics.
    pub fn with_uvs(mut self, uvs: [DVec2; 3]) -> Self {
        match &mut self.attributes {
            Some(a) => a.uvs = Some(uvs),
            None => {
                self.attributes = Some(Box::new(Attributes {
                    normals: None,
                    uvs: Some(uvs),
                }))
            }
        }
        self
    }

    /// The unit vertex normals, if the mesh has them.
    pub fn normals(&self) -> Option<&[DVec3; 3]> {
        self.attributes.as_ref()?.normals.as_ref()
    }

    /// The texture coordinates of the vertices: the given ones, or those
    /// that make a hit's coordinates its barycentrics ((0, 0), (1, 0), (0, 1)).
    pub fn vertex_uvs(&self) -> [DVec2; 3] {
        match self.attributes.as_ref().and_then(|a| a.uvs) {
            Some(uv) => uv,
            None => [DVec2::ZERO, DVec2::X, DVec2::Y],
        }
    }

    /// Twice the area, |(v1 − v0) × (v2 − v0)| (0 for a degenerate triangle).
    pub fn double_area(&self) -> f64 {
        let [a, b, c] = self.vertices;
        (b - a).cross(c - a).length()
    }

    /// The hit with `t_min < t < t_max`, two-sided; `u`, `v` are the
    /// barycentric weights of the second and third vertex.
    ///
    /// Watertight (Woop, Benthin, Wald 2013): a ray through a shared edge or
    /// vertex of a mesh hits at least one of the triangles around it.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let ad = ray.dir.abs();
        if ad.x >= ad.y && ad.x >= ad.z {
            self.intersect_along::<0>(ray, t_min, t_max)
        } else if ad.y >= ad.z {
            self.intersect_along::<1>(ray, t_min, t_max)
        } else {
            self.intersect_along::<2>(ray, t_min, t_max)
        }
    }

    /// The watertight test with axis `KZ` (the ray's dominant one) as depth.
    #[inline(always)]
    fn intersect_along<const KZ: usize>(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        // Cyclic permutation putting axis KZ last (keeps the handedness).
        let perm = |v: DVec3| match KZ {
            0 => DVec3::new(v.y, v.z, v.x),
            1 => DVec3::new(v.z, v.x, v.y),
            _ => v,
        };
        let d = perm(ray.dir);
        let sz = 1.0 / d.z;
        let (sx, sy) = (d.x * sz, d.y * sz);
        let a = perm(self.vertices[0] - ray.origin);
        let b = perm(self.vertices[1] - ray.origin);
        let c = perm(self.vertices[2] - ray.origin);
        // Shear so the ray runs along +z from the origin; vertices shared by two
        // triangles are transformed by the same operations, bit for bit.
        let (ax, ay) = (a.x - sx * a.z, a.y - sy * a.z);
        let (bx, by) = (b.x - sx * b.z, b.y - sy * b.z);
        let (cx, cy) = (c.x - sx * c.z, c.y - sy * c.z);
        // Edge functions: a shared edge gives exactly opposite values in its
        // two triangles (fl(p − q) = −fl(q − p)), so no ray slips between them.
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let t = (u * a.z + v * b.z + w * c.z) * sz / det;
        (t > t_min && t < t_max).then(|| Hit {
            t,
            part: 0,
            u: v / det,
            v: w / det,
        })
    }

    /// Point, normals and texture coordinates at a hit (the vertices'
    /// interpolated, or the barycentrics (u, v) when they have none).
    pub fn surface(&self, ray: &Ray, hit: &Hit) -> SurfacePoint {
        let [a, b, c] = self.vertices;
        let w = 1.0 - hit.u - hit.v;
        let point = a * w + b * hit.u + c * hit.v;
        let n = (b - a).cross(c - a).normalize_or_zero();
        // A degenerate triangle has no normal; facing the ray keeps shading finite.
        let normal = if n == DVec3::ZERO { -ray.dir } else { n };
        let shading_normal = match self.normals() {
            Some(ns) => {
                let [na, nb, nc] = *ns;
                let s = (na * w + nb * hit.u + nc * hit.v).normalize_or_zero();
                if s == DVec3::ZERO { normal } else { s }
            }
            None => normal,
        };
        SurfacePoint {
            point,
            normal,
            shading_normal,
            uv: match self.attributes.as_ref().and_then(|a| a.uvs) {
                Some(t) => t[0] * w + t[1] * hit.u + t[2] * hit.v,
                None => DVec2::new(hit.u, hit.v),
            },
        }
    }

    /// Bounds.
    pub fn bounds(&self) -> Aabb {
        let [a, b, c] = self.vertices;
        Aabb::from_points(a, b).grow(c)
    }
}
