//! Dialects (lineages.md §3, §5): which lineage a file is read as, and each
//! lineage's colour of a diffuse hit against its formula, computed here by
//! hand from §3.2.

use glam::DVec3;
use glint::{Dialect, PhotonMode, PhotonOptions, RenderOptions, Renderer, Scene, SceneError};

/// The scene of `text` read in dialect `forced` (or by its markers).
fn parse(text: &str, forced: Option<Dialect>) -> Result<Scene, SceneError> {
    Scene::parse_as(text, ".", forced)
}

/// The dialect the rules choose for `text`, and the reason given.
fn chosen(text: &str) -> (Dialect, String) {
    match parse(text, None) {
        Ok(s) => (s.dialect().dialect, s.dialect().reason.clone()),
        Err(e) => panic!("{e}"),
    }
}

const SPHERE: &str = "primitive sphere\n O= 0 5 0\n R= 1\n color= 1 1 1\n diff= 1\nend\n";

#[test]
fn each_rule_of_section_5_decides_in_order() {
    // Rule 2: an `object` header, or a camera `Dx=`.
    let (d, why) = chosen("object sphere\n O= 0 5 0\n R= 1\nend\n");
    assert_eq!(
        (d, why.as_str()),
        (Dialect::W, "an `object` block at line 1")
    );
    let (d, why) = chosen(&format!("camera\n Dx= 1 0 0\nend\n{SPHERE}"));
    assert_eq!((d, why.as_str()), (Dialect::W, "camera `Dx=` at line 1"));
    // ... before rule 4's NomalBall.
    let (d, _) = chosen("object NomalBall\n O= 0 5 0\n R= 1\nend\n");
    assert_eq!(d, Dialect::W);
    // Rule 4: V's primitives and keys.
    let (d, why) = chosen(&format!(
        "{SPHERE}primitive NomalBall\n O= 0 5 0\n R= 1\nend\n"
    ));
    assert_eq!(
        (d, why.as_str()),
        (Dialect::V, "primitive NomalBall at line 7")
    );
    let (d, why) = chosen("primitive sphere\n O= 0 5 0\n R= 1\n ratio= 2\nend\n");
    assert_eq!((d, why.as_str()), (Dialect::V, "key `ratio=` at line 1"));
    // Rule 6: `light area` or `primitive rectangle` without a framework marker.
    let (d, why) = chosen(&format!(
        "light area\n O= 0 0 5\n Dx= 1 0 0\n Dy= 0 1 0\n color= 1 1 1\nend\n{SPHERE}"
    ));
    assert_eq!((d, why.as_str()), (Dialect::Z14, "light area at line 1"));
    let rect = "primitive rectangle\n N= 0 0 1\n R= 0\n Dx= 1 0 0\n Dy= 0 1 0\nend\n";
    assert_eq!(chosen(rect).0, Dialect::Z14);
    // Z17's tensor-product bezier is no framework marker.
    let z17 = format!("{rect}primitive bezier\n N= 3\n M= 3\n newPoint= 0 0 0\nend\n");
    assert_eq!(chosen(&z17).0, Dialect::Z14);
    // Rule 7: with a framework marker, the framework reads `light area` as a square light.
    let (d, why) = chosen(&format!(
        "{rect}primitive square\n O= 0 5 0\n Dx= 1 0 0\n Dy= 0 0 1\nend\n"
    ));
    assert_eq!(
        (d, why.as_str()),
        (Dialect::F, "primitive square at line 7")
    );
    let (d, why) = chosen(&format!("background\n top= 1 1 1\nend\n{rect}"));
    assert_eq!(
        (d, why.as_str()),
        (Dialect::F, "background `top=`/`bottom=` at line 1")
    );
    // Nothing telling: the framework, with a hint when the lights are bright.
    let plain = format!("light point\n O= 0 0 5\n color= 1 1 1\nend\n{SPHERE}");
    assert_eq!(chosen(&plain).0, Dialect::F);
    let hinted = |s: &Scene| {
        s.warnings()
            .iter()
            .any(|w| w.message.contains("--dialect z14"))
    };
    assert!(!hinted(&parse(&plain, None).unwrap()));
    let bright = plain.replace(
        "color= 1 1 1\nend\nprimitive",
        "color= 8 8 8\nend\nprimitive",
    );
    assert!(hinted(&parse(&bright, None).unwrap()));
}

#[test]
fn resting_spheres_decide_the_plane_sign_and_a_tie_is_v() {
    let camera = "camera\n algorithm= PM\nend\n";
    // A sphere of radius 1 at z = 1 rests on z = 0 either way; one at z = 3
    // rests on the plane N = z, R = 2 only as N·P = R (V) and on R = −2
    // only as N·P + R = 0 (PM3).
    let pm3 = format!(
        "{camera}primitive plane\n N= 0 0 1\n R= -2\nend\nprimitive sphere\n O= 0 0 3\n R= 1\nend\n"
    );
    let (d, why) = chosen(&pm3);
    assert_eq!(d, Dialect::Pm3, "{why}");
    assert!(
        why.contains("1 as N·P + R = 0 (pm3), 0 as N·P = R (v)"),
        "{why}"
    );
    assert_eq!(chosen(&pm3.replace("R= -2", "R= 2")).0, Dialect::V);
    let (d, why) = chosen(&format!("{camera}{SPHERE}"));
    assert_eq!(d, Dialect::V);
    assert!(why.ends_with("plane sign undecided"), "{why}");
    // Within 1 % of the radius, not beyond.
    assert_eq!(
        chosen(&pm3.replace("O= 0 0 3", "O= 0 0 3.009")).0,
        Dialect::Pm3
    );
    assert_eq!(
        chosen(&pm3.replace("O= 0 0 3", "O= 0 0 3.02")).0,
        Dialect::V
    );
}

#[test]
fn dialect_flag_wins_and_says_what_the_file_reads_as() {
    let text =
        format!("light area\n O= 0 0 5\n Dx= 1 0 0\n Dy= 0 1 0\n color= 1 1 1\nend\n{SPHERE}");
    let s = parse(&text, Some(Dialect::Pm3)).unwrap();
    assert_eq!(s.dialect().dialect, Dialect::Pm3);
    assert_eq!(s.dialect().reason, "chosen by --dialect");
    assert!(
        s.warnings().iter().any(|w| w
            .message
            .contains("read as dialect z14: light area at line 1")),
        "{:#?}",
        s.warnings()
    );
    // The same dialect as the rules': no warning.
    assert!(
        parse(&text, Some(Dialect::Z14))
            .unwrap()
            .warnings()
            .is_empty()
    );
    assert_eq!(Dialect::from_name("raytrace"), Some(Dialect::W));
    assert_eq!(Dialect::from_name("PM3"), Some(Dialect::Pm3));
    assert_eq!(Dialect::from_name("q"), None);
}

/// The colour of pixel (x, y) of `text` rendered with one ray per pixel in
/// `dialect`, photons off: the ray-traced formulas of lineages.md §3.2.
fn pixel(text: &str, dialect: Dialect, (x, y): (u32, u32)) -> DVec3 {
    let scene = parse(text, Some(dialect)).unwrap();
    let options = RenderOptions {
        spp: Some(1),
        photons: PhotonOptions {
            mode: Some(PhotonMode::Off),
            ..PhotonOptions::default()
        },
        ..RenderOptions::default()
    };
    let image = Renderer::new(scene).render(&options).unwrap().into_image();
    DVec3::from_array(image.pixel(x, y).map(f64::from))
}

/// A wall facing the camera (the plane y = 5 in every dialect but PM3,
/// whose `R=` has the other sign) under one point light, with diffuse and
/// specular parts and an ambient background.
fn wall(r: f64) -> String {
    format!(
        "background\n color= 0.2 0.1 0.3\nend\n\
         camera\n O= 0 0 0\n N= 0 1 0\n image_W= 21\n image_H= 21\nend\n\
         light point\n O= 1 0 4\n color= 2 1.5 1\nend\n\
         primitive plane\n N= 0 -1 0\n R= {r}\n color= 0.5 0.8 1\n diff= 0.7\n spec= 0.3\nend\n"
    )
}

const K: DVec3 = DVec3::new(0.5, 0.8, 1.0);
const C: DVec3 = DVec3::new(2.0, 1.5, 1.0);
const BG: DVec3 = DVec3::new(0.2, 0.1, 0.3);
const LIGHT: DVec3 = DVec3::new(1.0, 0.0, 4.0);

#[test]
fn a_diffuse_hit_follows_each_lineages_formula() {
    // The centre pixel sees P = (0, 5, 0), N = −ŷ facing the ray, I = ŷ.
    let p = DVec3::new(0.0, 5.0, 0.0);
    let n = -DVec3::Y;
    let to = LIGHT - p;
    let (l, d2) = (to.normalize(), to.length_squared());
    let ln = l.dot(n);
    let r_i = DVec3::Y - 2.0 * DVec3::Y.dot(n) * n;
    let (diff, spec) = (0.7, 0.3);
    let near = |got: DVec3, want: DVec3, what: &str| {
        assert!(
            (got - want).abs().max_element() < 1e-6,
            "{what}: {got} vs {want}"
        );
        assert!(want.max_element() < 1.0, "{what}: the test must not clamp");
    };
    // F: k·c·(diff·L·N + spec·(L·N)^20), no ambient.
    let f = K * C * (diff * ln + spec * ln.powi(20));
    near(pixel(&wall(-5.0), Dialect::F, (10, 10)), f, "f");
    // Z14: diff·k·(bg + c·max(0, N·L)/d²), no specular.
    let z14 = diff * K * (BG + C * ln / d2);
    near(pixel(&wall(-5.0), Dialect::Z14, (10, 10)), z14, "z14");
    // PM3 and V: k·diff·bg + k·c·(diff·N·L + spec·(R_I·L)^50)/d²; PM3's plane is N·P + R = 0.
    let pm3 = K * diff * BG + K * C * (diff * ln + spec * r_i.dot(l).max(0.0).powi(50)) / d2;
    near(pixel(&wall(5.0), Dialect::Pm3, (10, 10)), pm3, "pm3");
    near(pixel(&wall(-5.0), Dialect::V, (10, 10)), pm3, "v");
    // The same file read by PM3's sign puts the wall behind the camera: the
    // ray meets nothing, black in PM3 (the background is only its ambient term).
    assert_eq!(
        pixel(&wall(-5.0), Dialect::Pm3, (10, 10)),
        DVec3::ZERO,
        "pm3 sign"
    );
    // W: its camera is aimed at pixel (0, 0), whose centre ray is
    // N + Dy·(2·½/H) + Dx·(2·½/W), Dx = unit(N × ẑ) = x̂ (no `Dx=`),
    // Dy = Dx × N = ẑ, both times lens/2 = 0.44.
    let dir = DVec3::new(0.44 / 21.0, 1.0, 0.44 / 21.0);
    let p = dir * (5.0 / dir.y);
    let l = (LIGHT - p).normalize();
    let ln = l.dot(n);
    let w = K * diff * BG + K * C * (diff * ln + spec * ln.powi(20));
    near(pixel(&wall(-5.0), Dialect::W, (0, 0)), w, "w");
}

#[test]
fn lineages_clamp_only_the_camera_ray() {
    // Two facing mirrors (x = ±1) and a bright wall behind the camera, seen
    // through a reflection: the framework clamps the wall at 1 before the
    // mirror's 0.5 weight, PM3 after it.
    let text = |r: f64| {
        format!(
            "camera\n O= 0 0 0\n N= 0 1 0\n image_W= 21\n image_H= 21\nend\n\
             light point\n O= 0 -2 0\n color= 10 10 10\nend\n\
             primitive plane\n N= 0 -1 0\n R= {r}\n color= 1 1 1\n refl= 0.5\nend\n\
             primitive plane\n N= 0 1 0\n R= {}\n color= 1 1 1\n diff= 1\nend\n",
            -r
        )
    };
    // The wall y = −3 (F: N·P = R with N = ŷ, R = −3), lit head-on from 1 away.
    let f = pixel(
        &text(-3.0).replace("R= 3\n", "R= -3\n"),
        Dialect::F,
        (10, 10),
    );
    assert!((f - DVec3::splat(0.5)).abs().max_element() < 1e-6, "{f}");
    // V: the wall's 10·1/1² reaches the mirror unclamped, 0.5 of it is 5, clamped to 1.
    let v = pixel(
        &text(-3.0).replace("R= 3\n", "R= -3\n"),
        Dialect::V,
        (10, 10),
    );
    assert!((v - DVec3::ONE).abs().max_element() < 1e-6, "{v}");
}

#[test]
fn the_lineages_refraction_flag_differs_from_the_face_on_planes() {
    // A slab of two planes y = 2 and y = 3, both facing the camera, of index
    // 1 (rays go straight) and absorption 1, before a white background (the
    // framework) or a white wall y = 4 lit by the ambient term alone (V,
    // whose rays see no background). The framework decides inside by the
    // face: the second plane is entered again, nothing absorbed. PM3's and
    // V's flag toggles at each refraction: the segment between the planes
    // ends inside, e^−1 left.
    let text = "background\n color= 1 1 1\nend\n\
                camera\n O= 0 0 0\n N= 0 1 0\n image_W= 21\n image_H= 21\nend\n\
                primitive plane\n N= 0 -1 0\n R= -2\n refr= 1\n rindex= 1\n absor= 1 1 1\nend\n\
                primitive plane\n N= 0 -1 0\n R= -3\n refr= 1\n rindex= 1\n absor= 1 1 1\nend\n";
    let walled =
        format!("{text}primitive plane\n N= 0 -1 0\n R= -4\n color= 1 1 1\n diff= 1\nend\n");
    let f = pixel(text, Dialect::F, (10, 10));
    assert!((f - DVec3::ONE).abs().max_element() < 1e-6, "{f}");
    let v = pixel(&walled, Dialect::V, (10, 10));
    let want = (-1f64).exp();
    assert!(
        (v - DVec3::splat(want)).abs().max_element() < 1e-6,
        "{v} vs {want}"
    );
}

#[test]
fn a_v_file_with_a_point_light_is_noted_as_likely_pm3s() {
    let text = format!(
        "camera\n algorithm= PM\nend\nlight point\n O= 0 0 5\n color= 1 1 1\nend\n{SPHERE}"
    );
    let s = parse(&text, None).unwrap();
    assert_eq!(s.dialect().dialect, Dialect::V);
    assert!(
        s.notes().iter().any(|n| n.contains("may be PM3's")),
        "{:?}",
        s.notes()
    );
    let s = parse(
        &text.replace("light point", "light area\n Dx= 1 0 0\n Dy= 0 1 0"),
        None,
    )
    .unwrap();
    assert!(!s.notes().iter().any(|n| n.contains("may be PM3's")));
}

#[test]
fn refraction_without_an_index_passes_in_the_framework_and_mirrors_in_the_lineages() {
    // A glass plane y = 2 without `rindex=` before a red wall y = 4 (lit
    // from y = 3), with a green wall y = −1 behind the camera (W's ambient
    // light shows it). The framework's dialect refracts with index 1
    // (straight on: red); W's index 0 takes the total-internal-reflection
    // path on entering (a mirror: green).
    let text = "background\n color= 1 1 1\nend\n\
                camera\n O= 0 0 0\n N= 0 1 0\n image_W= 21\n image_H= 21\nend\n\
                light point\n O= 0 3 0\n color= 1 1 1\nend\n\
                primitive plane\n N= 0 -1 0\n R= -2\n refr= 1\nend\n\
                primitive plane\n N= 0 -1 0\n R= -4\n color= 1 0 0\n diff= 1\nend\n\
                primitive plane\n N= 0 1 0\n R= -1\n color= 0 1 0\n diff= 1\nend\n";
    let f = pixel(text, Dialect::F, (10, 10));
    assert!(f.x > 0.0 && f.y == 0.0, "{f}");
    let w = pixel(text, Dialect::W, (10, 10));
    assert!(w.x == 0.0 && w.y > 0.0, "{w}");
}

#[test]
fn a_ray_that_meets_nothing_shows_the_background_only_in_the_framework() {
    // A camera looking at the empty sky, half the frame through a mirror
    // plane x = 1 (N·P = R in every dialect but PM3: its R= has the other
    // sign). The framework shows the background, 0.5·colour of it in the
    // mirror; the relatives' `RayTracing` returns black for a ray that
    // meets nothing (Z14, PM3, V, W `raytracer.cpp`): both black.
    let text = |r: f64| {
        format!(
            "background\n color= 0.4 0.6 0.8\nend\n\
             camera\n O= 0 0 0\n N= 0 1 0\n lens_W= 4\n image_W= 21\n image_H= 21\nend\n\
             primitive plane\n N= -1 1 0\n R= {r}\n color= 0.5 1 1\n refl= 1\nend\n"
        )
    };
    let sky = DVec3::new(0.4, 0.6, 0.8);
    let mirrored = sky * DVec3::new(0.5, 1.0, 1.0);
    let at = |dialect: Dialect, x: u32| {
        let r = if dialect == Dialect::Pm3 { -1.0 } else { 1.0 };
        pixel(&text(r), dialect, (x, 10))
    };
    let near = |got: DVec3, want: DVec3| (got - want).abs().max_element() < 1e-6;
    // Column 0 looks left of the mirror's line, column 20 into it (the
    // plane −x + y = √2 seen from the origin: x < −1 at y = 1 is beyond it).
    assert!(near(at(Dialect::F, 20), sky), "{}", at(Dialect::F, 20));
    assert!(near(at(Dialect::F, 0), mirrored), "{}", at(Dialect::F, 0));
    for d in [Dialect::Z14, Dialect::Pm3, Dialect::V, Dialect::W] {
        assert_eq!(at(d, 20), DVec3::ZERO, "{d:?} sky");
        assert_eq!(at(d, 0), DVec3::ZERO, "{d:?} mirror");
    }
}
