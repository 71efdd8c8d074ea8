//! The lineages' own primitives from the inside: normal-map normals against
//! values worked out by hand (V's frames with the spec's fixes), what the
//! blocks build (a polyhedron's MTL materials per face, V's `Bezier`
//! profile on the `bezier` surface, the rectangle), the errors naming the
//! missing files, and the blocks skipped with a warning.

use super::warnings;
use crate::Scene;
use crate::geometry::{Hit, Ray, Shape, Sphere, SurfacePoint, Triangle};
use crate::scene::{Diagnostic, SceneError};
use glam::{DVec2, DVec3};
use std::path::Path;

/// A fresh temporary folder, removed when dropped (a failing test's too).
fn temp_dir(what: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("glint-lin-{what}-"))
        .tempdir()
        .unwrap() // invariant: a test's scratch folder (a failure fails the test)
}

fn parse_in(dir: &Path, text: &str) -> Result<Scene, SceneError> {
    Scene::parse(text, dir)
}

fn ok_in(dir: &Path, text: &str) -> Scene {
    parse_in(dir, text).unwrap_or_else(|e| panic!("expected the scene to parse:\n{e}")) // invariant: the test's own fixed input (a failure fails the test)
}

fn errors_in(dir: &Path, text: &str) -> Vec<Diagnostic> {
    match parse_in(dir, text) {
        Ok(s) => panic!("expected errors, got a scene with {:?}", s.warnings()), // invariant: the test's own fixed input (a failure fails the test)
        Err(e) => e.errors().cloned().collect(),
    }
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-12
}

/// The surface point where a ray from `from` towards `to` first meets `shape`.
fn surface_towards(shape: &Shape, from: DVec3, to: DVec3) -> SurfacePoint {
    let ray = Ray::new(from, (to - from).normalize());
    let hit: Hit = shape
        .intersect(&ray, 0.0, f64::INFINITY)
        .expect("the ray hits"); // invariant: the test's own fixed input (a failure fails the test)
    shape.surface(&ray, &hit)
}

/// Texels that pick one channel each: n = (1, 0, 0), (0, 1, 0), and a mix.
const RED: DVec3 = DVec3::new(1.0, 0.5, 0.5);
const GREEN: DVec3 = DVec3::new(0.5, 1.0, 0.5);
const MIX: DVec3 = DVec3::new(0.75, 0.5, 1.0);

/// V's `NomalBall` frame, by hand, at C − O = 2·(0.6, 0, 0.8) on a sphere
/// centred at (1, 2, 3): I = (0.6, 0, 0.8); h = unit(q_y, −q_x, 0) =
/// (0, −1, 0); b = unit(I × h) = (0.8, 0, −0.6). So a pure red texel gives
/// b, pure green h, and (0.75, 0.5, 1) — n = (0.5, 0, 1) — unit(I + b/2) =
/// unit(1, 0, 0.5). V's own frame, from the world point C = (2.2, 2, 4.6),
/// would give h = unit(2, −2.2, 0) instead (spec §7.9).
#[test]
fn nomal_ball_normals_match_hand_values() {
    let o = DVec3::new(1.0, 2.0, 3.0);
    let shape = Shape::Sphere(Sphere::new(o, 2.0));
    let dir = DVec3::new(0.6, 0.0, 0.8);
    let s = surface_towards(&shape, o + dir * 5.0, o);
    assert!(close(s.point, o + dir * 2.0));
    assert!(close(
        shape.mapped_normal(&s, RED),
        DVec3::new(0.8, 0.0, -0.6)
    ));
    assert!(close(
        shape.mapped_normal(&s, GREEN),
        DVec3::new(0.0, -1.0, 0.0)
    ));
    let mix = DVec3::new(1.0, 0.0, 0.5).normalize();
    assert!(close(shape.mapped_normal(&s, MIX), mix));
    // A flat texel (½, ½, 1) keeps the sphere's normal.
    let flat = shape.mapped_normal(&s, DVec3::new(0.5, 0.5, 1.0));
    assert!(close(flat, dir));
}

/// V's `NomalPlane` frame, by hand: N = ẑ: h = x̂ (N has no x, y), so red
/// x̂, green ẑ × x̂ = ŷ. N = x̂ (vertical): h = (1, 0, 0) = N has no part
/// perpendicular to N, so red unit(N × ẑ) = −ŷ, green N × (−ŷ) = −ẑ (V's
/// N × h is 0 there). N = (1, 0, 1)/√2: h = (1/√2, 0, 0), its part
/// perpendicular to N is (1, 0, −1)/(2√2), so red (1, 0, −1)/√2, green
/// N × red = ŷ.
#[test]
fn nomal_plane_normals_match_hand_values() {
    let r2 = std::f64::consts::FRAC_1_SQRT_2;
    let cases = [
        (DVec3::Z, DVec3::X, DVec3::Y),
        (DVec3::X, -DVec3::Y, -DVec3::Z),
        (DVec3::new(r2, 0.0, r2), DVec3::new(r2, 0.0, -r2), DVec3::Y),
    ];
    for (n, red, green) in cases {
        let text = format!("primitive plane\n N= {} {} {}\n R= 1\nend\n", n.x, n.y, n.z);
        let scene = Scene::parse(&text, ".").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        let shape = scene.objects()[0].shape();
        let s = surface_towards(shape, n * 5.0 + DVec3::new(0.1, 0.2, 0.3), n * 0.0);
        assert!(close(shape.mapped_normal(&s, RED), red), "{n}: red");
        assert!(close(shape.mapped_normal(&s, GREEN), green), "{n}: green");
        let mix = (n + red * 0.5).normalize();
        assert!(close(shape.mapped_normal(&s, MIX), mix), "{n}: mix");
    }
}

/// The generic frame of a triangle: texture column (uv.y) growing along x
/// and row (uv.x) along y on the triangle (0,0,0), (2,0,0), (0,3,0): red is
/// x̂ (across the picture), green ŷ (up the picture), blue the normal ẑ.
#[test]
fn triangle_normal_map_frame_follows_its_texture_coordinates() {
    let t = Triangle::new(
        DVec3::ZERO,
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.0, 3.0, 0.0),
        None,
    )
    .with_uvs([DVec2::ZERO, DVec2::new(0.0, 1.0), DVec2::new(1.0, 0.0)]);
    let shape = Shape::Triangle(Box::new(t));
    let s = surface_towards(&shape, DVec3::new(0.5, 0.5, 4.0), DVec3::new(0.5, 0.5, 0.0));
    assert!(
        (s.uv - DVec2::new(0.5 / 3.0, 0.25)).length() < 1e-12,
        "{}",
        s.uv
    );
    assert!(close(shape.mapped_normal(&s, RED), DVec3::X));
    assert!(close(shape.mapped_normal(&s, GREEN), DVec3::Y));
    // The same triangle wound the other way keeps the texture's frame.
    let t = Triangle::new(
        DVec3::ZERO,
        DVec3::new(0.0, 3.0, 0.0),
        DVec3::new(2.0, 0.0, 0.0),
        None,
    )
    .with_uvs([DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0)]);
    let shape = Shape::Triangle(Box::new(t));
    let s = surface_towards(&shape, DVec3::new(0.5, 0.5, 4.0), DVec3::new(0.5, 0.5, 0.0));
    assert!(close(shape.mapped_normal(&s, RED), DVec3::X));
    assert!(close(shape.mapped_normal(&s, GREEN), DVec3::Y));
    assert!(close(
        shape.mapped_normal(&s, MIX),
        (-DVec3::Z + DVec3::X * 0.5).normalize()
    ));
}

/// Writes a w×h 24-bit BMP of one colour (bytes).
fn write_bmp(path: &Path, rgb: [u8; 3]) {
    image::RgbImage::from_pixel(2, 2, image::Rgb(rgb))
        .save(path)
        .unwrap(); // invariant: the test's own fixed input (a failure fails the test)
}

/// `NT=` is a material key: it loads like `texture=`, reaches the material
/// of a `NomalBall`, `NomalPlane` or plain sphere, a missing file is an
/// error naming it at its line, and kinds without a frame warn and drop it.
#[test]
fn nt_is_a_material_key_with_file_errors_and_frames() {
    let tmp = temp_dir("nt");
    let dir = tmp.path();
    write_bmp(&dir.join("n.bmp"), [255, 128, 128]);
    let s = ok_in(
        dir,
        "primitive NomalBall\n O= 0 0 0\n R= 1\n NT= n.bmp\nend\n\
         primitive NomalPlane\n N= 0 0 1\n R= -1\n NT= n.bmp\nend\n\
         primitive sphere\n O= 3 0 0\n R= 1\n NT= n.bmp\nend\n",
    );
    assert!(warnings(&s).is_empty(), "{:?}", warnings(&s));
    assert_eq!(s.objects().len(), 3);
    for o in s.objects() {
        assert_eq!(s.material_of(o).normal_map, Some(0));
    }
    assert_eq!(s.textures().len(), 1, "one file, decoded once");
    let e = errors_in(
        dir,
        "primitive sphere\n O= 0 0 0\n R= 1\n NT= absent.bmp\nend\n",
    );
    assert_eq!(e.len(), 1);
    assert!(
        e[0].message.contains("absent.bmp") && e[0].line == 4,
        "{}",
        e[0]
    );
    // A cube has no frame: warned, drawn without the map.
    let s = ok_in(
        dir,
        "primitive cube\n O= 0 0 0\n x= 1\n y= 1\n z= 1\n NT= n.bmp\nend\n",
    );
    assert_eq!(s.objects().len(), 1);
    assert_eq!(s.material_of(&s.objects()[0]).normal_map, None);
    let w = warnings(&s);
    assert!(w.len() == 1 && w[0].contains("tangent frame"), "{w:?}");
    // Without NT=, V's kinds draw their plain shape and warn.
    let s = ok_in(
        dir,
        "primitive NomalBall\n O= 0 0 0\n R= 1\nend\nprimitive NomalPlane\n N= 0 0 1\n R= 0\nend\n",
    );
    assert!(matches!(s.objects()[0].shape(), Shape::Sphere(_)));
    assert!(matches!(s.objects()[1].shape(), Shape::Plane(_)));
    let w = warnings(&s);
    assert!(
        w.len() == 2 && w.iter().all(|m| m.contains("without `NT=`")),
        "{w:?}"
    );
}

/// V's `Bezier` is the `bezier` surface with O1 = O + 38·ratio·ẑ, O2 = O
/// and P_k = (ratio·y_k, R + ratio·x_k); V's `scene.txt` values put its rim
/// at z = −0.746 with radius 0.2495. Missing `R=` or `ratio=`: an error.
#[test]
fn v_bezier_maps_onto_the_bezier_surface() {
    let s = ok_in(
        Path::new("."),
        "primitive Bezier\n O= 0 5.2 -2.0\n R= 0.2\n ratio= 0.033\nend\n",
    );
    let Shape::Bezier(b) = s.objects()[0].shape() else {
        panic!("not a bezier"); // invariant: the test's own fixed input (a failure fails the test)
    };
    assert!(
        (b.o1 - DVec3::new(0.0, 5.2, -0.746)).length() < 1e-12,
        "{}",
        b.o1
    );
    assert_eq!(b.o2, DVec3::new(0.0, 5.2, -2.0));
    assert_eq!(b.points.len(), 7);
    assert!(b.points[0].x.abs() < 1e-15 && (b.points[0].y - 0.2495).abs() < 1e-12);
    assert!((b.points[6].x - 38.0 * 0.033).abs() < 1e-12 && (b.points[6].y - 0.2).abs() < 1e-15);
    for missing in ["R= 0.2", "ratio= 0.033"] {
        let text =
            "primitive Bezier\n O= 0 0 0\n R= 0.2\n ratio= 0.033\nend\n".replace(missing, "");
        let e = errors_in(Path::new("."), &text);
        let key = missing.split('=').next().unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        assert!(
            e.len() == 1 && e[0].message.contains(&format!("`{key}=`")),
            "{e:?}"
        );
    }
}

/// A rectangle block builds the lineages' rectangle; N, Dx, Dy in one
/// plane (an unbounded strip) is an error at `Dy=`.
#[test]
fn rectangle_blocks() {
    let s = ok_in(
        Path::new("."),
        "primitive rectangle\n N= 0 0 2\n R= 1\n Dx= 3 0 0\n Dy= 0 2 0\nend\n",
    );
    let Shape::Rectangle(r) = s.objects()[0].shape() else {
        panic!("not a rectangle"); // invariant: the test's own fixed input (a failure fails the test)
    };
    let b = r.bounds();
    assert!((b.min - DVec3::new(0.0, 0.0, 1.0)).length() < 1e-9, "{b:?}");
    assert!((b.max - DVec3::new(3.0, 2.0, 1.0)).length() < 1e-9, "{b:?}");
    let e = errors_in(
        Path::new("."),
        "primitive rectangle\n N= 0 0 1\n R= 1\n Dx= 1 0 0\n Dy= 1 0 1\nend\n",
    );
    assert!(e.len() == 1 && e[0].line == 5, "{e:?}");
}

/// The blocks no lineage reads build nothing and warn, never an error.
#[test]
fn blocks_no_lineage_reads_are_skipped_with_a_warning() {
    let s = ok_in(
        Path::new("."),
        "primitive bezier\n N= 3\n M= 3\n newPoint= 0 0 0\n newPoint= 1 0 0\nend\n\
         primitive torus\n O= 0 0 0\n R_major= 2\n R_minor= 0.5\nend\n\
         primitive cylinder\n O= 0 0 0\n N= 0 0 1\n R= 1\n H= 2\nend\n\
         primitive cube\n O= 0 0 0\n size= 1\nend\n\
         primitive sphere\n O= 0 0 0\n R= 1\nend\n",
    );
    assert_eq!(s.objects().len(), 1);
    let w = warnings(&s);
    assert_eq!(w.len(), 4, "{w:?}");
    assert!(
        w.iter().all(|m| m.contains("no lineage reads this")),
        "{w:?}"
    );
}

/// An OBJ with two materials and faces before any `usemtl`.
const OBJ: &str = "mtllib m.mtl\n\
v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
f 1 2 3\n\
usemtl red\nf 1 3 4\n\
usemtl glass\nf 2 3 4\n\
usemtl nosuch\nf 1 2 4\n";

const MTL: &str = "newmtl red\nKd 0.5 0.25 0\nKs 0.35 0.35 0.35\n\
newmtl glass\nKd 0.8 0.8 0.8\nTf 0.5 0.75 1\nNi 1.5\nmap_bump bump.bmp\n";

/// `usemtl` replaces the block's material as PM3 reads MTL: Kd 0.5 0.25 0
/// gives diff 0.5, colour (1, 0.5, 0), `Ks` refl 0.35; a `Tf` of mean 0.75
/// makes glass (refr 1, absor Tf, rindex Ni, no diff or refl); faces before
/// any `usemtl`, and after an unknown one (warned), keep the block's.
#[test]
fn polyhedron_faces_take_their_mtl_materials() {
    let tmp = temp_dir("mtl");
    let dir = tmp.path();
    std::fs::write(dir.join("m.obj"), OBJ).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    std::fs::write(dir.join("m.mtl"), MTL).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let s = ok_in(
        dir,
        "primitive polyhedron\n mesh= m.obj\n color= 0 1 0\n diff= 0.9\nend\n",
    );
    let m: Vec<_> = s.objects().iter().map(|o| s.material_of(o)).collect();
    assert_eq!(m.len(), 4);
    assert_eq!((m[0].color, m[0].diff), (DVec3::Y, 0.9));
    assert_eq!(
        (m[1].color, m[1].diff, m[1].refl),
        (DVec3::new(1.0, 0.5, 0.0), 0.5, 0.35)
    );
    assert_eq!((m[2].refr, m[2].diff, m[2].refl), (1.0, 0.0, 0.0));
    assert_eq!((m[2].absor, m[2].rindex), (DVec3::new(0.5, 0.75, 1.0), 1.5));
    assert_eq!((m[3].color, m[3].diff), (DVec3::Y, 0.9));
    let w = warnings(&s);
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w.iter()
            .any(|m| m.contains("usemtl nosuch") && m.contains("line 11")),
        "{w:?}"
    );
    assert!(
        w.iter()
            .any(|m| m.contains("bump.bmp") && m.contains("not rendered")),
        "{w:?}"
    );
}

/// A missing mesh, MTL file or `map_Kd` texture is an error at the
/// `mesh=` line naming the file (and, for the MTL file, the OBJ line that
/// names it); a bad MTL value names its line.
#[test]
fn polyhedron_missing_files_are_errors_naming_them() {
    let tmp = temp_dir("missing");
    let dir = tmp.path();
    let block = "primitive polyhedron\n O= 0 0 0\n mesh= m.obj\nend\n";
    let e = errors_in(dir, block);
    assert!(
        e.len() == 1 && e[0].line == 3 && e[0].message.contains("m.obj"),
        "{e:?}"
    );
    std::fs::write(dir.join("m.obj"), OBJ).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let e = errors_in(dir, block);
    assert!(e.len() == 1 && e[0].line == 3, "{e:?}");
    assert!(
        e[0].message.contains("m.mtl") && e[0].message.contains("line 1"),
        "{}",
        e[0]
    );
    std::fs::write(dir.join("m.mtl"), "newmtl red\nmap_Kd absent.bmp\n").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let e = errors_in(dir, block);
    assert!(
        e.len() == 1 && e[0].line == 3 && e[0].message.contains("absent.bmp"),
        "{e:?}"
    );
    std::fs::write(dir.join("m.mtl"), "newmtl red\nKs\n").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let e = errors_in(dir, block);
    assert!(e.len() == 1 && e[0].message.contains("line 2"), "{e:?}");
}

#[test]
fn meshes_with_comments_in_a_local_encoding_load() {
    // PM3's dragon2.obj has a GBK comment on its second line.
    let tmp = temp_dir("gbk");
    let dir = tmp.path();
    let mut obj =
        b"# exporter\r\n# \xb4\xb4\xbd\xa8: 21.06\r\nv 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n"
            .to_vec();
    std::fs::write(dir.join("g.obj"), &obj).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let s = ok_in(dir, "primitive polyhedron\n mesh= g.obj\nend\n");
    assert_eq!(s.objects().len(), 1);
    // A bad byte outside a comment is still an error at its line.
    obj.extend_from_slice(b"f 1 2 \xb4\r\n");
    std::fs::write(dir.join("g.obj"), &obj).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let e = errors_in(dir, "primitive polyhedron\n mesh= g.obj\nend\n");
    assert!(e[0].message.contains("line 7"), "{}", e[0]);
}
