//! Fuzzing: no text, arbitrary, scene-like or a mutated scene file, may panic.

use super::shared_scene_texts;
use crate::Scene;
use crate::scene::Severity;
use proptest::prelude::*;

/// Edits that turn a valid scene into a plausible broken one.
#[derive(Clone, Debug)]
enum Edit {
    DeleteChar(usize),
    InsertText(usize, String),
    DeleteLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    Truncate(usize),
}

fn apply(text: &str, edit: &Edit) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut lines: Vec<&str> = text.lines().collect();
    let n = lines.len().max(1);
    match edit {
        Edit::DeleteChar(i) => {
            let mut c = chars;
            if !c.is_empty() {
                c.remove(i % c.len());
            }
            c.into_iter().collect()
        }
        Edit::InsertText(i, s) => {
            let mut c = chars;
            let at = i % (c.len() + 1);
            c.splice(at..at, s.chars());
            c.into_iter().collect()
        }
        Edit::DeleteLine(i) => {
            if !lines.is_empty() {
                lines.remove(i % n);
            }
            lines.join("\n")
        }
        Edit::DuplicateLine(i) => {
            if !lines.is_empty() {
                let l = lines[i % n];
                lines.insert(i % n, l);
            }
            lines.join("\n")
        }
        Edit::SwapLines(i, j) => {
            if !lines.is_empty() {
                lines.swap(i % n, j % n);
            }
            lines.join("\n")
        }
        Edit::Truncate(i) => chars[..i % (chars.len() + 1)].iter().collect(),
    }
}

fn edit() -> impl Strategy<Value = Edit> {
    let snippet = prop_oneof![
        Just("=".to_string()),
        Just(" ".to_string()),
        Just("\n".to_string()),
        Just("\r".to_string()),
        Just("\t".to_string()),
        Just("#".to_string()),
        Just("//".to_string()),
        Just("end\n".to_string()),
        Just("primitive ".to_string()),
        Just("light sphere\n".to_string()),
        Just(" 1e999".to_string()),
        Just(" nan".to_string()),
        Just(" -0".to_string()),
        Just(" 0 0 0".to_string()),
        Just(".".to_string()),
        Just("-".to_string()),
        Just("é".to_string()),
        Just("\u{feff}".to_string()),
        Just("P= 1 2\n".to_string()),
        Just("Cylinder\n".to_string()),
        "[ -~]{0,8}",
    ];
    prop_oneof![
        any::<usize>().prop_map(Edit::DeleteChar),
        (any::<usize>(), snippet).prop_map(|(i, s)| Edit::InsertText(i, s)),
        any::<usize>().prop_map(Edit::DeleteLine),
        any::<usize>().prop_map(Edit::DuplicateLine),
        (any::<usize>(), any::<usize>()).prop_map(|(i, j)| Edit::SwapLines(i, j)),
        any::<usize>().prop_map(Edit::Truncate),
    ]
}

/// A scene with every kind of block, to mutate.
const EVERYTHING: &str = "background\n top= 0.5 0.7 1\nend
camera\n O= 0 -5 1\n N= 0 1 0\n image_W= 64\n image_H= 48\nend
light point\n O= 3 3 3\n color= 1 1 1\nend
light square\n O= 0 0 5\n Dx= 1 0 0\n Dy= 0 1 0\n color= 1 1 1\nend
light sphere\n O= 0 0 4\n R= 0.5\n color= 1 1 1\n intensity= 2\nend
primitive sphere\n O= 0 0 0\n R= 1\n De= 0 0 1\n Dc= 0 1 0\n refr= 1\n rindex= 1.5\nend
primitive plane\n N= 0 0 1\n R= -1\n Dx= 2 0 0\nend
primitive square\n O= 0 2 0\n Dx= 1 0 0\n Dy= 0 0 1\nend
primitive cube\n O= 2 0 0\n Dx= 1 0 0\n Dy= 0 1 0\n x= 1\n y= 1\n z= 1\nend
primitive cylinder\n O1= 0 0 0\n O2= 0 0 1\n R= 0.5\nend
primitive bezier\n O1= 0 0 0\n O2= 0 0 1\n P= 0 1\n P= 1 1\n Cylinder\nend
primitive triangle\n O1= 0 0 0\n O2= 1 0 0\n O3= 0 1 0\nend
primitive mesh\n file= nowhere.obj\n O= 0 0 0\n scale= 1\n rotation= 0 0 0\nend
";

/// Parses `text` and checks the result is well-formed (no panic is the main point).
fn check_well_formed(text: &str, base: &str) {
    match Scene::parse(text, base) {
        Ok(s) => assert!(s.warnings().iter().all(|d| d.severity == Severity::Warning)),
        Err(e) => {
            assert!(e.errors().count() > 0);
            // `\r` alone also ends a line, so count both kinds of break.
            let lines = text.matches(['\n', '\r']).count() + 1;
            for d in &e.diagnostics {
                assert!(d.line >= 1 && d.line <= lines, "{d:?}");
                assert!(d.column >= 1 && d.len >= 1, "{d:?}");
                let _ = d.to_string();
            }
            let _ = e.to_string();
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_text_never_panics(text in any::<String>()) {
        check_well_formed(&text, "no/such/folder");
    }

    #[test]
    fn scene_like_text_never_panics(text in "((primitive|light|camera|background|end|[A-Za-z_]{1,6}=|[-+.0-9eE]{1,5}|sphere|mesh|bezier|P=|#|//|[ \t]|\n|\r\n){0,40})") {
        check_well_formed(&text, "no/such/folder");
    }

    #[test]
    fn mutated_scene_files_never_panic(
        which in 0usize..1000,
        edits in proptest::collection::vec(edit(), 1..6),
    ) {
        let texts = shared_scene_texts();
        let original = match texts.get(which % (texts.len() + 1)) {
            Some(t) => t.clone(),
            None => EVERYTHING.to_string(),
        };
        let mut text = original;
        for e in &edits {
            text = apply(&text, e);
        }
        // Texture and mesh paths resolve to nothing, so each case stays fast.
        check_well_formed(&text, "no/such/folder");
    }
}
