//! What every engine's job runs: `glint render --tile I/N` for each index
//! I, then one `glint merge`, over paths as the tasks see them.

use super::error::{JobError, unfit};
use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// The most tiles a job splits a render into: Kubernetes' most completions
/// of an Indexed Job, fewer than a render takes ([`crate::MAX_TILES`]).
pub const MAX_JOB_TILES: u32 = 100_000;

/// The tiles folder when none is given: the output with its extension
/// replaced by `.tiles` (`out.png` → `out.tiles`).
pub fn default_tiles_dir(output: &Path) -> PathBuf {
    output.with_extension("tiles")
}

/// A job's name when none is given: `glint-` and the output's stem.
pub fn default_name(output: &Path) -> String {
    let stem = output.file_stem().unwrap_or_default().to_string_lossy();
    format!("glint-{stem}")
}

/// The paths of a [`TileJob`], as its tasks will see them.
#[derive(Clone, Copy, Debug)]
pub struct JobPaths<'a> {
    /// The glint the tasks run.
    pub glint: &'a Path,
    /// The scene file.
    pub scene: &'a Path,
    /// The merged picture.
    pub output: &'a Path,
    /// The folder of the tiles.
    pub tiles_dir: &'a Path,
}

/// A render split into tiles: its paths (text with no control characters),
/// the tile count and the render options every task passes on.
#[derive(Clone, Debug)]
pub struct TileJob {
    pub(super) glint: String,
    pub(super) scene: String,
    pub(super) tiles: u32,
    pub(super) output: String,
    pub(super) tiles_dir: String,
    pub(super) options: Vec<String>,
}

impl TileJob {
    /// A job of `tiles` tiles (1 to [`MAX_JOB_TILES`]); `options` are `glint
    /// render`'s arguments as every task passes them (`--width`, `1920`, …).
    pub fn new(paths: JobPaths, tiles: u32, options: Vec<String>) -> Result<TileJob, JobError> {
        if !(1..=MAX_JOB_TILES).contains(&tiles) {
            return Err(JobError::Tiles {
                value: tiles,
                max: MAX_JOB_TILES,
            });
        }
        for option in &options {
            text("a render option", option)?;
        }
        Ok(TileJob {
            glint: path_text("--glint", paths.glint)?,
            scene: path_text("the scene", paths.scene)?,
            tiles,
            output: path_text("-o", paths.output)?,
            tiles_dir: path_text("--tiles-dir", paths.tiles_dir)?,
            options,
        })
    }

    /// The command that renders one tile: `tile` is the engine's expression
    /// for `I/N`, `threads` the value of `--threads`, if any.
    pub(super) fn render_command<'a>(
        &'a self,
        tile: Word<'a>,
        threads: Option<Word<'a>>,
    ) -> Vec<Word<'a>> {
        let mut words = vec![
            Word::text(&self.glint),
            Word::text("render"),
            Word::text(&self.scene),
            Word::text("--tile"),
            tile,
            Word::text("--tiles-dir"),
            Word::text(&self.tiles_dir),
        ];
        if let Some(threads) = threads {
            words.extend([Word::text("--threads"), threads]);
        }
        words.extend(self.options.iter().map(Word::text));
        words
    }

    /// The command that merges the tiles into the output.
    pub(super) fn merge_command(&self) -> Vec<Word<'_>> {
        let words = [&self.glint, "merge", &self.tiles_dir, "-o", &self.output];
        words.into_iter().map(Word::text).collect()
    }

    /// Every value a task's command holds, each with the option it came
    /// from (for an engine's own refusals).
    pub(super) fn values(&self) -> Vec<(&'static str, &str)> {
        let mut values = vec![
            ("--glint", self.glint.as_str()),
            ("the scene", &self.scene),
            ("-o", &self.output),
            ("--tiles-dir", &self.tiles_dir),
        ];
        values.extend(self.options.iter().map(|o| ("a render option", o.as_str())));
        values
    }
}

/// One word of a command a job runs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum Word<'a> {
    /// Passed as it is: each engine quotes it for its runner.
    Text(Cow<'a, str>),
    /// What the engine expands when the task runs (the tile index), written as it is.
    Engine(String),
}

impl<'a> Word<'a> {
    /// A [`Word::Text`].
    pub(super) fn text(text: impl Into<Cow<'a, str>>) -> Word<'a> {
        Word::Text(text.into())
    }
}

/// `value` of `option` when it has no control character (a line break
/// would end a line of a script or an `#SBATCH` setting).
pub(super) fn text<'a>(option: &'static str, value: &'a str) -> Result<&'a str, JobError> {
    let odd = |c: char| c.is_control() || c == '\u{2028}' || c == '\u{2029}';
    if value.chars().any(odd) {
        return Err(unfit(
            option,
            &value.escape_debug().to_string(),
            "it holds a line break or another control character",
        ));
    }
    Ok(value)
}

/// `path` of `option` as text: UTF-8, with no control character.
pub(super) fn path_text(option: &'static str, path: &Path) -> Result<String, JobError> {
    let Some(s) = path.to_str() else {
        return Err(unfit(
            option,
            &path.to_string_lossy(),
            "it is not UTF-8, which the job's text cannot hold",
        ));
    };
    text(option, s).map(str::to_string)
}
