//! The colon family (hta1996/Raytracing, `lineages.md`): which files are
//! read as its, and its pictures against its renderer's formulas worked
//! out by hand (`raytracer.cpp` `calcIllumination`, `object.h` `BRDF`,
//! `Camera::emit`).

use glam::DVec3;
use glint::{Dialect, PhotonMode, PhotonOptions, RenderOptions, Renderer, Scene};

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

/// Its progressive photon mapping: a floor lit by a point light of
/// `power:` P = 2π at height h = 1. A hit point weighs diff·k and a photon
/// diff·cos θ; each photon carries c·P/n, and the first estimate gathers
/// within r² = 0.2: the mean over that disc of E·cos θ/π r², with
/// E = P·h/(4π(h² + ρ²)^{3/2}), is P/(4π(h² + r²)) = 0.5/1.2 below the
/// light; pixel (4, 4)'s hit point is the family's ray through its integer
/// position, (∓0.0588, ±0.0588, 0), where the disc's mean is 0.41269
/// (integrated numerically). Without the cosine it would be 4 % more, with
/// 4π in place of `power:` twice as much. No ambient or
/// direct term joins it (its eye pass shades nothing else).
#[test]
fn its_photons_carry_their_lights_power_and_its_brdf() {
    let text = "background\n\tambientcolor: 0.5 0.5 0.5\nend\n\
                camera\n\teye: 0 0 3\n\tlookat: 0 0 0\n\tup: 0 1 0\n\tfovy: 20\n\th: 9\n\tw: 9\nend\n\
                light point\n\tO: 0 0 1\n\tcolor: 1 1 1\n\tpower: 6.283185307179586\nend\n\
                primitive plane\n\tN: 0 0 1\n\td: 0\n\tdiff: 1\n\tspec: 0\nend\n";
    let options = RenderOptions {
        photons: PhotonOptions {
            mode: Some(PhotonMode::Ppm),
            iterations: Some(1),
            emit: Some(2_000_000),
            ..PhotonOptions::default()
        },
        ..RenderOptions::default()
    };
    let image = Renderer::new(parse(text))
        .render(&options)
        .unwrap() // invariant: the test's own fixed input (a failure fails the test)
        .into_image();
    let got = DVec3::from_array(image.pixel(4, 4).map(f64::from));
    let want = 0.41269;
    assert!(
        (got - DVec3::splat(want)).abs().max_element() < 0.005,
        "{got} vs {want}"
    );
}
