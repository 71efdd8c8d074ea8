//! Integrators: what a camera sample's colour is, given the scene and its
//! acceleration structure. Each kind is a variant of [`Integrator`] (the
//! framework's ray tracer now; photon mapping and debugging views later),
//! generic over a [`PathObserver`] that watches the rays it traces.

mod model;
mod observer;
mod optics;
mod path;
pub(crate) mod photons;
mod tree;
mod visibility;
mod whitted;

pub(crate) use model::{Ambient, AntiAlias, Glossy, Lens, Model, PhotonBounce};
pub use observer::RayKind;
pub(crate) use observer::{AaHash, LightSeen, NoObserver, PathObserver, SurfaceSeen, mix};
pub use path::RayCounts;
pub(crate) use path::{PathState, SceneAccel, Stream};
pub(crate) use tree::RayTree;
pub use tree::{Blocker, HitInfo, LightTerm, PhotonTerm, RayNode};
pub(crate) use visibility::ShadowHints;
#[cfg(test)]
pub(crate) use visibility::{ShadowFrom, ShadowRays, shade_factor};

use crate::geometry::Ray;
use crate::scene::{Camera, Scene};
use glam::DVec3;
pub(crate) use whitted::PhotonShading;
#[cfg(test)]
pub(crate) use whitted::READ_AHEAD_MATERIALS;
use whitted::Whitted;

/// An integrator bound to a scene and its acceleration structure.
pub(crate) enum Integrator<'a> {
    /// The framework's Whitted-style ray tracer.
    Whitted(Whitted<'a>),
}

impl<'a> Integrator<'a> {
    /// The framework's ray tracer over `scene`, rendered through `camera`
    /// (its quality keys), querying `accel`, with `photons`.
    pub fn whitted(
        scene: &'a Scene,
        camera: &Camera,
        accel: &'a SceneAccel,
        photons: PhotonShading<'a>,
    ) -> Self {
        Integrator::Whitted(Whitted::new(scene, camera, accel, photons))
    }

    /// The lineage's model it shades with.
    pub fn model(&self) -> &Model {
        match self {
            Integrator::Whitted(w) => w.model(),
        }
    }

    /// The colours of up to [`crate::accel::PACKET_MAX`] camera rays into
    /// `out`, ray k with random stream `states[k]`, told to `observers[k]`.
    #[inline]
    pub fn trace_camera_packet<O: PathObserver>(
        &self,
        rays: &[Ray],
        states: &mut [PathState],
        observers: &mut [O],
        out: &mut [DVec3],
        hints: &mut ShadowHints,
    ) {
        match self {
            Integrator::Whitted(w) => w.trace_camera_packet(rays, states, observers, out, hints),
        }
    }

    /// The colour of one camera ray: the reference the packet tests compare with.
    #[cfg(test)]
    pub fn trace_camera<O: PathObserver>(
        &self,
        ray: &Ray,
        st: &mut PathState,
        obs: &mut O,
        hints: &mut ShadowHints,
    ) -> DVec3 {
        match self {
            Integrator::Whitted(w) => w.trace_camera(ray, st, obs, hints),
        }
    }
}
