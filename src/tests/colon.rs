//! The colon family (hta1996/Raytracing, `lineages.md`) read from the
//! inside: its `key:` lines replayed in file order as its reader replays
//! them, its blocks built into the one scene model with values worked out
//! by hand, and the framework's fractional qualities.

use crate::Scene;
use crate::geometry::{Ray, Shape};
use crate::integrator::Model;
use crate::scene::{Background, Camera, Dialect, LightKind, Severity};
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

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-12
}

/// The camera: the view is set up at `w:` from what was read before it
/// (tan(fovy/2) high and that times w/h wide at distance 1, right =
/// unit(direction × up)); `lookat:` resets the focus distance to 1.
#[test]
fn the_camera_keys_replay_in_file_order() {
    let s = ok("camera\n\
                 \teye: 1 -3 2\n\
                 \tfocal: 4\n\
                 \tlookat: 1 0 2\n\
                 \tup: 0 0 1\n\
                 \tfovy: 90\n\
                 \th: 50\n\
                 \tw: 100\n\
                 \taperture: 0.05\n\
                 end\n\
                 primitive sphere\n\tO: 1 3 2\n\tR: 1\nend\n");
    assert_eq!(s.dialect().dialect, Dialect::Colon);
    let c = s.camera();
    assert_eq!(c.origin, DVec3::new(1.0, -3.0, 2.0));
    assert!(close(c.dir, DVec3::Y), "{}", c.dir);
    assert!(
        close(c.right.unwrap_or_default(), DVec3::X),
        "{:?}",
        c.right
    );
    assert!((c.lens_h - 2.0).abs() < 1e-12, "{}", c.lens_h);
    assert!((c.lens_w - 4.0).abs() < 1e-12, "{}", c.lens_w);
    assert_eq!((c.width, c.height), (100, 50));
    assert_eq!(c.dof.aperture, 0.05);
    // `focal: 4` came before `lookat:`, which set the focus to 1.
    assert_eq!(c.dof.focal_len, 1.0);
    assert_eq!(c.dof.samples, 16);
    // The picture's height read after `w:` sizes the image, not the view.
    let s = ok(
        "camera\n eye: 0 0 0\n lookat: 0 1 0\n up: 0 0 1\n fovy: 90\n h: 100\n w: 100\n h: 50\nend\n\
                primitive sphere\n O: 0 3 0\n R: 1\nend\n",
    );
    let c = s.camera();
    assert_eq!((c.width, c.height), (100, 50));
    assert!((c.lens_w - 2.0).abs() < 1e-12, "{}", c.lens_w);
    // Without `up:` there is no image plane; the error names the key as written.
    let e = errors("camera\n eye: 0 0 0\n lookat: 0 1 0\n fovy: 45\n h: 10\n w: 10\nend\n");
    assert!(e.iter().any(|m| m.contains("`up:` is missing")), "{e:?}");
    let e = errors("primitive sphere\n O: 0 0 0\nend\n");
    assert!(
        e.iter()
            .any(|m| m.contains("a `primitive sphere` block needs `R:`")),
        "{e:?}"
    );
}

/// Background, area light, plane (N·P + d = 0), cylinder and sphere, with
/// the family's material defaults.
#[test]
fn the_colon_keys_build_the_scene_model() {
    let s = ok("background\n\tambientcolor: 0.1 0.2 0.3\nend\n\
                light area\n\tO: 0 0 2\n\tN: 0 0 -2\n\tDx: 0.5 0 0\n\tDy: 0 0.25 0\n\tcolor: 1 0.5 1\n\tpower: 6\nend\n\
                primitive plane\n\tN: 0 0 2\n\td: -1\nend\n\
                primitive cylinder\n\tO: 1 2 0\n\tR: 0.5\n\tH: 2\n\tcolor: 1 0 0\n\trefl: 0.3\nend\n\
                primitive sphere\n\tO: 0 5 0\n\tR: 1\nend\n");
    assert_eq!(s.dialect().dialect, Dialect::Colon);
    assert!(
        s.dialect().reason.contains("keys written `key:`"),
        "{}",
        s.dialect().reason
    );
    assert_eq!(s.background(), Background::Color(DVec3::new(0.1, 0.2, 0.3)));
    let light = &s.lights()[0];
    assert_eq!(
        light.kind,
        LightKind::Square {
            center: DVec3::new(0.0, 0.0, 2.0),
            dx: DVec3::new(0.5, 0.0, 0.0),
            dy: DVec3::new(0.0, 0.25, 0.0),
        }
    );
    assert_eq!(light.color, DVec3::new(1.0, 0.5, 1.0));
    assert_eq!(light.emission.power, Some(6.0));
    assert_eq!(light.emission.normal, Some(DVec3::new(0.0, 0.0, -1.0)));
    let shapes: Vec<&Shape> = s.objects().iter().map(|o| o.shape()).collect();
    // The visible surface of the light comes first.
    let plane = shapes.iter().find_map(|sh| match sh {
        Shape::Plane(p) => Some(p),
        _ => None,
    });
    let plane = plane.expect("a plane"); // invariant: the test's own fixed input (a failure fails the test)
    // 2z − 1 = 0: z = 0.5.
    assert_eq!((plane.normal, plane.offset), (DVec3::Z, 0.5));
    let cylinder = shapes.iter().find_map(|sh| match sh {
        Shape::Cylinder(c) => Some(c),
        _ => None,
    });
    let cylinder = cylinder.expect("a cylinder"); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(
        (cylinder.o1, cylinder.o2, cylinder.radius),
        (DVec3::new(1.0, 2.0, 0.0), DVec3::new(1.0, 2.0, 2.0), 0.5)
    );
    let sphere = shapes.iter().find_map(|sh| match sh {
        Shape::Sphere(c) => Some(c),
        _ => None,
    });
    let sphere = sphere.expect("a sphere"); // invariant: the test's own fixed input (a failure fails the test)
    assert_eq!(
        (sphere.center, sphere.radius),
        (DVec3::new(0.0, 5.0, 0.0), 1.0)
    );
    let materials: Vec<_> = s
        .objects()
        .iter()
        .filter(|o| matches!(o.shape(), Shape::Cylinder(_) | Shape::Sphere(_)))
        .map(|o| s.material_of(o))
        .collect();
    // The cylinder's keys, then its reader's defaults for the sphere.
    assert_eq!(
        (materials[0].color, materials[0].refl, materials[0].diff),
        (DVec3::X, 0.3, 0.8)
    );
    let m = &materials[1];
    assert_eq!(
        (m.color, m.diff, m.spec, m.refl, m.refr, m.rindex),
        (DVec3::ONE, 0.8, 0.2, 0.0, 0.0, 1.0)
    );
}

/// A word holding numbers run together is read as C++'s `>>` reads it:
/// `2.5.000000` is 2.5, then .0 (its files have such typos).
#[test]
fn numbers_run_together_read_as_its_stream_reads_them() {
    let s = ok(
        "light area\n O: 0 0 2\n Dx: 1 0 0\n Dy: 0.000000 2.5.000000 0.000000\n color: 1 1 1\n N: 0 0 -1\nend\n\
                primitive sphere\n O: 0 5 0\n R: 1\nend\n",
    );
    match s.lights()[0].kind {
        LightKind::Square { dy, .. } => assert_eq!(dy, DVec3::new(0.0, 2.5, 0.0)),
        other => panic!("not an area light: {other:?}"), // invariant: the test's own fixed input (a failure fails the test)
    }
    let w = warnings(&s);
    assert!(
        w.iter()
            .any(|m| m.contains("read as 0.000000 2.5 .000000 0.000000")),
        "{w:?}"
    );
}

/// `rotationbody`: each `curve:` (x y = radius height, times the `scale:`
/// read before it) is a cubic profile about the upright axis through `O:`;
/// its texture's profile coordinate runs over the curve's share of
/// `ratio:`, its angle from `ang:` degrees about +z.
#[test]
fn a_rotationbody_is_its_scaled_curves_about_the_upright_axis() {
    let s = ok("primitive rotationbody\n\
                 \tscale: 0.5\n\
                 \tcurve: 0 0 1 0 1 2 0 2\n\
                 \tscale: 2\n\
                 \tcurve: 0 2 0.5 2 0.5 3 0 3\n\
                 \tratio: 0.25 0.75\n\
                 \tang: 90\n\
                 \tO: 1 1 0\n\
                 end\n");
    let beziers: Vec<_> = s
        .objects()
        .iter()
        .filter_map(|o| match o.shape() {
            Shape::Bezier(b) => Some((o.shape(), b)),
            _ => None,
        })
        .collect();
    assert_eq!(beziers.len(), 2);
    // glint's profile points are (height, radius).
    let want = [
        [(0.0, 0.0), (0.0, 0.5), (1.0, 0.5), (1.0, 0.0)],
        [(4.0, 0.0), (4.0, 1.0), (6.0, 1.0), (6.0, 0.0)],
    ];
    for ((_, b), points) in beziers.iter().zip(want) {
        assert_eq!(
            (b.o1, b.o2),
            (DVec3::new(1.0, 1.0, 0.0), DVec3::new(1.0, 1.0, 1.0))
        );
        let got: Vec<(f64, f64)> = b.points.iter().map(|p| (p.x, p.y)).collect();
        assert_eq!(got, points);
    }
    // At s = ½ the first curve is at height ½, radius ⅜; the second at
    // height 5, radius ¾. Both hits face +x: 270° from `ang: 90` (+y).
    for ((shape, _), (z, r, u)) in beziers
        .iter()
        .zip([(0.5, 0.375, 0.125), (5.0, 0.75, 0.625)])
    {
        let ray = Ray::new(DVec3::new(6.0, 1.0, z), -DVec3::X);
        let hit = shape.intersect(&ray, 0.0, f64::INFINITY);
        let hit = hit.expect("the ray hits the body"); // invariant: the test's own fixed input (a failure fails the test)
        let p = shape.surface(&ray, &hit);
        assert!(close(p.point, DVec3::new(1.0 + r, 1.0, z)), "{}", p.point);
        assert!((p.uv - DVec2::new(u, 0.75)).length() < 1e-9, "{}", p.uv);
    }
    // A curve before any `scale:` is scaled by 1, with a warning.
    let s = ok("primitive rotationbody\n curve: 0 0 1 0 1 1 0 1\n O: 0 0 0\nend\n");
    assert!(
        warnings(&s).iter().any(|m| m.contains("no `scale:`")),
        "{:?}",
        warnings(&s)
    );
}

/// The framework's readers hold the qualities as reals and trace
/// int(16·q) rays (`shade_quality= 0.4`: 6); the relatives round them.
#[test]
fn fractional_qualities_are_sixteenths_in_the_framework_only() {
    let cam = Camera {
        shade_quality: 0.4,
        drefl_quality: 0.1,
        ..Camera::default()
    };
    let f = Model::of(Dialect::F, &cam);
    assert_eq!((f.shadow_rays, f.glossy_samples), (6, 1));
    let w = Model::of(Dialect::W, &cam);
    assert_eq!((w.shadow_rays, w.glossy_samples), (16, 16));
    let whole = Model::of(Dialect::F, &Camera::default());
    assert_eq!((whole.shadow_rays, whole.glossy_samples), (64, 64));
    // The colon family's soft shadows are its fixed 5×5 grid.
    assert_eq!(Model::of(Dialect::Colon, &cam).shadow_rays, 25);
    let s = ok("camera\n shade_quality= 0.4\n drefl_quality= 0.1\nend\n\
                light square\n O= 0 0 3\n Dx= 1 0 0\n Dy= 0 1 0\n color= 1 1 1\nend\n\
                primitive sphere\n O= 0 5 0\n R= 1\nend\n");
    assert_eq!(s.dialect().dialect, Dialect::F);
    assert_eq!(
        (s.camera().shade_quality, s.camera().drefl_quality),
        (0.4, 0.1)
    );
    let why = &s.dialect().reason;
    assert!(
        why.contains("`shade_quality= 0.4` read as a fraction") && why.contains("6 shadow rays"),
        "{why}"
    );
    assert!(why.contains("1 glossy rays"), "{why}");
}

/// Its files name textures `../picture/….bmp` (its program runs in
/// `build/`): found in the scene's folder's `picture/` as that program
/// finds them; on a plane the texture is loaded, a sphere's is not drawn
/// (its reader draws spheres untextured), with a warning. Files written
/// with `=` keep their lookup.
#[test]
fn its_textures_are_found_as_its_program_run_below_finds_them() {
    let tmp = tempfile::Builder::new()
        .prefix("glint-colon-")
        .tempdir()
        .unwrap(); // invariant: a test's scratch folder (a failure fails the test)
    let dir = tmp.path();
    std::fs::create_dir(dir.join("picture")).unwrap(); // invariant: a test's scratch folder (a failure fails the test)
    image::RgbImage::from_pixel(2, 2, image::Rgb([255, 0, 0]))
        .save(dir.join("picture/t.bmp"))
        .unwrap(); // invariant: the test's own fixed input (a failure fails the test)
    let s = Scene::parse(
        "primitive plane\n\tN: 0 0 1\n\td: 0\n\ttexture: ../picture/t.bmp\nend\n\
         primitive sphere\n\tO: 0 0 1\n\tR: 1\n\ttexture: ../picture/t.bmp\nend\n",
        dir,
    )
    .unwrap_or_else(|e| panic!("{e}")); // invariant: the test's own fixed input (a failure fails the test)
    let textures: Vec<_> = s
        .objects()
        .iter()
        .map(|o| s.material_of(o).texture)
        .collect();
    assert_eq!(textures, [Some(0), None]);
    assert!(
        warnings(&s).iter().any(|m| m.contains("untextured")),
        "{:?}",
        warnings(&s)
    );
    let e = Scene::parse(
        "primitive plane\n N= 0 0 1\n R= 0\n texture= ../picture/t.bmp\nend\n",
        dir,
    );
    assert!(
        e.is_err(),
        "a `=` file looks only beside the scene and in the working directory"
    );
}
