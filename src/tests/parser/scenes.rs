//! Whole scenes: the shared scene files, two of them in detail, and a large one.

use super::{close, ok, v};
use crate::Scene;
use crate::geometry::Shape;
use crate::scene::Background;
use crate::tests::common::{corpus, corpus_scenes};
use glam::DVec3;

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
