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
mod integrator;
mod output;
mod pass_files;
mod probe;
mod render;
mod sampling;
pub mod scene;
#[cfg(feature = "serve")]
pub mod serve;

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
}

pub use check::{CheckReport, Code, ESTIMATE_RAYS_PER_SECOND, Finding, check};
pub use compare::{CompareError, Comparison, DEFAULT_THRESHOLD, Group, compare, read_picture};
pub use geometry::Shape;
pub use integrator::{Blocker, HitInfo, LightTerm, RayCounts, RayKind, RayNode};
pub use output::{Format, Image, SaveError};
pub use pass_files::{
    PrimitiveTable, pass_path, primitive_colour, save_exr_layers, save_pass_images,
};
pub use probe::{
    MAX_RAY_ERRORS, ProbeHit, RayError, RaysError, parse_ray, read_rays, to_json, to_text,
};
pub use render::{
    Aov, Control, Explanation, Film, MAX_EXPLAINED_SPP, MAX_THREADS, Plane, Region, RenderError,
    RenderOptions, RenderStats, Renderer, Sampling, Stage, WorkEstimate, memory_needed,
};
pub use scene::{Dialect, DialectChoice, Scene, SceneError};

#[cfg(test)]
mod tests;
