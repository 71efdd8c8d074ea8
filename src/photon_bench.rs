//! Photon passes and estimates for the micro-benchmarks (`benches/photons.rs`):
//! photon-mapping internals built by hand; not a public API.

use crate::integrator::photons::{
    HitPoint, PhotonGrid, PhotonMap, PhotonMode, PhotonOptions, Plan, shoot, update_hit_point,
};
use crate::integrator::{Model, SceneAccel};
use glam::DVec3;

/// A scene ready for photon passes (PM's plan with `emit` photons a pass).
pub struct Prepared {
    scene: crate::Scene,
    accel: SceneAccel,
    plan: Plan,
    model: Model,
}

impl Prepared {
    /// Prepares `scene` for passes of `emit` photons gathering `k`.
    pub fn new(mut scene: crate::Scene, emit: u64, k: u64) -> Prepared {
        let accel = SceneAccel::build(scene.take_objects());
        let options = PhotonOptions {
            mode: Some(PhotonMode::Pm),
            emit: Some(emit),
            ..PhotonOptions::default()
        };
        let mut plan = Plan::of(&scene, &options).0;
        plan.k = k as usize;
        let model = Model::of(scene.dialect().dialect, scene.camera());
        Prepared {
            scene,
            accel,
            plan,
            model,
        }
    }

    /// Traces pass `pass`; returns the photons stored and the rays cast.
    pub fn shoot(&self, pass: u64) -> (usize, u64) {
        let pass = shoot(&self.scene, &self.accel, &self.model, &self.plan, 1, pass);
        (pass.photons.len(), pass.rays)
    }

    /// The photon map of pass 0.
    pub fn map(&self) -> Map {
        let pass = shoot(&self.scene, &self.accel, &self.model, &self.plan, 1, 0);
        Map(PhotonMap::new(
            pass.photons,
            self.plan.k,
            self.plan.radius,
            self.plan.filter,
        ))
    }

    /// One PPM iteration over `points` hit points spread over the plane
    /// z = 0 in [−s, s]²: a photon pass, its grid, every hit point's gather
    /// and update. Returns the photons found.
    pub fn ppm_iteration(&self, points: &mut [(DVec3, f64)], pass: u64) -> u64 {
        use rayon::prelude::*;
        let photons = shoot(&self.scene, &self.accel, &self.model, &self.plan, 1, pass).photons;
        let cell = points.iter().map(|p| p.1).fold(0.0, f64::max).sqrt();
        let grid = PhotonGrid::new(&photons, cell);
        points
            .par_iter_mut()
            .map(|(x, r2)| {
                let mut h = HitPoint {
                    pixel: 0,
                    point: *x,
                    side: DVec3::Z,
                    brdf: crate::integrator::photons::Brdf {
                        diff: 1.0,
                        spec: 0.0,
                        mirror: DVec3::Z,
                        cosine: None,
                    },
                    weight: DVec3::ONE,
                    r2: *r2,
                    n: 0.0,
                    m: 0,
                    tau: DVec3::ZERO,
                };
                h.gather(&grid);
                let m = h.m;
                update_hit_point(&mut h, 0.7);
                *r2 = h.r2;
                m
            })
            .sum()
    }
}

/// A photon map.
pub struct Map(PhotonMap);

impl Map {
    /// The K-nearest estimate's red channel at `x` on a surface facing `n`.
    pub fn estimate(&self, x: DVec3, n: DVec3) -> f64 {
        let brdf = crate::integrator::photons::Brdf {
            diff: 1.0,
            spec: 0.0,
            mirror: n,
            cosine: None,
        };
        self.0.estimate(x, n, &brdf).value.x
    }
}
