//! The lexical level: comments, number forms, key order and spacing, line endings.

use super::{DATA, error_at, ok, v, warning_at};
use crate::geometry::Shape;
use crate::scene::Background;
use glam::DVec3;
use std::path::Path;

#[test]
fn comments_of_all_kinds() {
    let s = ok("# a comment line
#no space after the hash
// a slash comment
background // trailing on a header
    color= 0.5 0.5 0.5  # trailing after values
end # trailing after end

camera
    # indented comment
    // indented slash comment
    O= 1 2 3 // trailing slashes
    N= 0 1 0#glued
end
primitive sphere
    R= 1
    texture= tiny.bmp # the texture
end
");
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
    assert_eq!(s.background(), Background::Color(DVec3::splat(0.5)));
    assert_eq!(
        (s.camera().origin, s.camera().dir),
        (v(1.0, 2.0, 3.0), DVec3::Y)
    );
    assert_eq!(s.textures().len(), 1);
}

#[test]
fn comments_glued_to_values_headers_and_end() {
    let s = ok("camera// the eye
    O= 0 5 0// centre
    N= 0 0 1# up
    lens_W= 2//wide
end// camera
primitive sphere//ball
    O= 1 2 3#c
    R= 2//r
end//x
primitive sphere
    R= 1
    texture= tiny.bmp// the texture
end#done
");
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
    assert_eq!(
        (s.camera().origin, s.camera().dir, s.camera().lens_w),
        (v(0.0, 5.0, 0.0), DVec3::Z, 2.0)
    );
    assert_eq!(s.objects().len(), 2);
    let Shape::Sphere(sp) = &s.objects()[0].shape else {
        panic!("not a sphere") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!((sp.center, sp.radius), (v(1.0, 2.0, 3.0), 2.0));
    assert_eq!(s.textures().len(), 1);
    // `end//x` closes its block: the next header is not swallowed by it.
    assert_eq!(
        ok("primitive sphere\n R= 1\nend//x\nprimitive sphere\n R= 2\nend")
            .objects()
            .len(),
        2
    );
}

#[test]
fn columns_stay_right_before_glued_comments() {
    let d = error_at("camera\n    O= 0 5 zz// centre\nend", 2, 12);
    assert_eq!(d.len, 2, "{d}");
    assert!(d.message.contains("`zz`"), "{d}");
    let d = error_at("camera\n  lens_W= 1,5#x\nend", 2, 11);
    assert_eq!(d.len, 3, "{d}");
    assert!(
        d.message.contains("`1,5`") && !d.message.contains('#'),
        "{d}"
    );
    let d = warning_at(
        "primitive spher// typo\n R= 1\nend\nprimitive sphere\n R= 1\nend",
        1,
        1,
    );
    assert!(d.message.contains("`spher`"), "{d}");
    // A missing value: the caret goes just after the key, not into the comment.
    let d = error_at("primitive sphere\n R=// none\nend", 2, 2);
    assert!(d.message.contains("found nothing"), "{d}");
    // The span of the text after `end` stops before the comment.
    let d = warning_at("camera\nend  extra words//c", 2, 6);
    assert_eq!(d.len, 11, "{d}");
}

/// The fuzz target's reading finds none of the files a scene names, though
/// they are there (next to the scene, in the working directory, absolute),
/// and says so as the ordinary reading says of a missing file.
#[test]
fn a_reading_without_files_finds_none() {
    let abs = std::fs::canonicalize(Path::new(DATA).join("tri.obj")).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let abs = abs.display();
    let text = format!(
        "primitive sphere\n R= 1\n texture= tiny.bmp\nend\n\
         primitive mesh\n file= {DATA}/tri.obj\nend\n\
         primitive mesh\n file= {abs}\nend\n"
    );
    // Found, as usual: next to the scene, in the working directory, absolute
    // (the sphere, and the one triangle of each mesh).
    let s = ok(&text);
    assert_eq!((s.textures().len(), s.objects().len()), (1, 3));
    let e = match crate::format::parse_text(&text, None, Path::new(DATA), None, false) {
        Ok(_) => panic!("a reading without files found them"), // invariant: the test's own fixed input (a failure fails the test)
        Err(e) => e,
    };
    let lines: Vec<(usize, bool)> = e
        .errors()
        .map(|d| (d.line, d.message.contains("not found")))
        .collect();
    assert_eq!(lines, [(3, true), (6, true), (9, true)], "{e}");
    let rendered = e.render(false);
    assert!(
        rendered.contains("texture file `tiny.bmp` not found"),
        "{rendered}"
    );
}

#[test]
fn double_slashes_inside_file_paths_are_kept() {
    // Glued inside a path: part of it (`.//tiny.bmp` is `./tiny.bmp`).
    let s = ok("primitive sphere\n R= 1\n texture= .//tiny.bmp\nend");
    assert_eq!(s.textures().len(), 1);
    let s = ok("primitive mesh\n file=.//tri.obj\nend");
    assert_eq!(s.objects().len(), 1);
    // Followed by a blank or the end of the line: a comment.
    let s = ok("primitive sphere\n R= 1\n texture= tiny.bmp//\nend");
    assert_eq!(s.textures().len(), 1);
    // Glued on both sides, it stays in the path, which then names no file.
    let d = error_at("primitive sphere\n R= 1\n texture= tiny.bmp//x\nend", 3, 2);
    assert!(d.message.contains("`tiny.bmp//x` not found"), "{d}");
}

#[test]
fn number_forms() {
    let s = ok("camera\n O= .5 -1e-3 +2\n lens_W= 1.\n lens_H= 5E-1\n image_W= 1e3\nend");
    assert_eq!(s.camera().origin, v(0.5, -0.001, 2.0));
    assert_eq!((s.camera().lens_w, s.camera().lens_h), (1.0, 0.5));
    assert_eq!(s.camera().width, 1000);
    let s = ok("primitive sphere\n O= -.25 +.75 -0\n R= 2.5e+0\nend");
    let Shape::Sphere(sp) = &s.objects()[0].shape else {
        panic!("not a sphere") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!((sp.center, sp.radius), (v(-0.25, 0.75, 0.0), 2.5));
}

#[test]
fn any_key_order_and_later_keys_override() {
    let s = ok("primitive sphere
    diff= 0.1
    R= 3
    color= 1 0 0
    O= 1 1 1
    R= 2
    diff= 0.9
    color= 0 0 1
end");
    let Shape::Sphere(sp) = &s.objects()[0].shape else {
        panic!("not a sphere") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!((sp.center, sp.radius), (DVec3::ONE, 2.0));
    let m = s.material(0);
    assert_eq!((m.color, m.diff), (DVec3::Z, 0.9));
    assert!(s.warnings().is_empty());
}

#[test]
fn lenient_key_spacing() {
    let s = ok("camera\n O=1 2 3\n N = 0 0 1\n lens_W =2\n lens_H= 3\nend");
    assert_eq!(s.camera().origin, v(1.0, 2.0, 3.0));
    assert_eq!(s.camera().dir, DVec3::Z);
    assert_eq!((s.camera().lens_w, s.camera().lens_h), (2.0, 3.0));
}

#[test]
fn line_endings_tabs_blank_lines_and_no_final_newline() {
    let s = ok("\r\n\r\ncamera\r\n\tO=\t1 2 3\r\n\r\n\tlens_W= 2\r\nend");
    assert_eq!(
        (s.camera().origin, s.camera().lens_w),
        (v(1.0, 2.0, 3.0), 2.0)
    );
    // A lone CR also ends a line; an error's line number counts it.
    let d = warning_at("camera\r O= 1 2\rend", 2, 2);
    assert!(d.message.contains("3 numbers"), "{d}");
    // A byte-order mark does not hide the first header.
    assert_eq!(ok("\u{feff}camera\n lens_W= 2\nend").camera().lens_w, 2.0);
}
