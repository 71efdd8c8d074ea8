//! `glint compare`: a planted defect's primitive ranks first; sizes that
//! differ are an error; the command writes the heat map and JSON.

use glint::{Aov, CompareError, RenderOptions, Renderer, Scene, compare};
use std::process::Command;

const SCENE: &str = "background\n color= 0.2 0.3 0.4\nend\n\
camera\n O= 0 -8 3\n N= 0 1 -0.3\n image_W= 48\n image_H= 36\nend\n\
light point\n O= 4 -6 8\n color= 1 1 1\nend\n\
primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.7 0.6\n diff= 0.7\nend\n\
primitive sphere\n O= -1.2 -0.5 1\n R= 1\n color= 0.1 0.9 0.3\n diff= 0.8\nend\n\
primitive cube\n O= 1.5 0 1\n x= 0.7\n y= 0.7\n z= 0.7\n color= 1 0.3 0.2\n diff= 0.6\nend\n";

/// The 1-based line of the header of primitive block `block` of [`SCENE`].
fn block_line(block: u32) -> u64 {
    let at = SCENE
        .lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with("primitive"))
        .nth(block as usize)
        .map_or(0, |(i, _)| i + 1);
    at as u64
}

fn renderer() -> Renderer {
    Renderer::new(Scene::parse(SCENE, ".").unwrap_or_else(|e| panic!("{e}")))
}

/// Glint's own bytes, and the primitive plane.
fn ours(r: &Renderer) -> (Vec<u8>, Vec<f32>) {
    let options = RenderOptions {
        aovs: vec![Aov::Primitive],
        ..RenderOptions::default()
    };
    let film = r.render(&options).unwrap_or_else(|e| panic!("{e}"));
    let prim = film
        .aov(Aov::Primitive)
        .map(|p| p.data.clone())
        .unwrap_or_default();
    (film.image().to_rgb8(), prim)
}

#[test]
fn glints_own_render_does_not_differ() {
    let r = renderer();
    let (bytes, _) = ours(&r);
    let c = compare(&r, &bytes, (48, 36), 8, &RenderOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((c.differing, c.groups.len(), c.mae), (0, 0, 0.0));
    assert_eq!(c.picture.to_rgb8(), bytes);
}

#[test]
fn the_mean_absolute_difference_and_share_count_every_channel() {
    // Theirs: glint's bytes, every red channel 12 up (capped at 255) and
    // the first 100 pixels' blue channel 4 down (floored at 0): MAE is the
    // sum of those steps over 3·48·36 channels; only the red steps over 8
    // count as differing pixels.
    let r = renderer();
    let (ours, _) = ours(&r);
    let mut theirs = ours.clone();
    let mut steps = 0u64;
    let mut over = 0u64;
    for (i, p) in theirs.chunks_mut(3).enumerate() {
        let red = p[0].saturating_add(12);
        steps += u64::from(red - p[0]);
        over += u64::from(red - p[0] > 8);
        p[0] = red;
        if i < 100 {
            let blue = p[2].saturating_sub(4);
            steps += u64::from(p[2] - blue);
            p[2] = blue;
        }
    }
    let c = compare(&r, &theirs, (48, 36), 8, &RenderOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(c.mae, steps as f64 / (3 * 48 * 36) as f64);
    assert_eq!(c.differing, over);
    assert_eq!(c.share(), over as f64 / (48 * 36) as f64);
    assert!(
        c.to_text()
            .contains(&format!("mean absolute difference {:.2}/255", c.mae))
    );
}

#[test]
fn a_recoloured_primitive_ranks_first() {
    let r = renderer();
    for block in [1u32, 2] {
        let (mut bytes, prim) = ours(&r);
        // A broken intersection: the block's pixels black in "theirs", and
        // a few background pixels off by a little less than the threshold.
        let mut planted = 0;
        for (i, &p) in prim.iter().enumerate() {
            if p == block as f32 && bytes[3 * i..3 * i + 3].iter().any(|&b| b > 8) {
                bytes[3 * i..3 * i + 3].copy_from_slice(&[0, 0, 0]);
                planted += 1;
            } else if p == -1.0 {
                bytes[3 * i] = bytes[3 * i].saturating_add(8);
            }
        }
        assert!(planted > 20, "{planted}");
        let c = compare(&r, &bytes, (48, 36), 8, &RenderOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let first = &c.groups[0];
        assert_eq!(first.primitive, Some(block));
        assert_eq!((first.differing, first.black_in_theirs), (planted, planted));
        assert_eq!(c.groups.len(), 1, "{:?}", c.groups);
        assert_eq!(first.line.map(u64::from), Some(block_line(block)));
        let (x, y) = first.example;
        assert_eq!(prim[(y * 48 + x) as usize], block as f32);
        assert_eq!(first.theirs, [0, 0, 0]);
    }
}

#[test]
fn sizes_that_differ_are_an_error() {
    let r = renderer();
    let e = compare(
        &r,
        &vec![0; 40 * 30 * 3],
        (40, 30),
        8,
        &RenderOptions::default(),
    );
    assert!(
        matches!(
            e,
            Err(CompareError::Size {
                theirs_w: 40,
                theirs_h: 30,
                ours_w: 48,
                ours_h: 36
            })
        ),
        "{e:?}"
    );
    let text = e.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(text.contains("40x30") && text.contains("48x36"), "{text}");
}

#[test]
fn the_command_writes_the_heat_map_and_json() {
    let tmp = tempfile::Builder::new()
        .prefix("glint-compare-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let scene = dir.join("s.txt");
    std::fs::write(&scene, SCENE).unwrap();
    let r = Renderer::new(Scene::from_file(&scene).unwrap());
    let (mut bytes, prim) = ours(&r);
    for (i, &p) in prim.iter().enumerate() {
        if p == 2.0 {
            bytes[3 * i..3 * i + 3].copy_from_slice(&[255, 255, 255]);
        }
    }
    let theirs = dir.join("theirs.png");
    let pixels = bytes
        .chunks(3)
        .map(|p| [0, 1, 2].map(|c| p[c] as f32 / 255.0 + 0.5 / 255.0))
        .collect();
    glint::Image::from_pixels(48, 36, pixels)
        .save(&theirs)
        .unwrap();
    let heat = dir.join("heat.png");
    let run = |args: &[&std::path::Path], extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_glint"))
            .arg("compare")
            .args(args)
            .args(extra)
            .output()
            .unwrap()
    };
    let ours_png = dir.join("ours.png");
    let o = run(
        &[&scene, &theirs],
        &[
            "-o",
            heat.to_str().unwrap(),
            "--ours",
            ours_png.to_str().unwrap(),
            "--json",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(json["mae"].as_f64() > Some(0.0), "{json}");
    assert_eq!(
        json["share"].as_f64(),
        json["differing"].as_f64().map(|d| d / (48.0 * 36.0))
    );
    // The render written beside is glint's, the bytes it compared.
    let (written, _) = glint::read_picture(&ours_png).unwrap();
    assert_eq!(written, ours(&r).0);
    assert_eq!(json["groups"][0]["primitive"], 2);
    assert_eq!(json["groups"][0]["type"], "cube");
    assert_eq!(json["groups"][0]["line"], block_line(2));
    let explain = json["groups"][0]["example"]["explain"]
        .as_str()
        .unwrap_or_default();
    assert!(
        explain.starts_with(&format!("glint explain {} --pixel ", scene.display())),
        "{explain}"
    );
    assert!(heat.is_file());
    // A picture of another size: exit 2 naming both sizes, no heat map.
    let small = dir.join("small.png");
    glint::Image::from_pixels(4, 3, vec![[0.0; 3]; 12])
        .save(&small)
        .unwrap();
    let heat2 = dir.join("heat2.png");
    let o = run(&[&scene, &small], &["-o", heat2.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("4x3") && err.contains("48x36"), "{err}");
    assert!(!heat2.exists());
    // Not a picture: exit 2 naming it.
    let o = run(&[&scene, &scene], &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("s.txt"));
}

/// The words of a POSIX shell command line made of plain words,
/// single-quoted ones and backslash escapes (all that
/// `Comparison::explain_command` writes).
fn shell_words(line: &str) -> Vec<String> {
    let (mut words, mut word, mut quoted, mut any) = (Vec::new(), String::new(), false, false);
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        match c {
            '\'' => (quoted, any) = (!quoted, true),
            '\\' if !quoted => {
                word.extend(chars.next());
                any = true;
            }
            ' ' if !quoted => {
                if any {
                    words.push(std::mem::take(&mut word));
                }
                any = false;
            }
            _ => (word, any) = (word + &c.to_string(), true),
        }
    }
    if any {
        words.push(word);
    }
    words
}

#[test]
fn the_explain_command_draws_glints_pixel_as_the_compare_did() {
    // A folder with a space and a quote: the file must be quoted.
    let tmp = tempfile::Builder::new()
        .prefix("glint compare's ")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let scene = dir.join("s.txt");
    std::fs::write(&scene, SCENE).unwrap();
    // Options that change pixels: another size, jittered samples, a seed, a dialect.
    let options = RenderOptions {
        width: Some(40),
        height: Some(30),
        spp: Some(3),
        seed: 7,
        ..RenderOptions::default()
    };
    let r = Renderer::new(Scene::from_file_as(&scene, Some(glint::Dialect::Z14)).unwrap());
    let film = r.render(&options).unwrap();
    let ours = film.image().to_rgb8();
    // Theirs: glint's, with every pixel of the left half black.
    let pixels = (0..40 * 30)
        .map(|i| {
            let p = &ours[3 * i..3 * i + 3];
            let keep = i % 40 >= 20;
            [0, 1, 2].map(|c| {
                if keep {
                    p[c] as f32 / 255.0 + 0.5 / 255.0
                } else {
                    0.0
                }
            })
        })
        .collect();
    let theirs = dir.join("theirs.png");
    glint::Image::from_pixels(40, 30, pixels)
        .save(&theirs)
        .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_glint"))
        .arg("compare")
        .args([&scene, &theirs])
        .args([
            "--width", "40", "--height", "30", "--spp", "3", "--seed", "7",
        ])
        .args(["--dialect", "z14", "--json"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let groups = json["groups"].as_array().cloned().unwrap_or_default();
    assert!(!groups.is_empty());
    for g in groups {
        let line = g["example"]["explain"].as_str().unwrap_or_default();
        let words = shell_words(line);
        assert_eq!(
            words[..3],
            ["glint", "explain", scene.to_str().unwrap()],
            "{line}"
        );
        for (flag, value) in [
            ("--width", "40"),
            ("--height", "30"),
            ("--spp", "3"),
            ("--seed", "7"),
            ("--dialect", "z14"),
        ] {
            let at = words.iter().position(|w| w == flag);
            assert_eq!(at.map(|i| words[i + 1].as_str()), Some(value), "{line}");
        }
        // Run as written: explain's bytes are the render's there.
        let e = Command::new(env!("CARGO_BIN_EXE_glint"))
            .args(&words[1..])
            .arg("--json")
            .output()
            .unwrap();
        assert!(e.status.success(), "{}", String::from_utf8_lossy(&e.stderr));
        let ex: serde_json::Value = serde_json::from_slice(&e.stdout).unwrap();
        let (x, y) = (
            ex["pixel"][0].as_u64().unwrap(),
            ex["pixel"][1].as_u64().unwrap(),
        );
        let i = 3 * (y * 40 + x) as usize;
        assert_eq!(ex["bytes"], serde_json::json!(ours[i..i + 3]), "{line}");
        assert_eq!(g["example"]["glint"], ex["bytes"], "{line}");
    }
}
