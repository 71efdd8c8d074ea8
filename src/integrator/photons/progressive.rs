//! The state of progressive photon mapping at one hit point and its update
//! after each pass (`photon-mapping.md`, PPM and SPPM; Hachisuka et al. 2008).

use super::gather::{FluxSum, PhotonGrid};
use super::map::Brdf;
use glam::DVec3;

/// A PPM hit point, or an SPPM pixel's running estimate.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct HitPoint {
    /// Its pixel's index in the region (rows from the top).
    pub pixel: u32,
    /// Where it is.
    pub point: DVec3,
    /// The unit normal on its lit side.
    pub side: DVec3,
    /// How photons are weighted there.
    pub brdf: Brdf,
    /// Path throughput × k: what its estimate is multiplied by in the pixel.
    pub weight: DVec3,
    /// R², shrinking.
    pub r2: f64,
    /// N: photons accumulated so far (after the α reduction).
    pub n: f64,
    /// M: photons found this pass.
    pub m: u64,
    /// τ: the accumulated, BRDF-weighted flux.
    pub tau: DVec3,
}

impl HitPoint {
    /// Adds the photons of `grid` within its radius on its lit side to M and τ.
    pub fn gather(&mut self, grid: &PhotonGrid<'_>) {
        let (m, tau) = gather(grid, self.point, self.side, &self.brdf, self.r2);
        self.m += m;
        self.tau += tau;
    }

    /// Its estimate's contribution to its pixel after `passes` passes:
    /// weight·τ/(π·R²·passes).
    pub fn radiance(&self, passes: u64) -> DVec3 {
        self.weight * self.tau / (std::f64::consts::PI * self.r2 * passes.max(1) as f64)
    }
}

/// The photons of `grid` within √`r2` of `point` that arrived on the side
/// `side` faces: their count and their `brdf`-weighted flux.
pub(crate) fn gather(
    grid: &PhotonGrid<'_>,
    point: DVec3,
    side: DVec3,
    brdf: &Brdf,
    r2: f64,
) -> (u64, DVec3) {
    let mut m = 0u64;
    // The weight is at most diff + spec: the terms' bound.
    let mut tau = FluxSum::new(grid.peak() * (brdf.diff.abs() + brdf.spec.abs()));
    grid.for_each_within(point, r2, |p| {
        if p.dir.dot(side) < 0.0 {
            m += 1;
            tau.add(p.power * brdf.weight(p.dir));
        }
    });
    (m, tau.total())
}

/// The update after a pass with reduction α: if M > 0,
/// f = (N + αM)/(N + M); R² ·= f; τ ·= f; N += αM; then M = 0.
pub(crate) fn update_hit_point(h: &mut HitPoint, alpha: f64) {
    if h.m > 0 {
        let m = h.m as f64;
        let f = (h.n + alpha * m) / (h.n + m);
        h.r2 *= f;
        h.tau *= f;
        h.n += alpha * m;
    }
    h.m = 0;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::photons::trace::Photon;
    use rand::{Rng, SeedableRng};

    #[test]
    fn a_gather_is_the_same_bytes_whatever_the_grids_cells() {
        // The cells follow the largest radius of the pixels rendered with
        // the grid (a region's, a part's): the sum must not follow them.
        let mut rng = rand_pcg::Pcg64::seed_from_u64(11);
        let photons: Vec<Photon> = (0..20_000)
            .map(|_| Photon {
                pos: DVec3::new(rng.random(), rng.random(), 0.0),
                dir: DVec3::new(rng.random::<f64>() - 0.5, 0.3, -1.0).normalize(),
                power: DVec3::new(rng.random(), rng.random(), rng.random()) * 1e-3,
                bounces: 0,
            })
            .collect();
        let grids = [0.05, 0.11, 0.3].map(|cell| PhotonGrid::new(&photons, cell));
        let brdf = Brdf {
            diff: 0.7,
            spec: 0.4,
            mirror: DVec3::new(0.0, 0.3, 1.0).normalize(),
            cosine: None,
        };
        let mut found = 0;
        for _ in 0..200 {
            let point = DVec3::new(rng.random(), rng.random(), 0.0);
            let r2 = 0.05f64.powi(2);
            let sums = grids
                .each_ref()
                .map(|g| gather(g, point, DVec3::Z, &brdf, r2));
            found += sums[0].0;
            assert_eq!(sums[0], sums[1], "at {point}");
            assert_eq!(sums[0], sums[2], "at {point}");
        }
        assert!(found > 10_000, "{found} photons gathered");
    }
}
