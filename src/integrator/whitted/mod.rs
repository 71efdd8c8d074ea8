//! The Whitted-style ray tracer of every lineage, computed exactly: the
//! framework's shading model (spec: "Shading model": diffuse and the `L·N`
//! specular per light with shadows, mirror and glossy reflection,
//! refraction with Beer absorption, the per-ray clamp, depth 10) and the
//! relatives' variations of it, read from a [`Model`].

//!
//! `shade` takes a hit apart as pbrt's `Li` does, one file a term: the
//! surface point (`surface`), a light's emitted colour (`emitted`), the
//! direct light of the 1/d² lineages and of the framework (`direct`), the
//! photon gather (`gather`), the reflected and the refracted ray
//! (`reflected`, `refracted`).

mod direct;
mod emitted;
mod fresnel;
mod gather;
mod reflected;
mod refracted;
mod surface;

use super::model::{Absorb, Ambient, Model, Split};
use super::observer::{PathObserver, RayKind, SurfaceSeen};
use super::path::{PathState, SceneAccel};
use super::photons::{PhotonBrdf, PhotonMap};
use super::visibility::ShadowHints;
use crate::accel::PACKET_MAX;
use crate::geometry::{Hit, Ray};
use crate::scene::{Camera, Scene};
use glam::DVec3;

/// What the ray tracer does about photons.
#[derive(Clone, Copy, Default)]
pub(crate) struct PhotonShading<'a> {
    /// The map gathered at diffuse hits (PM).
    pub map: Option<&'a PhotonMap>,
    /// Whether the lights' direct term is left out (Z14's model with
    /// photons: they carry all diffuse light).
    pub no_direct: bool,
    /// Whether gathered photons carry the lineage's specular lobe.
    pub specular: bool,
    /// How gathered photons are weighted.
    pub brdf: PhotonBrdf,
    /// Whether the ambient term is left out too (the colon family's PPM:
    /// its eye pass shades nothing but the photons).
    pub no_ambient: bool,
}

/// What a camera sample's tree of rays carries through the tracer: its
/// random stream and counts, the observer watching it, and the worker's
/// shadow hints.
pub(crate) struct PathContext<'p, O> {
    /// The sample's random stream and ray counts.
    pub st: &'p mut PathState,
    /// What watches its rays.
    pub obs: &'p mut O,
    /// What each light's last shadow ray on this worker met (its blocker, or none).
    pub hints: &'p mut ShadowHints,
}

/// Where a ray is in its tree: its depth (the camera ray's is 1), the
/// lineages' refraction flag (whether it is inside a refracting object)
/// and the colon family's weight (the product of the shares that led to it).
#[derive(Clone, Copy)]
struct Bounce {
    depth: u32,
    inside: bool,
    weight: f64,
}

impl Bounce {
    /// The camera ray's.
    const CAMERA: Bounce = Bounce {
        depth: 1,
        inside: false,
        weight: 1.0,
    };
}

/// The ray tracer over one scene, in its dialect's model.
pub(crate) struct Whitted<'a> {
    scene: &'a Scene,
    accel: &'a SceneAccel,
    shadow_samples: u32,
    model: Model,
    photons: PhotonShading<'a>,
}

/// Materials beyond which a camera packet reads its hits' materials ahead
/// (32 bytes each: 64 KiB, more than a core's first-level cache).
pub(crate) const READ_AHEAD_MATERIALS: usize = 2048;

impl<'a> Whitted<'a> {
    /// The tracer over `scene` (its dialect, its camera's quality keys)
    /// using `accel` (built over the scene's objects) for ray queries, with
    /// `photons`.
    pub fn new(
        scene: &'a Scene,
        camera: &Camera,
        accel: &'a SceneAccel,
        photons: PhotonShading<'a>,
    ) -> Self {
        let model = Model::of(scene.dialect().dialect, camera);
        Whitted {
            scene,
            accel,
            shadow_samples: model.shadow_rays,
            model,
            photons,
        }
    }

    /// The model it shades with.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The colour seen along one camera ray, told to `obs`: the reference
    /// the packet tests compare with.
    #[cfg(test)]
    pub fn trace_camera<O: PathObserver>(
        &self,
        ray: &Ray,
        st: &mut PathState,
        obs: &mut O,
        hints: &mut ShadowHints,
    ) -> DVec3 {
        st.rays.camera += 1;
        obs.ray(RayKind::Camera, 1, ray);
        let c = self.trace(ray, Bounce::CAMERA, &mut PathContext { st, obs, hints });
        obs.done(c, DVec3::ONE);
        c
    }

    /// The colours seen along up to [`PACKET_MAX`] camera rays into `out`,
    /// ray k told to `observers[k]`.
    pub fn trace_camera_packet<O: PathObserver>(
        &self,
        rays: &[Ray],
        states: &mut [PathState],
        observers: &mut [O],
        out: &mut [DVec3],
        hints: &mut ShadowHints,
    ) {
        let mut found = [None; PACKET_MAX];
        let found = &mut found[..rays.len()];
        if O::COUNTS_QUERIES {
            // Ray by ray, each query counted alone: the packet's answers.
            for (k, ray) in rays.iter().enumerate() {
                let tally = &mut observers[k].queries();
                found[k] = self.accel.intersect_tallied(ray, f64::INFINITY, tally);
            }
        } else {
            self.accel.intersect_packet(rays, found);
        }
        // The hits' materials read for the whole packet first, when there
        // are more than a cache holds: their misses (a million distinct
        // materials fill 32 MB) then overlap, where each ray's shading
        // would wait for its own in turn.
        if self.scene.material_count() > READ_AHEAD_MATERIALS {
            let objects = self.accel.objects();
            let ahead = found.iter().flatten().fold(0, |a, &(i, _)| {
                a ^ self.scene.read_material_ahead(&objects[i as usize])
            });
            std::hint::black_box(ahead);
        }
        for (k, (ray, &hit)) in rays.iter().zip(found.iter()).enumerate() {
            if O::COUNTS_QUERIES {
                // Each sample's cost its own: no blocker remembered from another.
                *hints = ShadowHints::default();
            }
            states[k].rays.camera += 1;
            let obs = &mut observers[k];
            obs.ray(RayKind::Camera, 1, ray);
            let mut cx = PathContext {
                st: &mut states[k],
                obs: &mut *obs,
                hints: &mut *hints,
            };
            out[k] = self.shade(ray, hit, Bounce::CAMERA, &mut cx);
            obs.done(out[k], DVec3::ONE);
        }
    }

    /// The framework's `RayTracing`: the colour along `ray` at `at`,
    /// clamped to at most 1 per channel (in the lineages that clamp only the
    /// camera ray, at depth 1).
    fn trace<O: PathObserver>(&self, ray: &Ray, at: Bounce, cx: &mut PathContext<O>) -> DVec3 {
        let found = self
            .accel
            .intersect_tallied(ray, f64::INFINITY, &mut cx.obs.queries());
        self.shade(ray, found, at, cx)
    }

    /// The colour `c` seen at `depth`, clamped as the model says.
    #[inline(always)]
    fn clamp(&self, c: DVec3, depth: u32) -> DVec3 {
        if self.model.clamp_every_ray || depth == 1 {
            c.min(DVec3::ONE)
        } else {
            c
        }
    }

    /// [`Whitted::trace`] for a ray whose nearest hit is `found`: the
    /// background, a light's surface, or the lit surface plus its
    /// reflected and refracted rays.
    fn shade<O: PathObserver>(
        &self,
        ray: &Ray,
        found: Option<(u32, Hit)>,
        at: Bounce,
        cx: &mut PathContext<O>,
    ) -> DVec3 {
        let scene = self.scene;
        let model = &self.model;
        let Some((index, hit)) = found else {
            if !model.background_seen {
                return DVec3::ZERO;
            }
            return self.clamp(scene.background().color(ray.dir), at.depth);
        };
        let object = &self.accel.objects()[index as usize];
        cx.obs.hit(object.origin());
        if let Some(light) = object.light() {
            return self.emitted(light, object.shape(), ray, &hit, cx.obs);
        }
        let p = self.surface_point((index, object), ray, &hit);
        let m = &p.material;
        cx.obs.surface(&SurfaceSeen {
            origin: object.origin(),
            shape: object.shape(),
            ray,
            hit: &hit,
            material: m,
        });
        let mut color = DVec3::ZERO;
        let lit = m.diff > 0.0 || (m.spec > 0.0 && model.lit_by_specular);
        if model.ambient == Ambient::Every {
            color += model.albedo(m, scene.textures(), p.uv) * scene.background().ambient();
        }
        if lit {
            let k = model.albedo(m, scene.textures(), p.uv);
            if model.ambient == Ambient::Diffuse && !self.photons.no_ambient {
                color += k * m.diff * scene.background().ambient();
            }
            self.direct(ray, &p, k, &mut color, cx);
            if let Some(map) = self.photons.map
                && m.diff > 0.0
            {
                color += self.gather(map, ray, &p, k, cx.obs);
            }
        }
        match model.split {
            Split::Separate => {
                if let Some(c) = self.reflected(ray, &p, at, cx) {
                    color += c;
                }
                if let Some(c) = self.refracted(ray, &p, at, cx) {
                    color += c;
                }
            }
            Split::Fresnel => color += self.fresnel(ray, &p, at, cx),
        }
        if model.absorb == Absorb::AtHit && !p.front {
            color *= (-m.absor * p.t).exp();
        }
        cx.obs.shaded(color);
        self.clamp(color, at.depth)
    }
}
