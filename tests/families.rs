//! The families found since the lineages spec (lineages.md, A18 and L17):
//! which files are read as abcbdf's (`obj` blocks, `center= V0= … V3=`
//! Béziers) and as lazycal's (`Dz= S= P= control_points=` Béziers), and
//! their pictures against their models' formulas worked out by hand.

use glam::DVec3;
use glint::{Dialect, PhotonMode, PhotonOptions, RenderOptions, Renderer, Scene};

/// The dialect the markers choose for `text`, and the reason given.
fn chosen(text: &str) -> (Dialect, String) {
    let s = Scene::parse(text, ".").unwrap_or_else(|e| panic!("{e}")); // invariant: the test's own fixed input (a failure fails the test)
    (s.dialect().dialect, s.dialect().reason.clone())
}

const LAZYCAL_BEZIER: &str =
    "primitive bezier\n Dz= 0 0 1\n S= 60\n P= 0 0 0\n control_points= 2  6 0  6 30\nend\n";
const ABCBDF_BEZIER: &str = "primitive bezier\n center= 0 6 -1.5\n V0= 0.5 6 -1\n V1= 0.2 6 -1.5\n V2= 1 6 -2\n V3= 0.2 6 -2\nend\n";

#[test]
fn each_family_is_told_by_its_markers() {
    let (d, why) = chosen("obj sphere\n O= 0 5 0\n R= 1\nend\n");
    assert_eq!(
        (d, why.as_str()),
        (Dialect::A18, "an `obj` block at line 1")
    );
    let (d, why) = chosen(&format!(
        "light area\n O= 3 3 3\n Dx= 1.5 0 0\n Dy= 0 1.5 0\n color= 1 1 1\nend\n{ABCBDF_BEZIER}"
    ));
    assert_eq!(
        (d, why.as_str()),
        (Dialect::A18, "a bezier's `center=` at line 7")
    );
    let (d, why) = chosen("primitive tetra\n V0= 0 0 0\n V1= 1 0 0\n V2= 0 1 0\n V3= 0 0 1\nend\n");
    assert_eq!(
        (d, why.as_str()),
        (Dialect::A18, "primitive tetra at line 1")
    );
    let (d, why) = chosen(LAZYCAL_BEZIER);
    assert_eq!(
        (d, why.as_str()),
        (Dialect::L17, "a bezier's `control_points=` at line 1")
    );
    // lazycal's `algorithm=` (read by nobody) does not make it PM3's or V's,
    // nor its `light area` Z14's, nor its `bezier` the framework's.
    let plate = format!(
        "camera\n algorithm= PM\nend\nlight area\n O= 0 0 3\n Dx= 1 0 0\n Dy= 0 1 0\n color= 200 200 200\nend\n\
         primitive sphere\n O= 0 5 -1.8\n R= 0.2\nend\nprimitive plane\n N= 0 0 1\n R= -2\nend\n{LAZYCAL_BEZIER}"
    );
    assert_eq!(chosen(&plate).0, Dialect::L17);
    // The framework's own bezier stays its marker.
    let f = "primitive bezier\n O1= 0 0 0\n O2= 0 0 1\n P= 0 1\n P= 1 1\nend\n";
    assert_eq!(chosen(f).0, Dialect::F);
    // Named on the command line by the repositories' names too.
    assert_eq!(
        Dialect::from_name("photon_mapping-bezier"),
        Some(Dialect::A18)
    );
    assert_eq!(Dialect::from_name("LAZYCAL"), Some(Dialect::L17));
}

/// The colour of pixel (x, y) of `text` (its centre ray: the pixels
/// tested are no edges, so none is refined), photons as `mode` says
/// (`None`: as the file's dialect says), one iteration of `emit` photons.
fn pixel(text: &str, mode: Option<PhotonMode>, emit: Option<u64>, (x, y): (u32, u32)) -> DVec3 {
    let scene = Scene::parse(text, ".").unwrap_or_else(|e| panic!("{e}")); // invariant: the test's own fixed input (a failure fails the test)
    let options = RenderOptions {
        photons: PhotonOptions {
            mode,
            iterations: Some(1),
            emit,
            ..PhotonOptions::default()
        },
        ..RenderOptions::default()
    };
    let image = Renderer::new(scene).render(&options).unwrap().into_image(); // invariant: the test's own fixed input (a failure fails the test)
    DVec3::from_array(image.pixel(x, y).map(f64::from))
}

fn near(got: DVec3, want: DVec3, tolerance: f64, what: &str) {
    assert!(
        (got - want).abs().max_element() < tolerance,
        "{what}: {got} vs {want}"
    );
    assert!(want.max_element() < 1.0, "{what}: the test must not clamp");
}

const K: DVec3 = DVec3::new(0.5, 0.8, 1.0);
const BG: DVec3 = DVec3::new(0.2, 0.1, 0.3);

/// abcbdf's lit sphere: k·diff·bg + k·c·(diff·L·N + spec·(L·N)^20), L
/// towards the light's centre (W's light through the framework's camera).
#[test]
fn abcbdf_shades_with_the_ambient_term_and_the_frameworks_light() {
    let text = "background\n color= 0.2 0.1 0.3\nend\n\
         camera\n O= 0 0 0\n N= 0 1 0\n image_W= 21\n image_H= 21\nend\n\
         light point\n O= 1 0 4\n color= 1 0.75 0.5\nend\n\
         obj sphere\n O= 0 5 0\n R= 1\n color= 0.5 0.8 1\n diff= 0.6\n spec= 0.3\nend\n";
    // The centre ray is N: it meets the sphere at (0, 4, 0), N = −ŷ.
    let p = DVec3::new(0.0, 4.0, 0.0);
    let l = (DVec3::new(1.0, 0.0, 4.0) - p).normalize();
    let ln = l.dot(-DVec3::Y);
    let c = DVec3::new(1.0, 0.75, 0.5);
    let want = K * 0.6 * BG + K * c * (0.6 * ln + 0.3 * ln.powi(20));
    near(pixel(text, None, None, (10, 10)), want, 1e-6, "a18");
}

/// lazycal's ray-traced light (its `_rt` picture, `--photons off`): k·bg
/// at every hit, plus k·c/mean(c)·share·(diff·L·N + spec·(H·N)^50), the
/// share that of its 9×9 grid over the light in front of the surface
/// and seen, L towards the light's centre, H halfway to the eye.
#[test]
fn lazycal_ray_traced_light_counts_its_grid() {
    let text = format!(
        "background\n color= 0.2 0.1 0.3\nend\n\
         camera\n O= 0 0 0\n N= 0 1 0\n image_W= 21\n image_H= 21\nend\n\
         light area\n O= 1 4.5 3\n Dx= 1 0 0\n Dy= 0 2 0\n color= 150 120 90\nend\n\
         primitive plane\n N= 0 -1 0\n R= -5\n color= 0.5 0.8 1\n diff= 0.7\n spec= 0.3\nend\n{LAZYCAL_BEZIER}"
    )
    .replace("P= 0 0 0", "P= 30 30 30");
    // The centre ray meets the wall y = 5 at P = (0, 5, 0), N = −ŷ. The
    // grid's rows lie at y = 4.5 + i/2 for i = −4..4: five rows (y ≤ 4.5)
    // are in front of the wall, the sixth (y = 5) in its plane: 45 of 81.
    let p = DVec3::new(0.0, 5.0, 0.0);
    let n = -DVec3::Y;
    let l = (DVec3::new(1.0, 4.5, 3.0) - p).normalize();
    let h = (l - DVec3::Y).normalize();
    let c = DVec3::new(150.0, 120.0, 90.0);
    let share = 45.0 / 81.0;
    let want = K * BG + K * c / 120.0 * share * (0.7 * l.dot(n) + 0.3 * h.dot(n).powi(50));
    near(
        pixel(&text, Some(PhotonMode::Off), None, (10, 10)),
        want,
        1e-6,
        "l17 rt",
    );
}

/// lazycal's picture is the photon estimate alone: a ray that meets
/// nothing is black (not the background), and a diffuse point under a
/// point light gets k·τ/(πR²) (not diff·k) with each photon carrying c/n: the share of
/// photons landing within R = 0.2 of the point below a light h above it is
/// (1 − h/√(h² + 0.04))/2, so the pixel is k·c·that/(π·0.04).
#[test]
fn lazycal_pictures_are_the_photon_estimate_alone() {
    let text = format!(
        "background\n color= 0.2 0.1 0.3\nend\n\
         camera\n O= 0 0 3\n N= 0 0 -1\n image_W= 21\n image_H= 21\n lens_W= 2\n lens_H= 2\nend\n\
         light point\n O= 0 0 1\n color= 10 10 10\nend\n\
         primitive sphere\n O= 0 0 -4\n R= 3\n color= 0.5 0.5 0.5\n diff= 0.5\nend\n{LAZYCAL_BEZIER}"
    )
    .replace("P= 0 0 0", "P= 30 30 30");
    // The top of the sphere, (0, 0, −1), is 2 below the light: the share
    // within R = 0.2 of it is (1 − 2/√4.04)/2, as on a plane (the cap
    // drops 0.007 over 0.2, well within the photons' noise).
    let share = (1.0 - 2.0 / 4.04f64.sqrt()) / 2.0;
    let want = DVec3::splat(0.5 * 10.0 * share / (std::f64::consts::PI * 0.04));
    let got = pixel(&text, None, Some(2_000_000), (10, 10));
    assert!(
        (got - want).abs().max_element() < 0.05 * want.x,
        "photon estimate: {got} vs {want}"
    );
    // The corner's ray misses the sphere: black, though the background is not.
    assert_eq!(pixel(&text, None, Some(1000), (0, 0)), DVec3::ZERO);
    let rt = pixel(&text, Some(PhotonMode::Off), None, (0, 0));
    assert!((rt - BG).abs().max_element() < 1e-6, "{rt}");
}
