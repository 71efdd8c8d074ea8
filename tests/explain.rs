//! `explain` against what `render` writes, `probe` and hand-planted causes.

mod common;

use common::camera_dir;
use glam::DVec3;
use glint::{Explanation, RayKind, RenderOptions, Renderer, Scene};

fn scene(text: &str) -> Scene {
    Scene::parse(text, ".").unwrap_or_else(|e| panic!("{e}"))
}

fn explain(r: &Renderer, options: &RenderOptions, x: u32, y: u32) -> Explanation {
    r.explain(options, x, y).unwrap_or_else(|e| panic!("{e}"))
}

/// Every primitive kind under a point light (scene A) or the two area
/// lights (scene B), with a mirror, glossy and glass materials.
fn scenes() -> Vec<String> {
    const SHAPES: &str = "background\n top= 0.5 0.6 0.9\n bottom= 0.1 0.1 0.1\nend\n\
        camera\n O= 0 -8 3\n N= 0 1 -0.3\n image_W= 22\n image_H= 16\n shade_quality= 1\n drefl_quality= 1\nend\n\
        primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 0.7\n refl= 0.2\n drefl= 0.1\nend\n\
        primitive cube\n O= 1.5 0 1\n x= 0.7\n y= 0.7\n z= 0.7\n color= 1 0.3 0.2\n diff= 0.6\n refl= 0.3\nend\n\
        primitive sphere\n O= -1.2 -0.5 1\n R= 1\n color= 1 1 1\n refr= 0.9\n rindex= 1.5\n absor= 0.2 0.1 0\nend\n\
        primitive cylinder\n O1= 0 2 0\n O2= 0 2 2.5\n R= 0.4\n color= 0.2 0.9 0.3\n diff= 0.8\n spec= 0.3\nend\n\
        primitive square\n O= -3 2 1.5\n Dx= 0.8 0 0\n Dy= 0 0 0.8\n color= 0.9 0.9 0.2\n diff= 0.9\nend\n\
        primitive triangle\n O1= 2.5 -1 0.2\n O2= 3.5 -1 0.2\n O3= 3 -1 1.6\n color= 0.3 0.3 1\n diff= 0.9\nend\n\
        primitive bezier\n O1= -2.6 -2 0\n O2= -2.6 -2 1.2\n P= 0 0.3\n P= 0.5 0.6\n P= 1 0.2\n color= 0.9 0.5 0.9\n diff= 0.8\n spec= 0.4\nend\n";
    vec![
        format!("{SHAPES}light point\n O= 4 -6 8\n color= 0.9 0.9 0.9\nend\n"),
        format!(
            "{SHAPES}light square\n O= -3 -2 6\n Dx= 0.7 0 0\n Dy= 0 0.7 0\n color= 0.6 0.6 0.6\nend\n\
             light sphere\n O= 3 -4 5\n R= 0.5\n color= 0.7 0.7 0.6\nend\n"
        ),
    ]
}

/// For every pixel of every scene, adaptive and at --spp 2: the bytes and
/// the f32 colour explain gives are those the render writes there.
#[test]
fn explain_gives_the_rendered_bytes_of_every_pixel() {
    for text in scenes() {
        let r = Renderer::new(scene(&text));
        for spp in [None, Some(2)] {
            let options = RenderOptions {
                spp,
                threads: Some(2),
                ..RenderOptions::default()
            };
            let image = r
                .render(&options)
                .unwrap_or_else(|e| panic!("{e}"))
                .into_image();
            let bytes = image.to_rgb8();
            let mut refined = 0;
            for y in 0..image.height() {
                for x in 0..image.width() {
                    let e = explain(&r, &options, x, y);
                    let k = ((y * image.width() + x) * 3) as usize;
                    assert_eq!(e.bytes, bytes[k..k + 3], "pixel {x} {y} spp {spp:?}");
                    assert_eq!(e.color, image.pixel(x, y), "pixel {x} {y} spp {spp:?}");
                    let want = match spp {
                        Some(n) => n as usize,
                        None if e.samples.len() == 49 => {
                            refined += 1;
                            49
                        }
                        None => 1,
                    };
                    assert_eq!(e.samples.len(), want);
                    assert!(!e.verdict.is_empty());
                }
            }
            if spp.is_none() {
                assert!(
                    refined > 10,
                    "{refined} pixels anti-aliased: edges were seen"
                );
            }
        }
    }
}

/// At --spp 1 the tree's camera ray is the spec's centre ray (computed here
/// from the camera), and its first hit is the probe's for that ray.
#[test]
fn the_first_hit_is_the_probes() {
    for text in scenes() {
        let s = scene(&text);
        let cam = s.camera().clone();
        let r = Renderer::new(s);
        let options = RenderOptions {
            spp: Some(1),
            ..RenderOptions::default()
        };
        let (mut hits, mut misses) = (0, 0);
        for y in 0..cam.height {
            for x in 0..cam.width {
                let e = explain(&r, &options, x, y);
                let root = &e.samples[0];
                assert_eq!(root.kind, RayKind::Camera);
                assert_eq!(root.depth, 1);
                let want = camera_dir(
                    cam.dir,
                    (cam.lens_w, cam.lens_h),
                    (cam.width, cam.height),
                    x,
                    y,
                );
                assert!((root.direction - want).length() < 1e-12, "pixel {x} {y}");
                assert_eq!(root.origin, cam.origin);
                let probe = r.probe(root.origin, root.direction);
                match (&root.hit, probe) {
                    (None, None) => misses += 1,
                    (Some(h), Some(p)) => {
                        hits += 1;
                        // The probe normalises the direction once more: the last bits may move.
                        let close =
                            |a: DVec3, b: DVec3| (a - b).length() <= 1e-12 * (1.0 + a.length());
                        assert!((h.t - p.t).abs() <= 1e-12 * p.t, "pixel {x} {y}");
                        assert!(close(h.point, p.point), "pixel {x} {y}");
                        assert!(close(h.normal, p.normal), "pixel {x} {y}");
                        assert_eq!(h.front, p.front);
                        assert_eq!(h.primitive, p.primitive);
                        assert!((h.uv - p.uv).length() < 1e-9, "pixel {x} {y}");
                    }
                    (h, p) => panic!("pixel {x} {y}: tree {h:?}, probe {p:?}"),
                }
            }
        }
        assert!(hits > 100 && misses > 10, "{hits} hits, {misses} misses");
    }
}

/// A floor under a point light, with a ball between them; a wall seen from
/// behind; a wall that faces away from the light; sky above.
const PLANTED: &str = "background\n color= 0.2 0.3 0.4\nend\n\
camera\n O= 0 0 1\n N= 0 1 0\n lens_W= 2\n lens_H= 2\n image_W= 40\n image_H= 40\nend\n\
light point\n O= 0 5 6\n color= 1 1 1\nend\n\
primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 0.9\nend\n\
primitive sphere\n O= 0 5 3\n R= 1\n color= 1 0 0\n diff= 0.9\nend\n\
primitive square\n O= -3 5 1\n Dx= 0 0.9 0\n Dy= 0 0 0.9\n color= 1 1 1\n diff= 0.9\nend\n\
primitive square\n O= 3 5 1\n Dx= 0 0.9 0\n Dy= 0 0 0.9\n color= 1 1 1\n diff= 0.9\nend\n";

/// The pixel whose centre ray (at --spp 1) first meets `want` there.
fn pixel_at(r: &Renderer, s: &Scene, want: DVec3) -> (u32, u32) {
    let cam = s.camera();
    let mut best = (0, 0, f64::INFINITY);
    for y in 0..cam.height {
        for x in 0..cam.width {
            let d = camera_dir(
                cam.dir,
                (cam.lens_w, cam.lens_h),
                (cam.width, cam.height),
                x,
                y,
            );
            if let Some(h) = r.probe(cam.origin, d) {
                let e = (h.point - want).length();
                if e < best.2 {
                    best = (x, y, e);
                }
            }
        }
    }
    assert!(best.2 < 0.3, "no pixel sees {want}");
    (best.0, best.1)
}

#[test]
fn verdicts_name_the_planted_causes() {
    let s = scene(PLANTED);
    let r = Renderer::new(s.clone());
    let one = RenderOptions {
        spp: Some(1),
        ..RenderOptions::default()
    };
    // The floor under the ball (lines: the sphere block starts at line 15).
    let sphere_line = PLANTED
        .lines()
        .position(|l| l == "primitive sphere")
        .map(|i| i + 1);
    assert_eq!(s.block_line(1), sphere_line.map(|l| l as u32));
    let (x, y) = pixel_at(&r, &s, DVec3::new(0.0, 4.5, 0.0));
    let e = explain(&r, &one, x, y);
    let light = &e.samples[0].lights[0];
    assert_eq!(light.s, 0.0);
    let blocker = light.blocker.as_ref().expect("a blocker");
    assert_eq!(blocker.primitive, Some(1));
    // The shadow ray from (0, 4.5, 0) to (0, 5, 6) meets the ball of radius 1 at (0, 5, 3).
    let (p, l) = (DVec3::new(0.0, 4.5, 0.0), DVec3::new(0.0, 5.0, 6.0));
    let d = (l - p).normalize();
    let oc = p - DVec3::new(0.0, 5.0, 3.0);
    let b = oc.dot(d);
    let t = -b - (b * b - oc.length_squared() + 1.0).sqrt();
    assert!((blocker.t - t).abs() < 0.05, "{} vs {t}", blocker.t);
    let at = format!("line {}", sphere_line.unwrap_or(0));
    assert!(
        e.verdict.contains("shadow") && e.verdict.contains(&at),
        "{}",
        e.verdict
    );
    assert_eq!(e.bytes, [0, 0, 0]);

    // The sky.
    let e = explain(&r, &one, 20, 0);
    assert!(e.samples[0].hit.is_none());
    assert!(e.verdict.starts_with("background"), "{}", e.verdict);
    assert_eq!(e.bytes, [51, 76, 102]);

    // The left square's normal is +x (Dx × Dy = y × z): the camera at x = 0
    // sees its front, lit from x = 0 too. The right one's normal is +x as
    // well: seen from behind, and facing away from the light.
    let (x, y) = pixel_at(&r, &s, DVec3::new(3.0, 5.0, 1.0));
    let e = explain(&r, &one, x, y);
    let hit = e.samples[0].hit.as_ref().expect("a hit");
    assert_eq!(hit.primitive, Some(3));
    assert!(!hit.front);
    assert!(e.verdict.contains("back face"), "{}", e.verdict);
    // The light at x = 0 is on the side the camera sees: lit, not away.
    assert!(e.samples[0].lights[0].l_dot_n > 0.0);

    let (x, y) = pixel_at(&r, &s, DVec3::new(-3.0, 5.0, 1.0));
    let e = explain(&r, &one, x, y);
    assert!(e.samples[0].hit.as_ref().is_some_and(|h| h.front));
}

/// A wall whose lit side faces away from the only light: black, and said so.
#[test]
fn a_face_turned_from_every_light_is_black_and_said_to_be() {
    let s = scene(
        "camera\n O= 0 0 0\n N= 0 1 0\n image_W= 9\n image_H= 9\nend\n\
         light point\n O= 0 10 0\n color= 1 1 1\nend\n\
         primitive plane\n N= 0 -1 0\n R= -5\n color= 1 1 1\n diff= 1\nend\n",
    );
    let r = Renderer::new(s);
    // The plane y = 5 faces the camera (N = -y); the light behind it is on its other side.
    let e = explain(&r, &RenderOptions::default(), 0, 0);
    let root = &e.samples[0];
    assert!(
        root.hit
            .as_ref()
            .is_some_and(|h| h.front && h.primitive == Some(0))
    );
    assert!(root.lights[0].l_dot_n < 0.0);
    assert_eq!(root.lights[0].rays, 0);
    assert_eq!(e.bytes, [0, 0, 0]);
    assert!(
        e.verdict.contains("faces away from every light"),
        "{}",
        e.verdict
    );
    // The JSON is one object with the documented fields, finite numbers only.
    let v: serde_json::Value =
        serde_json::from_str(&e.to_json(false)).unwrap_or_else(|err| panic!("{err}"));
    assert_eq!(v["bytes"], serde_json::json!([0, 0, 0]));
    assert_eq!(v["samples"][0]["hit"]["primitive"], 0);
    assert_eq!(v["samples"][0]["hit"]["line"], 11);
    assert_eq!(v["samples"][0]["kind"], "camera");
    assert!(v["verdict"].is_string());
}

/// Out of the frame is an error, not a panic.
#[test]
fn a_pixel_outside_the_frame_is_an_error() {
    let r = Renderer::new(scene("camera\n image_W= 4\n image_H= 3\nend\n"));
    let options = RenderOptions::default();
    assert!(r.explain(&options, 4, 0).is_err());
    assert!(r.explain(&options, 0, 3).is_err());
    assert!(r.explain(&options, u32::MAX, u32::MAX).is_err());
    assert!(r.explain(&options, 3, 2).is_ok());
    // Every sample's tree is kept: a huge --spp is refused, not a crash.
    let many = RenderOptions {
        spp: Some(u32::MAX),
        ..RenderOptions::default()
    };
    assert!(matches!(
        r.explain(&many, 0, 0),
        Err(glint::RenderError::Samples { .. })
    ));
}

/// Glass whose lit side faces away from the camera is not called black:
/// its colour is what it lets through.
#[test]
fn glass_facing_away_from_the_light_is_not_called_black() {
    let s = scene(
        "background\n color= 0.5 0.6 0.9\nend\n\
         camera\n O= 0 -8 0\n N= 0 1 0\n image_W= 21\n image_H= 21\nend\n\
         light point\n O= 0 8 0\n color= 1 1 1\nend\n\
         primitive sphere\n O= 0 0 0\n R= 2\n color= 1 1 1\n spec= 0.3\n refr= 0.9\n rindex= 1.5\nend\n",
    );
    let r = Renderer::new(s);
    let options = RenderOptions {
        spp: Some(1),
        ..RenderOptions::default()
    };
    let e = explain(&r, &options, 10, 10);
    assert_ne!(e.bytes, [0, 0, 0]);
    assert!(
        e.verdict.contains("faces away from every light"),
        "{}",
        e.verdict
    );
    assert!(!e.verdict.starts_with("black"), "{}", e.verdict);
    assert!(
        e.verdict.contains("reflects or lets through"),
        "{}",
        e.verdict
    );
}

/// A ball lit from the camera, on the background, at --spp 4: a pixel on
/// its silhouette has samples on the ball and samples on the background
/// (counted here by probing each sample's camera ray), and its verdict
/// names both sides with their counts; a pixel wholly on one side names
/// no edge.
#[test]
fn a_silhouette_pixel_is_called_an_edge_between_its_sides() {
    const BALL: &str = "background\n color= 0.2 0.3 0.4\nend\n\
        camera\n O= 0 -6 0\n N= 0 1 0\n image_W= 24\n image_H= 18\nend\n\
        light point\n O= 0 -6 0\n color= 1 1 1\nend\n\
        primitive sphere\n O= 0 0 0\n R= 1.5\n color= 0.9 0.5 0.2\n diff= 0.8\nend\n";
    let line = BALL
        .lines()
        .position(|l| l == "primitive sphere")
        .unwrap_or(0)
        + 1;
    let r = Renderer::new(scene(BALL));
    let options = RenderOptions {
        spp: Some(4),
        ..RenderOptions::default()
    };
    let (mut edges, mut whole) = (0, 0);
    for y in 0..18 {
        for x in 0..24 {
            let e = explain(&r, &options, x, y);
            assert_eq!(e.samples.len(), 4);
            let on_ball = e
                .samples
                .iter()
                .filter(|s| r.probe(s.origin, s.direction).is_some())
                .count();
            let v = &e.verdict;
            if on_ball == 0 || on_ball == 4 {
                assert!(!v.contains("edge"), "({x}, {y}): {v}");
                whole += 1;
                continue;
            }
            edges += 1;
            let ball = format!("sphere #0 (line {line}) (lit: {on_ball} of 4 samples)");
            let sky = format!("the background ({} of 4 samples)", 4 - on_ball);
            // The side more samples see first; of two and two, the one seen first.
            let ball_first = match on_ball {
                2 => r
                    .probe(e.samples[0].origin, e.samples[0].direction)
                    .is_some(),
                n => n > 2,
            };
            let (first, second) = if ball_first { (ball, sky) } else { (sky, ball) };
            assert!(
                v.starts_with(&format!(
                    "edge between {first} and {second}: the pixel is their mean."
                )),
                "({x}, {y}): {v}"
            );
            // The first side is explained.
            let told = match (on_ball, ball_first) {
                (2, true) => "The first of the largest sides: sphere #0",
                (2, false) => "The first of the largest sides: background",
                (_, true) => "Most samples: sphere #0",
                (_, false) => "Most samples: background",
            };
            assert!(v.contains(told), "({x}, {y}): {v}");
        }
    }
    assert!(
        edges >= 8 && whole >= 100,
        "{edges} edge pixels, {whole} whole"
    );
}
