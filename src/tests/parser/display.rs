//! Diagnostics as they are printed: like rustc, with the file name.

use super::{DATA, parse};
use crate::Scene;
use std::path::Path;

#[test]
fn diagnostics_render_like_rustc_without_colours() {
    let e = parse("primitive sphere\n R= 1\n diff= x\nend").unwrap_err();
    let shown = e.diagnostics[0].to_string();
    assert_eq!(
        shown,
        "error: expected a number after `diff=`, found `x`
 --> <input>:3:8
  |
3 |  diff= x
  |        ^
  |"
    );
    assert!(!e.to_string().contains('\u{1b}'));
    // Tabs are expanded so the caret stays under the span.
    let e = parse("camera\n\tO= 1 x\nend").unwrap_err();
    let shown = e.diagnostics[0].to_string();
    assert!(shown.contains("2 |     O= 1 x\n  |          ^"), "{shown}");
}

#[test]
fn file_names_appear_in_diagnostics() {
    let path = Path::new(DATA).join("bad_scene.txt");
    let e = Scene::from_file(&path).unwrap_err();
    let d = &e.diagnostics[0];
    assert_eq!(d.file, path.display().to_string());
    assert_eq!((d.line, d.column), (3, 5));
    assert_eq!(d.source_line, "    R= -1");
    let e = Scene::from_file(Path::new(DATA).join("no_such_scene.txt")).unwrap_err();
    assert_eq!(e.diagnostics[0].line, 0);
}
