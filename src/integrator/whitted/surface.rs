//! The surface point a ray hit, as shading sees it: its material, texture
//! coordinates, the normal map applied, and both normals turned to face
//! the ray.

use super::Whitted;
use crate::geometry::{Hit, Ray};
use crate::scene::{Material, Object};
use glam::{DVec2, DVec3};

/// A lit surface's point, as the shading terms read it.
pub(super) struct ShadingPoint {
    /// The object hit (its index in the structure).
    pub object: u32,
    /// Its material.
    pub material: Material,
    /// The ray's distance to the point.
    pub t: f64,
    /// The point.
    pub point: DVec3,
    /// Its texture coordinates.
    pub uv: DVec2,
    /// Whether the ray hit the outside.
    pub front: bool,
    /// The geometric normal facing the ray (for nudging new rays).
    pub side: DVec3,
    /// The shading normal facing the ray.
    pub n: DVec3,
}

impl Whitted<'_> {
    /// The point where `ray` hit `object` (index `index`) at `hit`.
    #[inline(always)]
    pub(super) fn surface_point(
        &self,
        (index, object): (u32, &Object),
        ray: &Ray,
        hit: &Hit,
    ) -> ShadingPoint {
        let scene = self.scene;
        let m = scene.material_of(object);
        let shape = object.shape();
        let mut surface = if m.texture.is_some() || m.normal_map.is_some() {
            shape.surface(ray, hit)
        } else {
            shape.surface_untextured(ray, hit)
        };
        if let Some(map) = m.normal_map.and_then(|t| scene.textures().get(t as usize)) {
            surface.shading_normal = shape.mapped_normal(&surface, map.sample(surface.uv));
        }
        let front = surface.normal.dot(ray.dir) < 0.0;
        let (side, n) = if front {
            (surface.normal, surface.shading_normal)
        } else {
            (-surface.normal, -surface.shading_normal)
        };
        ShadingPoint {
            object: index,
            material: m,
            t: hit.t,
            point: surface.point,
            uv: surface.uv,
            front,
            side,
            n,
        }
    }
}
