//! `glint render --tile`, `glint merge` and `glint tiles` through the
//! command line, the parts run one after another (the cluster tests run
//! them as Slurm tasks): the merged files are the very bytes of one
//! render for every format, with AOVs, `--spp`, a region, more parts than
//! bands and photons; tiles missing, corrupt, foreign, of another program
//! or of a newer glint are named (exit 3) and nothing is written; bad
//! options are exit 2.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use tempfile::TempDir;

const GLINT: &str = env!("CARGO_BIN_EXE_glint");

/// Edges across the band boundary at row 32, a mirror, glass, two lights.
const SCENE: &str = "background\n color= 0.1 0.15 0.3\nend\n\
    camera\n O= 0 -8 3\n N= 0 1 -0.3\n image_W= 48\n image_H= 70\n shade_quality= 1\n drefl_quality= 1\nend\n\
    light point\n O= 4 -6 8\n color= 0.8 0.8 0.8\nend\n\
    light square\n O= -3 0 6\n Dx= 0.5 0 0\n Dy= 0 0.5 0\n color= 0.4 0.4 0.4\nend\n\
    primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 0.7\n refl= 0.2\nend\n\
    primitive cube\n O= 1.5 0 1\n x= 0.7\n y= 0.7\n z= 0.7\n color= 1 0.3 0.2\n diff= 0.6\n refl= 0.3\nend\n\
    primitive sphere\n O= -1.2 -0.5 1\n R= 1\n color= 1 1 1\n refr= 0.9\n rindex= 1.5\nend\n";

/// A glass ball on a floor under a point light: photon keys of dialect v.
const GLASS: &str = "camera\n O= 0 -6 2\n N= 0 1 -0.2\n image_W= 40\n image_H= 70\n\
    sample_photons= 20\n sample_dist= 0.3\n algorithm= RT\nend\n\
    light point\n O= 0 0 5\n color= 20 20 20\nend\n\
    primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 1\nend\n\
    primitive sphere\n O= 0 0 1\n R= 1\n color= 1 1 1\n refr= 1\n rindex= 1.5\nend\n";

fn glint(args: &[&str], dir: &Path) -> Output {
    Command::new(GLINT)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("glint runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A scratch folder holding `scene.txt` with `text`, and an empty `t/`.
fn scratch(text: &str) -> TempDir {
    let dir = TempDir::new().expect("a scratch folder");
    std::fs::write(dir.path().join("scene.txt"), text).expect("writes the scene");
    std::fs::create_dir(dir.path().join("t")).expect("makes the tiles folder");
    dir
}

/// Renders every part of `n` into `t/` with `options`.
fn parts(dir: &Path, n: u32, options: &[&str]) {
    for i in 0..n {
        let tile = format!("{i}/{n}");
        let mut args = vec![
            "render",
            "scene.txt",
            "--quiet",
            "--tile",
            &tile,
            "--tiles-dir",
            "t",
        ];
        args.extend(options);
        let o = glint(&args, dir);
        assert!(o.status.success(), "part {tile}: {}", stderr(&o));
    }
}

fn bytes(path: PathBuf) -> Vec<u8> {
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Renders whole into `one.EXT` and merges `t/` into `merged.EXT`, and
/// compares every file the two wrote (the picture and its AOVs).
fn same_as_one_render(dir: &Path, ext: &str, options: &[&str], files: &[&str]) {
    let one = format!("one.{ext}");
    let mut args = vec!["render", "scene.txt", "--quiet", "-o", &one];
    args.extend(options);
    let o = glint(&args, dir);
    assert!(o.status.success(), "{}", stderr(&o));
    let merged = format!("merged.{ext}");
    let o = glint(&["merge", "t", "-o", &merged], dir);
    assert!(o.status.success(), "merge: {}", stderr(&o));
    for f in files {
        let (a, b) = (format!("one{f}"), format!("merged{f}"));
        assert!(
            bytes(dir.join(&a)) == bytes(dir.join(&b)),
            "{a} and {b} differ ({options:?})"
        );
    }
}

#[test]
fn merged_parts_are_the_bytes_of_one_render_in_every_format() {
    let dir = scratch(SCENE);
    let d = dir.path();
    parts(d, 5, &[]);
    for ext in ["png", "bmp", "exr", "hdr"] {
        same_as_one_render(d, ext, &[], &[&format!(".{ext}")]);
    }
}

#[test]
fn merged_parts_keep_aovs_spp_regions_and_take_more_parts_than_bands() {
    for (n, options, ext, files) in [
        (
            3,
            vec!["--aov", "normal,primitive,depth"],
            "png",
            vec![
                ".png",
                ".normal.png",
                ".primitive.png",
                ".primitive.json",
                ".depth.png",
                ".depth.json",
            ],
        ),
        (2, vec!["--aov", "normal,why"], "exr", vec![".exr"]),
        (4, vec!["--spp", "3"], "bmp", vec![".bmp"]),
        (2, vec!["--region", "5,20,40,69"], "png", vec![".png"]),
        (7, vec![], "png", vec![".png"]), // 70 rows: 3 bands, 4 empty parts
    ] {
        let dir = scratch(SCENE);
        parts(dir.path(), n, &options);
        same_as_one_render(dir.path(), ext, &options, &files);
    }
}

#[test]
fn merged_photon_parts_are_the_bytes_of_one_render() {
    for mode in ["pm", "ppm", "sppm"] {
        let dir = scratch(GLASS);
        let options = ["--photons", mode, "--emit", "20000", "--iterations", "3"];
        parts(dir.path(), 3, &options);
        same_as_one_render(dir.path(), "png", &options, &[".png"]);
    }
}

#[test]
fn tiles_not_done_are_named_with_the_command_that_renders_them() {
    let dir = scratch(SCENE);
    let d = dir.path();
    parts(d, 7, &["--spp", "1"]);
    // Missing, corrupt (a byte changed), foreign (another seed), another
    // program's file, a newer glint's; 0 and 6 are whole.
    std::fs::remove_file(d.join("t/tile-1-of-7.glt")).expect("removes");
    let mut changed = bytes(d.join("t/tile-2-of-7.glt"));
    let mid = changed.len() / 2;
    changed[mid] ^= 0x40;
    std::fs::write(d.join("t/tile-2-of-7.glt"), changed).expect("writes");
    let o = glint(
        &[
            "render",
            "scene.txt",
            "--quiet",
            "--spp",
            "1",
            "--seed",
            "9",
            "--tile",
            "3/7",
            "--tiles-dir",
            "t",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(d.join("t/tile-4-of-7.glt"), b"P6\n1 1\n255\n\0\0\0").expect("writes");
    let mut newer = bytes(d.join("t/tile-5-of-7.glt"));
    newer[8] = 9; // the format's version
    std::fs::write(d.join("t/tile-5-of-7.glt"), newer).expect("writes");

    let o = glint(&["merge", "t", "-o", "out.png"], d);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let e = stderr(&o);
    for line in [
        "tile 1 of 7: missing",
        "tile 2 of 7: corrupt: its checksum does not match",
        "tile 3 of 7: foreign: another render's: seed 9, not 0",
        "tile 4 of 7: corrupt: not a glint tile file",
        "tile 5 of 7: corrupt: written by a newer glint (tile format 9",
        "to render again: 1-5",
        "rerun: for i in 1 2 3 4 5; do ",
        "--tile \"$i/7\" --tiles-dir t --spp 1",
    ] {
        assert!(e.contains(line), "`{line}` not in:\n{e}");
    }
    assert!(
        !e.contains("tile 0 of 7") && !e.contains("tile 6 of 7"),
        "{e}"
    );
    assert!(!d.join("out.png").exists(), "nothing is written");
    // `tiles` says the same on stdout, exit 3.
    let o = glint(&["tiles", "t"], d);
    assert_eq!(o.status.code(), Some(3));
    let listed = String::from_utf8_lossy(&o.stdout);
    assert!(
        listed.contains("missing: 1 (1)") && listed.contains("foreign: 1 (3)"),
        "{listed}"
    );
    // With the Slurm script `glint job slurm` writes beside the tiles, the
    // rerun is an array job of just those.
    std::fs::write(d.join("t/render.sbatch"), "#!/bin/bash\n").expect("writes");
    let o = glint(&["merge", "t", "-o", "out.png"], d);
    assert!(
        stderr(&o).contains("rerun: sbatch --array=1-5 t/render.sbatch"),
        "{}",
        stderr(&o)
    );
    // Rendered again, each alone, the merge is whole.
    for i in 1..6 {
        let tile = format!("{i}/7");
        let o = glint(
            &[
                "render",
                "scene.txt",
                "--quiet",
                "--spp",
                "1",
                "--tile",
                &tile,
                "--tiles-dir",
                "t",
            ],
            d,
        );
        assert!(o.status.success(), "{}", stderr(&o));
    }
    same_as_one_render(d, "png", &["--spp", "1"], &[".png"]);
}

#[test]
fn skip_existing_leaves_a_valid_tile_of_the_same_render_alone() {
    let dir = scratch(SCENE);
    let d = dir.path();
    let run = |seed: &str| {
        glint(
            &[
                "render",
                "scene.txt",
                "--spp",
                "1",
                "--seed",
                seed,
                "--tile",
                "0/2",
                "--tiles-dir",
                "t",
                "--skip-existing",
            ],
            d,
        )
    };
    assert!(run("1").status.success());
    let path = d.join("t/tile-0-of-2.glt");
    let first = std::fs::metadata(&path)
        .and_then(|m| m.modified())
        .expect("written");
    let o = run("1");
    assert!(stderr(&o).contains("left alone"), "{}", stderr(&o));
    assert_eq!(
        std::fs::metadata(&path).and_then(|m| m.modified()).ok(),
        Some(first)
    );
    // Another seed is another render: rendered again.
    let o = run("2");
    assert!(!stderr(&o).contains("left alone"), "{}", stderr(&o));
    // The same part rendered twice writes the same bytes (a requeue, a duplicate).
    let again = bytes(path.clone());
    std::fs::remove_file(&path).expect("removes");
    assert!(run("2").status.success());
    assert!(bytes(path) == again);
    let left: Vec<_> = std::fs::read_dir(d.join("t"))
        .expect("lists")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(left.len(), 1, "no temporary file is left: {left:?}");
}

#[test]
fn bad_parts_folders_and_outputs_are_refused_naming_them() {
    let dir = scratch(SCENE);
    let d = dir.path();
    for (args, says) in [
        (vec!["--tile", "5/5", "--tiles-dir", "t"], "--tile"),
        (vec!["--tile", "0/0", "--tiles-dir", "t"], "--tile"),
        (vec!["--tile", "a/b", "--tiles-dir", "t"], "--tile"),
        (vec!["--tile", "0/2"], "--tiles-dir"),
        (vec!["--tiles-dir", "t"], "--tile"),
        (
            vec!["--tile", "0/2", "--tiles-dir", "t", "-o", "x.png"],
            "--output",
        ),
        (
            vec!["--tile", "0/2", "--tiles-dir", "nowhere"],
            "--tiles-dir nowhere",
        ),
        (
            vec!["--tile", "0/2", "--tiles-dir", "scene.txt"],
            "not a folder",
        ),
    ] {
        let mut all = vec!["render", "scene.txt"];
        all.extend(&args);
        let o = glint(&all, d);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(
            stderr(&o).contains(says),
            "{args:?}: `{says}` not in {}",
            stderr(&o)
        );
    }
    // A folder with no tiles, a missing folder, an unknown format: exit 2.
    for (args, says) in [
        (vec!["merge", "t", "-o", "x.png"], "no tile files"),
        (vec!["merge", "nowhere", "-o", "x.png"], "nowhere"),
        (vec!["merge", "t", "-o", "x.jpg"], "unknown image format"),
        (vec!["tiles", "t"], "no tile files"),
    ] {
        let o = glint(&args, d);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(says), "{args:?}: {}", stderr(&o));
    }
    let left: Vec<_> = std::fs::read_dir(d)
        .expect("lists")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(left.len(), 2, "nothing half-written: {left:?}");
}

#[test]
fn the_tiles_picture_shows_which_part_rendered_which_band() {
    let dir = scratch(SCENE);
    let d = dir.path();
    parts(d, 3, &["--spp", "1"]); // 70 rows: bands 0-31, 32-63, 64-69
    std::fs::remove_file(d.join("t/tile-1-of-3.glt")).expect("removes");
    let o = glint(&["tiles", "t", "--picture", "map.png"], d);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let map = image::open(d.join("map.png")).expect("a picture").to_rgb8();
    assert_eq!(map.dimensions(), (48, 70));
    let row = |y: u32| (0..48).map(|x| map.get_pixel(x, y).0).collect::<Vec<_>>();
    // The missing part's band is black; the others are tinted, each its own colour.
    assert!(row(40).iter().all(|p| *p == [0, 0, 0]));
    assert!(row(10).iter().all(|p| p.iter().any(|&c| c > 0)));
    assert_ne!(row(10)[0], row(66)[0], "two parts, two colours");
}
