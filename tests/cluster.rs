//! Tiles over real engines, merged to the very bytes of one render (issue
//! #30): Slurm array tasks running `glint render --tile I/N` and `glint
//! merge` against `glint render` for every format, adaptive anti-aliasing
//! across a band edge, `--spp`, AOVs, more parts than bands, PM, PPM and
//! SPPM; a missing, a corrupt and a foreign tile named, and the missing one
//! rerun alone; a task requeued mid-render; the script `glint job slurm`
//! prints, run for real; the Kubernetes Indexed Job's command run index by
//! index; the GNU parallel line, run for real.
//!
//! The Slurm tests need a cluster that answers (`scripts/slurm-local.sh
//! start`, then `source` the env file it names: `SLURM_CONF`); without one
//! they say they were skipped and why, unless `GLINT_REQUIRE_SLURM=1` (as in
//! `.ci/run`), which makes that a failure. The GNU parallel test likewise,
//! with `GLINT_REQUIRE_PARALLEL=1`. The Kubernetes test needs neither.

#[path = "cluster_support/mod.rs"]
mod support;

use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant};
use support::*;

/// 64×48, adaptive anti-aliasing: the sphere's silhouette and its shadow
/// cross the edge between band 0 (rows 0–31) and band 1 (rows 32–47).
const EDGE: &str = "camera
    image_W= 64
    image_H= 48
end
light point
    O= 2 0 6
    color= 1 1 1
end
primitive plane
    N= 0 0 1
    R= -1
    color= 0.3 0.6 0.3
    diff= 1
end
primitive sphere
    O= 0.3 5 -0.5
    R= 1
    color= 1 0 0
    diff= 1
end
";

/// 64×48, the variant dialect's glass ball over a floor under a point light:
/// a caustic for the photon algorithms (as in `tests/photons.rs`).
const GLASS: &str = "camera
    O= 0 -6 2
    N= 0 1 -0.2
    image_W= 64
    image_H= 48
    sample_photons= 20
    sample_dist= 0.3
    algorithm= RT
end
light point
    O= 0 0 5
    color= 20 20 20
end
primitive plane
    N= 0 0 1
    R= 0
    color= 0.8 0.8 0.8
    diff= 1
end
primitive plane
    N= 0 -1 0
    R= -3
    color= 0.8 0.3 0.3
    diff= 1
end
primitive sphere
    O= 0 0 1
    R= 1
    color= 1 1 1
    refr= 1
    rindex= 1.5
end
";

/// Every render of these tests is seeded, so that a tile of another seed is foreign.
const SEED: &str = "7";

/// One way of splitting a render: its render options, the parts, the formats merged.
struct Case<'a> {
    name: &'a str,
    scene: &'a Path,
    args: Vec<&'a str>,
    parts: usize,
    exts: &'a [&'a str],
}

/// `args` with the seed.
fn seeded<'a>(args: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["--seed", SEED];
    v.extend_from_slice(args);
    v
}

/// Renders `scene` whole into `out` (`glint render SCENE -o OUT --quiet ARGS`).
fn render(scene: &Path, out: &Path, args: &[&str]) {
    let mut all = vec!["render", text(scene), "-o", text(out), "--quiet"];
    all.extend_from_slice(args);
    assert_ok(&glint(&all), &format!("glint {}", all.join(" ")));
}

/// `glint merge TILES -o OUT`.
fn merge(tiles: &Path, out: &Path) -> Output {
    glint(&["merge", text(tiles), "-o", text(out)])
}

/// Renders each case's parts as a Slurm array (all cases at once), merges
/// them into every format and compares each with the single render's files.
fn merged_equals_single(s: &Scratch, cases: &[Case]) {
    let mut jobs = Vec::new();
    for c in cases {
        let script = s.path().join(format!("{}.sbatch", c.name));
        let tiles = s.sub(&format!("{}.tiles", c.name));
        s.task_script(&script, "", c.scene, c.parts, &tiles, &seeded(&c.args));
        jobs.push((script, format!("0-{}", c.parts - 1)));
    }
    let jobs: Vec<(&Path, &str)> = jobs
        .iter()
        .map(|(p, i)| (p.as_path(), i.as_str()))
        .collect();
    s.arrays(&jobs);
    for c in cases {
        let tiles = s.path().join(format!("{}.tiles", c.name));
        let want: Vec<String> = (0..c.parts)
            .map(|i| format!("tile-{i}-of-{}.glt", c.parts))
            .collect();
        assert_eq!(
            names(&tiles),
            want,
            "{}: one tile a task, nothing else",
            c.name
        );
        for ext in c.exts {
            let single = s.sub(&format!("{}.single.{ext}", c.name));
            let merged = s.sub(&format!("{}.merged.{ext}", c.name));
            render(
                c.scene,
                &single.join(format!("out.{ext}")),
                &seeded(&c.args),
            );
            let out = merge(&tiles, &merged.join(format!("out.{ext}")));
            assert_ok(&out, &format!("{}: glint merge into .{ext}", c.name));
            assert_same_files(&single, &merged, &format!("{} (.{ext})", c.name));
        }
    }
}

#[test]
fn merged_tiles_are_the_single_renders_bytes_in_every_format() {
    if !slurm_ready("merged_tiles_are_the_single_renders_bytes_in_every_format") {
        return;
    }
    let s = Scratch::for_slurm("formats");
    let scene = s.write("edge.txt", EDGE);
    // The premise: anti-aliasing refines pixels on both sides of the band edge.
    let (aa, one) = (s.path().join("aa.png"), s.path().join("one.png"));
    render(&scene, &aa, &seeded(&[]));
    render(&scene, &one, &seeded(&["--spp", "1"]));
    let (aa, one) = (image_rows(&aa), image_rows(&one));
    for row in [31, 32] {
        assert_ne!(aa[row], one[row], "no pixel of row {row} is refined");
    }
    let case = Case {
        name: "edge",
        scene: &scene,
        args: vec![],
        parts: 5,
        exts: &["png", "bmp", "exr", "hdr"],
    };
    merged_equals_single(&s, &[case]);
}

/// The rows of the picture at `p`, as RGB bytes.
fn image_rows(p: &Path) -> Vec<Vec<u8>> {
    let img = image::open(p)
        .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
        .to_rgb8();
    img.rows()
        .map(|r| r.flat_map(|px| px.0).collect())
        .collect()
}

#[test]
fn merged_tiles_match_with_spp_aovs_and_more_parts_than_bands() {
    if !slurm_ready("merged_tiles_match_with_spp_aovs_and_more_parts_than_bands") {
        return;
    }
    let s = Scratch::for_slurm("options");
    let scene = s.write("edge.txt", EDGE);
    merged_equals_single(
        &s,
        &[
            Case {
                name: "spp3",
                scene: &scene,
                args: vec!["--spp", "3"],
                parts: 5,
                exts: &["png", "exr"],
            },
            Case {
                name: "aovs",
                scene: &scene,
                args: vec!["--aov", "normal,depth"],
                parts: 5,
                exts: &["exr", "png"],
            },
            // 48 rows are 2 bands: parts 2 to 6 are empty, and valid.
            Case {
                name: "seven",
                scene: &scene,
                args: vec![],
                parts: 7,
                exts: &["png", "exr"],
            },
        ],
    );
}

#[test]
fn photon_mapped_tiles_merge_to_the_single_render() {
    if !slurm_ready("photon_mapped_tiles_merge_to_the_single_render") {
        return;
    }
    let s = Scratch::for_slurm("photons");
    let scene = s.write("glass.txt", GLASS);
    // Small maps and few iterations: what matters is that every task traces
    // the same photons.
    let case = |mode| Case {
        name: mode,
        scene: &scene,
        args: vec!["--photons", mode, "--emit", "3000", "--iterations", "2"],
        parts: 5,
        exts: &["exr", "png"],
    };
    merged_equals_single(&s, &[case("pm"), case("ppm"), case("sppm")]);
}

/// Whether a line of `stderr` names tile `index` (a number of its own) and says `why`.
fn names_tile(stderr: &str, index: usize, why: &str) -> bool {
    stderr.lines().any(|line| {
        let line = line.to_lowercase();
        line.contains(why)
            && line
                .split(|c: char| !c.is_ascii_digit())
                .any(|n| n == index.to_string())
    })
}

/// Runs `glint merge TILES -o OUT/out.png` expecting exit 3, a line naming
/// tile `index` with `why`, and nothing written in OUT; returns its stderr.
fn merge_refused(tiles: &Path, out: &Path, index: usize, why: &str) -> String {
    let o = merge(tiles, &out.join("out.png"));
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(
        o.status.code(),
        Some(3),
        "merge with tile {index} {why}:\n{err}"
    );
    assert!(
        names_tile(&err, index, why),
        "no line names tile {index} as {why}:\n{err}"
    );
    let left = names(out);
    assert!(
        left.is_empty(),
        "a refused merge wrote {left:?} in {}",
        out.display()
    );
    err
}

/// Copies the files of folder `from` into a new folder `to`.
fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap_or_else(|e| panic!("{}: {e}", to.display()));
    for e in std::fs::read_dir(from).unwrap_or_else(|e| panic!("{}: {e}", from.display())) {
        let p = e
            .unwrap_or_else(|e| panic!("{}: {e}", from.display()))
            .path();
        let name = p.file_name().expect("a listed file has a name");
        std::fs::copy(&p, to.join(name)).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    }
}

#[test]
fn a_missing_corrupt_or_foreign_tile_is_named_and_a_rerun_completes_the_set() {
    if !slurm_ready("a_missing_corrupt_or_foreign_tile_is_named_and_a_rerun_completes_the_set") {
        return;
    }
    let s = Scratch::for_slurm("damaged");
    let scene = s.write("edge.txt", EDGE);
    // 160 rows: 5 bands, one in each part, so that every damaged tile holds pixels.
    let opts = seeded(&["--height", "160"]);
    let single = s.sub("single");
    render(&scene, &single.join("out.png"), &opts);
    // The task script sits in the tiles folder as render.sbatch, as `glint job
    // slurm` writes it: merge's rerun line names it.
    let tiles = s.sub("t");
    let script = tiles.join("render.sbatch");
    s.task_script(&script, "", &scene, 5, &tiles, &opts);
    s.arrays(&[(&script, "0-4")]);
    let tile = |dir: &Path, i: usize| dir.join(format!("tile-{i}-of-5.glt"));

    // A byte flipped in the middle of tile 1: corrupt.
    let corrupt = s.path().join("corrupt");
    copy_dir(&tiles, &corrupt);
    let mut bytes = read(&tile(&corrupt, 1));
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0xff;
    std::fs::write(tile(&corrupt, 1), bytes).expect("the copied tile is writable");
    merge_refused(&corrupt, &s.sub("out-corrupt"), 1, "corrupt");

    // Tile 3 of a render with another seed: foreign.
    let foreign = s.path().join("foreign");
    copy_dir(&tiles, &foreign);
    let other = s.sub("other-seed");
    let o = glint(&[
        "render",
        text(&scene),
        "--tile",
        "3/5",
        "--tiles-dir",
        text(&other),
        "--quiet",
        "--seed",
        "8",
        "--height",
        "160",
    ]);
    assert_ok(&o, "glint render --tile 3/5 --seed 8 --height 160");
    std::fs::copy(tile(&other, 3), tile(&foreign, 3)).expect("the tile of another seed is copied");
    merge_refused(&foreign, &s.sub("out-foreign"), 3, "foreign");

    // Tile 2 deleted: missing, and the rerun line is the array of that one.
    std::fs::remove_file(tile(&tiles, 2)).expect("tile 2 was written");
    let err = merge_refused(&tiles, &s.sub("out-missing"), 2, "missing");
    let rerun = format!("sbatch --array=2 {}", text(&script));
    assert!(err.contains(&rerun), "no `{rerun}` in:\n{err}");
    let status = glint(&["tiles", text(&tiles)]);
    assert_eq!(
        status.status.code(),
        Some(3),
        "glint tiles with tile 2 missing"
    );
    s.arrays(&[(&script, "2")]);
    let status = glint(&["tiles", text(&tiles)]);
    assert_ok(&status, "glint tiles after the rerun");
    let merged = s.sub("merged");
    assert_ok(
        &merge(&tiles, &merged.join("out.png")),
        "merge after the rerun",
    );
    assert_same_files(&single, &merged, "the rerun set");
}

#[test]
fn a_task_requeued_mid_render_leaves_the_same_tiles() {
    if !slurm_ready("a_task_requeued_mid_render_leaves_the_same_tiles") {
        return;
    }
    let s = Scratch::for_slurm("requeue");
    let scene = s.write("edge.txt", EDGE);
    let single = s.sub("single");
    render(&scene, &single.join("out.exr"), &seeded(&[]));
    // Task 1's first attempt marks itself and hangs where it would render;
    // `scontrol requeue` kills it and starts it again (SLURM_RESTART_COUNT=1).
    let tiles = s.sub("t");
    let attempts = s.sub("attempts");
    let before = format!(
        "if [ \"$SLURM_ARRAY_TASK_ID\" = 1 ]; then\n    touch {}/\"${{SLURM_RESTART_COUNT:-0}}\"\n    \
         [ \"${{SLURM_RESTART_COUNT:-0}}\" != 0 ] || sleep 150\nfi\n",
        sh_quote(text(&attempts))
    );
    let script = s.path().join("requeue.sbatch");
    s.task_script(&script, &before, &scene, 4, &tiles, &seeded(&[]));
    let (sbatch, job) = s.submit(&script, "0-3");
    let task = format!("{job}_1");
    let start = Instant::now();
    while !attempts.join("0").exists() {
        assert!(start.elapsed() < WAIT, "task 1 did not start: {}", s.logs());
        std::thread::sleep(Duration::from_millis(100));
    }
    assert!(
        !tiles.join("tile-1-of-4.glt").exists(),
        "task 1 wrote its tile before it rendered"
    );
    // The test is what the tasks leave: every tile, and task 1 run again.
    let all_tiles = || (0..4).all(|i| tiles.join(format!("tile-{i}-of-4.glt")).is_file());
    requeue(
        &task,
        || all_tiles() && attempts.join("1").exists(),
        || {
            format!(
                "attempts: {:?}, tiles: {:?}\n{}",
                names(&attempts),
                names(&tiles),
                s.logs()
            )
        },
    );
    // `sbatch --wait` may end with the first attempt's status (seen: 1 in
    // one CI run, 0 in others): the tasks' tiles and the merge are the test.
    let _ = sbatch.finish(WAIT);
    // The array has ended once squeue lists none of it twice in a row.
    let start = Instant::now();
    let mut empty = 0;
    while empty < 2 {
        empty = if job_state(&job).is_empty() {
            empty + 1
        } else {
            0
        };
        assert!(
            start.elapsed() < WAIT,
            "the array did not end: {}",
            s.logs()
        );
        std::thread::sleep(Duration::from_millis(500));
    }
    let merged = s.sub("merged");
    assert_ok(
        &merge(&tiles, &merged.join("out.exr")),
        "merge after the requeue",
    );
    assert_same_files(&single, &merged, "the requeued set");
}

#[test]
fn the_script_glint_job_slurm_prints_renders_the_picture() {
    if !slurm_ready("the_script_glint_job_slurm_prints_renders_the_picture") {
        return;
    }
    let s = Scratch::for_slurm("job-slurm");
    let scene = s.write("edge.txt", EDGE);
    let single = s.sub("single");
    render(&scene, &single.join("out.png"), &seeded(&[]));
    let out = s.sub("out").join("out.png");
    let printed = glint(&[
        "job",
        "slurm",
        text(&scene),
        "--tiles",
        "4",
        "-o",
        text(&out),
        "--seed",
        SEED,
    ]);
    assert_ok(&printed, "glint job slurm");
    let script = s.write("submit.sh", &String::from_utf8_lossy(&printed.stdout));
    let submitted = run(Command::new("bash").arg(&script).current_dir(s.path()));
    assert_ok(
        &submitted,
        "bash submit.sh (the script glint job slurm printed)",
    );
    let ids = s.wait_for_jobs();
    // The default tiles folder: OUT with its extension replaced by .tiles.
    let tiles = s.path().join("out/out.tiles");
    for f in ["render.sbatch", "merge.sbatch"] {
        assert!(tiles.join(f).is_file(), "no {f} in {}", tiles.display());
    }
    let said = String::from_utf8_lossy(&submitted.stdout);
    assert_eq!(ids.len(), 2, "an array job and a merge job: {ids:?}");
    for id in &ids {
        assert!(
            said.split(|c: char| !c.is_ascii_digit()).any(|n| n == id),
            "job {id} is not among the IDs the script printed:\n{said}"
        );
    }
    assert!(
        out.is_file(),
        "the merge job wrote no {}; task logs:\n{}",
        out.display(),
        s.logs()
    );
    assert_same_bytes(&single.join("out.png"), &out, "glint job slurm");
}

/// The file names in `dir`, sorted (none when it does not exist).
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The strings of a YAML sequence (a container's `command` or `args`).
fn strings(v: &serde_norway::Value) -> Vec<String> {
    v.as_sequence()
        .map(|s| {
            s.iter()
                .map(|x| x.as_str().map_or_else(|| format!("{x:?}"), str::to_string))
                .collect()
        })
        .unwrap_or_default()
}

/// Runs a Kubernetes container's `command` + `args` here, as the kubelet
/// would with `JOB_COMPLETION_INDEX` set to `index` (`$(VAR)` expanded as
/// Kubernetes does, and in the environment for a shell). The image's `glint`
/// is the one under test: in place of a `glint` command, and in `bin`, first
/// on PATH. It runs in `dir` (a pod's folder is its image's: the paths are absolute).
fn run_container(
    container: &serde_norway::Value,
    index: Option<usize>,
    bin: &Path,
    dir: &Path,
    what: &str,
) {
    let mut argv = strings(&container["command"]);
    argv.extend(strings(&container["args"]));
    assert!(
        !argv.is_empty(),
        "{what}: a container with no command: {container:?}"
    );
    if let Some(i) = index {
        for a in &mut argv {
            *a = a.replace("$(JOB_COMPLETION_INDEX)", &i.to_string());
        }
    }
    let program = match Path::new(&argv[0]).file_name() {
        Some(n) if n == "glint" => GLINT,
        _ => &argv[0],
    };
    let path = std::env::var_os("PATH").unwrap_or_default();
    let path = std::env::join_paths(
        std::iter::once(bin.to_path_buf()).chain(std::env::split_paths(&path)),
    )
    .expect("PATH's folders join");
    let mut cmd = Command::new(program);
    cmd.args(&argv[1..]).env("PATH", path).current_dir(dir);
    if let Some(i) = index {
        cmd.env("JOB_COMPLETION_INDEX", i.to_string());
    }
    assert_ok(&run(&mut cmd), &format!("{what}: {}", argv.join(" ")));
}

#[test]
fn the_kubernetes_indexed_job_renders_the_picture_index_by_index() {
    // No cluster: the YAML is parsed and each index's command run here.
    let s = Scratch::new("job-k8s");
    let scene = s.write("edge.txt", EDGE);
    let single = s.sub("single");
    render(&scene, &single.join("out.png"), &seeded(&[]));
    let out = s.sub("out").join("out.png");
    let tiles = s.path().join("tiles");
    let printed = glint(&[
        "job",
        "k8s",
        text(&scene),
        "--tiles",
        "3",
        "-o",
        text(&out),
        "--tiles-dir",
        text(&tiles),
        "--seed",
        SEED,
        "--image",
        "x",
        "--claim",
        "y",
    ]);
    assert_ok(&printed, "glint job k8s");
    let yaml = String::from_utf8_lossy(&printed.stdout);
    let docs = yaml_documents(&yaml);
    let jobs: Vec<_> = docs.iter().filter(|d| d["kind"] == "Job").collect();
    let indexed: Vec<_> = jobs
        .iter()
        .filter(|j| j["spec"]["completionMode"] == "Indexed")
        .collect();
    let merging: Vec<_> = jobs
        .iter()
        .filter(|j| j["spec"]["completionMode"] != "Indexed")
        .collect();
    assert_eq!(
        (indexed.len(), merging.len()),
        (1, 1),
        "an Indexed Job and a merge Job:\n{yaml}"
    );
    let spec = &indexed[0]["spec"];
    assert_eq!(
        spec["completions"].as_u64(),
        Some(3),
        "completions:\n{yaml}"
    );
    let fails_on_2 = fails_job_on_exit_2(&spec["podFailurePolicy"]["rules"]);
    assert!(
        fails_on_2,
        "no podFailurePolicy rule failing the job on exit code 2:\n{yaml}"
    );
    let container =
        |job: &serde_norway::Value| job["spec"]["template"]["spec"]["containers"][0].clone();
    let bin = s.sub("bin");
    std::os::unix::fs::symlink(GLINT, bin.join("glint")).expect("a glint on PATH");
    // Each pod runs its init containers (the tiles folder made) first.
    let inits = indexed[0]["spec"]["template"]["spec"]["initContainers"].clone();
    for i in 0..3 {
        let what = format!("index {i}");
        for init in inits.as_sequence().into_iter().flatten() {
            run_container(init, Some(i), &bin, s.path(), &format!("{what}'s init"));
        }
        run_container(&container(indexed[0]), Some(i), &bin, s.path(), &what);
    }
    run_container(
        &container(merging[0]),
        None,
        &bin,
        s.path(),
        "the merge Job",
    );
    assert!(out.is_file(), "the merge Job wrote no {}", out.display());
    assert_same_bytes(&single.join("out.png"), &out, "glint job k8s");
}

/// The documents of a YAML stream (`---` lines between them), empty ones left out.
fn yaml_documents(yaml: &str) -> Vec<serde_norway::Value> {
    let mut docs = vec![String::new()];
    for line in yaml.lines() {
        if line.trim_end() == "---" {
            docs.push(String::new());
        } else if let Some(doc) = docs.last_mut() {
            *doc += line;
            doc.push('\n');
        }
    }
    docs.iter()
        .map(|d| serde_norway::from_str(d).unwrap_or_else(|e| panic!("YAML: {e}\n{yaml}")))
        .filter(|d: &serde_norway::Value| !d.is_null())
        .collect()
}

/// Whether a `podFailurePolicy`'s rules fail the job on exit code 2.
fn fails_job_on_exit_2(rules: &serde_norway::Value) -> bool {
    rules.as_sequence().into_iter().flatten().any(|r| {
        r["action"] == "FailJob"
            && r["onExitCodes"]["operator"] == "In"
            && r["onExitCodes"]["values"]
                .as_sequence()
                .is_some_and(|v| v.iter().any(|c| c.as_u64() == Some(2)))
    })
}

#[test]
fn the_gnu_parallel_line_renders_the_picture() {
    if !on_path("parallel") {
        skip(
            "the_gnu_parallel_line_renders_the_picture",
            "GLINT_REQUIRE_PARALLEL",
            "no `parallel` on PATH (Debian's parallel)",
        );
        return;
    }
    let s = Scratch::new("job-parallel");
    let scene = s.write("edge.txt", EDGE);
    let single = s.sub("single");
    render(&scene, &single.join("out.png"), &seeded(&[]));
    let out = s.sub("out").join("out.png");
    let tiles = s.path().join("tiles");
    let printed = glint(&[
        "job",
        "parallel",
        text(&scene),
        "--tiles",
        "4",
        "-o",
        text(&out),
        "--tiles-dir",
        text(&tiles),
        "--seed",
        SEED,
    ]);
    assert_ok(&printed, "glint job parallel");
    let line = String::from_utf8_lossy(&printed.stdout).into_owned();
    for flag in ["--joblog", "--resume-failed"] {
        assert!(line.contains(flag), "no {flag} in:\n{line}");
    }
    // parallel keeps its state in $PARALLEL_HOME (else ~/.parallel): here.
    let home = s.sub("parallel-home");
    let o = run(Command::new("bash")
        .args(["-c", &line])
        .current_dir(s.path())
        .env("PARALLEL_HOME", &home));
    assert_ok(&o, &format!("the parallel line: {line}"));
    for i in 0..4 {
        let t = tiles.join(format!("tile-{i}-of-4.glt"));
        assert!(t.is_file(), "the parallel line wrote no {}", t.display());
    }
    if !out.exists() {
        // The line renders the tiles; the merge may be left to the user.
        assert_ok(&merge(&tiles, &out), "glint merge after the parallel line");
    }
    assert_same_bytes(&single.join("out.png"), &out, "glint job parallel");
}
