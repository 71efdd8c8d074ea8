//! Photon-mapped renders through the library: the same bytes whatever the
//! threads (PM, PPM, SPPM), the hit-point cap as an error naming its key,
//! checkpoints every N iterations, a cancel keeping the last complete
//! iteration, and the photon term brightening what the direct light leaves dark.

use glint::{Aov, Control, PhotonMode, PhotonOptions, RenderError, RenderOptions, Renderer, Scene};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// A glass ball over a floor under a point light, in the variant dialect v.
const GLASS: &str = include_str!("data/glass.txt");

fn renderer(text: &str) -> Renderer {
    Renderer::new(Scene::parse(text, ".").unwrap_or_else(|e| panic!("parses:\n{e}")))
}

fn options(mode: PhotonMode, threads: usize) -> RenderOptions {
    RenderOptions {
        threads: Some(threads),
        seed: 3,
        photons: PhotonOptions {
            mode: Some(mode),
            iterations: Some(3),
            emit: Some(20_000),
            ..PhotonOptions::default()
        },
        ..RenderOptions::default()
    }
}

fn bytes(r: &Renderer, o: &RenderOptions) -> Vec<u8> {
    r.render(o).expect("renders").image().to_rgb8()
}

#[test]
fn same_bytes_with_1_2_and_7_threads() {
    let r = renderer(GLASS);
    for mode in [PhotonMode::Pm, PhotonMode::Ppm, PhotonMode::Sppm] {
        let one = bytes(&r, &options(mode, 1));
        assert_eq!(one, bytes(&r, &options(mode, 2)), "{mode:?}, 2 threads");
        assert_eq!(one, bytes(&r, &options(mode, 7)), "{mode:?}, 7 threads");
    }
}

#[test]
fn photons_brighten_the_caustic_and_the_indirect_light() {
    let r = renderer(GLASS);
    let off = bytes(&r, &options(PhotonMode::Off, 2));
    let sum = |b: &[u8]| b.iter().map(|&v| v as u64).sum::<u64>();
    for mode in [PhotonMode::Pm, PhotonMode::Ppm, PhotonMode::Sppm] {
        let on = bytes(&r, &options(mode, 2));
        // Photon light only adds (it is clamped with the direct light).
        let darker = off.iter().zip(&on).filter(|(a, b)| b < a).count();
        assert!(
            sum(&on) > sum(&off) + sum(&off) / 50,
            "{mode:?}: photons add light ({} → {})",
            sum(&off),
            sum(&on)
        );
        if mode == PhotonMode::Pm {
            assert_eq!(darker, 0, "PM only adds to the direct light");
        }
    }
}

#[test]
fn too_many_hit_points_is_an_error_naming_the_key() {
    let text = GLASS.replace(" algorithm= RT\n", " algorithm= RT\n max_hitpoints= 100\n");
    let r = renderer(&text);
    match r.render(&options(PhotonMode::Ppm, 1)) {
        Err(e @ RenderError::HitPoints { max: 100, .. }) => {
            assert!(e.to_string().contains("max_hitpoints="), "{e}")
        }
        other => panic!("expected the hit-point cap, got {:?}", other.map(|_| ())),
    }
}

#[test]
fn checkpoints_every_n_iterations_and_a_cancel_keeps_the_last_complete_one() {
    let r = renderer(GLASS);
    let mut o = options(PhotonMode::Ppm, 2);
    o.photons.iterations = Some(5);
    let seen = Mutex::new(Vec::new());
    let stop = AtomicBool::new(false);
    let checkpoint = |i: u64, film: &glint::Film| {
        seen.lock().unwrap().push((i, film.image().to_rgb8()));
    };
    let control = Control {
        checkpoint: Some(&checkpoint),
        checkpoint_every: 2,
        ..Control::default()
    };
    let (film, stats) = r.render_with(&o, control).expect("renders");
    let got: Vec<u64> = seen.lock().unwrap().iter().map(|(i, _)| *i).collect();
    assert_eq!(got, vec![2, 4, 5]);
    assert_eq!(stats.photons.iterations, 5);
    assert_eq!(seen.lock().unwrap()[2].1, film.image().to_rgb8());

    // Cancelled at the first checkpoint: the picture of iteration 2.
    seen.lock().unwrap().clear();
    let cancelling = |i: u64, film: &glint::Film| {
        seen.lock().unwrap().push((i, film.image().to_rgb8()));
        stop.store(true, Ordering::Relaxed);
    };
    let control = Control {
        cancel: Some(&stop),
        checkpoint: Some(&cancelling),
        checkpoint_every: 2,
        ..Control::default()
    };
    let (film, stats) = r
        .render_with(&o, control)
        .expect("the last complete iteration");
    assert_eq!(stats.photons.iterations, 2);
    assert_eq!(seen.lock().unwrap()[0].1, film.image().to_rgb8());
}

#[test]
fn sppm_direct_light_is_the_pixels_own_jittered_samples() {
    // One photon a pass gathers nothing (fewer than 8), so SPPM's picture is
    // the mean of its iterations' jittered samples of each pixel: what 64
    // stratified samples a pixel give, but for the noise of 16 samples
    // where a pixel's samples differ (silhouettes, the view through the ball).
    let r = renderer(GLASS);
    let mut o = options(PhotonMode::Sppm, 2);
    o.photons.emit = Some(1);
    o.photons.iterations = Some(16);
    let sppm = bytes(&r, &o);
    let mut aa = options(PhotonMode::Off, 2);
    aa.spp = Some(64);
    let rt = bytes(&r, &aa);
    let diff: Vec<i32> = sppm
        .iter()
        .zip(&rt)
        .map(|(&a, &b)| (a as i32 - b as i32).abs())
        .collect();
    let mean = diff.iter().sum::<i32>() as f64 / diff.len() as f64;
    let close = diff.iter().filter(|&&d| d <= 2).count() as f64 / diff.len() as f64;
    assert!(
        mean < 1.5 && close > 0.9,
        "mean |Δ| {mean}, share within 2: {close}"
    );
}

#[test]
fn explain_shows_the_photon_term_and_ends_in_the_rendered_bytes() {
    let r = renderer(GLASS);
    let o = options(PhotonMode::Pm, 2);
    let image = r.render(&o).expect("renders").into_image();
    let mut with_photons = 0;
    for (x, y) in [(20, 25), (5, 28), (20, 15), (35, 5), (12, 20)] {
        let e = r.explain(&o, x, y).expect("explains");
        let px = image.pixel(x, y).map(|c| (c * 255.0) as u8);
        assert_eq!(e.bytes, px, "pixel ({x}, {y})");
        // The camera ray's hit is diffuse here (floor or wall): the map was asked.
        let root = &e.samples[0];
        if let Some(p) = &root.photons {
            with_photons += 1;
            assert!(p.radius > 0.0 && p.radius <= 0.3 + 1e-12, "{p:?}");
            assert!(p.term.min_element() >= 0.0);
        }
    }
    assert!(
        with_photons >= 3,
        "{with_photons} of 5 pixels show a photon term"
    );
}

#[test]
fn the_photons_pass_is_the_term_explain_shows_and_ppms_estimate() {
    let r = renderer(GLASS);
    let mut o = options(PhotonMode::Pm, 2);
    o.spp = Some(1);
    o.photons.emit = Some(200_000);
    o.aovs = vec![glint::Aov::Photons];
    let film = r.render(&o).expect("renders");
    let plane = film.aov(Aov::Photons).expect("a photons AOV");
    let mut lit = 0;
    for (x, y) in [(20, 25), (5, 28), (35, 5), (12, 20), (30, 27)] {
        let at = ((y * 40 + x) * 3) as usize;
        let e = r.explain(&o, x, y).expect("explains");
        let want = e.samples[0]
            .photons
            .as_ref()
            .map_or([0.0; 3], |p| p.term.as_vec3().to_array());
        assert_eq!(&plane.data[at..at + 3], &want, "pixel ({x}, {y})");
        lit += usize::from(want[0] > 0.0);
    }
    assert!(lit >= 3, "{lit} of 5 pixels have photon light");
    // PPM: the pass is each pixel's estimate, and the picture holds it.
    o.photons.mode = Some(PhotonMode::Ppm);
    let film = r.render(&o).expect("renders");
    let plane = film.aov(Aov::Photons).expect("a photons AOV");
    let image = film.image();
    let mut nonzero = 0;
    for y in 0..30 {
        for x in 0..40 {
            let at = ((y * 40 + x) * 3) as usize;
            let px = image.pixel(x, y);
            for (c, &p) in px.iter().enumerate() {
                let term = plane.data[at + c];
                assert!(term >= 0.0);
                assert!(p + 1e-6 >= term.min(1.0), "({x}, {y})");
            }
            nonzero += usize::from(plane.data[at] > 0.0);
        }
    }
    assert!(nonzero > 100, "{nonzero} pixels with a photon estimate");
}

#[test]
fn ppm_hit_points_are_the_pictures_own_samples() {
    // Looking straight down at a floor: every camera sample lands on it, so
    // PPM keeps one hit point a sample: one a pixel, N with `--spp N`, and
    // `dofSample=` with an open lens.
    let floor = "camera\n O= 0 0 4\n N= 0 0 -1\n image_W= 12\n image_H= 9\n\
        sample_photons= 20\n sample_dist= 0.3\n algorithm= RT\nend\n\
        light point\n O= 0 0 3\n color= 2 2 2\nend\n\
        primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 1\nend\n";
    let points = |text: &str, spp: Option<u32>| {
        let mut o = options(PhotonMode::Ppm, 2);
        o.spp = spp;
        o.photons.iterations = Some(1);
        o.photons.emit = Some(1000);
        let (_, stats) = renderer(text)
            .render_with(&o, Control::default())
            .expect("renders");
        stats.photons.hit_points
    };
    assert_eq!(points(floor, None), 12 * 9);
    assert_eq!(points(floor, Some(4)), 4 * 12 * 9);
    let lens = floor.replace(
        " algorithm= RT\n",
        " algorithm= RT\n aperture= 0.2\n focalLen= 4\n dofSample= 3\n",
    );
    assert_eq!(points(&lens, None), 3 * 12 * 9);
}

#[test]
fn ppm_under_an_open_lens_blurs_the_caustic_it_does_not_focus() {
    // The caustic under the glass ball, seen through a wide lens focused far
    // beyond it: PPM's photon term (the photons pass) spreads over more
    // pixels and its peak falls, as the ray-traced part's picture does.
    let peak_and_spread = |lens: &str| {
        let text = GLASS.replace(" algorithm= RT\n", &format!(" algorithm= RT\n{lens}"));
        let mut o = options(PhotonMode::Ppm, 2);
        o.photons.emit = Some(50_000);
        o.aovs = vec![glint::Aov::Photons];
        let film = renderer(&text).render(&o).expect("renders");
        let plane = film.aov(Aov::Photons).expect("a photons AOV");
        let red: Vec<f32> = plane.data.chunks(3).map(|c| c[0]).collect();
        let peak = red.iter().copied().fold(0.0, f32::max);
        let spread = red.iter().filter(|&&v| v > peak / 4.0).count();
        (peak, spread)
    };
    let (sharp, sharp_spread) = peak_and_spread("");
    let (blurred, blurred_spread) =
        peak_and_spread(" aperture= 0.6\n focalLen= 40\n dofSample= 16\n");
    assert!(sharp > 0.0, "a caustic");
    assert!(
        blurred < 0.75 * sharp,
        "peak {sharp} through the pinhole, {blurred} through the lens"
    );
    assert!(
        blurred_spread > sharp_spread,
        "{sharp_spread} pixels above a quarter of the peak through the pinhole, {blurred_spread} through the lens"
    );
}

#[test]
fn explain_under_ppm_and_sppm_ends_in_the_rendered_bytes() {
    // explain repeats the render's iterations over the pixel's own hit
    // points, with the same photons: its colour is the rendered pixel's
    // (to the rounding of the gather's order, which follows the grid's
    // cell, sized by the region's largest radius) and so are its bytes.
    let r = renderer(GLASS);
    for (mode, spp) in [
        (PhotonMode::Ppm, None),
        (PhotonMode::Ppm, Some(2)),
        (PhotonMode::Sppm, None),
    ] {
        let mut o = options(mode, 2);
        o.spp = spp;
        let film = r.render(&o).expect("renders");
        let image = film.image();
        let bytes = image.to_rgb8();
        let mut with_photons = 0;
        for (x, y) in [(20, 25), (19, 26), (5, 28), (35, 5), (12, 20), (30, 27)] {
            let e = r.explain(&o, x, y).expect("explains");
            let at = ((y * 40 + x) * 3) as usize;
            let want = image.pixel(x, y);
            for c in 0..3 {
                assert!(
                    (e.color[c] - want[c]).abs() <= 1e-6 * want[c].abs().max(1e-3),
                    "{mode:?} {spp:?} ({x}, {y}): colour {:?}, rendered {want:?}",
                    e.color
                );
            }
            assert_eq!(
                &e.bytes[..],
                &bytes[at..at + 3],
                "{mode:?} {spp:?} ({x}, {y})"
            );
            let p = e.progressive.as_ref().expect("the photon term");
            assert_eq!(p.iterations, 3);
            let term: f64 = p.points.iter().map(|h| h.term.x).sum();
            // The picture is the ray-traced part plus the photon term.
            let sum = (f64::from(p.direct[0]) + term).min(1.0);
            assert!(
                (sum - f64::from(e.color[0])).abs() < 1e-6,
                "{sum} {:?}",
                e.color
            );
            with_photons += usize::from(term > 0.0);
        }
        assert!(
            with_photons >= 3,
            "{mode:?}: {with_photons} pixels with photon light"
        );
    }
}
