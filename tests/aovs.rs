//! Passes (AOVs) against the probe, the scene's materials, and the files
//! `glint render --aov` writes.

mod common;

use common::camera_dir;
use glam::DVec3;
use glint::{Aov, Film, RenderOptions, Renderer, Scene};

/// Spheres, a cube and a floor with known colours, under one light.
const SCENE: &str = "background\n color= 0.2 0.3 0.4\nend\n\
camera\n O= 0 -8 3\n N= 0 1 -0.3\n image_W= 40\n image_H= 30\nend\n\
light point\n O= 4 -6 8\n color= 1 1 1\nend\n\
primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.7 0.6\n diff= 0.7\n refl= 0.2\nend\n\
primitive sphere\n O= -1.2 -0.5 1\n R= 1\n color= 0.1 0.9 0.3\n diff= 0.5\n refr= 0.5\n rindex= 1.5\nend\n\
primitive cube\n O= 1.5 0 1\n x= 0.7\n y= 0.7\n z= 0.7\n color= 1 0.3 0.2\n diff= 0.6\nend\n";

/// The material colour of each primitive block of [`SCENE`].
const COLOURS: [[f32; 3]; 3] = [[0.8, 0.7, 0.6], [0.1, 0.9, 0.3], [1.0, 0.3, 0.2]];

fn film(spp: Option<u32>) -> (Scene, Renderer, Film) {
    let s = Scene::parse(SCENE, ".").unwrap_or_else(|e| panic!("{e}"));
    let r = Renderer::new(s.clone());
    let options = RenderOptions {
        spp,
        aovs: Aov::ALL.to_vec(),
        ..RenderOptions::default()
    };
    let f = r.render(&options).unwrap_or_else(|e| panic!("{e}"));
    (s, r, f)
}

#[test]
fn first_hit_passes_match_the_probe_and_the_materials() {
    let (s, r, f) = film(None);
    let cam = s.camera().clone();
    let plane = |aov: Aov| f.aov(aov).unwrap_or_else(|| panic!("no {aov:?} AOV"));
    let (normal, depth, position, prim, albedo, uv) = (
        plane(Aov::Normal),
        plane(Aov::Depth),
        plane(Aov::Position),
        plane(Aov::Primitive),
        plane(Aov::Albedo),
        plane(Aov::Uv),
    );
    assert_eq!(
        (normal.channels(), depth.channels(), uv.channels()),
        (3, 1, 2)
    );
    let (mut hits, mut misses) = (0, 0);
    for y in 0..cam.height {
        for x in 0..cam.width {
            let i = (y * cam.width + x) as usize;
            let d = camera_dir(
                cam.dir,
                (cam.lens_w, cam.lens_h),
                (cam.width, cam.height),
                x,
                y,
            );
            let v3 = |p: &glint::AovImage| {
                DVec3::new(
                    p.data[3 * i] as f64,
                    p.data[3 * i + 1] as f64,
                    p.data[3 * i + 2] as f64,
                )
            };
            match r.probe(cam.origin, d) {
                None => {
                    misses += 1;
                    assert_eq!(prim.data[i], -1.0, "pixel {x} {y}");
                    assert_eq!(depth.data[i], 0.0);
                }
                Some(h) => {
                    hits += 1;
                    let b = h.primitive.unwrap_or(u32::MAX);
                    assert_eq!(prim.data[i], b as f32, "pixel {x} {y}");
                    let tol = 1e-5 * (1.0 + h.t);
                    assert!((depth.data[i] as f64 - h.t).abs() < tol, "pixel {x} {y}");
                    assert!((v3(normal) - h.normal).length() < 1e-5, "pixel {x} {y}");
                    assert!((v3(position) - h.point).length() < tol, "pixel {x} {y}");
                    let want = COLOURS[b as usize];
                    assert_eq!(&albedo.data[3 * i..3 * i + 3], &want[..], "pixel {x} {y}");
                }
            }
        }
    }
    assert!(hits > 300 && misses > 50, "{hits} hits, {misses} misses");
}

#[test]
fn passes_leave_the_picture_alone_and_follow_a_region() {
    for spp in [None, Some(2)] {
        let (_, r, f) = film(spp);
        let plain = r
            .render(&RenderOptions {
                spp,
                ..RenderOptions::default()
            })
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(f.image(), plain.image());
        assert!(plain.aovs().is_empty());
        let region = glint::Region {
            x: 7,
            y: 5,
            width: 11,
            height: 9,
        };
        let part = r
            .render(&RenderOptions {
                spp,
                region: Some(region),
                aovs: Aov::ALL.to_vec(),
                ..RenderOptions::default()
            })
            .unwrap_or_else(|e| panic!("{e}"));
        for aov in Aov::ALL {
            let (whole, cut) = (f.aov(aov).map(|p| &p.data), part.aov(aov).map(|p| &p.data));
            let (Some(whole), Some(cut)) = (whole, cut) else {
                panic!("{} missing", aov.name());
            };
            let c = aov.channels();
            for j in 0..region.height as usize {
                for i in 0..region.width as usize {
                    let a = ((region.y as usize + j) * 40 + region.x as usize + i) * c;
                    let b = (j * region.width as usize + i) * c;
                    assert_eq!(whole[a..a + c], cut[b..b + c], "{} {i} {j}", aov.name());
                }
            }
        }
    }
}

#[test]
fn pass_lists_parse_and_unknown_names_are_refused() {
    assert_eq!(
        Aov::parse_list("normal, depth,normal"),
        Ok(vec![Aov::Normal, Aov::Depth])
    );
    assert!(
        Aov::parse_list("normals").is_err_and(|e| e.contains("normals") && e.contains("albedo"))
    );
}

/// `--aov` with a PNG writes one file per pass and the legends, the
/// normals as floor(255·(0.5 + 0.5·n)).
#[test]
fn the_cli_writes_pass_files_beside_the_picture() {
    let tmp = tempfile::Builder::new()
        .prefix("glint-passes-")
        .tempdir()
        .unwrap_or_else(|e| panic!("{e}"));
    let dir = tmp.path();
    let scene = dir.join("s.txt");
    std::fs::write(&scene, SCENE).unwrap_or_else(|e| panic!("{e}"));
    let out = dir.join("shot.png");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["render", "--quiet", "--aov", "normal,depth,primitive", "-o"])
        .arg(&out)
        .arg(&scene)
        .status()
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(status.success());
    for f in [
        "shot.png",
        "shot.normal.png",
        "shot.depth.png",
        "shot.depth.json",
        "shot.primitive.png",
        "shot.primitive.json",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    let legend: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("shot.primitive.json")).unwrap_or_default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let entries = legend.as_object().map(|m| m.len()).unwrap_or(0);
    assert_eq!(entries, 3, "{legend}");
    let cube = glint::primitive_colour(2.0);
    let key = format!("#{:02x}{:02x}{:02x}", cube[0], cube[1], cube[2]);
    assert_eq!(legend[&key]["type"], "cube");
    let line = SCENE
        .lines()
        .position(|l| l == "primitive cube")
        .map(|i| i + 1);
    assert_eq!(legend[&key]["line"].as_u64(), line.map(|l| l as u64));

    let img = image::open(dir.join("shot.normal.png"))
        .unwrap_or_else(|e| panic!("{e}"))
        .to_rgb8();
    let (_, r, f) = film(None);
    drop(r);
    let n = f
        .aov(Aov::Normal)
        .map(|p| p.data.clone())
        .unwrap_or_default();
    let prim = f
        .aov(Aov::Primitive)
        .map(|p| p.data.clone())
        .unwrap_or_default();
    for (i, px) in img.pixels().enumerate() {
        if prim[i] == -1.0 {
            assert_eq!(px.0, [0, 0, 0]);
            continue;
        }
        for c in 0..3 {
            let want = (255.0 * (0.5 + 0.5 * n[3 * i + c]).clamp(0.0, 1.0)).floor() as u8;
            assert_eq!(px.0[c], want, "pixel {i}");
        }
    }
}

/// An `.exr` holds the picture and every pass as layers, values exact.
#[test]
fn an_exr_holds_the_passes_as_layers() {
    let (_, _, f) = film(Some(1));
    let tmp = tempfile::Builder::new()
        .prefix("glint-layers-")
        .tempdir()
        .unwrap_or_else(|e| panic!("{e}"));
    let path = tmp.path().join("layers.exr");
    glint::save_exr_layers(&f, &path, &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let image =
        exr::prelude::read_all_flat_layers_from_file(&path).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<String> = image
        .layer_data
        .iter()
        .map(|l| {
            l.attributes
                .layer_name
                .as_ref()
                .map(|n| n.to_string())
                .unwrap_or_default()
        })
        .collect();
    let want: Vec<String> = std::iter::once("color".to_string())
        .chain(Aov::ALL.iter().map(|a| a.name().into_owned()))
        .collect();
    assert_eq!(names, want);
    let depth = &image.layer_data[2].channel_data.list[0].sample_data;
    let want = f
        .aov(Aov::Depth)
        .map(|p| p.data.clone())
        .unwrap_or_default();
    let got: Vec<f32> = depth.values_as_f32().collect();
    assert_eq!(got, want);
}

/// Rays per pixel: at --spp 1 over a lit floor, the camera ray and one
/// shadow ray where the floor is hit, the camera ray alone elsewhere; with
/// the anti-aliasing, the plane adds up to the render's tally.
#[test]
fn the_rays_pass_counts_each_pixels_rays() {
    let s = Scene::parse(
        "camera\n O= 0 0 1\n N= 0 1 0\n image_W= 12\n image_H= 10\nend\n\
         light point\n O= 0 5 6\n color= 1 1 1\nend\n\
         primitive plane\n N= 0 0 1\n R= 0\n color= 1 1 1\n diff= 1\nend\n",
        ".",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let r = Renderer::new(s.clone());
    let options = RenderOptions {
        spp: Some(1),
        aovs: vec![Aov::Rays, Aov::Depth],
        ..RenderOptions::default()
    };
    let f = r.render(&options).unwrap_or_else(|e| panic!("{e}"));
    let rays = f.aov(Aov::Rays).map(|p| p.data.clone()).unwrap_or_default();
    let cam = s.camera();
    for y in 0..cam.height {
        for x in 0..cam.width {
            let d = camera_dir(cam.dir, (cam.lens_w, cam.lens_h), (12, 10), x, y);
            let want = if r.probe(cam.origin, d).is_some() {
                2.0
            } else {
                1.0
            };
            assert_eq!(rays[(y * 12 + x) as usize], want, "pixel {x} {y}");
        }
    }
    assert_eq!(f.aovs()[0].aov, Aov::Rays, "in the order asked for");
    let (_, r, _) = film(None);
    let adaptive = RenderOptions {
        aovs: vec![Aov::Rays],
        ..RenderOptions::default()
    };
    let (f, stats) = r
        .render_with(&adaptive, glint::Control::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let sum: f64 = f
        .aov(Aov::Rays)
        .map_or(0.0, |p| p.data.iter().map(|&v| v as f64).sum());
    assert_eq!(sum, stats.rays.total() as f64);
    assert!(stats.refined_pixels > 0);
}

/// Diffuse and specular only (no reflection or refraction), a point light
/// and a square light, one bright enough to clamp: the picture at --spp 1
/// is the clamped sum of the light:N planes.
const LIT: &str = "background\n color= 0.2 0.3 0.4\nend\n\
camera\n O= 0 -8 3\n N= 0 1 -0.3\n image_W= 40\n image_H= 30\n shade_quality= 1\nend\n\
light point\n O= 4 -6 8\n color= 1.6 1.6 1.6\nend\n\
light square\n O= -3 -2 6\n Dx= 0.7 0 0\n Dy= 0 0.7 0\n color= 0.5 0.4 0.3\nend\n\
primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.7 0.6\n diff= 0.7\nend\n\
primitive sphere\n O= -1.2 -0.5 1\n R= 1\n color= 0.1 0.9 0.3\n diff= 0.5\n spec= 0.4\nend\n\
primitive cube\n O= 1.5 0 1\n x= 0.7\n y= 0.7\n z= 0.7\n color= 1 0.3 0.2\n diff= 0.6\nend\n";

fn lit_film(aovs: Vec<Aov>) -> (Scene, Film) {
    let s = Scene::parse(LIT, ".").unwrap_or_else(|e| panic!("{e}"));
    let r = Renderer::new(s.clone());
    let options = RenderOptions {
        spp: Some(1),
        aovs,
        ..RenderOptions::default()
    };
    (s, r.render(&options).unwrap_or_else(|e| panic!("{e}")))
}

#[test]
fn the_lights_sum_to_the_picture_and_the_clamp_is_the_excess() {
    let (s, f) = lit_film(vec![
        Aov::Light(0),
        Aov::Light(1),
        Aov::Clamp,
        Aov::Primitive,
    ]);
    let plane = |aov: Aov| f.aov(aov).unwrap_or_else(|| panic!("no {aov:?} AOV"));
    let (l0, l1, clamp, prim) = (
        plane(Aov::Light(0)),
        plane(Aov::Light(1)),
        plane(Aov::Clamp),
        plane(Aov::Primitive),
    );
    let cam = s.camera();
    let (mut lit, mut clamped) = (0, 0);
    for y in 0..cam.height {
        for x in 0..cam.width {
            let i = (y * cam.width + x) as usize;
            if prim.data[i] < 0.0 {
                // Background or a light's surface: no light terms, no clamp here.
                assert!((0..3).all(|c| l0.data[3 * i + c] == 0.0 && clamp.data[3 * i + c] == 0.0));
                continue;
            }
            let px = f.image().pixel(x, y);
            for (c, &got) in px.iter().enumerate() {
                let sum = l0.data[3 * i + c] as f64 + l1.data[3 * i + c] as f64;
                let want = sum.min(1.0);
                assert!(
                    (got as f64 - want).abs() < 1e-5,
                    "({x}, {y}) channel {c}: picture {got} but lights sum to {sum}"
                );
                let over = (sum - 1.0).max(0.0);
                assert!(
                    (clamp.data[3 * i + c] as f64 - over).abs() < 1e-5,
                    "({x}, {y}) clamp"
                );
                lit += usize::from(sum > 0.0);
                clamped += usize::from(over > 0.0);
            }
        }
    }
    // The planted scene has both lit and clamped pixels.
    assert!(
        lit > 1000 && clamped > 50,
        "{lit} lit, {clamped} clamped channels"
    );
}

#[test]
fn shade_and_why_follow_shadow_rays_traced_by_the_probe() {
    // One point light: the shade factor is 1 or 0, and the verdict's kind
    // is background, faces away, in shadow, or lit.
    let text = LIT.replace(
        "light square\n O= -3 -2 6\n Dx= 0.7 0 0\n Dy= 0 0.7 0\n color= 0.5 0.4 0.3\nend\n",
        "",
    );
    let s = Scene::parse(&text, ".").unwrap_or_else(|e| panic!("{e}"));
    let r = Renderer::new(s.clone());
    let options = RenderOptions {
        spp: Some(1),
        aovs: vec![Aov::Shade, Aov::Why],
        ..RenderOptions::default()
    };
    let f = r.render(&options).unwrap_or_else(|e| panic!("{e}"));
    let (shade, why) = (f.aov(Aov::Shade).unwrap(), f.aov(Aov::Why).unwrap());
    let cam = s.camera().clone();
    let light = DVec3::new(4.0, -6.0, 8.0);
    // The legend's order (docs/debugging.md): background 0, faces away 5, in shadow 6, lit 8.
    let mut seen = [0; 9];
    for y in 0..cam.height {
        for x in 0..cam.width {
            let i = (y * cam.width + x) as usize;
            let d = camera_dir(
                cam.dir,
                (cam.lens_w, cam.lens_h),
                (cam.width, cam.height),
                x,
                y,
            );
            let (want_shade, want_why) = match r.probe(cam.origin, d) {
                None => (None, 0),
                Some(h) => {
                    let to = light - h.point;
                    if to.dot(h.normal) <= 0.0 {
                        (None, 5)
                    } else {
                        let from = h.point + h.normal * 1e-7;
                        let blocked = r.probe(from, to).is_some_and(|b| b.t < to.length());
                        if blocked {
                            (Some(0.0), 6)
                        } else {
                            (Some(1.0), 8)
                        }
                    }
                }
            };
            assert_eq!(why.data[i], want_why as f32, "why at ({x}, {y})");
            let got = (shade.data[2 * i], shade.data[2 * i + 1]);
            match want_shade {
                Some(v) => assert_eq!(got, (v, v), "shade at ({x}, {y})"),
                None => assert_eq!(got, (0.0, 0.0), "shade at ({x}, {y})"),
            }
            seen[want_why] += 1;
        }
    }
    assert!(
        seen[0] > 0 && seen[5] > 0 && seen[6] > 0 && seen[8] > 0,
        "{seen:?}"
    );
}

/// Planes alone (no tree): every query, nearest-hit or any-hit, of every
/// ray tests each plane once, as nothing blocks a shadow ray. So each
/// pixel's cost is no node and three tests per ray it traced (the `rays`
/// pass), whatever the sampling; at --spp 1 a pixel on the mirror floor
/// traces a camera, a shadow and a reflected ray (the probe says which).
#[test]
fn cost_counts_every_query_of_every_ray() {
    let planes = "camera\n O= 0 -8 3\n N= 0 1 -0.3\n image_W= 20\n image_H= 15\nend\n\
                  light point\n O= 0 0 10\n color= 1 1 1\nend\n\
                  primitive plane\n N= 0 0 1\n R= 0\n color= 1 1 1\n diff= 0.5\n refl= 0.5\nend\n\
                  primitive plane\n N= 0 0 1\n R= -20\n color= 1 1 1\n diff= 1\nend\n\
                  primitive plane\n N= 0 1 0\n R= -50\n color= 1 1 1\n diff= 1\nend\n";
    let s = Scene::parse(planes, ".").unwrap_or_else(|e| panic!("{e}"));
    let r = Renderer::new(s.clone());
    let cam = s.camera().clone();
    for spp in [Some(1), None, Some(4)] {
        let options = RenderOptions {
            spp,
            aovs: vec![Aov::Cost, Aov::Rays],
            ..RenderOptions::default()
        };
        let f = r.render(&options).unwrap_or_else(|e| panic!("{e}"));
        let (cost, rays) = (f.aov(Aov::Cost).unwrap(), f.aov(Aov::Rays).unwrap());
        let mut floor = 0;
        for y in 0..cam.height {
            for x in 0..cam.width {
                let i = (y * cam.width + x) as usize;
                let (nodes, tests) = (cost.data[2 * i], cost.data[2 * i + 1]);
                assert_eq!(
                    (nodes, tests),
                    (0.0, 3.0 * rays.data[i]),
                    "({x}, {y}) {spp:?}"
                );
                if spp == Some(1) {
                    let d = camera_dir(cam.dir, (cam.lens_w, cam.lens_h), (20, 15), x, y);
                    let on_floor = r.probe(cam.origin, d).is_some();
                    assert_eq!(tests, if on_floor { 9.0 } else { 3.0 }, "({x}, {y})");
                    floor += usize::from(on_floor);
                }
            }
        }
        assert!(
            spp != Some(1) || (50..300).contains(&floor),
            "{floor} floor pixels"
        );
    }
}

/// With a tree: every pixel's queries test the plane, and a pixel whose
/// camera ray hits a bounded object visited a node (its leaf) and tested
/// it. (The counts of a walk are tested against brute force in
/// `accel/bvh.rs`.)
#[test]
fn cost_counts_nodes_of_the_tree() {
    let (s, r, f) = film(Some(1));
    let (cost, prim) = (f.aov(Aov::Cost).unwrap(), f.aov(Aov::Primitive).unwrap());
    let cam = s.camera();
    let mut bounded = 0;
    for i in 0..(cam.width * cam.height) as usize {
        let (nodes, tests) = (cost.data[2 * i], cost.data[2 * i + 1]);
        // The plane is tested by every query; one query at the least.
        assert!(tests >= 1.0, "pixel {i}: {nodes} {tests}");
        if prim.data[i] >= 1.0 {
            bounded += 1;
            assert!(nodes >= 1.0 && tests >= 2.0, "pixel {i}: {nodes} {tests}");
        }
    }
    assert!(bounded > 50, "{bounded}");
    let _ = r;
}

#[test]
fn more_light_passes_than_one_render_takes_are_an_error() {
    let r = Renderer::new(Scene::parse(LIT, ".").unwrap_or_else(|e| panic!("{e}")));
    let asking = |n: u32| RenderOptions {
        width: Some(8),
        aovs: (0..n).map(Aov::Light).collect(),
        ..RenderOptions::default()
    };
    let max = glint::LIGHT_AOVS_MAX as u32;
    let f = r.render(&asking(max)).unwrap_or_else(|e| panic!("{e}"));
    // Lights the scene lacks are black planes.
    assert!(
        f.aov(Aov::Light(max - 1))
            .is_some_and(|p| p.data.iter().all(|&v| v == 0.0))
    );
    assert_eq!(
        r.render(&asking(max + 1)).err(),
        Some(glint::RenderError::LightAovs {
            asked: max as usize + 1,
            max: max as usize
        })
    );
}
