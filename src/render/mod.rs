//! Rendering: a [`Renderer`] keeps a prepared scene (its acceleration
//! structure built once) and renders it, or a region of it, to a [`Film`]
//! as [`RenderOptions`] say: on any number of threads, with a progress
//! callback and a flag another thread can set to stop it.
//!
//! The folder's table of contents: the [`Renderer`] (`renderer`), what it is
//! asked ([`options`](RenderOptions)) and answers ([`stats`](RenderStats),
//! [`error`](RenderError), [`estimate`](WorkEstimate)); the camera rays
//! (`camera`), the frame of samples (`frame`), the anti-aliasing's passes over
//! bands, one file a layer (`region` runs them: `buffers`, pass 1 over a
//! band in `band`, pass 2 in `refine`, the observer picked in `observe`,
//! `progress`), the shading layers (`shading_aovs`), PPM's and SPPM's
//! iterations (`photons`), the film (`film`, `aov`), the memory bound
//! (`memory`), threads (`schedule`), `explain` and the verdict's rules it
//! shares with the `why` layer (`verdict`).

mod aov;
mod band;
mod buffers;
mod camera;
mod error;
mod estimate;
mod explain;
mod film;
mod frame;
mod key;
mod memory;
mod observe;
mod options;
mod photons;
mod progress;
mod refine;
mod region;
mod renderer;
mod schedule;
mod shading_aovs;
mod stats;
mod tile;
mod verdict;

pub use aov::Aov;
#[cfg(feature = "serve")]
pub(crate) use camera::basis;
pub use error::RenderError;
pub use estimate::{Driver, WorkEstimate};
pub use explain::{Explanation, HitPointTerm, MAX_EXPLAINED_SPP, ProgressiveTerm, Sampling};
pub use film::{AovImage, AssembleError, Film, Region};
pub use key::CameraKey;
pub use memory::{Encoding, Fit, MemoryNeed};
pub use options::{Checkpoint, Control, RenderOptions, Stage};
pub use photons::PhotonStats;
pub use renderer::Renderer;
pub use schedule::{MAX_THREADS, with_threads};
pub use shading_aovs::LIGHT_AOVS_MAX;
pub use stats::RenderStats;
pub use tile::{MAX_TILES, TILE_BAND, Tile};
pub(crate) use verdict::{Cause, place};
