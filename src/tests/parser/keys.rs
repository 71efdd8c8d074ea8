//! Every key of every block into its field, and the defaults.

use super::{close, ok, v, warning_at};
use crate::geometry::Shape;
use crate::scene::{Background, LightKind};
use glam::{DVec2, DVec3};

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
    assert_eq!((c.shade_quality, c.drefl_quality), (2.0, 3.0));
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
    assert_eq!((c.shade_quality, c.drefl_quality), (4.0, 4.0));
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
    // The sphere, the plane and the square, with the same (default)
    // material, share it; the light's surface keeps its own.
    let materials: Vec<_> = s.objects().iter().map(|o| o.material).collect();
    assert_eq!(materials, vec![0, 1, 0, 0]);
    assert_eq!(s.material_count(), 2);
    // The light's surface differs only in colour: all share one finish.
    assert_eq!(s.finish_count(), 1);
}
