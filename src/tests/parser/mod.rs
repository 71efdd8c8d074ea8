//! The scene-file parser: every key into its field, comments, number forms,
//! overrides, every kind of error and warning at its exact line and column,
//! the real scene files, and fuzzing (no input may panic), one concern a
//! file; the helpers below are shared by them.

mod display;
mod errors;
mod files;
mod fuzzing;
mod keys;
mod lexical;
mod scenes;
mod sharing;
mod warnings;

use super::common::corpus_scenes;
use crate::Scene;
use crate::scene::{Diagnostic, SceneError, Severity};
use glam::DVec3;

/// Folder with the test fixtures (a 2×2 BMP, a non-image, a one-triangle OBJ).
const DATA: &str = "tests/data";

fn parse(text: &str) -> Result<Scene, SceneError> {
    Scene::parse(text, DATA)
}

fn ok(text: &str) -> Scene {
    match parse(text) {
        Ok(s) => s,
        Err(e) => panic!("expected the scene to parse:\n{e}"), // invariant: the test's own fixed input (a failure fails the test)
    }
}

fn diagnostics(text: &str) -> Vec<Diagnostic> {
    match parse(text) {
        Ok(s) => {
            let warnings = s.warnings();
            panic!("expected errors, got a scene with warnings {warnings:?}") // invariant: the test's own fixed input (a failure fails the test)
        }
        Err(e) => e.diagnostics,
    }
}

fn errors(text: &str) -> Vec<Diagnostic> {
    diagnostics(text)
        .into_iter()
        .filter(|d| d.severity == Severity::Error)
        .collect()
}

/// The one error of `text`, checked to be at `line`:`column`.
fn error_at(text: &str, line: usize, column: usize) -> Diagnostic {
    let errs = errors(text);
    assert_eq!(errs.len(), 1, "expected exactly one error, got {errs:#?}");
    let d = errs.into_iter().next().unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(
        (d.line, d.column),
        (line, column),
        "error at the wrong place: {d}"
    );
    d
}

/// The one warning of a scene that parses, checked to be at `line`:`column`.
fn warning_at(text: &str, line: usize, column: usize) -> Diagnostic {
    let s = ok(text);
    assert_eq!(
        s.warnings().len(),
        1,
        "expected one warning: {:#?}",
        s.warnings()
    );
    let d = s.warnings()[0].clone();
    assert_eq!(d.severity, Severity::Warning);
    assert_eq!(
        (d.line, d.column),
        (line, column),
        "warning at the wrong place: {d}"
    );
    d
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() <= 1e-12 * (1.0 + b.length())
}

/// A sphere block with the given colour and other material keys.
fn sphere_with(color: &str, keys: &str) -> String {
    format!("primitive sphere\n R= 1\n color= {color}\n{keys}end\n")
}

/// The sphere blocks [`sphere_with`] makes of each (colour, keys) pair, one
/// after the other.
fn spheres(blocks: &[(&str, &str)]) -> String {
    blocks
        .iter()
        .map(|&(color, keys)| sphere_with(color, keys))
        .collect()
}

/// The text of every shared scene file (both folders), read once.
fn shared_scene_texts() -> &'static [String] {
    static TEXTS: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    TEXTS.get_or_init(|| {
        ["framework", "community"]
            .into_iter()
            .flat_map(corpus_scenes)
            .map(|p| std::fs::read_to_string(p).unwrap()) // invariant: the test's own fixed input (a failure fails the test)
            .collect()
    })
}
