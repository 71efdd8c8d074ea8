//! The eye pass of PPM and SPPM: a [`PathObserver`] that keeps each
//! diffuse hit of a camera sample's tree (glossy sub-samples included)
//! with the weight of the path that reached it.

use crate::geometry::Ray;
use crate::integrator::observer::{PathObserver, RayKind, SurfaceSeen};
use crate::integrator::optics::reflect;
use crate::scene::{Material, Origin};
use glam::{DVec2, DVec3};

/// A diffuse eye hit, before its material's colour is looked up.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct HitPointSeed {
    /// The point.
    pub point: DVec3,
    /// The unit geometric normal on the side the eye ray came from.
    pub side: DVec3,
    /// The eye ray's mirror direction about the shading normal.
    pub mirror: DVec3,
    /// Texture coordinates.
    pub uv: DVec2,
    /// The surface's material.
    pub material: Material,
    /// The product of the weights of the rays that led here (the camera ray: 1).
    pub throughput: DVec3,
}

/// Collects the diffuse hits of one camera sample's tree.
#[derive(Clone, Default)]
pub(crate) struct HitPointObserver {
    /// The hits, in the order the tracer met them.
    pub seeds: Vec<HitPointSeed>,
    /// For each ray being traced, where its subtree's hits start.
    open: Vec<usize>,
}

impl PathObserver for HitPointObserver {
    type Fan<'s> = &'s mut HitPointObserver;

    fn fan(&mut self) -> &mut HitPointObserver {
        self
    }

    type Queries<'q> = ();

    fn queries(&mut self) {}

    fn hit(&mut self, _: Origin) {}

    fn point_light(&mut self, _: u32) {}

    fn ray(&mut self, _kind: RayKind, _depth: u32, _ray: &Ray) {
        self.open.push(self.seeds.len());
    }

    fn surface(&mut self, seen: &SurfaceSeen<'_>) {
        if seen.material.diff <= 0.0 {
            return;
        }
        let s = seen.shape.surface(seen.ray, seen.hit);
        let front = s.normal.dot(seen.ray.dir) < 0.0;
        let (side, n) = if front {
            (s.normal, s.shading_normal)
        } else {
            (-s.normal, -s.shading_normal)
        };
        self.seeds.push(HitPointSeed {
            point: s.point,
            side,
            mirror: reflect(seen.ray.dir, n),
            uv: s.uv,
            material: *seen.material,
            throughput: DVec3::ONE,
        });
    }

    fn done(&mut self, _color: DVec3, weight: DVec3) {
        if let Some(start) = self.open.pop() {
            for s in &mut self.seeds[start..] {
                s.throughput *= weight;
            }
        }
    }
}
