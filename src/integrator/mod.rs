//! Integrators: what a camera sample's colour is, given the scene and its
//! acceleration structure. Each kind is a variant of [`Integrator`] (the
//! framework's ray tracer now; photon mapping and debugging views later),
//! generic over a [`PathObserver`] that watches the rays it traces.

mod observer;
mod visibility;
mod whitted;

pub(crate) use observer::{AaHash, NoObserver, PathObserver, mix};
pub(crate) use visibility::ShadowHints;
#[cfg(test)]
pub(crate) use visibility::{ShadowFrom, shade_factor};

use crate::accel::{Accel, Primitive};
use crate::geometry::{Ray, Shape};
use crate::scene::{Camera, Object, Scene};
use glam::DVec3;
use rand_pcg::Pcg32;
use whitted::Whitted;

/// The acceleration structure over a scene's objects.
pub(crate) type SceneAccel = Accel<Object>;

impl Primitive for Object {
    #[inline(always)]
    fn shape(&self) -> &Shape {
        Object::shape(self)
    }

    #[inline(always)]
    fn light(&self) -> Option<u32> {
        Object::light(self)
    }
}

/// Rays traced, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Primary rays.
    pub camera: u64,
    /// Mirror and glossy reflection rays.
    pub reflected: u64,
    /// Refraction (and total-internal-reflection) rays.
    pub refracted: u64,
    /// Shadow rays.
    pub shadow: u64,
}

impl RayCounts {
    /// All rays together.
    pub fn total(&self) -> u64 {
        self.camera + self.reflected + self.refracted + self.shadow
    }

    /// Adds another tally to this one.
    pub fn add(&mut self, o: &RayCounts) {
        self.camera += o.camera;
        self.reflected += o.reflected;
        self.refracted += o.refracted;
        self.shadow += o.shadow;
    }
}

/// The state one camera sample carries down its tree of rays.
pub(crate) struct PathState {
    /// The sample's own random stream.
    pub rng: Pcg32,
    /// Rays traced so far.
    pub rays: RayCounts,
}

/// An integrator bound to a scene and its acceleration structure.
pub(crate) enum Integrator<'a> {
    /// The framework's Whitted-style ray tracer.
    Whitted(Whitted<'a>),
}

impl<'a> Integrator<'a> {
    /// The framework's ray tracer over `scene`, rendered through `camera`
    /// (its quality keys), querying `accel`.
    pub fn whitted(scene: &'a Scene, camera: &Camera, accel: &'a SceneAccel) -> Self {
        Integrator::Whitted(Whitted::new(scene, camera, accel))
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
