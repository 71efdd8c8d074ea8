//! glint: a fast, exact ray tracer for the scene format of the C++ teaching
//! ray tracer (spheres, planes, squares, cubes, cylinders, Bézier surfaces of
//! revolution; point, square and sphere lights; BMP textures).
//!
//! Data flows one way: text → [`Scene`] → acceleration structure →
//! [`render()`] → [`Image`] → file.
//!
//! ```no_run
//! let scene = glint::Scene::from_file("examples/showcase.txt")?;
//! let image = glint::render(&scene, &glint::RenderOptions::default());
//! image.save("showcase.png")?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod accel;
pub mod geometry;
pub mod output;
pub mod probe;
pub mod render;
pub mod scene;
pub mod shading;

pub use output::Image;
pub use render::{
    MAX_THREADS, RenderOptions, RenderStats, memory_needed, render, render_with_progress,
};
pub use scene::{Scene, SceneError};
