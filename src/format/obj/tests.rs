//! The OBJ reader: placement (transform order, normals, winding,
//! mirroring), skipped degenerates, errors as messages at their line, and
//! the shipped meshes.

use super::load_obj;
use crate::geometry::{Aabb, Ray};
use crate::tests::common::corpus;
use crate::tests::geometry::{INF, assert_vclose, nearest, v};
use glam::DVec3;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// A fresh temporary folder for one test, removed when dropped (a failing
/// test's too).
fn temp_dir(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("glint-obj-{name}-"))
        .tempdir()
        .unwrap() // invariant: a test's scratch folder (a failure fails the test)
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    p
}

#[test]
fn obj_transform_order_normals_and_degenerates() {
    let tmp = temp_dir("obj");
    let dir = tmp.path();
    let path = write(
        dir,
        "two.obj",
        "# a quad, a smooth triangle in a second object, a degenerate one\n\
         mtllib missing.mtl\n\
         o quad\n\
         v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
         f 1 2 3 4\n\
         o smooth\n\
         v 1 2 3\nv 2 2 3\nv 1 3 3\n\
         vn 0 0 1\nvn 1 1 0\n\
         f 5//1 6//1 7//2\n\
         o flat\n\
         v 0 0 0\nv 1 1 1\nv 2 2 2\n\
         f 8 9 10\n",
    );
    let origin = v(10.0, 20.0, 30.0);
    let scale = v(2.0, 3.0, 4.0);
    // Rx(π/2) then Rz(π/2): (x, y, z) → (x, −z, y) → (z, x, y).
    let rotation = v(PI / 2.0, 0.0, PI / 2.0);
    let tris = load_obj(&path, origin, scale, rotation).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(
        tris.len(),
        3,
        "quad → 2 triangles, smooth → 1, degenerate skipped"
    );
    let place = |p: DVec3| {
        let s = p * scale;
        origin + v(s.z, s.x, s.y)
    };
    // The quad's vertices, in some triangulation, all placed.
    for t in &tris[..2] {
        for p in t.vertices {
            let found = [
                v(0.0, 0.0, 0.0),
                v(1.0, 0.0, 0.0),
                v(1.0, 1.0, 0.0),
                v(0.0, 1.0, 0.0),
            ]
            .iter()
            .any(|q| (place(*q) - p).length() < 1e-12);
            assert!(found, "vertex {p} not a placed quad vertex");
        }
        assert!(t.normals().is_none());
    }
    // (1, 2, 3) → scaled (2, 6, 12) → (12, 2, 6) + origin.
    let smooth = &tris[2];
    assert_vclose(smooth.vertices[0], v(22.0, 22.0, 36.0), 1e-12);
    let ns = smooth.normals().expect("vertex normals kept"); // invariant: the test's own fixed input (a failure fails the test)
    // (0,0,1): S⁻¹ keeps it, then → (1, 0, 0).
    assert_vclose(ns[0], DVec3::X, 1e-12);
    // (1,1,0): S⁻¹ → (1/2, 1/3, 0), normalised, then (x, y, z) → (z, x, y).
    let m = v(0.5, 1.0 / 3.0, 0.0).normalize();
    assert_vclose(ns[2], v(m.z, m.x, m.y), 1e-12);
    // Its winding normal was (0,0,1) too: after the transform it still agrees with the vertex normals.
    let r = Ray::new(smooth.vertices[0] + v(5.0, 0.2, 0.2), -DVec3::X);
    let hit = smooth.intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let s = smooth.surface(&r, &hit);
    assert!(s.normal.dot(ns[0]) > 0.99);
}

#[test]
fn obj_winding_follows_normals_and_mirroring_keeps_outside() {
    let tmp = temp_dir("wind");
    let dir = tmp.path();
    // Winding says +z, the vertex normals say −z: the normals win.
    let path = write(
        dir,
        "w.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -1\nf 1//1 2//1 3//1\n",
    );
    let tris = load_obj(&path, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let r = Ray::new(v(0.2, 0.2, 1.0), -DVec3::Z);
    let h = tris[0].intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let s = tris[0].surface(&r, &h);
    assert_vclose(s.normal, -DVec3::Z, 1e-15);
    assert_vclose(s.shading_normal, -DVec3::Z, 1e-15);
    // No normals, mirrored in x: the plane z = 0 keeps its +z outside.
    let path = write(dir, "m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let tris = load_obj(&path, DVec3::ZERO, v(-1.0, 1.0, 1.0), DVec3::ZERO).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let r = Ray::new(v(-0.2, 0.2, 1.0), -DVec3::Z);
    let h = tris[0].intersect(&r, 0.0, INF).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    assert_vclose(tris[0].surface(&r, &h).normal, DVec3::Z, 1e-15);
}

#[test]
fn obj_errors_are_messages_not_panics() {
    let tmp = temp_dir("err");
    let dir = tmp.path();
    let missing = dir.join("nope.obj");
    let e = load_obj(&missing, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
    assert!(e.contains("nope.obj"), "{e}");
    for (name, text) in [
        ("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
        ("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"),
        ("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
        ("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
        ("garbage.obj", "v 0 zero 0\nf 1 2 3\n"),
        ("empty.obj", ""),
    ] {
        let p = write(dir, name, text);
        let e = load_obj(&p, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
        assert!(e.contains(name), "{name}: {e}");
    }
    // Bad OBJ text is reported at its line, invalid UTF-8 too.
    for (text, line) in [
        ("v 0 0 0\nv 1 0 0\n# c\nv 0 zero 0\nf 1 2 3\n", "line 4:"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nvn 1 x 0", "line 5:"),
    ] {
        let p = write(dir, "line.obj", text);
        let e = load_obj(&p, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
        assert!(e.contains(line), "{text:?}: {e}");
    }
    let p = dir.join("utf8.obj");
    std::fs::write(&p, b"v 0 0 0\nv 1 0 0\n\nv 0 1 0 \xff\n").unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let e = load_obj(&p, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
    assert!(e.contains("line 4:"), "{e}");
    let p = dir.join("nul.obj");
    std::fs::write(&p, vec![0u8; (1 << 20) + 10]).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let e = load_obj(&p, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
    assert!(e.contains("line 1 is longer than 1 MiB"), "{e}");
    let e = load_obj(dir, DVec3::ZERO, DVec3::ONE, DVec3::ZERO).unwrap_err();
    assert!(e.contains("is a directory"), "{e}");
    // A flattening scale: every triangle degenerate → an error, no NaN triangles.
    let p = write(dir, "ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    assert!(load_obj(&p, DVec3::ZERO, v(1.0, 1.0, 0.0), DVec3::ZERO).is_ok());
    assert!(load_obj(&p, DVec3::ZERO, v(1.0, 0.0, 1.0), DVec3::ZERO).is_err());
}

#[test]
fn shipped_meshes_load() {
    let Some(meshes) = corpus("meshes") else {
        return;
    };
    let path = &meshes.join("stanford-bunny.obj");
    let start = std::time::Instant::now();
    // The transform of community/scene_final.txt.
    let tris = load_obj(
        path,
        v(74.0, -138.0, -8.0),
        DVec3::splat(240.0),
        v(1.6, 0.0, -1.0),
    )
    .unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    eprintln!("bunny: {} triangles in {:?}", tris.len(), start.elapsed());
    assert!(
        tris.len() > 69_000 && tris.len() <= 69_451,
        "{} triangles",
        tris.len()
    );
    assert!(
        tris.iter()
            .all(|t| t.double_area() > 0.0 && t.vertices.iter().all(|p| p.is_finite()))
    );
    let b = tris.iter().fold(Aabb::EMPTY, |b, t| b.union(&t.bounds()));
    // The bunny is about 0.15 units across, so about 36 once scaled.
    let size = b.max - b.min;
    assert!(
        size.max_element() > 20.0 && size.max_element() < 60.0,
        "{size}"
    );
    // Rotated about x by 1.6 rad: the model's up (y) is now about +z, so the
    // box is taller in z than the model is deep.
    let r = Ray::new(v(b.center().x, b.center().y, b.max.z + 10.0), -DVec3::Z);
    let hit = nearest(&tris, &r, |t, r, a, b| t.intersect(r, a, b));
    assert!(
        hit.is_some(),
        "a ray down through the bunny's middle hits it"
    );
    for lucy in ["lucy3_tris_normalized.obj", "lucy3_tris_smooth.obj"] {
        let path = meshes.join(lucy);
        let tris = load_obj(&path, DVec3::ZERO, DVec3::splat(3.0), DVec3::ZERO).unwrap(); // invariant: the test's own fixed input (a failure fails the test)
        assert!(
            tris.len() > 33_000 && tris.len() <= 33_446,
            "{lucy}: {} triangles",
            tris.len()
        );
    }
}
