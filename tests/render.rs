//! Rendering tests whose expected values are computed independently here.

use glint::{RenderOptions, Scene, render};

fn scene(text: &str) -> Scene {
    Scene::parse(text, ".").unwrap_or_else(|e| panic!("{e}"))
}

/// The framework's output byte for a linear value.
fn byte(c: f64) -> u8 {
    (255.0 * c.clamp(0.0, 1.0)).floor() as u8
}

/// Centre pixel of a diffuse + specular sphere under a point light, by hand:
/// the camera ray through the centre of a 21×21 image goes straight along N
/// and meets the sphere at (0, 4, 0) with normal (0, −1, 0).
#[test]
fn diffuse_sphere_centre_pixel_matches_hand_computation() {
    let s = scene(
        "camera
            O= 0 0 0
            N= 0 1 0
            image_W= 21
            image_H= 21
         end
         light point
            O= 0 0 5
            color= 0.9 0.8 0.7
         end
         primitive sphere
            O= 0 5 0
            R= 1
            color= 1 0.5 0.25
            diff= 0.8
            spec= 0.3
         end",
    );
    let img = render(
        &s,
        &RenderOptions {
            spp: Some(1),
            ..RenderOptions::default()
        },
    );
    // L = unit((0,0,5) − (0,4,0)) = (0,−4,5)/√41; d = L·N = 4/√41.
    let d = 4.0 / 41f64.sqrt();
    let weight = 0.8 * d + 0.3 * d.powi(20);
    let want = [1.0 * 0.9 * weight, 0.5 * 0.8 * weight, 0.25 * 0.7 * weight];
    let got = img.pixel(10, 10);
    for c in 0..3 {
        assert!(
            (got[c] as f64 - want[c]).abs() < 1e-6,
            "channel {c}: {} vs {}",
            got[c],
            want[c]
        );
    }
    let bytes = img.to_rgb8();
    let centre = (10 * 21 + 10) * 3;
    assert_eq!(
        &bytes[centre..centre + 3],
        &[byte(want[0]), byte(want[1]), byte(want[2])]
    );
    // A corner pixel misses the sphere: the (black) background.
    assert_eq!(img.pixel(0, 0), [0.0; 3]);
}

/// A point blocked from the light gets no diffuse light (hard shadow), and a
/// mirror shows what it reflects, weighted by color × refl, clamped at 1.
#[test]
fn shadow_and_mirror_follow_the_model() {
    // Floor z = 0 seen from above; a blocker sphere between the light and the point below the eye.
    let s = scene(
        "camera
            O= 0 0 10
            N= 0 0 -1
            image_W= 11
            image_H= 11
         end
         light point
            O= 0 0 20
            color= 1 1 1
         end
         primitive sphere
            O= 0 0 15
            R= 1
            color= 1 1 1
            diff= 1
         end
         primitive plane
            N= 0 0 1
            R= 0
            color= 0.5 0.5 0.5
            diff= 1
         end",
    );
    let img = render(
        &s,
        &RenderOptions {
            spp: Some(1),
            ..RenderOptions::default()
        },
    );
    // The centre ray hits the floor at the origin: the light is straight above,
    // behind the sphere, so the floor is black there.
    assert_eq!(img.pixel(5, 5), [0.0; 3]);

    // Now a mirror floor under a red background-lit sphere... use a gradient
    // background: a perfect mirror facing up shows the top colour times color·refl.
    let s = scene(
        "background
            top= 0.2 0.4 0.6
            bottom= 1 1 1
         end
         camera
            O= 0 0 10
            N= 0 0 -1
            image_W= 11
            image_H= 11
         end
         primitive plane
            N= 0 0 1
            R= 0
            color= 1 0.5 1
            refl= 0.5
         end",
    );
    let img = render(
        &s,
        &RenderOptions {
            spp: Some(1),
            ..RenderOptions::default()
        },
    );
    // Reflected ray goes straight up: background t = (1 + 1)/2 = 1 -> top.
    let want = [0.2 * 1.0 * 0.5, 0.4 * 0.5 * 0.5, 0.6 * 1.0 * 0.5];
    let got = img.pixel(5, 5);
    for c in 0..3 {
        assert!(
            (got[c] as f64 - want[c]).abs() < 1e-6,
            "{got:?} vs {want:?}"
        );
    }
}

/// Glass: a ray through the centre of a sphere is not bent, and leaving it
/// after travelling 2R inside is attenuated by exp(−absor·2R) (Beer).
#[test]
fn glass_sphere_absorbs_along_the_chord() {
    let s = scene(
        "background
            color= 1 1 1
         end
         camera
            O= 0 0 0
            N= 0 1 0
            image_W= 21
            image_H= 21
         end
         primitive sphere
            O= 0 5 0
            R= 1
            refr= 1
            rindex= 1.5
            absor= 0 0.5 2
         end",
    );
    let img = render(
        &s,
        &RenderOptions {
            spp: Some(1),
            ..RenderOptions::default()
        },
    );
    let got = img.pixel(10, 10);
    let want = [1.0, (-0.5f64 * 2.0).exp(), (-2.0f64 * 2.0).exp()];
    for c in 0..3 {
        assert!(
            (got[c] as f64 - want[c]).abs() < 1e-6,
            "{got:?} vs {want:?}"
        );
    }
}

/// `--spp 1` is exactly one ray through each pixel's centre, rows from the top:
/// a light sphere seen at a known pixel centre lights exactly that pixel.
#[test]
fn one_sample_goes_through_the_pixel_centre() {
    // 4×2 image, lens 1×1: pixel (x=3, y=0) is framework row i = 1, column j = 3,
    // direction N + Dy·(2·1.5/2 − 1) + Dx·(2·3.5/4 − 1) = (0.375, 1, 0.25).
    let s = scene(
        "camera
            N= 0 1 0
            lens_W= 1
            lens_H= 1
            image_W= 4
            image_H= 2
         end
         light sphere
            O= 3.75 10 2.5
            R= 0.05
            color= 1 1 1
         end",
    );
    let img = render(
        &s,
        &RenderOptions {
            spp: Some(1),
            ..RenderOptions::default()
        },
    );
    for y in 0..2 {
        for x in 0..4 {
            let lit = img.pixel(x, y) == [1.0; 3];
            assert_eq!(lit, (x, y) == (3, 0), "pixel ({x}, {y})");
        }
    }
}

fn busy_scene() -> Scene {
    scene(
        "background
            top= 0.5 0.7 1
         end
         camera
            O= 0 -6 1
            N= 0 1 -0.1
            image_W= 48
            image_H= 32
            shade_quality= 1
            drefl_quality= 1
         end
         light sphere
            O= 2 -2 5
            R= 0.5
            color= 1 1 1
         end
         primitive sphere
            O= 0 0 1
            R= 1
            color= 0.8 0.8 0.8
            diff= 0.5
            refl= 0.5
            drefl= 0.2
         end
         primitive plane
            N= 0 0 1
            R= 0
            color= 1 1 1
            diff= 0.7
            refl= 0.2
            drefl= 0.15
         end",
    )
}

/// The same scene and seed give the same bytes with 1 thread or 4, in both
/// sampling modes; another seed changes the noise.
#[test]
fn same_seed_same_bytes_whatever_the_threads() {
    let s = busy_scene();
    for spp in [None, Some(4)] {
        let one = render(
            &s,
            &RenderOptions {
                threads: Some(1),
                seed: 7,
                spp,
            },
        );
        let four = render(
            &s,
            &RenderOptions {
                threads: Some(4),
                seed: 7,
                spp,
            },
        );
        assert_eq!(one.to_rgb8(), four.to_rgb8(), "spp {spp:?}");
        let other = render(
            &s,
            &RenderOptions {
                threads: Some(4),
                seed: 8,
                spp,
            },
        );
        assert_ne!(
            one.to_rgb8(),
            other.to_rgb8(),
            "spp {spp:?}: the seed must matter"
        );
    }
}

/// Every framework scene renders (at a reduced size) to a picture with
/// content: finite values, many distinct colours, not just the background.
#[test]
fn framework_scenes_render() {
    let dir = std::path::Path::new("../shared/scenes/framework");
    let mut count = 0;
    for entry in
        std::fs::read_dir(dir).expect("../shared/scenes/framework is beside the repository")
    {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "txt") {
            continue;
        }
        let mut s = Scene::from_file(&path).unwrap_or_else(|e| panic!("{e}"));
        s.camera.width /= 8;
        s.camera.height /= 8;
        let img = render(&s, &RenderOptions::default());
        let bytes = img.to_rgb8();
        let mut colours: Vec<&[u8]> = bytes.chunks(3).collect();
        colours.sort();
        colours.dedup();
        assert!(
            colours.len() > 200,
            "{}: only {} colours",
            path.display(),
            colours.len()
        );
        for y in 0..img.height() {
            for x in 0..img.width() {
                assert!(img.pixel(x, y).iter().all(|c| c.is_finite() && *c >= 0.0));
            }
        }
        count += 1;
    }
    assert!(count >= 2, "found {count} framework scenes");
}
