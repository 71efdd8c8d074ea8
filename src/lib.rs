//! glint: a fast, exact ray tracer for the scene format of the C++ teaching
//! ray tracer (spheres, planes, squares, cubes, cylinders, Bézier surfaces of
//! revolution; point, square and sphere lights; BMP textures).
//!
//! Data flows one way: text → [`Scene`] → [`Renderer`] (which owns the
//! acceleration structure) → [`Film`] → [`Image`] → file.
//!
//! ```no_run
//! let scene = glint::Scene::from_file("examples/showcase.txt")?;
//! let renderer = glint::Renderer::new(scene);
//! let film = renderer.render(&glint::RenderOptions::default())?;
//! film.image().save("showcase.png")?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

#[cfg(feature = "bench")]
#[doc(hidden)]
pub mod accel;
#[cfg(not(feature = "bench"))]
mod accel;
mod check;
mod compare;
mod format;
#[cfg(feature = "bench")]
#[doc(hidden)]
pub mod geometry;
#[cfg(not(feature = "bench"))]
mod geometry;
mod image;
mod integrator;
mod output;
mod probe;
mod render;
mod sampling;
pub mod scene;
#[cfg(feature = "serve")]
pub mod serve;

/// Photon passes and estimates for the micro-benchmarks (`benches/photons.rs`).
#[cfg(feature = "bench")]
#[doc(hidden)]
pub mod photon_bench {
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
            };
            self.0.estimate(x, n, &brdf).value.x
        }
    }
}

/// The private readers the fuzz targets (`fuzz/`) drive; not a public API.
#[cfg(feature = "fuzzing")]
#[doc(hidden)]
pub mod fuzzing {
    /// Parses OBJ text as a `primitive mesh` file would be (errors are messages).
    pub fn obj(bytes: &[u8]) -> Result<usize, String> {
        crate::format::parse_obj(bytes).map(|models| models.len())
    }

    /// Decodes image bytes as a texture would be (errors are messages).
    pub fn texture(bytes: &[u8]) -> Result<(), String> {
        crate::format::decode_texture_bytes(bytes).map(|_| ())
    }

    /// Parses scene text as [`Scene::parse`](crate::Scene::parse) does, but
    /// finds none of the files it names, without touching the file system:
    /// each is reported not found, with the places it would have been looked
    /// for. A fuzz run then does not depend on its working directory (the
    /// OBJ and texture readers have targets of their own).
    pub fn scene(text: &str) -> Result<crate::Scene, crate::SceneError> {
        crate::format::parse_text(text, None, std::path::Path::new("scene-dir"), None, false)
    }
}

pub use check::{CheckReport, Code, ESTIMATE_RAYS_PER_SECOND, Finding, check};
pub use compare::{CompareError, Comparison, DEFAULT_THRESHOLD, Group, compare, read_picture};
pub use geometry::Shape;
pub use image::Image;
pub use integrator::photons::{PhotonFilter, PhotonMode, PhotonOptions};
pub use integrator::{Blocker, HitInfo, LightTerm, PhotonTerm, RayCounts, RayKind, RayNode};
pub use output::{
    Format, PrimitiveTable, SaveError, pass_path, primitive_colour, save_exr_layers,
    save_pass_images,
};
pub use probe::{
    MAX_RAY_ERRORS, ProbeHit, RayError, RaysError, parse_ray, read_rays, to_json, to_text,
};
pub use render::{
    Aov, CameraKey, Checkpoint, Control, Driver, Explanation, Film, HitPointTerm, LIGHT_AOVS_MAX,
    MAX_EXPLAINED_SPP, MAX_THREADS, PhotonStats, Plane, ProgressiveTerm, Region, RenderError,
    RenderOptions, RenderStats, Renderer, Sampling, Stage, WorkEstimate,
};
pub use scene::{Dialect, DialectChoice, Scene, SceneError};

#[cfg(test)]
mod tests;
