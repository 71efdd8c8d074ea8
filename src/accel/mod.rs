//! Ray queries over all of a scene's objects: nearest hit and any hit.

use crate::geometry::{Hit, Ray};
use crate::scene::Object;

/// Answers ray queries over a list of objects.
pub struct Accel<'a> {
    objects: &'a [Object],
}

impl<'a> Accel<'a> {
    /// Builds the structure over `objects` (indices into it are returned by queries).
    pub fn build(objects: &'a [Object]) -> Self {
        Accel { objects }
    }

    /// The objects the queries run over.
    pub fn objects(&self) -> &'a [Object] {
        self.objects
    }

    /// The nearest hit with 0 < t < `t_max`: the object's index and the hit.
    pub fn intersect(&self, ray: &Ray, t_max: f64) -> Option<(u32, Hit)> {
        let mut best = None;
        let mut t_best = t_max;
        for (i, o) in self.objects.iter().enumerate() {
            if let Some(h) = o.shape.intersect(ray, 0.0, t_best) {
                t_best = h.t;
                best = Some((i as u32, h));
            }
        }
        best
    }

    /// Whether anything lies on the ray with 0 < t < `t_max`, not counting
    /// the visible surface of light `ignore_light`.
    pub fn occluded(&self, ray: &Ray, t_max: f64, ignore_light: Option<u32>) -> bool {
        self.objects.iter().any(|o| {
            (o.light.is_none() || o.light != ignore_light)
                && o.shape.intersect(ray, 0.0, t_max).is_some()
        })
    }
}
