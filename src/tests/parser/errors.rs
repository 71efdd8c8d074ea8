//! Every kind of error, at its exact line and column, all reported together.

use super::{diagnostics, error_at, ok, v, warning_at};
use crate::scene::{SceneError, Severity};

#[test]
fn malformed_numbers() {
    let d = error_at("primitive sphere\n  O= 1 2,5 3\n  R= 1\nend", 2, 8);
    assert_eq!(d.severity, Severity::Error);
    assert!(d.message.contains("`2,5`"), "{d}");
    assert_eq!(d.len, 3);
    error_at("camera\n lens_W= 1.2.3\nend", 2, 10);
    error_at("camera\n lens_W= abc\nend", 2, 10);
    error_at("camera\n lens_W= 1e\nend", 2, 10);
    error_at("camera\n lens_W= -\nend", 2, 10);
}

#[test]
fn non_finite_numbers() {
    let d = error_at("camera\n O= 0 inf 0\nend", 2, 7);
    assert!(d.message.contains("finite"), "{d}");
    error_at("camera\n O= 0 0 NaN\nend", 2, 9);
    let d = error_at("camera\n O= 1e999 0 0\nend", 2, 5);
    assert!(d.message.contains("too large"), "{d}");
}

#[test]
fn missing_values_and_wrong_counts() {
    let d = error_at("camera\n    O=\nend", 2, 5);
    assert!(
        d.message.contains("expects 3 numbers, found nothing"),
        "{d}"
    );
    // As the lineages' readers do: missing values are 0, extra ones dropped.
    let text = "camera\n    O= 1 2\nend";
    let d = warning_at(text, 2, 5);
    assert!(d.message.contains("takes 3 numbers, found 2"), "{d}");
    assert_eq!(d.len, "O= 1 2".len());
    assert_eq!(ok(text).camera().origin, v(1.0, 2.0, 0.0));
    let text = "camera\n    O= 1 2 3 4 x\nend";
    let d = warning_at(text, 2, 14);
    assert!(d.message.contains("found 5: the rest is ignored"), "{d}");
    assert_eq!(d.len, 3);
    assert_eq!(ok(text).camera().origin, v(1.0, 2.0, 3.0));
    let text = "primitive bezier\n O1= 0 0 0\n O2= 0 0 1\n P= 1\n P= 2 2\n P= 3 3\nend";
    warning_at(text, 4, 2);
    error_at("primitive mesh\n file=\nend", 2, 2);
    let text = "light point\n color= 1 1 1\n intensity= 1 2\nend";
    warning_at(text, 3, 2);
    assert_eq!(ok(text).lights()[0].color, v(1.0, 2.0, 0.0));
}

#[test]
fn unknown_block_and_type_with_did_you_mean() {
    // Every lineage's reader skips an unknown type through its `end`: a
    // warning at the header, the rest of the file still read.
    let sphere = "primitive sphere\n R= 1\nend\n";
    let d = warning_at(&format!("primitive spher\n R= 1\nend\n{sphere}"), 1, 1);
    assert!(d.message.contains("unknown primitive type `spher`"), "{d}");
    assert!(d.message.contains("skipped"), "{d}");
    assert_eq!(d.help.as_deref(), Some("did you mean `sphere`?"));
    // A suggestion only where the block's keys fit the suggested type.
    let d = warning_at(&format!("primitive spher\n O1= 0 0 0\nend\n{sphere}"), 1, 1);
    assert!(
        !d.help.clone().unwrap_or_default().contains("did you mean"),
        "{d}"
    );
    let d = warning_at(&format!("\nlight spot\n O= 0 0 0\nend\n{sphere}"), 2, 1);
    assert!(d.help.unwrap().contains("`point`")); // invariant: the test's own fixed input (a failure fails the test)
    let d = warning_at(&format!("primtive sphere\n R= 1\nend\n{sphere}"), 1, 1);
    assert_eq!(d.help.as_deref(), Some("did you mean `primitive`?"));
    let d = warning_at(&format!("primitive\nend\n{sphere}"), 1, 11);
    assert!(d.message.contains("expected a primitive type"), "{d}");
    assert_eq!(
        ok(&format!("primitive torus\n R_major= 2\nend\n{sphere}"))
            .objects()
            .len(),
        1
    );
}

#[test]
fn a_file_without_blocks_is_not_a_scene() {
    let d = error_at("BM6\u{0}\u{1} binary junk\n", 1, 1);
    assert!(d.message.contains("not a scene file"), "{d}");
}

#[test]
fn text_outside_a_block() {
    // Dropped by every lineage's reader: a warning, skipped to the next `end`.
    let d = warning_at("camera\nend\n  O= 1 2 3\n junk\nend\n", 3, 3);
    assert!(d.message.contains("outside a block"), "{d}");
    let d = warning_at("camera\nend\nend\n", 3, 1);
    assert!(d.message.contains("`end` without a block"), "{d}");
}

#[test]
fn a_block_without_end_points_at_its_header() {
    let d = warning_at("camera\n O= 1 2 3\nend\n\nprimitive sphere\n  R= 1\n", 5, 1);
    assert!(d.message.contains("no `end`"), "{d}");
    assert_eq!(d.len, "primitive sphere".len());
    // Running into the next header: the unclosed block is still the one
    // blamed, and both blocks are read.
    let text = "primitive sphere\n R= 1\nprimitive sphere\n R= 2\nend";
    let d = warning_at(text, 1, 1);
    assert!(d.help.unwrap().contains("before line 3")); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(ok(text).objects().len(), 2);
}

#[test]
fn bare_words_inside_a_block() {
    // A key without `=` is ignored by every lineage's reader (W's files have them).
    let text = "camera\n  lens_W 2\nend";
    let d = warning_at(text, 2, 3);
    assert!(d.message.contains("`lens_W` without `=`"), "{d}");
    assert_eq!(d.help.as_deref(), Some("did you mean `lens_W=`?"));
    assert_eq!(ok(text).camera().lens_w, 0.88);
    let d = warning_at("camera\n  ned\nend", 2, 3);
    assert_eq!(d.help.as_deref(), Some("did you mean `end`?"));
    error_at("camera\n = 2\nend", 2, 2);
}

#[test]
fn sample_counts_past_the_maximum_are_refused_at_their_line() {
    let d = error_at("camera\n shade_quality= 268435455\nend", 2, 2);
    assert!(d.message.contains("at most 1024"), "{d}");
    let d = error_at("camera\n image_W= 4\n drefl_quality= 1025\nend", 3, 2);
    assert!(d.message.contains("`drefl_quality=` is too large"), "{d}");
    let warned = crate::Scene::parse("camera\n shade_quality= 1024\nend", ".");
    assert!(warned.is_ok());
}

#[test]
fn missing_and_unreadable_files() {
    let d = error_at("primitive sphere\n R= 1\n texture= nowhere.bmp\nend", 3, 2);
    assert!(d.message.contains("not found"), "{d}");
    let d = error_at(
        "primitive sphere\n R= 1\n texture= not_an_image.bmp\nend",
        3,
        2,
    );
    assert!(d.message.contains("cannot read texture"), "{d}");
    let d = error_at("primitive mesh\n  file= nowhere.obj\nend", 2, 3);
    assert!(
        d.message.contains("mesh file `nowhere.obj` not found"),
        "{d}"
    );
    let d = error_at("primitive mesh\n  O= 0 0 0\nend", 1, 1);
    assert!(d.message.contains("`file=`"), "{d}");
    // A directory or a device: said so at the key, never "not found".
    let d = error_at("primitive sphere\n R= 1\n texture= /tmp\nend", 3, 2);
    assert!(d.message.contains("/tmp) is a directory"), "{d}");
    let d = error_at("primitive mesh\n  file= /dev/zero\nend", 2, 3);
    assert!(d.message.contains("is not a regular file"), "{d}");
}

#[test]
fn radii_must_be_positive() {
    error_at("primitive sphere\n R= 0\nend", 2, 2);
    error_at("primitive sphere\n R= -1\nend", 2, 2);
    error_at(
        "primitive cylinder\n O1= 0 0 0\n O2= 0 0 1\n R= 0\nend",
        4,
        2,
    );
    error_at("light sphere\n color= 1 1 1\n R= -2\nend", 3, 2);
    let d = error_at("primitive sphere\n O= 1 1 1\nend", 1, 1);
    assert!(d.message.contains("needs `R=`"), "{d}");
}

#[test]
fn zero_length_directions() {
    error_at("camera\n N= 0 0 0\nend", 2, 2);
    error_at("primitive plane\n N= 0 0 0\nend", 2, 2);
    let d = error_at(
        "primitive cylinder\n O1= 1 2 3\n O2= 1 2 3\n R= 1\nend",
        3,
        2,
    );
    assert!(d.message.contains("zero length"), "{d}");
    error_at(
        "primitive bezier\n O1= 1 2 3\n O2= 1 2 3\n P= 0 1\n P= 1 1\nend",
        3,
        2,
    );
    error_at("primitive cube\n Dx= 0 0 0\n x= 1\n y= 1\n z= 1\nend", 2, 2);
    error_at("primitive cube\n Dy= 0 0 0\n x= 1\n y= 1\n z= 1\nend", 2, 2);
    error_at("primitive square\n Dx= 0 0 0\n Dy= 0 1 0\nend", 2, 2);
    error_at("primitive square\n Dx= 1 0 0\n Dy= 0 0 0\nend", 3, 2);
    error_at(
        "light square\n color= 1 1 1\n Dx= 1 0 0\n Dy= 0 0 0\nend",
        4,
        2,
    );
}

#[test]
fn parallel_spans() {
    let d = error_at("primitive square\n Dx= 1 0 0\n Dy= -2 0 0\nend", 3, 2);
    assert!(d.message.contains("parallel"), "{d}");
    error_at(
        "primitive cube\n Dx= 0 1 0\n Dy= 0 3 0\n x= 1\n y= 1\n z= 1\nend",
        3,
        2,
    );
    error_at(
        "light square\n color= 1 1 1\n Dx= 1 1 0\n Dy= 2 2 0\nend",
        4,
        2,
    );
}

#[test]
fn bezier_needs_two_control_points() {
    let d = error_at(
        "primitive bezier\n O1= 0 0 0\n O2= 0 0 1\n P= 0 1\nend",
        4,
        2,
    );
    assert!(d.message.contains("at least 2"), "{d}");
    error_at("primitive bezier\n O1= 0 0 0\n O2= 0 0 1\nend", 1, 1);
    // Degree 64 (65 points) is the most glint accepts; the 66th point is the error.
    let points = |n: usize| (0..n).map(|k| format!(" P= {k} 1\n")).collect::<String>();
    ok(&format!(
        "primitive bezier\n O1= 0 0 0\n O2= 0 0 1\n{}end",
        points(65)
    ));
    let d = error_at(
        &format!(
            "primitive bezier\n O1= 0 0 0\n O2= 0 0 1\n{}end",
            points(66)
        ),
        69,
        2,
    );
    assert!(d.message.contains("at most 65"), "{d}");
}

#[test]
fn image_sizes_and_qualities() {
    error_at("camera\n image_W= 0\nend", 2, 2);
    error_at("camera\n image_H= 32769\nend", 2, 2);
    ok("camera\n image_W= 32768\n image_H= 1\nend");
    // Integer keys are read as written (rounded), with a warning where the
    // lineages' readers (an integer `>>`) read another value.
    let text = "camera\n image_W= 640.5\n max_photons= 1e7\n image_H= 300\nend";
    let s = ok(text);
    assert_eq!((s.camera().width, s.camera().height), (641, 300));
    assert_eq!(s.camera().photons.max_photons, 10_000_000);
    let w: Vec<_> = s
        .warnings()
        .iter()
        .map(|d| (d.line, d.message.as_str()))
        .collect();
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].1
            .contains("read as 641; the lineages' readers read 640"),
        "{w:?}"
    );
    assert!(
        w[1].1
            .contains("read as 10000000; the lineages' readers read 1 "),
        "{w:?}"
    );
    // The qualities are reals (the framework's readers keep fractions): the
    // error spans the key and its value.
    let d = error_at("camera\n shade_quality= -1\nend", 2, 2);
    assert!(d.message.contains("negative"), "{d}");
    error_at("camera\n drefl_quality= -2\nend", 2, 2);
    error_at("camera\n max_photons= -5\nend", 2, 15);
    error_at("camera\n sample_dist= -1\nend", 2, 2);
    error_at("camera\n lens_W= 0\nend", 2, 2);
}

#[test]
fn degenerate_triangles() {
    let d = error_at(
        "primitive triangle\n O1= 0 0 0\n O2= 1 1 1\n O3= 2 2 2\nend",
        1,
        1,
    );
    assert!(d.message.contains("collinear"), "{d}");
    error_at(
        "primitive triangle\n O1= 0 0 0\n O2= 0 0 0\n O3= 1 0 0\nend",
        1,
        1,
    );
}

#[test]
fn zero_mesh_scale_is_an_error() {
    error_at("primitive mesh\n file= tri.obj\n scale= 0\nend", 3, 2);
}

#[test]
fn all_errors_are_reported_together_in_file_order() {
    let text = "primitive spher
    R= 1
end
camera
    O= 1 x
    colour= 1 1 1
    image_W= 0
end
primitive sphere
    R= -1
";
    let d = diagnostics(text);
    let got: Vec<_> = d.iter().map(|d| (d.severity, d.line, d.column)).collect();
    use Severity::{Error, Warning};
    assert_eq!(
        got,
        vec![
            (Warning, 1, 1),
            (Error, 5, 10),
            (Warning, 6, 5),
            (Error, 7, 5),
            (Warning, 9, 1),
            (Error, 10, 5),
        ],
        "{d:#?}"
    );
    let e = SceneError { diagnostics: d };
    assert!(
        e.to_string()
            .ends_with("3 errors in the scene; nothing was rendered")
    );
}
