//! The framework's text format, read into a [`Scene`](crate::scene::Scene).
//!
//! A file is a sequence of blocks (`background`, `camera`, `light TYPE`,
//! `primitive TYPE`), each closed by `end`, holding `key= values` lines; see
//! `docs/format.md` for every key. The [`reader`] splits the text into
//! blocks, the [`builder`] checks each against its row of the [`schema`] and
//! builds it ([`setup`] for the blocks around the primitives, [`shapes`]),
//! loading the files it names
//! ([`assets`], [`obj`]); every problem becomes a diagnostic with its place;
//! [`detect`] picks the dialect from the markers the reader saw.

mod assets;
mod bezier_forms;
mod block_keys;
mod builder;
mod colon;
mod detect;
mod diags;
mod lexer;
mod limits;
mod obj;
mod reader;
mod schema;
mod setup;
mod shapes;
mod suggest;
mod values;

#[cfg(feature = "fuzzing")]
pub(crate) use assets::decode_texture_bytes;
pub(crate) use limits::{Limits, read_bounded};
#[cfg(feature = "fuzzing")]
pub(crate) use obj::parse_obj;
#[cfg(any(test, feature = "fuzzing"))]
pub(crate) use reader::parse_text;
pub(crate) use reader::{parse_file, parse_str};
pub(crate) use values::{NumberError, parse_number};

use crate::scene::{Dialect, Scene, SceneError};
use std::path::Path;

/// Reading scenes in the framework's format.
impl Scene {
    /// Reads and validates a scene file; relative texture and mesh paths
    /// are looked up next to the file first, then in the working directory.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        parse_file(path.as_ref(), None)
    }

    /// [`Scene::from_file`] in dialect `dialect` (`None`: chosen by the
    /// file's markers, see [`Scene::dialect`]).
    pub fn from_file_as(
        path: impl AsRef<Path>,
        dialect: Option<Dialect>,
    ) -> Result<Scene, SceneError> {
        parse_file(path.as_ref(), dialect)
    }

    /// Parses scene text; relative paths are looked up in `base_dir`, then
    /// in the working directory.
    pub fn parse(text: &str, base_dir: impl AsRef<Path>) -> Result<Scene, SceneError> {
        parse_str(text, None, base_dir.as_ref(), None)
    }

    /// [`Scene::parse`] in dialect `dialect` (`None`: chosen by the markers).
    pub fn parse_as(
        text: &str,
        base_dir: impl AsRef<Path>,
        dialect: Option<Dialect>,
    ) -> Result<Scene, SceneError> {
        parse_str(text, None, base_dir.as_ref(), dialect)
    }
}
