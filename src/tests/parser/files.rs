//! The files a scene names: textures and meshes, found and loaded.

use super::ok;
use crate::Scene;
use crate::geometry::Shape;

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
