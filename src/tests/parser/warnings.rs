//! Every kind of warning, at its exact line and column.

use super::{DATA, error_at, ok, parse, warning_at};
use crate::Scene;
use crate::scene::{Diagnostic, Severity};

#[test]
fn misspelt_keys_warn_with_did_you_mean() {
    let d = warning_at("primitive sphere\n R= 1\n  colour= 1 0 0\nend", 3, 3);
    assert!(d.message.contains("unknown key `colour=`"), "{d}");
    assert_eq!(d.help.as_deref(), Some("did you mean `color=`?"));
    assert_eq!(d.len, "colour=".len());
    let d = warning_at("camera\n lens_w= 1\nend", 2, 2);
    assert_eq!(d.help.as_deref(), Some("did you mean `lens_W=`?"));
    let d = warning_at("camera\n zoom= 1\nend", 2, 2);
    assert_eq!(d.help, None);
}

#[test]
fn keys_a_block_does_not_use_warn() {
    let d = warning_at("primitive square\n Dx= 1 0 0\n Dy= 0 1 0\n R= 2\nend", 4, 2);
    assert!(
        d.message.contains("not used by a `primitive square`"),
        "{d}"
    );
    let d = warning_at("light point\n color= 1 1 1\n diff= 1\nend", 3, 2);
    assert!(d.message.contains("not used"), "{d}");
    // P= in a mesh: warnings, and the only errors (if any) come from loading the mesh.
    let text = "primitive mesh\n file= tri.obj\n P= 1 5\n P= 10 10\nend";
    let ws: Vec<Diagnostic> = match parse(text) {
        Ok(s) => s.warnings().to_vec(),
        Err(e) => {
            assert!(e.errors().all(|d| d.line == 2), "{e}");
            e.diagnostics
                .into_iter()
                .filter(|d| d.severity == Severity::Warning)
                .collect()
        }
    };
    let at: Vec<_> = ws.iter().map(|d| (d.line, d.column)).collect();
    assert_eq!(at, vec![(3, 2), (4, 2)], "{ws:#?}");
    assert!(
        ws.iter()
            .all(|d| d.message.contains("`P=` is not used by a `primitive mesh`"))
    );
}

#[test]
fn refraction_without_index_is_warned() {
    // Kept as written; the framework's dialect refracts with index 1 (see
    // tests/dialects.rs for the pictures), the lineages' reflect.
    let text = "primitive sphere\n R= 1\n refr= 1\nend";
    let d = warning_at(text, 3, 2);
    assert!(d.message.contains("using rindex 1"), "{d}");
    assert_eq!(ok(text).material(0).rindex, 0.0);
    let text = "primitive sphere\n R= 1\n rindex= -2\n refr= 0.5\nend";
    warning_at(text, 3, 2);
    assert_eq!(ok(text).material(0).rindex, -2.0);
    let lineage = Scene::parse_as(text, DATA, Some(crate::scene::Dialect::Pm3)).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert!(
        lineage
            .warnings()
            .iter()
            .any(|w| w.message.contains("acts as a mirror")),
        "{:?}",
        lineage.warnings()
    );
    // Without refraction the index does not matter.
    assert!(
        ok("primitive sphere\n R= 1\n rindex= 0\nend")
            .warnings()
            .is_empty()
    );
}

#[test]
fn other_warnings() {
    warning_at("primitive sphere\n R= 1\n blur= gauss\nend", 3, 2);
    warning_at("camera extra words\nend", 1, 8);
    warning_at("camera\nend trailing\n", 2, 5);
    warning_at("primitive sphere\n R= 1\n Cylinder\nend", 3, 2);
    // A zero texture direction matters only with a texture.
    warning_at("primitive sphere\n R= 1\n De= 0 0 0\nend", 3, 2);
    error_at(
        "primitive sphere\n R= 1\n De= 0 0 0\n texture= tiny.bmp\nend",
        3,
        2,
    );
    warning_at("primitive plane\n N= 0 0 1\n Dx= 0 0 0\nend", 3, 2);
    error_at(
        "primitive plane\n N= 0 0 1\n Dx= 0 0 0\n texture= tiny.bmp\nend",
        3,
        2,
    );
}

#[test]
fn sample_counts_far_above_the_default_warn_at_the_key() {
    // 64 (1024 rays) is the last value without a warning.
    for key in ["shade_quality", "drefl_quality"] {
        let s = ok(&format!("camera\n {key}= 64\nend"));
        assert!(s.warnings().is_empty(), "{:?}", s.warnings());
        let d = warning_at(&format!("camera\n O= 0 0 0\n  {key}= 65\nend"), 3, 3);
        assert!(d.message.contains("1040") && d.message.contains(key), "{d}");
        let d = warning_at(&format!("camera\n {key}= 1024\nend"), 2, 2);
        assert!(d.message.contains("16384"), "{d}");
    }
    let s = ok("camera\n shade_quality= 65\nend");
    assert_eq!(s.camera().shade_quality, 65.0, "the value is kept");
}
