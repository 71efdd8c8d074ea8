//! The `glint` command as a user runs it: exit codes, diagnostics, files
//! written or not, and the probe's answers against closed forms.

mod common;

use common::{json_field, json_number, json_vec3};
use std::path::Path;
use std::process::{Command, Output, Stdio};

fn glint(args: &[&str], stdin: Option<&str>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_glint"));
    cmd.args(args).stdin(if stdin.is_some() {
        Stdio::piped()
    } else {
        Stdio::null()
    });
    cmd.stdout(Stdio::piped()).stderr(Stdio::piped());
    let mut child = cmd.spawn().expect("glint runs");
    if let Some(text) = stdin {
        use std::io::Write;
        child
            .stdin
            .take()
            .unwrap()
            .write_all(text.as_bytes())
            .unwrap();
    }
    child.wait_with_output().unwrap()
}

/// Runs `glint render SCENE -o OUT` followed by the `extra` arguments.
fn render(scene: &str, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["render", scene, "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    glint(&args, None)
}

/// A fresh folder for one test, removed when dropped (a failing test's too).
fn scratch(name: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("glint-cli-{name}-"))
        .tempdir()
        .unwrap()
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

/// A red ball under a point light, 32×24.
const SMALL: &str = include_str!("data/small.txt");

#[test]
fn render_writes_the_image_and_a_summary() {
    let tmp = scratch("render");
    let dir = tmp.path();
    let scene = write(dir, "small.txt", SMALL);
    let out = dir.join("small.bmp");
    let o = render(&scene, &out, &["--spp", "1"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (32, 24));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("32x24") && err.contains("Mrays/s"), "{err}");
    // --width alone keeps the aspect; --quiet prints nothing.
    let o = render(&scene, &out, &["--width", "16", "--quiet"]);
    assert!(o.status.success());
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (16, 12));
    // No temporary file left beside it.
    let names: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn a_broken_scene_exits_2_with_every_error_and_writes_nothing() {
    let tmp = scratch("broken");
    let dir = tmp.path();
    let scene = write(
        dir,
        "broken.txt",
        "camera\n    image_W= 32\nend\nprimitive spher\n    O= 0 5 0\nend\nprimitive sphere\n    O= 0 5 x\n    R= -1\nend\n",
    );
    let out = dir.join("broken.png");
    std::fs::write(&out, b"keep me").unwrap();
    let o = render(&scene, &out, &[]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    // Each error with file:line:column; the misspelt type (skipped, with a
    // warning) gets a suggestion.
    assert!(err.contains("broken.txt:4:1"), "{err}");
    assert!(err.contains("did you mean `sphere`"), "{err}");
    assert!(err.contains("broken.txt:8:12"), "{err}");
    assert!(err.contains("broken.txt:9:5"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    // The existing file is untouched.
    assert_eq!(std::fs::read(&out).unwrap(), b"keep me");
}

#[test]
fn bad_arguments_exit_2_and_write_nothing() {
    let tmp = scratch("args");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", SMALL);
    let out = dir.join("s.png");
    for args in [
        vec![
            "render",
            &scene,
            "-o",
            out.to_str().unwrap(),
            "--width",
            "0",
        ],
        vec![
            "render",
            &scene,
            "-o",
            out.to_str().unwrap(),
            "--height",
            "40000",
        ],
        vec!["render", &scene, "-o", dir.join("s.tiff").to_str().unwrap()],
        vec!["render", dir.join("missing.txt").to_str().unwrap()],
        vec!["render", &scene, "--spp", "many"],
    ] {
        let o = glint(&args, None);
        assert_eq!(
            o.status.code(),
            Some(2),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(!String::from_utf8_lossy(&o.stderr).contains("panicked"));
    }
    assert!(!out.exists());
    // A folder that does not exist for the output: exit 2, nothing created.
    let o = render(&scene, &dir.join("no/such/dir/x.png"), &["--quiet"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!dir.join("no").exists());
}

/// Renders `scene` to `out` with the argument `flag value`, which must be
/// refused: exit 2, clap's message naming the argument and saying `why`,
/// and no image. Returns the error output.
fn refused(scene: &str, out: &Path, flag: &str, value: &str, why: &str) -> String {
    let o = render(scene, out, &[flag, value]);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{flag} {value}: {err}");
    let name = flag.trim_start_matches('-').to_uppercase();
    assert!(
        err.contains(&format!("invalid value '{value}' for '{flag} <{name}>'"))
            && err.contains(why),
        "{flag} {value}: {err}"
    );
    assert!(!out.exists(), "{flag} {value} wrote {}", out.display());
    err
}

#[test]
fn zero_spp_or_threads_exit_2_and_write_nothing() {
    let tmp = scratch("zero");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", SMALL);
    let out = dir.join("s.png");
    for flag in ["--spp", "--threads"] {
        let err = refused(&scene, &out, flag, "0", "must be at least 1");
        assert!(!err.contains("panicked"), "{err}");
        // Nothing else either (no temporary file): only the scene is there.
        assert_eq!(std::fs::read_dir(dir).unwrap().count(), 1, "{flag} 0");
    }
    // 1 is the smallest value accepted.
    let o = render(&scene, &out, &["--spp", "1", "--threads", "1"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.exists());
}

#[test]
fn absurd_thread_counts_exit_2_at_once_and_write_nothing() {
    let tmp = scratch("threads");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", SMALL);
    let out = dir.join("s.png");
    // Each would start that many threads (10 000 idle ones took minutes).
    for n in ["1025", "100000", "18446744073709551615"] {
        refused(&scene, &out, "--threads", n, "must be at most 1024");
    }
    // 1024 is the largest value accepted.
    let o = render(&scene, &out, &["--threads", "1024", "--width", "8"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.exists());
}

#[test]
fn piped_stderr_gets_the_summary_line_but_no_progress_bar() {
    let tmp = scratch("progress");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", SMALL);
    let out = dir.join("s.png");
    // Large enough that a shown bar would be drawn; `glint` pipes stderr.
    let o = render(&scene, &out, &["--width", "640"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains('\r'), "a progress bar on a pipe: {err:?}");
    assert!(!err.contains("ETA"), "a progress bar on a pipe: {err:?}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(
        lines.len(),
        2,
        "expected the dialect and the summary line: {err:?}"
    );
    assert!(lines[0].starts_with("dialect f: "), "{err:?}");
    assert!(
        lines[1].contains("640x480") && lines[1].contains("Mrays/s"),
        "{err:?}"
    );
    assert!(out.exists());
    // --quiet: not even the summary line, and the image is still written.
    std::fs::remove_file(&out).unwrap();
    let o = render(&scene, &out, &["--quiet"]);
    assert!(o.status.success());
    assert!(
        o.stderr.is_empty(),
        "--quiet printed: {:?}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.exists());
}

/// (t, point, normal, front, primitive) of one probe answer.
type Expected = (f64, [f64; 3], [f64; 3], bool, &'static str);

#[test]
fn probe_answers_match_closed_forms() {
    let tmp = scratch("probe");
    let dir = tmp.path();
    let scene = write(
        dir,
        "p.txt",
        "camera\nend
light sphere\n    O= 0 -20 0\n    R= 1\n    color= 1 1 1\nend
primitive sphere\n    O= 0 5 0\n    R= 2\nend
primitive plane\n    N= 0 0 1\n    R= -3\nend
primitive square\n    O= 10 0 0\n    Dx= 1 0 0\n    Dy= 0 0 1\nend
primitive cylinder\n    O1= -10 0 -1\n    O2= -10 0 1\n    R= 0.5\nend
primitive cube\n    O= 0 0 10\n    Dx= 1 0 0\n    Dy= 0 1 0\n    x= 1\n    y= 2\n    z= 3\nend
",
    );
    let rays = "0 0 0 0 1 0
0 5 0 0 0 1
0 0 0 0 0 -2
10 -5 0.5 0 1 0
-10 -5 0 0 1 0
-10 0 5 0 0 -1
0 0 0 0 0 1
0 0 10 1 0 0
0 0 0 0 -1 0
0 0 0 1 0 0.01
";
    let o = glint(&["probe", &scene, "--rays", "-", "--json"], Some(rays));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 10);
    // (t, point, normal, front, primitive) expected by hand.
    let want: [Expected; 9] = [
        (3.0, [0.0, 3.0, 0.0], [0.0, -1.0, 0.0], true, "0"), // sphere front
        (2.0, [0.0, 5.0, 2.0], [0.0, 0.0, -1.0], false, "0"), // from inside the sphere
        (3.0, [0.0, 0.0, -3.0], [0.0, 0.0, 1.0], true, "1"), // plane below
        (5.0, [10.0, 0.0, 0.5], [0.0, -1.0, 0.0], true, "2"), // square: normal Dx × Dy = −y
        (4.5, [-10.0, -0.5, 0.0], [0.0, -1.0, 0.0], true, "3"), // cylinder side
        (4.0, [-10.0, 0.0, 1.0], [0.0, 0.0, 1.0], true, "3"), // cylinder cap
        (7.0, [0.0, 0.0, 7.0], [0.0, 0.0, -1.0], true, "4"), // cube bottom face
        (1.0, [1.0, 0.0, 10.0], [-1.0, 0.0, 0.0], false, "4"), // cube from inside
        (19.0, [0.0, -19.0, 0.0], [0.0, 1.0, 0.0], true, "null"), // the sphere light's surface
    ];
    for (line, (t, p, n, front, prim)) in lines.iter().zip(want) {
        assert_eq!(json_field(line, "hit"), "true", "{line}");
        let got_t = json_number(json_field(line, "t"));
        assert!((got_t - t).abs() <= 1e-9 * t, "{line}");
        let (gp, gn) = (
            json_vec3(json_field(line, "point")),
            json_vec3(json_field(line, "normal")),
        );
        for k in 0..3 {
            assert!((gp[k] - p[k]).abs() <= 1e-9 * (1.0 + p[k].abs()), "{line}");
            assert!((gn[k] - n[k]).abs() <= 1e-9, "{line}");
        }
        assert_eq!(json_field(line, "front"), front.to_string(), "{line}");
        assert_eq!(json_field(line, "primitive"), prim, "{line}");
    }
    assert_eq!(lines[9], "{\"hit\":false}");
}

#[test]
fn probe_rejects_bad_rays_with_line_and_column() {
    let tmp = scratch("probe-bad");
    let dir = tmp.path();
    let scene = write(dir, "p.txt", SMALL);
    let rays = write(
        dir,
        "rays.txt",
        "0 0 0 0 1 0\n\n0 0 zero 0 1 0\n0 0 0 0 0 0\n",
    );
    let o = glint(&["probe", &scene, "--rays", &rays, "--json"], None);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        o.stdout.is_empty(),
        "nothing printed before the input is known good"
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("rays.txt:3:5") && err.contains("`zero` is not a number"),
        "{err}"
    );
    assert!(err.contains("rays.txt:4:"), "{err}");
}

#[test]
fn control_characters_from_a_scene_reach_the_terminal_escaped() {
    let tmp = scratch("escape");
    let dir = tmp.path();
    let out = dir.join("s.png");
    // Two warnings (unknown key, text outside a block), each quoting a word
    // that holds an escape sequence, and an error.
    let scene = write(
        dir,
        "s.txt",
        "camera\n \u{1b}[31mO= 1 2 3\nend\n\u{1b}[2Jprimitive sphere\nend\nprimitive sphere\n R= x\nend\n",
    );
    let o = render(&scene, &out, &["--quiet"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        !err.contains('\u{1b}'),
        "a raw escape reached the terminal: {err:?}"
    );
    assert!(
        err.contains("`\\u{1b}[31mO=`") && err.contains("`\\u{1b}[2Jprimitive`"),
        "{err}"
    );
    // The caret still lines up: the quoted line shows the escape as its
    // text, and the carets span it.
    assert!(
        err.contains("2 |  \\u{1b}[31mO= 1 2 3\n  |  ^^^^^^^^^^^^\n"),
        "{err}"
    );
}

/// A scene with a warning (a misspelt key) and errors (words that are no
/// numbers, the last after a Chinese comment-like word).
const FLAWED: &str = "camera\n colour= 1 0 0\nend\nprimitive sphere\n O= 1 中文注释 x\nend\n";

/// Runs `glint render` on a scene with `NO_COLOR` set to `no_color` (or unset).
fn render_with_no_color(scene: &str, out: &Path, no_color: Option<&str>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_glint"));
    cmd.args(["render", scene, "-o", out.to_str().unwrap(), "--quiet"]);
    match no_color {
        Some(v) => cmd.env("NO_COLOR", v),
        None => cmd.env_remove("NO_COLOR"),
    };
    cmd.stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    cmd.output().expect("glint runs")
}

#[test]
fn diagnostics_have_no_colour_in_a_pipe_or_with_no_color() {
    let tmp = scratch("no-colour");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", FLAWED);
    let out = dir.join("s.png");
    for no_color in [None, Some(""), Some("1")] {
        let o = render_with_no_color(&scene, &out, no_color);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(!o.stderr.contains(&0x1b), "{no_color:?}: {err:?}");
        assert!(
            err.contains("warning: unknown key `colour=`") && err.contains("s.txt:5:12"),
            "{err}"
        );
        assert!(
            err.ends_with("3 errors in the scene; nothing was rendered\n"),
            "{err}"
        );
    }
}

#[test]
fn carets_line_up_under_chinese_text() {
    let tmp = scratch("wide");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", FLAWED);
    let o = render(&scene, &dir.join("s.png"), &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    let block = err
        .split("\n\n")
        .find(|b| b.contains("found `x`"))
        .unwrap_or_else(|| panic!("{err}"));
    let lines: Vec<&str> = block.lines().collect();
    let at = lines.iter().position(|l| l.starts_with("5 | "));
    let Some(at) = at else { panic!("{block}") };
    assert_eq!(lines[at], "5 |  O= 1 中文注释 x", "{block}");
    // ` O= 1 ` is 6 columns and each of the 4 ideographs 2, then a blank.
    let carets = lines[at + 1].strip_prefix("  | ").unwrap_or_default();
    assert_eq!(carets, format!("{}^", " ".repeat(6 + 4 * 2 + 1)), "{block}");
}

/// Runs `glint render` with its output on a terminal (through `script`),
/// with `NO_COLOR` set to `no_color` (or unset); None without `script`.
fn render_on_a_terminal(scene: &str, out: &Path, no_color: Option<&str>) -> Option<Vec<u8>> {
    let script = Path::new("/usr/bin/script");
    if !script.exists() {
        return None;
    }
    let line = format!(
        "{} render {scene} -o {} --quiet",
        env!("CARGO_BIN_EXE_glint"),
        out.display()
    );
    let mut cmd = Command::new(script);
    cmd.args(["-q", "-e", "-c", &line, "/dev/null"]);
    match no_color {
        Some(v) => cmd.env("NO_COLOR", v),
        None => cmd.env_remove("NO_COLOR"),
    };
    cmd.stdin(Stdio::null()).stderr(Stdio::piped());
    Some(cmd.output().expect("script runs").stdout)
}

#[test]
fn diagnostics_are_coloured_on_a_terminal_unless_no_color() {
    let tmp = scratch("colour");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", FLAWED);
    let out = dir.join("s.png");
    let Some(shown) = render_on_a_terminal(&scene, &out, None) else {
        eprintln!("no /usr/bin/script: the terminal case is left untested");
        return;
    };
    let text = String::from_utf8_lossy(&shown);
    assert!(text.contains("s.txt:5:12"), "{text:?}");
    assert!(text.contains("\u{1b}["), "{text:?}");
    let shown = render_on_a_terminal(&scene, &out, Some("")).unwrap_or_default();
    assert!(shown.contains(&0x1b), "an empty NO_COLOR does not count");
    let shown = render_on_a_terminal(&scene, &out, Some("1")).unwrap_or_default();
    let text = String::from_utf8_lossy(&shown);
    assert!(text.contains("s.txt:5:12"), "{text:?}");
    assert!(!shown.contains(&0x1b), "{text:?}");
}

#[test]
fn a_scene_is_never_overwritten_by_its_own_output() {
    let tmp = scratch("self-overwrite");
    let dir = tmp.path();
    let scene = write(dir, "a.png", SMALL);
    // -o naming the scene, spelled another way.
    let other = dir.join(".").join("a.png");
    let o = render(&scene, &other, &["--spp", "1"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("is the scene file"), "{err}");
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), SMALL);
    // The default output name (the scene's stem + .png) in the scene's folder.
    let o = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["render", "a.png", "--spp", "1"])
        .current_dir(dir)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), SMALL);
    // A hard link to the scene is the same file.
    let link = dir.join("b.png");
    std::fs::hard_link(&scene, &link).unwrap();
    let o = render(&scene, &link, &["--spp", "1"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&scene).unwrap(), SMALL);
    assert_eq!(
        std::fs::read_dir(dir).unwrap().count(),
        2,
        "nothing else written"
    );
}

/// Starts `glint render SCENE -o OUT --quiet` and the `extra` arguments, stderr piped.
fn spawn_render(scene: &str, out: &Path, extra: &[&str]) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["render", scene, "-o", out.to_str().unwrap(), "--quiet"])
        .args(extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Sends SIGTERM to a child.
fn terminate(child: &std::process::Child) -> bool {
    let pid = child.id().to_string();
    let status = Command::new("kill").args(["-TERM", &pid]).status();
    status.is_ok_and(|s| s.success())
}

#[test]
fn a_signal_stops_the_render_and_leaves_no_file() {
    let tmp = scratch("signal");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", SMALL);
    let out = dir.join("s.png");
    let child = spawn_render(&scene, &out, &["--width", "2000", "--spp", "4096"]);
    std::thread::sleep(std::time::Duration::from_millis(300));
    let start = std::time::Instant::now();
    assert!(terminate(&child));
    let o = child.wait_with_output().unwrap();
    assert!(start.elapsed().as_secs() < 10, "stopped promptly");
    assert_eq!(o.status.code(), Some(130));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("interrupted"), "{err}");
    assert_eq!(std::fs::read_dir(dir).unwrap().count(), 1, "only the scene");
}

/// Runs glint with stdout or stderr (`which`: 1 or 2) going to /dev/full.
fn glint_into_full(args: &[&str], which: u8) -> Output {
    let full = || {
        Stdio::from(
            std::fs::OpenOptions::new()
                .write(true)
                .open("/dev/full")
                .unwrap(),
        )
    };
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_glint"));
    cmd.args(args).stdin(Stdio::null());
    if which == 1 {
        cmd.stdout(full()).stderr(Stdio::piped());
    } else {
        cmd.stdout(Stdio::piped()).stderr(full());
    }
    cmd.output().unwrap()
}

#[test]
fn an_unwritable_stderr_keeps_the_exit_codes() {
    let tmp = scratch("stderr-full");
    let dir = tmp.path();
    let bad = write(dir, "bad.txt", "camera\n image_W= -3\nend\n");
    let o = glint_into_full(&["render", &bad, "-o", "/nonexistent/x.png"], 2);
    assert_eq!(o.status.code(), Some(2));
    let warns = write(
        dir,
        "warn.txt",
        &SMALL.replace("diff= 1", "diff= 1\n    bogus= 3"),
    );
    let out = dir.join("w.png");
    let o = glint_into_full(&["render", &warns, "-o", out.to_str().unwrap()], 2);
    assert_eq!(o.status.code(), Some(0));
    assert!(out.is_file());
}

#[test]
fn probe_output_errors_are_reported_but_a_closed_pipe_is_quiet() {
    let tmp = scratch("probe-full");
    let dir = tmp.path();
    let scene = write(dir, "p.txt", SMALL);
    let rays = write(dir, "rays.txt", "0 0 0 0 1 0\n");
    let o = glint_into_full(&["probe", &scene, "--rays", &rays, "--json"], 1);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("cannot write the probe answers"), "{err}");
    // A reader that is gone: exit 0, nothing said.
    let many = write(dir, "many.txt", &"0 0 0 0 1 0\n".repeat(200_000));
    let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(["probe", &scene, "--rays", &many, "--json"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(0));
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn argument_and_path_messages_are_escaped() {
    let tmp = scratch("escape-args");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", SMALL);
    // An override that would turn the rest of the line around.
    let o = glint(&["render", &scene, "--width", "1\u{202e}2"], None);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !err.contains('\u{202e}') && err.contains("\\u{202e}"),
        "{err}"
    );
    // The summary line names the output.
    let out = dir.join("x\u{1b}[2J\u{202e}.png");
    let o = render(&scene, &out, &["--spp", "1"]);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains('\u{1b}') && err.contains("\\u{1b}"), "{err}");
    assert!(!err.contains('\u{202e}'), "{err}");
}

#[test]
fn endless_or_odd_files_are_refused_with_their_name() {
    let tmp = scratch("endless");
    let dir = tmp.path();
    let out = dir.join("x.png");
    for (scene, why) in [
        ("/dev/zero", "is not a regular file"),
        ("/tmp", "is a directory"),
    ] {
        let o = render(scene, &out, &[]);
        assert_eq!(o.status.code(), Some(2));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(why) && err.contains(scene), "{err}");
    }
    // NUL bytes without a line break: the line limit, with the line.
    let nul = dir.join("nul.txt");
    std::fs::write(&nul, vec![0u8; (1 << 20) + 1]).unwrap();
    let o = render(nul.to_str().unwrap(), &out, &[]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("nul.txt:1:1") && err.contains("line 1 is longer than 1 MiB"),
        "{err}"
    );
    // Rays from an endless source.
    let scene = write(dir, "p.txt", SMALL);
    let o = glint(&["probe", &scene, "--rays", "/dev/zero"], None);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("/dev/zero") && err.contains("line 1 is longer"),
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn probe_rays_keep_the_scene_limits_and_json_stays_json() {
    let tmp = scratch("probe-limits");
    let dir = tmp.path();
    let scene = write(
        dir,
        "plane.txt",
        "primitive plane\n O= 0 0 0\n N= 0 0 1\n color= 1 1 1\nend\n",
    );
    let rays = write(dir, "r.txt", "0 0 1 0 0 -1\n1e308 7 -1e308 1e100 1 1e100\n");
    let o = glint(&["probe", &scene, "--rays", &rays, "--json"], None);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("r.txt:2:1:") && err.contains("1e100"), "{err}");
    // Within the limits, a hit far away along a grazing ray: no inf or NaN.
    let rays = write(
        dir,
        "r.txt",
        "0 0 1e100 1 0 -1e-300\n1e100 0 1e100 1 1 -1e-100\n",
    );
    let o = glint(&["probe", &scene, "--rays", &rays, "--json"], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout);
    for line in out.lines() {
        assert!(!line.contains("inf") && !line.contains("NaN"), "{line}");
    }
    // Bad UTF-8 in a rays file: its line and column.
    let bad = dir.join("u.txt");
    std::fs::write(&bad, b"0 0 1 0 0 -1\n0 0 \xff 0 0 1\n").unwrap();
    let o = glint(&["probe", &scene, "--rays", bad.to_str().unwrap()], None);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("u.txt:2:5:"), "{err}");
}

#[test]
fn reports_stay_small_for_a_line_of_many_bad_words() {
    let tmp = scratch("many-bad");
    let dir = tmp.path();
    let words = "x ".repeat(20_000);
    let scene = write(
        dir,
        "m.txt",
        &format!("{SMALL}primitive sphere\n R= 1\n O= {words}\nend\n"),
    );
    let o = render(&scene, &dir.join("m.png"), &[]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.len() < 20_000, "{} bytes of messages", err.len());
    // The three values `O=` takes are reported; the rest is ignored at once.
    assert_eq!(
        err.matches("expected a number after `O=`").count(),
        3,
        "{err}"
    );
    assert!(err.contains("found 20000: the rest is ignored"), "{err}");
}

#[test]
fn a_long_render_is_announced_with_what_drives_it() {
    use std::io::BufRead;
    let tmp = scratch("slow");
    let dir = tmp.path();
    let text = SMALL
        .replace("image_H= 24\n", "image_H= 24\n    shade_quality= 1024\n")
        .replace("light point", "light sphere\n    R= 1");
    let scene = write(dir, "slow.txt", &text);
    let out = dir.join("s.png");
    let mut child = spawn_render(&scene, &out, &["--width", "4000", "--spp", "64"]);
    // The warning comes before the render starts; then stop it.
    let mut first = String::new();
    let err = std::io::BufReader::new(child.stderr.take().unwrap());
    for line in err.lines() {
        let line = line.unwrap();
        if line.contains("this render") {
            first = line;
            break;
        }
    }
    terminate(&child);
    let _ = child.wait();
    assert!(
        first.contains("slow.txt") && first.contains("rays"),
        "{first}"
    );
    assert!(
        first.contains("`shade_quality=1024`") && first.contains("--spp 64"),
        "{first}"
    );
}

/// The first line of `glint render` that announces a long render (the
/// render itself is stopped once it is read).
fn slow_warning(scene: &str, out: &Path, extra: &[&str]) -> String {
    use std::io::BufRead;
    let mut child = spawn_render(scene, out, extra);
    let mut first = String::new();
    let err = std::io::BufReader::new(child.stderr.take().unwrap());
    for line in err.lines() {
        let Ok(line) = line else { break };
        if line.contains("this render") {
            first = line;
            break;
        }
    }
    terminate(&child);
    let _ = child.wait();
    first
}

/// The keys that make a render long are named with their `file:line`: the
/// image size, `shade_quality=` (the second camera block's, which
/// overrides the first's) and the area lights' headers.
#[test]
fn a_long_render_names_the_lines_of_the_keys_that_drive_it() {
    let tmp = scratch("slow-lines");
    let dir = tmp.path();
    let text = "camera
    image_W= 4000
    image_H= 3000
    shade_quality= 8
end
camera
    shade_quality= 1024
end
light sphere
    R= 1
    O= 0 0 5
    color= 1 1 1
end
primitive sphere
    R= 1
end
";
    let scene = write(dir, "lines.txt", text);
    let first = slow_warning(&scene, &dir.join("l.png"), &[]);
    // Places as the user named the file, the lines counted by hand above.
    for (line, what) in [
        (2, "`image_W=4000`"),
        (3, "`image_H=3000`"),
        (7, "`shade_quality=1024`"),
    ] {
        let want = format!("{scene}:{line} {what}");
        assert!(first.contains(&want), "{want} not in: {first}");
    }
    assert!(
        first.contains(&format!("area light(s) ({scene}:9)")),
        "{first}"
    );
    assert!(!first.contains(&format!("{scene}:4")), "{first}");
    // Sizes from the command line are not the file's keys.
    let first = slow_warning(&scene, &dir.join("l.png"), &["--width", "4000"]);
    assert!(
        first.contains(&format!("{scene}:7 `shade_quality=1024`")),
        "{first}"
    );
    assert!(!first.contains("image_W"), "{first}");
}

#[test]
fn the_memory_check_respects_the_address_space_limit() {
    let tmp = scratch("rlimit");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", SMALL);
    let out = dir.join("big.png");
    // 2 GB of address space; a 20000×20000 image needs far more.
    let script = format!(
        "ulimit -v 2000000 && exec '{}' render '{scene}' -o '{}' --width 20000 --height 20000 --spp 1",
        env!("CARGO_BIN_EXE_glint"),
        out.display()
    );
    let o = Command::new("sh").args(["-c", &script]).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("needs up to"), "{err}");
    assert!(!out.exists());
}

/// Runs `glint` with `args` and returns its stderr and its peak resident
/// memory in bytes: the kernel's figure for that one child (wait4).
#[expect(
    clippy::zombie_processes,
    reason = "reaped by wait4, which reads its rusage"
)]
fn glint_peak_memory(args: &[&str]) -> (String, u64) {
    use std::io::Read;
    let mut child = Command::new(env!("CARGO_BIN_EXE_glint"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let mut status = 0;
    // SAFETY: a zeroed rusage is a valid value for wait4 to fill.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: the pid is this test's own unreaped child; both pointers are
    // to live locals.
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as libc::pid_t);
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "{args:?}: {err}"
    );
    // Linux gives ru_maxrss in KiB.
    (err, usage.ru_maxrss as u64 * 1024)
}

/// The memory estimate `render -v` states (and refuses renders by) is an
/// estimate, not a fear: the process's peak resident memory, as the kernel
/// measured it, stays under it and above half of it, at small and large
/// sizes, for each output format, with adaptive anti-aliasing on an image
/// of edges, `--spp`, every pass, and PM, PPM and SPPM at several photon
/// counts, `max_photons=` reached or not.
#[test]
fn peak_memory_is_under_the_stated_estimate_and_above_half_of_it() {
    let tmp = scratch("memory-bound");
    let dir = tmp.path();
    let mut text = String::from(
        "camera\n O= 0 -14 5\n N= 0 1 -0.3\n image_W= 64\n image_H= 48\nend\n\
         light point\n O= 3 -6 8\n color= 1 1 1\nend\n\
         primitive plane\n N= 0 0 1\n R= 0\n color= 0.8 0.8 0.8\n diff= 0.8\nend\n",
    );
    // 16×10 small balls: edges everywhere, so the anti-aliasing works hard.
    for i in 0..16 {
        for j in 0..10 {
            text += &format!(
                "primitive sphere\n O= {} {} 0.5\n R= 0.3\n color= 0.9 0.4 0.2\n diff= 0.7\n refl= 0.2\nend\n",
                f64::from(i) * 0.8 - 6.0,
                f64::from(j) * 0.8 - 2.0
            );
        }
    }
    let scene = write(dir, "edges.txt", &text);
    // The same with a cap on the photons a pass keeps.
    let capped = write(
        dir,
        "capped.txt",
        &text.replace(" image_H= 48\n", " image_H= 48\n max_photons= 40000\n"),
    );
    let every_pass = "normal,depth,position,uv,primitive,albedo,light:1,shade,why,rays,cost,clamp";
    let photons = |mode, emit| vec!["--photons", mode, "--iterations", "2", "--emit", emit];
    let cases: Vec<(&str, &str, Vec<&str>)> = vec![
        ("64x48", "png", vec![]),
        ("64x48", "exr", vec!["--aov", every_pass]),
        ("1200x900", "png", vec![]),
        ("1200x900", "exr", vec![]),
        ("1200x900", "hdr", vec!["--spp", "4"]),
        ("1200x900", "bmp", vec![]),
        ("600x450", "exr", vec!["--aov", every_pass]),
        ("600x450", "png", vec!["--aov", every_pass]),
        ("600x450", "png", photons("pm", "20000")),
        ("600x450", "png", photons("pm", "400000")),
        ("600x450", "png", photons("ppm", "20000")),
        ("300x225", "png", photons("ppm", "200000")),
        (
            "300x225",
            "png",
            [photons("ppm", "20000"), vec!["--spp", "4"]].concat(),
        ),
        ("600x450", "exr", photons("sppm", "20000")),
        ("300x225", "png", photons("sppm", "200000")),
        // Z14 stores every diffuse hit (the framework only caustics).
        (
            "300x225",
            "png",
            [
                photons("pm", "400000"),
                vec!["--dialect", "z14", "--scene-cap"],
            ]
            .concat(),
        ),
        (
            "300x225",
            "png",
            [
                photons("ppm", "400000"),
                vec!["--dialect", "z14", "--scene-cap"],
            ]
            .concat(),
        ),
        (
            "600x450",
            "png",
            [photons("sppm", "400000"), vec!["--dialect", "z14"]].concat(),
        ),
    ];
    for (size, ext, extra) in cases {
        // `--scene-cap`: the scene with `max_photons=` (this test's own flag).
        let capped_scene = extra.contains(&"--scene-cap");
        let extra: Vec<&str> = extra.into_iter().filter(|a| *a != "--scene-cap").collect();
        let scene = if capped_scene { &capped } else { &scene };
        let (w, h) = size.split_once('x').unwrap();
        let out = dir.join(format!("o.{ext}"));
        let mut args = vec![
            "render",
            &scene,
            "-o",
            out.to_str().unwrap(),
            "-v",
            "--width",
            w,
            "--height",
            h,
        ];
        args.extend(extra.iter().copied());
        let (err, peak) = glint_peak_memory(&args);
        let bound = err
            .split("note: memory: at most ")
            .nth(1)
            .and_then(|rest| rest.split(" MiB").next())
            .and_then(|mib| mib.parse::<f64>().ok())
            .unwrap_or_else(|| panic!("no bound in: {err}"));
        let peak_mib = peak as f64 / f64::from(1 << 20);
        eprintln!("{size} .{ext} {extra:?}: peak {peak_mib:.1} MiB, estimate {bound} MiB");
        assert!(
            peak_mib <= bound,
            "{size} .{ext} {extra:?}: peak {peak_mib:.1} MiB over the estimate {bound} MiB"
        );
        assert!(
            bound <= 2.0 * peak_mib,
            "{size} .{ext} {extra:?}: the estimate {bound} MiB is over twice the peak {peak_mib:.1} MiB"
        );
        if capped_scene {
            assert!(err.contains("`max_photons=40000` reached"), "{err}");
        }
    }
}

/// `glint check`: exit 0 with warnings, 1 with --deny-warnings, 2 on
/// errors; text and JSON name the file and line.
#[test]
fn check_exit_codes_text_and_json() {
    let tmp = scratch("check");
    let dir = tmp.path();
    let clean = "camera\n O= 0 -8 2\n N= 0 1 -0.2\n image_W= 64\n image_H= 48\n lens_W= 1\n lens_H= 0.75\nend\n\
                 light point\n O= 3 -6 8\n color= 1 1 1\nend\n\
                 primitive sphere\n O= 0 0 1\n R= 1\n color= 1 0.3 0.2\n diff= 0.7\nend\n";
    let good = write(dir, "good.txt", clean);
    let o = glint(&["check", &good, "--deny-warnings"], None);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    // A stretched lens (line 1: the camera block) and a black ball (line 13).
    let bad = write(
        dir,
        "bad.txt",
        &clean
            .replace("lens_H= 0.75", "lens_H= 0.5")
            .replace("color= 1 0.3 0.2", "color= 0 0 0"),
    );
    let o = glint(&["check", &bad], None);
    assert_eq!(o.status.code(), Some(0));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains(&format!("{bad}:1: warning[lens-aspect]")),
        "{text}"
    );
    assert!(
        text.contains(&format!("{bad}:13: warning[zero-material]")),
        "{text}"
    );
    assert!(text.contains("help: set `lens_H= 0.7500`"), "{text}");
    assert_eq!(
        glint(&["check", &bad, "--deny-warnings"], None)
            .status
            .code(),
        Some(1)
    );
    let o = glint(&["check", &bad, "--json"], None);
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["warnings"], 2);
    assert_eq!(json["findings"][0]["code"], "zero-material");
    assert_eq!(json["findings"][1]["code"], "lens-aspect");
    assert_eq!(json["findings"][1]["line"], 1);
    assert_eq!(json["findings"][1]["severity"], "warning");
    assert_eq!(json["findings"][1]["file"], bad.as_str());
    assert!(
        json["estimate"]["rays"]
            .as_u64()
            .is_some_and(|r| r >= 64 * 48)
    );
    // A scene that cannot be read: exit 2, its errors as findings.
    let broken = write(dir, "broken.txt", "primitive sphere\n R= -1\nend\n");
    let o = glint(&["check", &broken, "--json"], None);
    assert_eq!(o.status.code(), Some(2));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["findings"][0]["severity"], "error");
    assert_eq!(json["estimate"], serde_json::Value::Null);
    assert_eq!(
        glint(&["check", &dir.join("none.txt").to_string_lossy()], None)
            .status
            .code(),
        Some(2)
    );
}

/// `--aov light:0,shade,why,clamp` writes OUT.light-0.png ... and the why
/// legend; a bad `light:` is an argument error naming it, nothing written.
#[test]
fn shading_aovs_are_written_with_the_why_legend() {
    let tmp = scratch("shading-passes");
    let dir = tmp.path();
    let scene = write(dir, "s.txt", SMALL);
    let out = dir.join("shot.png");
    let o = render(&scene, &out, &["--aov", "light:0,shade,why,clamp", "-q"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for name in [
        "shot.light-0.png",
        "shot.shade.png",
        "shot.why.png",
        "shot.clamp.png",
        "shot.why.json",
    ] {
        assert!(dir.join(name).is_file(), "{name} missing");
    }
    let legend: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("shot.why.json")).unwrap()).unwrap();
    let kinds: Vec<&str> = legend
        .as_object()
        .unwrap()
        .values()
        .filter_map(|v| v["kind"].as_str())
        .collect();
    assert!(kinds.contains(&"background"), "{legend}");
    let bad = dir.join("bad.png");
    let o = render(&scene, &bad, &["--aov", "light:x"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("light:x"));
    assert!(!bad.exists());
}

/// A floor, spheres and a tessellated cone of triangles under a point light
/// and a square light: closest hits, packets and both kinds of shadow rays.
fn simd_scene() -> String {
    let mut s = String::from(
        "camera\n    O= 0 -6 2.5\n    N= 0 1 -0.35\n    image_W= 48\n    image_H= 36\nend\n\
         light point\n    O= 3 -4 6\n    color= 0.8 0.8 0.8\nend\n\
         light square\n    O= -2 -1 5\n    Dx= 0.7 0 0\n    Dy= 0 0.7 0\n    color= 0.6 0.6 0.6\nend\n\
         primitive plane\n    N= 0 0 1\n    R= 0\n    color= 0.8 0.8 0.8\n    diff= 0.8\nend\n",
    );
    for (k, x) in [-1.6f64, 0.0, 1.6].iter().enumerate() {
        s += &format!(
            "primitive sphere\n    O= {x} 1.5 0.5\n    R= 0.5\n    color= 0.9 0.{k} 0.3\n    diff= 0.7\n    spec= 0.3\nend\n"
        );
    }
    let n = 24;
    for i in 0..n {
        let (a, b) = (
            std::f64::consts::TAU * i as f64 / n as f64,
            std::f64::consts::TAU * (i + 1) as f64 / n as f64,
        );
        s += &format!(
            "primitive triangle\n    O1= {} {} 0\n    O2= {} {} 0\n    O3= 0 0 1.8\n    color= 0.3 0.6 0.9\n    diff= 0.8\nend\n",
            a.cos() * 0.9,
            a.sin() * 0.9 - 0.5,
            b.cos() * 0.9,
            b.sin() * 0.9 - 0.5,
        );
    }
    s
}

/// The ray queries run in the instruction set `GLINT_SIMD` names: every
/// one this CPU has draws the same bytes as the baseline; one it lacks,
/// or a name glint does not know, exits 2 and writes nothing.
#[test]
fn every_instruction_set_draws_the_same_bytes() {
    let tmp = scratch("simd");
    let dir = tmp.path();
    let scene = write(dir, "simd.txt", &simd_scene());
    let run = |isa: &str, out: &Path| {
        Command::new(env!("CARGO_BIN_EXE_glint"))
            .args(["render", &scene, "-o", out.to_str().unwrap(), "-v"])
            .env("GLINT_SIMD", isa)
            .output()
            .unwrap()
    };
    let base = dir.join("baseline.png");
    let o = run("baseline", &base);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("ray queries in baseline"));
    let want = std::fs::read(&base).unwrap();
    let mut compared = 0;
    for isa in ["best", "avx2", "avx512", "neon"] {
        let out = dir.join(format!("{isa}.png"));
        let o = run(isa, &out);
        let err = String::from_utf8_lossy(&o.stderr);
        if o.status.success() {
            assert_eq!(std::fs::read(&out).unwrap(), want, "{isa}: other bytes");
            compared += 1;
        } else {
            assert_eq!(o.status.code(), Some(2), "{isa}: {err}");
            assert!(err.contains(&format!("this CPU has no {isa}")), "{err}");
            assert!(!out.exists(), "{isa} wrote {}", out.display());
        }
    }
    assert!(compared >= 1, "`best` is always there");
    let out = dir.join("bogus.png");
    let o = run("sse9", &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("GLINT_SIMD=sse9: expected best, baseline"),
        "{err}"
    );
    assert!(!out.exists());
}
