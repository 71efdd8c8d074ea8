//! The scene-file parser: every key into its field, comments, number forms,
//! overrides, every kind of error and warning at its exact line and column,
//! the real scene files, and fuzzing (no input may panic).

use super::common::{corpus, corpus_scenes};
use crate::Scene;
use crate::geometry::Shape;
use crate::scene::{Background, Diagnostic, LightKind, SceneError, Severity};
use glam::{DVec2, DVec3};
use proptest::prelude::*;
use std::path::Path;

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

// ---------------------------------------------------------------- keys

#[test]
fn camera_keys_all_reach_their_fields() {
    let s = ok("camera
    O= 1 2 3
    N= 0 3 4
    lens_W= 1.5
    lens_H= 0.75
    image_W= 640
    image_H= 480
    shade_quality= 2
    drefl_quality= 3
    max_photons= 5000
    emit_photons= 4000
    sample_photons= 50
    sample_dist= 0.25
    aperture= 0.1
    focalLen= 7
    dofSample= 9
    max_hitpoints= 123
    iterations= 45
    reduction= 0.7
end
");
    let c = &s.camera();
    assert_eq!(c.origin, v(1.0, 2.0, 3.0));
    assert!(close(c.dir, v(0.0, 0.6, 0.8)), "{:?}", c.dir);
    assert_eq!((c.lens_w, c.lens_h), (1.5, 0.75));
    assert_eq!((c.width, c.height), (640, 480));
    assert_eq!((c.shade_quality, c.drefl_quality), (2, 3));
    assert_eq!(c.photons.max_photons, 5000);
    assert_eq!(c.photons.emit_photons, 4000);
    assert_eq!(c.photons.sample_photons, 50);
    assert_eq!(c.photons.sample_dist, 0.25);
    assert_eq!(c.photons.max_hitpoints, Some(123));
    assert_eq!(c.photons.iterations, Some(45));
    assert_eq!(c.photons.reduction, Some(0.7));
    assert_eq!(c.dof.aperture, 0.1);
    assert_eq!(c.dof.focal_len, 7.0);
    assert_eq!(c.dof.samples, 9);
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
}

#[test]
fn camera_defaults_match_the_spec() {
    let c = ok("camera\nend\n").camera().clone();
    assert_eq!(c.origin, DVec3::ZERO);
    assert_eq!(c.dir, DVec3::Y);
    assert_eq!(
        (c.lens_w, c.lens_h, c.width, c.height),
        (0.88, 0.88, 420, 420)
    );
    assert_eq!((c.shade_quality, c.drefl_quality), (4, 4));
    assert_eq!(
        (
            c.photons.max_photons,
            c.photons.emit_photons,
            c.photons.sample_photons
        ),
        (2_000_000, 1_000_000, 100)
    );
    assert_eq!(c.photons.sample_dist, 1.0);
    assert_eq!(c.dof.aperture, 0.0);
}

#[test]
fn background_color_and_gradients() {
    assert_eq!(ok("").background(), Background::Color(DVec3::ZERO));
    assert_eq!(
        ok("background\n color= 0.1 0.2 0.3\nend").background(),
        Background::Color(v(0.1, 0.2, 0.3))
    );
    assert_eq!(
        ok("background\n top= 0.5 0.7 1\nend").background(),
        Background::Gradient {
            top: v(0.5, 0.7, 1.0),
            bottom: DVec3::ONE
        }
    );
    assert_eq!(
        ok("background\n bottom= 0 0 0.5\n top= 1 0 0\nend").background(),
        Background::Gradient {
            top: v(1.0, 0.0, 0.0),
            bottom: v(0.0, 0.0, 0.5)
        }
    );
    // The later key wins between a uniform colour and a gradient.
    assert_eq!(
        ok("background\n top= 1 0 0\n color= 0 1 0\nend").background(),
        Background::Color(v(0.0, 1.0, 0.0))
    );
}

#[test]
fn material_keys_all_reach_their_fields() {
    let s = ok("primitive sphere
    R= 1
    color= 0.1 0.2 0.3
    diff= 0.4
    spec= 0.5
    refl= 0.6
    drefl= 0.7
    blur= exp
    refr= 0.8
    rindex= 1.5
    absor= 0.01 0.02 0.03
    texture= tiny.bmp
end
");
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
    let m = s.material_of(&s.objects()[0]);
    assert_eq!(m.color, v(0.1, 0.2, 0.3));
    assert_eq!((m.diff, m.spec, m.refl, m.drefl), (0.4, 0.5, 0.6, 0.7));
    assert_eq!((m.refr, m.rindex), (0.8, 1.5));
    assert_eq!(m.absor, v(0.01, 0.02, 0.03));
    let t = &s.textures()[m.texture.unwrap() as usize]; // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!((t.width(), t.height()), (2, 2));
    // Row 0 is the bottom row of the BMP: red, then green; the framework
    // divides a byte by 256 (its `bmp.h`), so 255 reads as 255/256.
    let full = f64::from(255f32 / 256.0);
    assert_eq!(t.sample(DVec2::new(0.0, 0.0)), v(full, 0.0, 0.0));
    assert_eq!(t.sample(DVec2::new(0.0, 0.5)), v(0.0, full, 0.0));
}

#[test]
fn material_defaults_are_zero() {
    let s = ok("primitive sphere\n R= 1\nend");
    let m = s.material_of(&s.objects()[0]);
    assert_eq!(m.color, DVec3::ZERO);
    assert_eq!(
        (m.diff, m.spec, m.refl, m.drefl, m.refr, m.rindex),
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    );
    assert_eq!(m.texture, None);
}

#[test]
fn sphere_keys() {
    let s = ok("primitive sphere\n O= 1 2 3\n R= 0.5\n De= 0 0 2\n Dc= 3 0 0\nend");
    let Shape::Sphere(sp) = &s.objects()[0].shape else {
        panic!("not a sphere") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!((sp.center, sp.radius), (v(1.0, 2.0, 3.0), 0.5));
    assert_eq!((sp.de(), sp.dc()), (DVec3::Z, DVec3::X));
    let s = ok("primitive sphere\n R= 1\nend");
    let Shape::Sphere(sp) = &s.objects()[0].shape else {
        panic!("not a sphere") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!(
        (sp.center, sp.de(), sp.dc()),
        (DVec3::ZERO, DVec3::Z, DVec3::Y)
    );
}

#[test]
fn plane_keys() {
    let s = ok("primitive plane\n N= 0 0 -2\n R= -4\n Dx= 8 0 0\n Dy= 0 8 0\nend");
    let Shape::Plane(p) = &s.objects()[0].shape else {
        panic!("not a plane") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!((p.normal, p.offset), (-DVec3::Z, -4.0));
    assert_eq!((p.dx, p.dy), (v(8.0, 0.0, 0.0), v(0.0, 8.0, 0.0)));
}

#[test]
fn plane_default_texture_axes_are_perpendicular_and_follow_n() {
    for (n, given) in [
        (v(0.0, 0.0, 1.0), ""),
        (v(1.0, 2.0, 3.0), ""),
        (v(0.0, 0.0, 1.0), "Dx= 2 0 0"),
        (v(1.0, -1.0, 0.5), "Dy= 3 3 0"),
    ] {
        let text = format!(
            "primitive plane\n N= {} {} {}\n {given}\nend",
            n.x, n.y, n.z
        );
        let s = ok(&text);
        let Shape::Plane(p) = &s.objects()[0].shape else {
            panic!("not a plane") // invariant: the test's own fixed input (a failure fails the test)
        };
        let nu = n.normalize();
        assert!(
            p.dx.dot(nu).abs() < 1e-12 && p.dy.dot(nu).abs() < 1e-12,
            "{text}"
        );
        assert!(p.dx.dot(p.dy).abs() < 1e-12, "{text}");
        assert!(
            close(p.dx.cross(p.dy).normalize(), nu),
            "{text}: Dx × Dy along N"
        );
        assert!((p.dx.length() - p.dy.length()).abs() < 1e-12, "{text}");
        if given.is_empty() {
            assert!((p.dx.length() - 1.0).abs() < 1e-12, "{text}");
        }
    }
    let s = ok("primitive plane\n N= 0 0 1\nend");
    let Shape::Plane(p) = &s.objects()[0].shape else {
        panic!("not a plane") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!((p.dx, p.dy, p.offset), (DVec3::X, DVec3::Y, 0.0));
}

#[test]
fn square_keys() {
    let s = ok("primitive square\n O= 1 1 1\n Dx= 2 0 0\n Dy= 0 0 3\nend");
    let Shape::Square(q) = &s.objects()[0].shape else {
        panic!("not a square") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!(
        (q.center, q.dx, q.dy),
        (DVec3::ONE, v(2.0, 0.0, 0.0), v(0.0, 0.0, 3.0))
    );
    assert_eq!(q.normal, -DVec3::Y);
}

#[test]
fn cube_keys_orthonormal_input_is_kept_without_warning() {
    let c = std::f64::consts::FRAC_1_SQRT_2;
    let text = format!(
        "primitive cube\n O= 1 2 3\n Dx= {c} {c} 0\n Dy= -{c} {c} 0\n x= 1\n y= 2\n z= 3\nend"
    );
    let s = ok(&text);
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
    let Shape::Cube(b) = &s.objects()[0].shape else {
        panic!("not a cube") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!(b.center, v(1.0, 2.0, 3.0));
    assert_eq!(b.half, v(1.0, 2.0, 3.0));
    assert!(close(b.axes[0], v(c, c, 0.0)) && close(b.axes[1], v(-c, c, 0.0)));
    assert!(close(b.axes[2], DVec3::Z));
}

#[test]
fn cube_axes_are_orthonormalised_with_warnings_at_the_keys() {
    let text = "primitive cube\n Dx= 2 0 0\n Dy= 1 1 0\n x= 1\n y= 1\n z= 1\nend";
    let s = ok(text);
    let Shape::Cube(b) = &s.objects()[0].shape else {
        panic!("not a cube") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert!(close(b.axes[0], DVec3::X), "{:?}", b.axes);
    assert!(close(b.axes[1], DVec3::Y), "{:?}", b.axes);
    assert!(close(b.axes[2], DVec3::Z), "{:?}", b.axes);
    let at: Vec<_> = s.warnings().iter().map(|d| (d.line, d.column)).collect();
    assert_eq!(at, vec![(2, 2), (3, 2)], "{:#?}", s.warnings());
    // Unit but not perpendicular: only Dy is adjusted.
    let s = ok("primitive cube\n Dx= 0 1 0\n Dy= 0.6 0.8 0\n x= 1\n y= 1\n z= 1\nend");
    let Shape::Cube(b) = &s.objects()[0].shape else {
        panic!("not a cube") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert!(
        close(b.axes[0], DVec3::Y) && close(b.axes[1], DVec3::X),
        "{:?}",
        b.axes
    );
    assert_eq!(s.warnings().len(), 1);
    assert_eq!((s.warnings()[0].line, s.warnings()[0].column), (3, 2));
    // Without Dx/Dy the box is axis-aligned.
    let s = ok("primitive cube\n x= 1\n y= 1\n z= 1\nend");
    let Shape::Cube(b) = &s.objects()[0].shape else {
        panic!("not a cube") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!(b.axes, [DVec3::X, DVec3::Y, DVec3::Z]);
}

#[test]
fn cylinder_keys() {
    let s = ok("primitive cylinder\n O1= 0 0 0\n O2= 0 0 2\n R= 0.5\nend");
    let Shape::Cylinder(c) = &s.objects()[0].shape else {
        panic!("not a cylinder") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!((c.o1, c.o2, c.radius), (DVec3::ZERO, v(0.0, 0.0, 2.0), 0.5));
}

#[test]
fn bezier_p_lines_accumulate_in_order_with_or_without_cylinder() {
    for tail in ["", "    Cylinder\n"] {
        let text = format!(
            "primitive bezier\n    O1= 80 -10 0\n    O2= 80 -10 30\n    P= 5 5\n    P= 10 6\n    P= 15 7\n    P= 2 9\n{tail}    refl= 0.3\nend\n"
        );
        let s = ok(&text);
        assert!(s.warnings().is_empty(), "{:?}", s.warnings());
        let Shape::Bezier(b) = &s.objects()[0].shape else {
            panic!("not a bezier") // invariant: the test's own fixed input (a failure fails the test)
        };
        assert_eq!((b.o1, b.o2), (v(80.0, -10.0, 0.0), v(80.0, -10.0, 30.0)));
        let p = |z, r| DVec2::new(z, r);
        assert_eq!(
            b.points,
            vec![p(5.0, 5.0), p(10.0, 6.0), p(15.0, 7.0), p(2.0, 9.0)]
        );
    }
}

#[test]
fn triangle_keys() {
    let s = ok("primitive triangle\n O1= 0 0 0\n O2= 1 0 0\n O3= 0 1 0\nend");
    let Shape::Triangle(t) = &s.objects()[0].shape else {
        panic!("not a triangle") // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!(t.vertices, [DVec3::ZERO, DVec3::X, DVec3::Y]);
    assert_eq!(t.normals(), None);
}

#[test]
fn light_keys_and_intensity() {
    let s = ok("light point
    O= 3 3 3
    color= 2 2 2
end
light square
    O= 0 0 5
    Dx= 1 0 0
    Dy= 0 1 0
    color= 1 0.5 0.25
    intensity= 2
end
light sphere
    intensity= 1 2 3
    O= 1 1 1
    R= 0.5
    color= 1 1 1
end
");
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
    assert_eq!(s.lights().len(), 3);
    assert_eq!(
        s.lights()[0].kind,
        LightKind::Point {
            pos: v(3.0, 3.0, 3.0)
        }
    );
    assert_eq!(s.lights()[0].color, v(2.0, 2.0, 2.0));
    assert_eq!(
        s.lights()[1].kind,
        LightKind::Square {
            center: v(0.0, 0.0, 5.0),
            dx: DVec3::X,
            dy: DVec3::Y
        }
    );
    assert_eq!(s.lights()[1].color, v(2.0, 1.0, 0.5));
    assert_eq!(
        s.lights()[2].kind,
        LightKind::Sphere {
            center: DVec3::ONE,
            radius: 0.5
        }
    );
    assert_eq!(s.lights()[2].color, v(1.0, 2.0, 3.0));
    // The area lights' visible surfaces, with no block index.
    assert_eq!(s.objects().len(), 2);
    assert_eq!(
        s.objects()
            .iter()
            .map(|o| (o.block(), o.light()))
            .collect::<Vec<_>>(),
        vec![(None, Some(1)), (None, Some(2))]
    );
}

#[test]
fn a_light_without_color_warns_at_its_header() {
    let d = warning_at("\nlight point\n O= 1 1 1\nend", 2, 1);
    assert!(d.message.contains("color"), "{d}");
}

#[test]
fn block_indices_count_primitive_blocks_in_file_order() {
    let s = ok("primitive sphere\n R= 1\nend
light sphere\n R= 1\n color= 1 1 1\nend
primitive plane\n N= 0 0 1\nend
camera\nend
primitive square\n Dx= 1 0 0\n Dy= 0 1 0\nend
");
    let blocks: Vec<_> = s.objects().iter().map(|o| o.block()).collect();
    assert_eq!(blocks, vec![Some(0), None, Some(1), Some(2)]);
    // The plane and the square, one after the other with the same (default)
    // material, share it; the others keep their own.
    let materials: Vec<_> = s.objects().iter().map(|o| o.material).collect();
    assert_eq!(materials, vec![0, 1, 2, 2]);
    assert_eq!(s.material_count(), 3);
    // The light's surface differs only in colour: all share one finish.
    assert_eq!(s.finish_count(), 1);
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

#[test]
fn only_equal_materials_are_shared() {
    let diff = " diff= 0.5\n";
    let s = ok(&spheres(&[
        ("1 0 0", diff),
        ("1 0 0", diff),
        ("0 1 0", diff),
        ("1 0 0", diff),
    ]));
    // A whole material is shared only with the one just before it ...
    let materials: Vec<_> = s.objects().iter().map(|o| o.material).collect();
    assert_eq!(materials, vec![0, 0, 1, 2]);
    let colors: Vec<_> = s.materials().map(|m| m.color).collect();
    assert_eq!(
        colors,
        vec![v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(1.0, 0.0, 0.0)]
    );
    // ... its keys other than the colour with every other.
    assert_eq!(s.finish_count(), 1);
    assert!(s.materials().all(|m| m.diff == 0.5));
}

#[test]
fn equal_finishes_far_apart_in_the_file_are_shared() {
    let glass = " refr= 0.9\n rindex= 1.5\n absor= 0.1 0.2 0.3\n spec= 0.25\n";
    let mut text = sphere_with("1 0 0", glass);
    for i in 0..50 {
        text += &sphere_with(&format!("0 {} 0", i as f64 / 50.0), " diff= 0.7\n");
        text += "primitive plane\n N= 0 0 1\n refl= 0.5\n drefl= 0.1\nend\n";
    }
    text += &sphere_with("0 0 1", glass);
    let s = ok(&text);
    assert_eq!(s.objects().len(), 102);
    assert_eq!(s.finish_count(), 3);
    // Every sphere and plane its own material: the colours alternate.
    assert_eq!(s.material_count(), 102);
    let first = s.material_of(&s.objects()[0]);
    let last = s.material_of(&s.objects()[101]);
    assert_eq!(
        (first.color, last.color),
        (v(1.0, 0.0, 0.0), v(0.0, 0.0, 1.0))
    );
    for m in [first, last] {
        assert_eq!((m.refr, m.rindex, m.spec), (0.9, 1.5, 0.25));
        assert_eq!(m.absor, v(0.1, 0.2, 0.3));
        assert_eq!((m.diff, m.refl, m.drefl, m.texture), (0.0, 0.0, 0.0, None));
    }
    let plane = s.material_of(&s.objects()[100]);
    assert_eq!((plane.refl, plane.drefl, plane.diff), (0.5, 0.1, 0.0));
}

#[test]
fn different_colours_with_one_finish_cost_one_finish() {
    let colors: Vec<_> = (0..300)
        .map(|i| v(i as f64 / 300.0, 1.0 - i as f64 / 300.0, 0.5))
        .collect();
    let text: String = colors
        .iter()
        .map(|c| {
            sphere_with(
                &format!("{} {} {}", c.x, c.y, c.z),
                " diff= 0.9\n spec= 0.1\n",
            )
        })
        .collect();
    let s = ok(&text);
    assert_eq!((s.material_count(), s.finish_count()), (300, 1));
    for (o, c) in s.objects().iter().zip(&colors) {
        let m = s.material_of(o);
        assert_eq!((m.color, m.diff, m.spec), (*c, 0.9, 0.1));
    }
}

#[test]
fn textured_and_untextured_materials_never_share() {
    let s = ok(&spheres(&[
        ("1 1 1", " diff= 0.5\n texture= tiny.bmp\n"),
        ("1 1 1", " diff= 0.5\n"),
        ("0 1 1", " diff= 0.5\n texture= tiny.bmp\n"),
        ("0 1 1", " diff= 0.5\n"),
    ]));
    assert_eq!(s.finish_count(), 2);
    assert_eq!(s.material_count(), 4);
    let textures: Vec<_> = s
        .objects()
        .iter()
        .map(|o| s.material_of(o).texture)
        .collect();
    assert_eq!(textures, vec![Some(0), None, Some(0), None]);
}

#[test]
fn sharing_is_bit_exact_so_minus_zero_keeps_its_sign() {
    // -0 == 0 as numbers, but 1/-0 is -inf: nothing is shared that is not
    // the same bits, so every value is the one the file gave.
    let s = ok(&spheres(&[
        ("0 0 0", " diff= 0\n"),
        ("-0 0 0", " diff= 0\n"),
        ("-0 0 0", " diff= -0\n"),
        ("-0 0 0", " diff= 0\n"),
    ]));
    let materials: Vec<_> = s.objects().iter().map(|o| o.material).collect();
    assert_eq!(materials, vec![0, 1, 2, 3]);
    assert_eq!(s.finish_count(), 2);
    let m: Vec<_> = s.materials().collect();
    assert!(m[0].color.x.is_sign_positive() && m[1].color.x.is_sign_negative());
    assert!(m[1].diff.is_sign_positive() && m[2].diff.is_sign_negative());
    assert!(m[3].diff.is_sign_positive());
}

// ---------------------------------------------------------------- lexical

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

// ---------------------------------------------------------------- errors

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
    let d = error_at("camera\n shade_quality= -1\nend", 2, 17);
    assert!(d.message.contains("negative"), "{d}");
    error_at("camera\n drefl_quality= -2\nend", 2, 17);
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

// ---------------------------------------------------------------- warnings

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

// ---------------------------------------------------------------- rendering

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

// ---------------------------------------------------------------- files

#[test]
fn textures_are_found_beside_the_scene_first_then_in_the_working_directory() {
    let s = ok("primitive sphere\n R= 1\n texture= tiny.bmp\nend");
    assert!(
        s.notes().iter().any(|n| n.contains("scene file's folder")),
        "{:?}",
        s.notes()
    );
    // Not beside the scene (the base folder does not exist): the working
    // directory, which is the project root under `cargo test`.
    let s = Scene::parse(
        "primitive sphere\n R= 1\n texture= tests/data/tiny.bmp\nend",
        "no/such/folder",
    )
    .unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(s.textures().len(), 1);
    assert!(
        s.notes().iter().any(|n| n.contains("working directory")),
        "{:?}",
        s.notes()
    );
}

#[test]
fn identical_texture_paths_are_decoded_once() {
    let s = ok("primitive sphere\n R= 1\n texture= tiny.bmp\nend
primitive sphere\n R= 2\n texture= ./tiny.bmp\nend
primitive plane\n N= 0 0 1\n texture= tiny.bmp\nend");
    assert_eq!(s.textures().len(), 1);
    assert!(s.materials().all(|m| m.texture == Some(0)));
}

#[test]
fn mesh_keys_reach_the_loader() {
    // The one triangle of `tri.obj` comes back scaled and moved.
    let text = "primitive sphere\n R= 1\nend
primitive mesh
    O= 10 20 30
    scale= 2 3 4
    rotation= 0 0 0
    file= tri.obj
end";
    let s = ok(text);
    assert_eq!(s.objects().len(), 2);
    assert_eq!(s.objects()[1].block(), Some(1));
    let Shape::Triangle(t) = &s.objects()[1].shape else {
        panic!("not a triangle") // invariant: the test's own fixed input (a failure fails the test)
    };
    let mut corners = t.vertices.map(|p| p.to_array());
    corners.sort_by(|a, b| a.partial_cmp(b).unwrap()); // invariant: the test's own fixed input (a failure fails the test)
    let want = [[10.0, 20.0, 30.0], [10.0, 23.0, 30.0], [12.0, 20.0, 30.0]];
    assert_eq!(corners, want);
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

#[test]
fn shared_scene_files_parse() {
    // Warnings expected in the files known today (keys a block does not use);
    // files added later must parse too, with whatever warnings they carry.
    let known_warnings = [
        ("scene1.txt", 0),
        ("scene2.txt", 0),
        ("scene3.txt", 0),
        ("scene_stacks.txt", 0),
        ("scene_mesh1.txt", 4), // P= left in mesh blocks
        ("scene_final.txt", 0),
    ];
    let mut seen = 0;
    for folder in ["framework", "community"] {
        for path in corpus_scenes(folder) {
            let s = match Scene::from_file(&path) {
                Ok(s) => s,
                Err(e) => panic!("{} does not parse:\n{e}", path.display()), // invariant: the test's own fixed input (a failure fails the test)
            };
            assert!(!s.objects().is_empty(), "{}", path.display());
            let name = path.file_name().unwrap().to_string_lossy(); // invariant: the test's own fixed input (a failure fails the test)
            if let Some(&(_, n)) = known_warnings.iter().find(|(k, _)| *k == name) {
                seen += 1;
                assert_eq!(
                    s.warnings().len(),
                    n,
                    "{}: {:#?}",
                    path.display(),
                    s.warnings()
                );
            }
        }
    }
    if corpus("framework").is_some() {
        assert_eq!(seen, known_warnings.len(), "a known scene file is missing");
    }
}

#[test]
fn scene1_in_detail() {
    let Some(dir) = corpus("framework") else {
        return;
    };
    let s = Scene::from_file(dir.join("scene1.txt")).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
    assert_eq!(s.background(), Background::Color(DVec3::splat(0.1)));
    assert_eq!((s.camera().width, s.camera().height), (1280, 760));
    assert_eq!((s.camera().lens_w, s.camera().lens_h), (1.0, 0.6));
    assert!(close(s.camera().dir, v(0.6, 1.0, -0.6).normalize()));
    assert_eq!(s.lights().len(), 1);
    assert_eq!(s.objects().len(), 6);
    assert_eq!(s.textures().len(), 2);
    let blocks: Vec<_> = s.objects().iter().map(|o| o.block().unwrap()).collect(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(blocks, vec![0, 1, 2, 3, 4, 5]);
    let glass = s.material_of(&s.objects()[0]);
    assert_eq!(
        (glass.refr, glass.rindex, glass.absor),
        (1.0, 1.7, DVec3::Z)
    );
    let floor = s.material_of(&s.objects()[4]);
    assert!(floor.texture.is_some());
    assert!(s.notes().iter().any(|n| n.contains("floor.bmp")));
}

#[test]
fn scene_stacks_bezier() {
    let Some(dir) = corpus("community") else {
        return;
    };
    let s = Scene::from_file(dir.join("scene_stacks.txt")).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert!(matches!(s.background(), Background::Gradient { .. }));
    let Some(Shape::Bezier(b)) = s
        .objects()
        .iter()
        .map(|o| &o.shape)
        .find(|s| matches!(s, Shape::Bezier(_)))
    else {
        panic!("no bezier"); // invariant: the test's own fixed input (a failure fails the test)
    };
    assert_eq!(b.points.len(), 4);
    let m = s.material_of(s.objects().last().unwrap()); // invariant: the test's own fixed input (a failure fails the test)
    // `refl=` appears twice; the later 0 wins.
    assert_eq!(m.refl, 0.0);
}

#[test]
fn a_large_scene_parses() {
    // About 1 MB of spheres, each with a key a sphere does not use.
    let mut text = String::from("camera\n O= 0 0 0\nend\n");
    let n = 12_000;
    for i in 0..n {
        text.push_str(&format!(
            "primitive sphere\n    O= {i} {} -3.25\n    R= 0.{}\n    color= 1 0.5 0.25\n    N= 0 0 1\nend\n",
            i * 2,
            i % 9 + 1
        ));
    }
    assert!(text.len() > 1_000_000);
    let s = ok(&text);
    assert_eq!(s.objects().len(), n);
    assert_eq!(s.objects()[n - 1].block(), Some(n as u32 - 1));
    // 200 of them are listed (the last at the 200th sphere), then a count.
    let w = s.warnings();
    assert_eq!(w.len(), 201);
    assert_eq!(w[199].line, 4 + 6 * 199 + 4);
    assert_eq!(w[200].message, format!("… and {} more", n - 200));
}

// ---------------------------------------------------------------- fuzzing

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
    assert_eq!(s.camera().shade_quality, 65, "the value is kept");
}
