//! The colon family (hta1996/Raytracing, `lineages.md`): which files are
//! read as its, and its pictures against its renderer's formulas worked
//! out by hand (`raytracer.cpp` `calcIllumination`, `object.h` `BRDF`,
//! `Camera::emit`).

use glam::DVec3;
use glint::{Dialect, RenderOptions, Renderer, Scene};

fn parse(text: &str) -> Scene {
    Scene::parse(text, ".").unwrap_or_else(|e| panic!("{e}")) // invariant: the test's own fixed input (a failure fails the test)
}

#[test]
fn keys_written_with_colons_are_the_colon_familys() {
    let s = parse(
        "background\n\tambientcolor: 0.1 0.1 0.1\nend\nprimitive sphere\n\tO: 0 5 0\n\tR: 1\nend\n",
    );
    assert_eq!(s.dialect().dialect, Dialect::Colon);
    assert_eq!(
        s.dialect().reason,
        "keys written `key:` (hta1996/Raytracing's reader) at line 2"
    );
    // Its `light area` (Z14's marker when written `key=`) stays its.
    let s =
        parse("light area\n O: 0 0 2\n N: 0 0 -1\n Dx: 1 0 0\n Dy: 0 1 0\n color: 1 1 1\nend\n");
    assert_eq!(s.dialect().dialect, Dialect::Colon);
    assert_eq!(Dialect::from_name("hta1996"), Some(Dialect::Colon));
    assert_eq!(Dialect::from_name("colon"), Some(Dialect::Colon));
    // A `key:` in a block of `key=` lines is only a warning there.
    let s = parse("primitive sphere\n O= 0 5 0\n R: 1\n R= 1\nend\n");
    assert_eq!(s.dialect().dialect, Dialect::F);
    assert!(
        s.warnings()
            .iter()
            .any(|d| d.message.contains("`R:` in a block of `key=` lines")),
        "{:?}",
        s.warnings()
    );
}

/// A 3×3 picture of a wall y = 2 facing the eye at the origin, fovy 90:
/// pixel (1, 1) is the family's ray through its integer pixel position,
/// d = N + Dw·(2/3 − 1) + Dh·(2/3 − 1) = (−⅓, 1, ⅓) (Dh points down), so
/// it meets the wall at P = 2d. A point light on P's mirror ray (at
/// P + 2|d|·R̂ = (−4/3, 0, 4/3)) gives R_I·L = 1 and L·N = 1/|d| = 3/√11:
/// colour·(ambient·diff + light·(diff·L·N + spec·1)).
#[test]
fn a_pixel_is_its_ambient_lambert_and_phong_terms() {
    let text = "background\n\tambientcolor: 0.2 0.2 0.2\nend\n\
                camera\n\teye: 0 0 0\n\tlookat: 0 1 0\n\tup: 0 0 1\n\tfovy: 90\n\th: 3\n\tw: 3\nend\n\
                light point\n\tO: -1.3333333333333333 0 1.3333333333333333\n\tcolor: 1 1 1\nend\n\
                primitive plane\n\tN: 0 -1 0\n\td: 2\n\tcolor: 1 0.5 0.25\n\tdiff: 0.5\n\tspec: 0.25\nend\n";
    let scene = parse(text);
    assert_eq!(scene.dialect().dialect, Dialect::Colon);
    let image = Renderer::new(scene)
        .render(&RenderOptions::default())
        .unwrap() // invariant: the test's own fixed input (a failure fails the test)
        .into_image();
    let got = DVec3::from_array(image.pixel(1, 1).map(f64::from));
    let lambert = 3.0 / 11f64.sqrt();
    let want = DVec3::new(1.0, 0.5, 0.25) * (0.2 * 0.5 + 0.5 * lambert + 0.25);
    assert!((got - want).abs().max_element() < 1e-6, "{got} vs {want}");
}
