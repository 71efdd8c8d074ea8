//! Rendering tests whose expected values are computed independently here.

mod common;

use common::camera_dir;

use glam::DVec3;
use glint::{Image, RenderOptions, Renderer, Scene};

/// A ray of the reference computations: origin and unit direction.
#[derive(Clone, Copy, Debug)]
struct Ray {
    origin: DVec3,
    dir: DVec3,
}

impl Ray {
    fn new(origin: DVec3, dir: DVec3) -> Ray {
        Ray { origin, dir }
    }

    fn at(&self, t: f64) -> DVec3 {
        self.origin + self.dir * t
    }
}

/// `s` rendered as `options` say.
fn render(s: &Scene, options: &RenderOptions) -> Image {
    let renderer = Renderer::new(s.clone());
    match renderer.render(options) {
        Ok(film) => film.into_image(),
        Err(e) => panic!("{e}"),
    }
}

fn scene(text: &str) -> Scene {
    Scene::parse(text, ".").unwrap_or_else(|e| panic!("{e}"))
}

/// The framework's output byte for a linear value.
fn byte(c: f64) -> u8 {
    (255.0 * c.clamp(0.0, 1.0)).floor() as u8
}

/// Renders `s` with one sample per pixel (through the pixel centres).
fn render_one_spp(s: &Scene) -> Image {
    render(
        s,
        &RenderOptions {
            spp: Some(1),
            ..RenderOptions::default()
        },
    )
}

/// How many distinct 8-bit colours the image holds.
fn distinct_colours(img: &Image) -> usize {
    let bytes = img.to_rgb8();
    let mut colours: Vec<&[u8]> = bytes.chunks(3).collect();
    colours.sort();
    colours.dedup();
    colours.len()
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
    let img = render_one_spp(&s);
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
    let img = render_one_spp(&s);
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
    let img = render_one_spp(&s);
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
    let img = render_one_spp(&s);
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
    let img = render_one_spp(&s);
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
                ..RenderOptions::default()
            },
        );
        let four = render(
            &s,
            &RenderOptions {
                threads: Some(4),
                seed: 7,
                spp,
                ..RenderOptions::default()
            },
        );
        assert_eq!(one.to_rgb8(), four.to_rgb8(), "spp {spp:?}");
        let other = render(
            &s,
            &RenderOptions {
                threads: Some(4),
                seed: 8,
                spp,
                ..RenderOptions::default()
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
    if common::corpus("framework").is_none() {
        return;
    }
    let mut count = 0;
    for path in common::corpus_scenes("framework") {
        let s = Scene::from_file(&path).unwrap_or_else(|e| panic!("{e}"));
        let small = RenderOptions {
            width: Some(s.camera().width / 8),
            height: Some(s.camera().height / 8),
            ..RenderOptions::default()
        };
        let img = render(&s, &small);
        let colours = distinct_colours(&img);
        assert!(colours > 200, "{}: only {colours} colours", path.display());
        for y in 0..img.height() {
            for x in 0..img.width() {
                assert!(img.pixel(x, y).iter().all(|c| c.is_finite() && *c >= 0.0));
            }
        }
        count += 1;
    }
    assert!(count >= 2, "found {count} framework scenes");
}

/// Where a ray meets the plane z = `h` (if ahead).
fn at_height(ray: &Ray, h: f64) -> Option<DVec3> {
    let t = (h - ray.origin.z) / ray.dir.z;
    (t > 0.0).then(|| ray.at(t))
}

/// Whether a ray passes within `radius` of `centre` ahead of its origin.
fn passes_sphere(ray: &Ray, centre: DVec3, radius: f64) -> bool {
    let t = (centre - ray.origin).dot(ray.dir);
    t > 0.0 && (ray.at(t) - centre).length() < radius
}

/// Light emitters: a coloured square light and a sphere light with
/// `intensity=`, seen directly and in a perfect mirror floor. Seen directly
/// an emitter is its colour × intensity, clamped to 1; in the mirror it is
/// that clamped colour × the mirror's `refl=` × its `color=` (the reflected
/// ray is clamped before it is weighted).
#[test]
fn emitters_seen_directly_and_in_a_mirror() {
    let s = scene(
        "camera
            O= 0 0 0
            N= 0 1 0
            lens_W= 1
            lens_H= 1
            image_W= 20
            image_H= 20
         end
         light square
            O= -1 5 0
            Dx= 0.6 0 0
            Dy= 0 0 0.6
            color= 0.3 0.5 0.8
            intensity= 1.5
         end
         light sphere
            O= 2 8 0
            R= 0.5
            color= 0.21 0.9 0.33
            intensity= 2
         end
         primitive plane
            N= 0 0 1
            R= -1
            color= 0.8 0.6 1
            refl= 0.5
         end",
    );
    assert!(s.warnings().is_empty(), "intensity= is a light key");
    let img = render_one_spp(&s);
    let bytes = img.to_rgb8();
    let at = |x: u32, y: u32| -> [u8; 3] {
        let k = ((y * 20 + x) * 3) as usize;
        [bytes[k], bytes[k + 1], bytes[k + 2]]
    };
    let ray = |x: u32, y: u32| {
        Ray::new(
            DVec3::ZERO,
            camera_dir(DVec3::Y, (1.0, 1.0), (20, 20), x, y),
        )
    };
    // The mirror image of a ray that meets the floor z = −1: it continues
    // as if through the floor into the mirrored world (z → −2 − z).
    let mirrored = |r: &Ray| {
        let p = at_height(r, -1.0).expect("reaches the floor");
        Ray::new(p, DVec3::new(r.dir.x, r.dir.y, -r.dir.z))
    };
    // Inside the square light O ± Dx ± Dy at y = 5?
    let on_square = |r: &Ray| {
        let t = (5.0 - r.origin.y) / r.dir.y;
        let p = r.at(t);
        t > 0.0 && (p.x + 1.0).abs() < 0.6 && p.z.abs() < 0.6
    };
    let square = [0.3 * 1.5, 0.5 * 1.5, 0.8 * 1.5];
    let sphere = [0.21 * 2.0, 0.9 * 2.0, 0.33 * 2.0];
    let mirror = [0.8, 0.6, 1.0];
    let direct = |c: [f64; 3]| c.map(|v| byte(v.min(1.0)));
    let reflected = |c: [f64; 3]| [0, 1, 2].map(|k| byte(c[k].min(1.0) * mirror[k] * 0.5));

    // Pixel (5, 10): direction (−0.225, 1, −0.025) meets the square light
    // at (−1.125, 5, −0.125), before the floor (which it would reach at y = 40).
    let r = ray(5, 10);
    assert!(on_square(&r) && at_height(&r, -1.0).is_some_and(|p| p.y > 5.0));
    assert_eq!(at(5, 10), direct(square));
    assert_eq!(direct(square), [114, 191, 255], "blue clamped to 1");
    // Pixel (5, 18): direction (−0.225, 1, −0.425) meets the floor at y ≈ 2.35
    // and its reflection meets the square light at (−1.125, 5, 0.125).
    let r = ray(5, 18);
    assert!(at_height(&r, -1.0).is_some_and(|p| p.y < 5.0) && on_square(&mirrored(&r)));
    assert_eq!(at(5, 18), reflected(square));
    // Blue: the clamped 1 (not 1.2) times refl 0.5 and color 1: 127, not 153.
    assert_eq!(reflected(square), [45, 57, 127]);
    // Pixel (14, 10): direction (0.225, 1, −0.025) passes 0.28 from the
    // sphere light's centre (radius 0.5).
    let r = ray(14, 10);
    assert!(passes_sphere(&r, DVec3::new(2.0, 8.0, 0.0), 0.5));
    assert_eq!(at(14, 10), direct(sphere));
    assert_eq!(direct(sphere), [107, 255, 168], "green clamped to 1");
    // Pixel (14, 15): direction (0.225, 1, −0.275) reaches the floor at y ≈ 3.6;
    // its reflection passes 0.28 from the sphere's centre.
    let r = ray(14, 15);
    assert!(
        at_height(&r, -1.0).is_some_and(|p| p.y < 7.5)
            && passes_sphere(&mirrored(&r), DVec3::new(2.0, 8.0, 0.0), 0.5)
    );
    assert_eq!(at(14, 15), reflected(sphere));
    assert_eq!(reflected(sphere), [42, 76, 84]);
    // Pixel (10, 19): the floor, whose reflection misses both lights: the
    // floor has no diffuse term and the background is black.
    let r = ray(10, 19);
    let m = mirrored(&r);
    assert!(!on_square(&m) && !passes_sphere(&m, DVec3::new(2.0, 8.0, 0.0), 0.6));
    assert_eq!(at(10, 19), [0, 0, 0]);
    // Pixel (10, 0): up into the black background.
    assert_eq!(at(10, 0), [0, 0, 0]);
    // And in linear values (no byte rounding): exactly the clamped colours.
    let got = img.pixel(5, 10);
    for k in 0..3 {
        assert!((got[k] as f64 - square[k].min(1.0)).abs() < 1e-6, "{got:?}");
    }
}

/// The showcase (the README's first command) parses with no warning and
/// renders, at 96 × 54, to a clean picture with plenty of detail.
#[test]
fn showcase_is_clean_and_renders() {
    let s = Scene::from_file("examples/showcase.txt").unwrap_or_else(|e| panic!("{e}"));
    let warnings: Vec<String> = s.warnings().iter().map(|w| w.to_string()).collect();
    assert!(warnings.is_empty(), "{}", warnings.join("\n"));
    assert_eq!((s.camera().width, s.camera().height), (960, 540));
    assert_eq!(s.lights().len(), 2);
    // Every primitive block (none is a mesh), plus the visible surfaces of
    // the two area lights.
    let text = std::fs::read_to_string("examples/showcase.txt").unwrap();
    let blocks = text.lines().filter(|l| l.starts_with("primitive ")).count();
    assert_eq!(blocks, 16);
    assert_eq!(s.objects().len(), blocks + 2);
    // As `--width 96` does: the aspect kept.
    let small = RenderOptions {
        width: Some(96),
        ..RenderOptions::default()
    };
    let img = render(&s, &small);
    assert_eq!((img.width(), img.height()), (96, 54));
    let mut sum = 0.0;
    for y in 0..54 {
        for x in 0..96 {
            let p = img.pixel(x, y);
            assert!(
                p.iter().all(|c| c.is_finite() && (0.0..=1.0).contains(c)),
                "pixel ({x}, {y}) = {p:?}"
            );
            sum += p.iter().sum::<f32>() as f64 / 3.0;
        }
    }
    let mean = sum / (96.0 * 54.0);
    assert!(mean > 0.1 && mean < 0.7, "mean brightness {mean}");
    let colours = distinct_colours(&img);
    assert!(colours > 1500, "only {colours} distinct colours");
}
