//! The three families found since the lineages spec (`lineages.md`, A18 and
//! L17) read from the inside: their Bézier forms built into the framework's
//! surface with control points worked out by hand, abcbdf's triangle and
//! tetrahedron, `obj` blocks, and lazycal's reader (it stops at a word `end`
//! outside a block and keeps its last light).

use crate::Scene;
use crate::geometry::{Ray, Shape};
use crate::scene::{Dialect, Severity};
use glam::{DVec2, DVec3};
use std::path::Path;

fn ok(text: &str) -> Scene {
    Scene::parse(text, Path::new("."))
        .unwrap_or_else(|e| panic!("expected the scene to parse:\n{e}")) // invariant: the test's own fixed input (a failure fails the test)
}

fn warnings(s: &Scene) -> Vec<String> {
    s.warnings()
        .iter()
        .filter(|d| d.severity == Severity::Warning)
        .map(|d| d.message.clone())
        .collect()
}

fn errors(text: &str) -> Vec<String> {
    match Scene::parse(text, Path::new(".")) {
        Ok(_) => panic!("expected errors: {text}"), // invariant: the test's own fixed input (a failure fails the test)
        Err(e) => e.errors().map(|d| d.message.clone()).collect(),
    }
}

fn near(a: DVec2, b: DVec2) -> bool {
    (a - b).length() < 1e-12
}

/// The only bezier of `text`.
fn bezier_of(text: &str) -> (Scene, crate::geometry::Bezier) {
    let s = ok(text);
    let b = match s.objects().first().map(|o| o.shape()) {
        Some(Shape::Bezier(b)) => (**b).clone(),
        other => panic!("not a bezier: {other:?}"), // invariant: the test's own fixed input (a failure fails the test)
    };
    (s, b)
}

/// The texture coordinates where the ray from `from` along `dir` first meets `shape`.
fn uv_at(shape: &Shape, from: DVec3, dir: DVec3) -> (DVec3, DVec2) {
    let ray = Ray::new(from, dir.normalize());
    let hit = shape
        .intersect(&ray, 0.0, f64::INFINITY)
        .expect("the ray hits"); // invariant: the test's own fixed input (a failure fails the test)
    let p = shape.surface(&ray, &hit);
    (p.point, p.uv)
}

/// lazycal's form: the axis from P along unit(Dz), the pairs r h divided
/// by S, as the framework's (z, r): (0, 0.5), (2, −1), (3, 0).
#[test]
fn lazycal_control_points_are_the_frameworks_profile_over_s() {
    let (s, b) = bezier_of(
        "primitive bezier\n Dz= 0 3 4\n S= 10\n P= 1 2 3\n control_points= 3  5 0  -10 20  0 30\nend\n",
    );
    assert_eq!(s.dialect().dialect, Dialect::L17);
    assert_eq!(b.o1, DVec3::new(1.0, 2.0, 3.0));
    assert!(
        (b.o2 - DVec3::new(1.0, 2.6, 3.8)).length() < 1e-12,
        "{}",
        b.o2
    );
    let want = [(0.0, 0.5), (2.0, -1.0), (3.0, 0.0)];
    assert_eq!(b.points.len(), 3);
    for (p, (z, r)) in b.points.iter().zip(want) {
        assert!(near(*p, DVec2::new(z, r)), "{p} vs ({z}, {r})");
    }
    // Miscounts are errors at the key; more numbers than the count a warning.
    let e = errors("primitive bezier\n S= 1\n control_points= 3  1 0  1 1\nend\n");
    assert!(e[0].contains("needs 6 numbers after the count"), "{e:?}");
    let e = errors("primitive bezier\n S= 1\n control_points= 2.5  1 0  1 1\nend\n");
    assert!(e[0].contains("a whole number from 2"), "{e:?}");
    let e = errors("primitive bezier\n S= 0\n control_points= 2  1 0  1 1\nend\n");
    assert!(e[0].contains("`S=` is 0"), "{e:?}");
    let s = ok("primitive bezier\n S= 1\n control_points= 2  1 0  1 1  7\nend\n");
    assert!(
        warnings(&s)
            .iter()
            .any(|w| w.contains("the 1 after them are ignored")),
        "{:?}",
        warnings(&s)
    );
}

/// lazycal's texture coordinates: the row is θ/2π + ½ with θ measured
/// from Dx = unit(ŷ × Dz) towards Dz × Dx (here x̂ and ŷ), half a turn
/// more where the radius is negative; the column is the curve parameter.
#[test]
fn lazycal_texture_coordinates() {
    let cylinder = |r: f64| {
        format!(
            "primitive bezier\n Dz= 0 0 1\n S= 1\n P= 0 0 0\n control_points= 2  {r} 0  {r} 2\nend\n"
        )
    };
    // The point (0, 1, 1): θ = π/2, t = ½.
    let (_, b) = bezier_of(&cylinder(1.0));
    let (p, uv) = uv_at(
        &Shape::Bezier(Box::new(b)),
        DVec3::new(0.0, 5.0, 1.0),
        -DVec3::Y,
    );
    assert!((p - DVec3::new(0.0, 1.0, 1.0)).length() < 1e-9, "{p}");
    assert!(near(uv, DVec2::new(0.75, 0.5)), "{uv}");
    // With radius −1 the same point is θ = 3π/2 of lazycal's parameter: row ¼.
    let (_, b) = bezier_of(&cylinder(-1.0));
    let (_, uv) = uv_at(
        &Shape::Bezier(Box::new(b)),
        DVec3::new(0.0, 5.0, 1.0),
        -DVec3::Y,
    );
    assert!(
        near(DVec2::new(uv.x.fract(), uv.y), DVec2::new(0.25, 0.5)),
        "{uv}"
    );
}

/// abcbdf's form: radius x − center.x, height z − center.z about the
/// vertical line through the centre, y not read; the profile runs from V3
/// back to V0.
#[test]
fn abcbdf_cubic_profile_of_points() {
    let text = "obj bezier\n center= 1 2 3\n V0= 1.5 9 4\n V1= 2 9 3.5\n V2= 0.5 9 3\n V3= 1.25 9 2\nend\n";
    let (s, b) = bezier_of(text);
    assert_eq!(s.dialect().dialect, Dialect::A18);
    assert_eq!(
        (b.o1, b.o2),
        (DVec3::new(1.0, 2.0, 3.0), DVec3::new(1.0, 2.0, 4.0))
    );
    let want = [(-1.0, 0.25), (0.0, -0.5), (0.5, 1.0), (1.0, 0.5)];
    for (p, (z, r)) in b.points.iter().zip(want) {
        assert!(near(*p, DVec2::new(z, r)), "{p} vs ({z}, {r})");
    }
    // abcbdf's point at t = ½: (V0 + 3·V1 + 3·V2 + V3)/8 = (1.28125, ·, 3.1875):
    // radius 0.28125, seen from +x. Its texture row is 1 − t = ½ and its
    // column θ/2π + ¾ = ¾ (θ = 0).
    let (p, uv) = uv_at(
        &Shape::Bezier(Box::new(b)),
        DVec3::new(5.0, 2.0, 3.1875),
        -DVec3::X,
    );
    assert!(
        (p - DVec3::new(1.28125, 2.0, 3.1875)).length() < 1e-9,
        "{p}"
    );
    assert!(near(uv, DVec2::new(0.5, 0.75)), "{uv}");
    let e = errors("primitive bezier\n center= 0 0 0\n V0= 1 0 0\n V1= 1 0 1\n V3= 1 0 2\nend\n");
    assert!(e[0].contains("missing `V2=`"), "{e:?}");
}

/// `obj triangle A0= A1= A2= N=` and `obj tetra V0= … V3=` (abcbdf).
#[test]
fn abcbdf_triangle_and_tetrahedron() {
    let s = ok("obj triangle\n A0= 0 0 0\n A1= 1 0 0\n A2= 0 1 0\n N= 0 0 2\nend\n");
    match s.objects()[0].shape() {
        Shape::Triangle(t) => {
            assert_eq!(t.vertices[1], DVec3::X);
            assert_eq!(t.normals(), Some(&[DVec3::Z; 3]));
        }
        other => panic!("not a triangle: {other:?}"), // invariant: the test's own fixed input (a failure fails the test)
    }
    let s = ok("obj tetra\n V0= 0 0 0\n V1= 1 0 0\n V2= 0 1 0\n V3= 0 0 1\nend\n");
    let corners = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    assert_eq!(s.objects().len(), 4);
    for o in s.objects() {
        let Shape::Triangle(t) = o.shape() else {
            panic!("not a triangle"); // invariant: the test's own fixed input (a failure fails the test)
        };
        let [a, b, c] = t.vertices;
        let outward = (b - a).cross(c - a);
        let away = corners
            .iter()
            .find(|v| ![a, b, c].contains(v))
            .copied()
            .unwrap_or_default();
        assert!(outward.dot(a - away) > 0.0, "face {a} {b} {c}");
    }
    assert!(
        warnings(&s)
            .iter()
            .any(|w| w.contains("abcbdf's reader draws no tetrahedron")),
        "{:?}",
        warnings(&s)
    );
    let e = errors("obj tetra\n V0= 0 0 0\n V1= 1 0 0\n V2= 0 1 0\n V3= 1 1 0\nend\n");
    assert!(e[0].contains("degenerate tetrahedron"), "{e:?}");
}

/// `obj` opens a primitive; outside abcbdf's dialect it says so.
#[test]
fn obj_blocks_are_primitives() {
    let text = "obj sphere\n O= 0 5 0\n R= 1\nend\n";
    let s = ok(text);
    assert_eq!(s.objects().len(), 1);
    assert!(warnings(&s).is_empty(), "{:?}", warnings(&s));
    let forced = Scene::parse_as(text, Path::new("."), Some(Dialect::F)).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert!(
        warnings(&forced)
            .iter()
            .any(|w| w.contains("`obj` opens a primitive only in abcbdf's reader")),
        "{:?}",
        warnings(&forced)
    );
}

/// lazycal's reader stops at a word `end` outside a block, keeps its last
/// light, and its light has no surface; in other dialects such an `end`
/// is a warning and reading goes on.
#[test]
fn lazycal_reader_stops_at_end_and_keeps_the_last_light() {
    let bezier = "primitive bezier\n S= 1\n control_points= 2  1 0  1 1\nend\n";
    let text = format!(
        "light area\n O= 0 0 5\n Dx= 1 0 0\n Dy= 0 1 0\n color= 100 100 100\nend\n\
         light area\n O= 0 0 6\n Dx= 1 0 0\n Dy= 0 1 0\n color= 200 200 200\nend\n\
         {bezier}end =======\nprimitive sphere\n O= 0 5 0\n R= 1\nend\n"
    );
    let s = ok(&text);
    assert_eq!(s.dialect().dialect, Dialect::L17);
    assert_eq!(s.objects().len(), 1, "the sphere after `end` is not read");
    assert!(
        s.notes()
            .iter()
            .any(|n| n.contains("line 17: lazycal's reader stops")),
        "{:?}",
        s.notes()
    );
    assert_eq!(s.lights().len(), 1);
    assert_eq!(s.lights()[0].color, DVec3::splat(200.0));
    assert_eq!(s.light_line(0), Some(7));
    // Without lazycal's bezier the `end` is a warning and the sphere is read.
    let plain = text.replace(bezier, "");
    let s = ok(&plain);
    assert_eq!(
        s.objects().iter().filter(|o| o.light().is_none()).count(),
        1
    );
    assert!(
        warnings(&s)
            .iter()
            .any(|w| w.contains("`end` without a block")),
        "{:?}",
        warnings(&s)
    );
}
