//! Figures about a finished render.

use super::photons::PhotonStats;
use crate::integrator::RayCounts;
use std::time::Duration;

/// Figures about a finished render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Rays traced, by kind.
    pub rays: RayCounts,
    /// Wall time of the render (not counting parsing or the acceleration structure).
    pub elapsed: Duration,
    /// Wall time of the acceleration-structure build (when the renderer was made).
    pub build: Duration,
    /// Pixels re-rendered by the adaptive anti-aliasing.
    pub refined_pixels: u64,
    /// The photon passes' figures (all zero without photons).
    pub photons: PhotonStats,
}

impl RenderStats {
    /// Millions of rays per second, the acceleration structure's build counted in.
    pub fn mrays_per_sec(&self) -> f64 {
        let secs = (self.elapsed + self.build).as_secs_f64().max(1e-9);
        self.rays.total() as f64 / secs / 1e6
    }
}
