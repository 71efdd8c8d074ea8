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
#[cfg(feature = "fuzzing")]
#[doc(hidden)]
pub mod fuzzing;
#[cfg(feature = "bench")]
#[doc(hidden)]
pub mod geometry;
#[cfg(not(feature = "bench"))]
mod geometry;
mod image;
mod integrator;
pub mod job;
mod output;
#[cfg(feature = "bench")]
#[doc(hidden)]
pub mod photon_bench;
pub mod probe;
mod render;
mod sampling;
pub mod scene;
#[cfg(feature = "serve")]
pub mod serve;
pub mod tiles;

pub use accel::Isa;
pub use check::{CheckReport, Code, ESTIMATE_RAYS_PER_SECOND, Finding, check};
pub use compare::{CompareError, Comparison, DEFAULT_THRESHOLD, Group, compare, read_picture};
pub use geometry::Shape;
pub use image::Image;
pub use integrator::photons::{PhotonFilter, PhotonMode, PhotonOptions};
pub use integrator::{Blocker, HitInfo, LightTerm, PhotonTerm, RayCounts, RayKind, RayNode};
pub use output::{
    Format, PrimitiveTable, SaveError, aov_path, primitive_colour, save_aov_images,
    save_exr_layers, save_film,
};
pub use probe::{MAX_RAY_ERRORS, ProbeHit, RayError, RaysError, parse_ray, read_rays};
pub use render::{
    Aov, AovImage, AssembleError, CameraKey, Checkpoint, Control, Driver, Encoding, Explanation,
    Film, Fit, HitPointTerm, LIGHT_AOVS_MAX, MAX_EXPLAINED_SPP, MAX_THREADS, MAX_TILES, MemoryNeed,
    PhotonStats, ProgressiveTerm, Region, RenderError, RenderOptions, RenderStats, Renderer,
    Sampling, Stage, TILE_BAND, Tile, WorkEstimate, with_threads,
};
pub use scene::{Dialect, DialectChoice, Scene, SceneError};

#[cfg(test)]
mod tests;
