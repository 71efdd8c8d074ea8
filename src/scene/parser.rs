//! The scene-file parser (to be written).

use super::{Diagnostic, Scene, SceneError, Severity};
use std::path::Path;

pub(super) fn parse_file(path: &Path) -> Result<Scene, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| SceneError {
        diagnostics: vec![Diagnostic {
            severity: Severity::Error,
            message: format!("cannot read the scene file: {e}"),
            file: path.display().to_string(),
            line: 0,
            column: 0,
            len: 0,
            source_line: String::new(),
            help: None,
        }],
    })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    parse_str(&text, Some(path), dir)
}

pub(super) fn parse_str(
    _text: &str,
    _path: Option<&Path>,
    _base: &Path,
) -> Result<Scene, SceneError> {
    Ok(Scene::empty())
}
