//! What a ray sees where it meets an area light's visible surface.

use super::Whitted;
use crate::geometry::{Hit, Ray, Shape};
use crate::integrator::model::Emitter;
use crate::integrator::observer::PathObserver;
use glam::DVec3;

impl Whitted<'_> {
    /// The colour of light `light`'s surface `shape`, hit by `ray` at
    /// `hit`, as the model shows emitters; told to `obs`.
    #[inline(always)]
    pub(super) fn emitted<O: PathObserver>(
        &self,
        light: u32,
        shape: &Shape,
        ray: &Ray,
        hit: &Hit,
        obs: &mut O,
    ) -> DVec3 {
        obs.emitter(light, shape, ray, hit);
        let c = self.scene.lights()[light as usize].color;
        match self.model.emitter {
            Emitter::Clamped => c.min(DVec3::ONE),
            Emitter::Normalised if c.max_element() > 0.0 => c / c.max_element(),
            Emitter::Normalised => c,
        }
    }
}
