//! `glint job slurm|k8s|parallel`: the scripts run with bash against fake
//! `sbatch`, `parallel` and `glint` commands that record their arguments,
//! the Kubernetes YAML read as the API's Jobs, and the refusals.

use k8s_openapi::api::batch::v1::Job;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A folder name no quoting mistake survives: spaces, both quotes, `$`, `%`.
const ODD: &str = "dir with 'quote' \"dq\" $x %p";

/// A scratch folder with an odd-named working folder holding a scene, and
/// fake commands that write their arguments, a line each, into `log`.
struct Setup {
    _root: tempfile::TempDir,
    /// Where glint and the scripts run.
    work: PathBuf,
    /// The fake commands: `sbatch`, `parallel` (on PATH) and `glint` (by `--glint`).
    bin: PathBuf,
    /// What the fakes record.
    log: PathBuf,
    /// The scene, `work/sc ene's.txt`.
    scene: PathBuf,
}

/// `sbatch`: records its arguments and the batch file, prints a job ID
/// (the first with a cluster name, as `--parsable` prints it on federations).
const FAKE_SBATCH: &str = r#"#!/bin/bash
n=$(( $(ls "$GLINT_TEST_LOG" | grep -c '^sbatch-[0-9]*$') + 1 ))
printf '%s\n' "$@" > "$GLINT_TEST_LOG/sbatch-$n"
cat "${@: -1}" > "$GLINT_TEST_LOG/sbatch-$n.file"
if [ "$n" = 1 ]; then echo "1234;cluster"; else echo 1235; fi
"#;

/// `glint`: records its arguments under its subcommand's name.
const FAKE_GLINT: &str = r#"#!/bin/bash
printf '%s\n' "$@" > "$GLINT_TEST_LOG/glint-$1"
"#;

/// `parallel`: records its arguments.
const FAKE_PARALLEL: &str = r#"#!/bin/bash
printf '%s\n' "$@" > "$GLINT_TEST_LOG/parallel"
"#;

/// A red ball under a point light, 32×24.
const SCENE: &str = include_str!("data/small.txt");

fn setup() -> Setup {
    let root = tempfile::Builder::new()
        .prefix("glint-job-")
        .tempdir()
        .unwrap();
    let work = root.path().join(ODD);
    let bin = root.path().join("fake bin");
    let log = root.path().join("log");
    for dir in [&work, &bin, &log] {
        std::fs::create_dir(dir).unwrap();
    }
    for (name, text) in [
        ("sbatch", FAKE_SBATCH),
        ("glint", FAKE_GLINT),
        ("parallel", FAKE_PARALLEL),
    ] {
        executable(&bin.join(name), text);
    }
    let scene = work.join("sc ene's.txt");
    std::fs::write(&scene, SCENE).unwrap();
    Setup {
        _root: root,
        work,
        bin,
        log,
        scene,
    }
}

fn executable(path: &Path, text: &str) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::write(path, text).unwrap();
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).unwrap();
}

impl Setup {
    /// `glint job ARGS` run in `work`.
    fn job<S: AsRef<std::ffi::OsStr>>(&self, args: &[S]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_glint"))
            .arg("job")
            .args(args)
            .current_dir(&self.work)
            .output()
            .unwrap()
    }

    /// `glint job ARGS` that must succeed: its stdout.
    fn script(&self, args: &[&str]) -> String {
        let out = self.job(args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
    }

    /// The fake glint's path.
    fn glint(&self) -> String {
        self.bin.join("glint").to_str().unwrap().to_string()
    }

    /// `bash -c SCRIPT` in `work`, the fakes first on PATH, with `env`.
    fn bash(&self, script: &str, env: &[(&str, &str)]) -> Output {
        let path = format!("{}:{}", self.bin.display(), std::env::var("PATH").unwrap());
        Command::new("bash")
            .arg("-c")
            .arg(script)
            .current_dir(&self.work)
            .env("PATH", path)
            .env("GLINT_TEST_LOG", &self.log)
            .env_remove("SLURM_CPUS_PER_TASK")
            .envs(env.iter().copied())
            .output()
            .unwrap()
    }

    /// The arguments a fake recorded in `log/NAME`, a line each.
    fn recorded(&self, name: &str) -> Vec<String> {
        let text = std::fs::read_to_string(self.log.join(name))
            .unwrap_or_else(|e| panic!("{name} was not run: {e}"));
        text.lines().map(str::to_string).collect()
    }
}

fn strings(words: &[&str]) -> Vec<String> {
    words.iter().map(|w| w.to_string()).collect()
}

/// The arguments sbatch reads from a batch script's `#SBATCH` lines, split
/// and unquoted as sbatch's `_get_argument` (src/sbatch/opt.c) does: single
/// or double quotes, a backslash escaping any character, `#` a comment.
fn sbatch_directives(script: &str) -> Vec<String> {
    let mut args = Vec::new();
    for line in script.lines().skip(1) {
        let Some(rest) = line.strip_prefix("#SBATCH") else {
            if line.starts_with('#') || line.trim().is_empty() {
                continue;
            }
            break; // sbatch stops at the first command
        };
        let mut chars = rest.chars().peekable();
        'line: loop {
            while chars.next_if(|c| c.is_whitespace()).is_some() {}
            if chars.peek().is_none() {
                break;
            }
            let (mut arg, mut quote, mut escaped) = (String::new(), None, false);
            while let Some(&c) = chars.peek() {
                if quote.is_none() && c.is_whitespace() {
                    break;
                }
                chars.next();
                match (escaped, quote, c) {
                    (true, _, c) => {
                        arg.push(c);
                        escaped = false;
                    }
                    (false, _, '\\') => escaped = true,
                    (false, Some(q), c) if c == q => quote = None,
                    (false, Some(_), c) => arg.push(c),
                    (false, None, '"' | '\'') => quote = Some(c),
                    (false, None, '#') => {
                        args.push(arg);
                        break 'line;
                    }
                    (false, None, c) => arg.push(c),
                }
            }
            args.push(arg);
        }
    }
    args
}

/// A string as Kubernetes expands a container's command: `$(VAR)` of a
/// defined VAR is its value, `$$` is `$`, anything else stays.
fn k8s_expand(text: &str, env: &HashMap<&str, String>) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find('$') {
        out.push_str(&rest[..at]);
        rest = &rest[at..];
        if let Some(after) = rest.strip_prefix("$$") {
            out.push('$');
            rest = after;
        } else if let Some(var) = rest.strip_prefix("$(")
            && let Some(end) = var.find(')')
            && let Some(value) = env.get(&var[..end])
        {
            out.push_str(value);
            rest = &var[end + 1..];
        } else {
            out.push('$');
            rest = &rest[1..];
        }
    }
    out.push_str(rest);
    out
}

/// The documents of a multi-document YAML, as Jobs.
fn jobs(yaml: &str) -> Vec<Job> {
    use k8s_openapi::serde::Deserialize;
    serde_norway::Deserializer::from_str(yaml)
        .map(|doc| Job::deserialize(doc).unwrap())
        .collect()
}

/// The command of the pod's container (or init container) `name`, as
/// Kubernetes runs it for completion index `index`.
fn command(job: &Job, name: &str, index: u32) -> Vec<String> {
    let pod = job.spec.as_ref().unwrap().template.spec.as_ref().unwrap();
    let init = pod.init_containers.iter().flatten();
    let container = pod
        .containers
        .iter()
        .chain(init)
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no container {name}"));
    let env = HashMap::from([("JOB_COMPLETION_INDEX", index.to_string())]);
    let words = container.command.as_ref().unwrap();
    words.iter().map(|w| k8s_expand(w, &env)).collect()
}

#[test]
fn slurm_script_writes_both_batch_files_submits_them_and_names_the_jobs() {
    let s = setup();
    let script = s.script(&[
        "slurm",
        "sc ene's.txt",
        "--tiles",
        "5",
        "-o",
        "out dir/pic.png",
        "--glint",
        &s.glint(),
        "--spp",
        "4",
        "--time",
        "1:00:00",
        "--cpus-per-task",
        "2",
        "--partition",
        "p q",
        "--account",
        "a'b",
        "--mem",
        "4G",
        "--job-name",
        r#"my "job" \ #1"#,
    ]);
    assert!(script.starts_with("#!/bin/bash\n"), "{script}");
    assert!(script.contains("\nset -euo pipefail\n"), "{script}");
    let ran = s.bash(&script, &[]);
    assert!(
        ran.status.success(),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let work = s.work.to_str().unwrap();
    let dir = format!("{work}/out dir/pic.tiles");
    let out = format!("{work}/out dir/pic.png");
    assert_eq!(
        String::from_utf8_lossy(&ran.stdout),
        format!("render job 1234 (5 tasks), merge job 1235 -> {out}\n")
    );
    assert!(Path::new(&dir).join("logs").is_dir());

    // The render array first, then the merge after it, each from DIR.
    let render = format!("{dir}/render.sbatch");
    let merge = format!("{dir}/merge.sbatch");
    assert_eq!(s.recorded("sbatch-1"), strings(&["--parsable", &render]));
    assert_eq!(
        s.recorded("sbatch-2"),
        strings(&["--parsable", "--dependency=afterok:1234", &merge])
    );
    let render_text = std::fs::read_to_string(&render).unwrap();
    let merge_text = std::fs::read_to_string(&merge).unwrap();
    assert_eq!(
        std::fs::read_to_string(s.log.join("sbatch-1.file")).unwrap(),
        render_text
    );
    assert_eq!(
        std::fs::read_to_string(s.log.join("sbatch-2.file")).unwrap(),
        merge_text
    );

    // The settings as sbatch reads them: `%` in a log's name is `%%`.
    let logs = format!("{work}/out dir/pic.tiles/logs").replace('%', "%%");
    assert_eq!(
        sbatch_directives(&render_text),
        strings(&[
            r#"--job-name=my "job" \ #1"#,
            "--array=0-4",
            &format!("--output={logs}/render-%A_%a.out"),
            "--cpus-per-task=2",
            "--time=1:00:00",
            "--partition=p q",
            "--account=a'b",
            "--mem=4G",
        ])
    );
    assert_eq!(
        sbatch_directives(&merge_text),
        strings(&[
            r#"--job-name=my "job" \ #1-merge"#,
            &format!("--output={logs}/merge-%j.out"),
            "--kill-on-invalid-dep=yes",
            "--time=1:00:00",
            "--partition=p q",
            "--account=a'b",
            "--mem=4G",
        ])
    );

    // A task renders its tile with the CPUs Slurm gave it; the merge merges.
    let task = s.bash(
        &format!("bash {}", shell_quote(&render)),
        &[("SLURM_ARRAY_TASK_ID", "3"), ("SLURM_CPUS_PER_TASK", "2")],
    );
    assert!(
        task.status.success(),
        "{}",
        String::from_utf8_lossy(&task.stderr)
    );
    let scene = s.scene.to_str().unwrap();
    assert_eq!(
        s.recorded("glint-render"),
        strings(&[
            "render",
            scene,
            "--tile",
            "3/5",
            "--tiles-dir",
            &dir,
            "--threads",
            "2",
            "--spp",
            "4"
        ])
    );
    let task = s.bash(&format!("bash {}", shell_quote(&merge)), &[]);
    assert!(
        task.status.success(),
        "{}",
        String::from_utf8_lossy(&task.stderr)
    );
    assert_eq!(
        s.recorded("glint-merge"),
        strings(&["merge", &dir, "-o", &out])
    );
}

/// `word` in single quotes for bash (the tests' own, apart from glint's).
fn shell_quote(word: &str) -> String {
    format!("'{}'", word.replace('\'', r"'\''"))
}

#[test]
fn glint_sbatch_names_the_sbatch_command_and_a_failed_submission_stops_the_script() {
    let s = setup();
    let other = s.bin.join("other sbatch");
    executable(&other, FAKE_SBATCH);
    std::fs::remove_file(s.bin.join("sbatch")).unwrap();
    let tiles_dir = s.work.join("t");
    let script = s.script(&[
        "slurm",
        "sc ene's.txt",
        "--tiles",
        "1",
        "-o",
        "o.exr",
        "--tiles-dir",
        "t",
        "--glint",
        &s.glint(),
    ]);
    let ran = s.bash(&script, &[("GLINT_SBATCH", other.to_str().unwrap())]);
    assert!(
        ran.status.success(),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let render = format!("{}/render.sbatch", tiles_dir.display());
    assert_eq!(s.recorded("sbatch-1"), strings(&["--parsable", &render]));
    assert!(
        sbatch_directives(&std::fs::read_to_string(&render).unwrap())
            .contains(&"--array=0-0".to_string())
    );

    // Without SLURM_CPUS_PER_TASK a task runs one thread.
    let task = s.bash(
        &format!("bash {}", shell_quote(&render)),
        &[("SLURM_ARRAY_TASK_ID", "0")],
    );
    assert!(
        task.status.success(),
        "{}",
        String::from_utf8_lossy(&task.stderr)
    );
    let args = s.recorded("glint-render");
    assert_eq!(args[args.len() - 2..], strings(&["--threads", "1"]));

    // An sbatch that fails: the script stops before submitting the merge.
    executable(
        &other,
        "#!/bin/bash\necho 'sbatch: error: no partition' >&2\nexit 1\n",
    );
    std::fs::remove_dir_all(&s.log).unwrap();
    std::fs::create_dir(&s.log).unwrap();
    let ran = s.bash(&script, &[("GLINT_SBATCH", other.to_str().unwrap())]);
    assert!(!ran.status.success());
    assert!(
        ran.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&ran.stdout)
    );
    assert!(String::from_utf8_lossy(&ran.stderr).contains("no partition"));
}

#[test]
fn render_options_are_passed_on_exactly_as_given() {
    let s = setup();
    let task = |extra: &[&str]| {
        let mut args = vec!["k8s", "s.txt", "--tiles", "4", "-o", "o.png"];
        args.extend(["--image", "i", "--claim", "c"]);
        args.extend_from_slice(extra);
        let yaml = s.script(&args);
        command(&jobs(&yaml)[0], "render", 1)[9..].to_vec()
    };
    assert_eq!(task(&[]), Vec::<String>::new());
    let all = [
        "--width",
        "1920",
        "--height",
        "1080",
        "--seed",
        "3",
        "--spp",
        "4",
        "--aov",
        "normal,depth",
        "--region",
        "0,8,32,16",
        "--dialect",
        "v",
        "--photons",
        "ppm",
        "--iterations",
        "100",
        "--emit",
        "5000",
        "--photon-filter",
        "cone",
        "--skip-existing",
    ];
    assert_eq!(task(&all), strings(&all));
    // Defaults are left out; aliases are given by their names.
    let defaults = [
        "--seed",
        "0",
        "--photon-filter",
        "box",
        "--dialect",
        "raytrace",
    ];
    assert_eq!(task(&defaults), strings(&["--dialect", "w"]));
}

#[test]
fn k8s_yaml_is_an_indexed_job_and_a_merge_job() {
    let s = setup();
    let yaml = s.script(&[
        "k8s",
        "scenes/a b.txt",
        "--tiles",
        "20",
        "-o",
        "/claim/out/$(JOB_COMPLETION_INDEX) $$HOME.png",
        "--image",
        "registry.example/glint:1",
        "--claim",
        "renders",
        "--mount",
        "/claim",
        "--cpus",
        "4",
        "--mem",
        "4Gi",
    ]);
    let jobs = jobs(&yaml);
    assert_eq!(jobs.len(), 2, "{yaml}");
    let (render, merge) = (&jobs[0], &jobs[1]);
    assert_eq!(
        render.metadata.name.as_deref(),
        Some("glint-job-completion-index-home")
    );
    assert_eq!(
        merge.metadata.name.as_deref(),
        Some("glint-job-completion-index-home-merge")
    );
    let spec = render.spec.as_ref().unwrap();
    assert_eq!(spec.completion_mode.as_deref(), Some("Indexed"));
    assert_eq!(spec.completions, Some(20));
    assert_eq!(spec.parallelism, Some(16));
    assert_eq!(spec.backoff_limit_per_index, Some(3));
    let rules = &spec.pod_failure_policy.as_ref().unwrap().rules;
    let fail_job: Vec<_> = rules.iter().filter(|r| r.action == "FailJob").collect();
    assert_eq!(fail_job.len(), 1);
    let codes = fail_job[0].on_exit_codes.as_ref().unwrap();
    assert_eq!(
        (codes.operator.as_str(), &codes.values[..]),
        ("In", &[2][..])
    );
    assert_eq!(codes.container_name.as_deref(), Some("render"));

    for job in &jobs {
        let pod = job.spec.as_ref().unwrap().template.spec.as_ref().unwrap();
        assert_eq!(pod.restart_policy.as_deref(), Some("Never"));
        let claim = pod.volumes.as_ref().unwrap()[0]
            .persistent_volume_claim
            .as_ref();
        assert_eq!(claim.unwrap().claim_name, "renders");
        for c in pod
            .containers
            .iter()
            .chain(pod.init_containers.iter().flatten())
        {
            assert_eq!(c.image.as_deref(), Some("registry.example/glint:1"));
            let mount = &c.volume_mounts.as_ref().unwrap()[0];
            assert_eq!(mount.mount_path, "/claim");
        }
        let requests = pod.containers[0]
            .resources
            .as_ref()
            .unwrap()
            .requests
            .as_ref();
        assert_eq!(requests.unwrap()["memory"].0, "4Gi");
    }

    // Relative paths are on the claim; `$(…)` and `$$` of a path survive
    // Kubernetes' expansion.
    let dir = "/claim/out/$(JOB_COMPLETION_INDEX) $$HOME.tiles";
    for i in [0, 7, 19] {
        let tile = format!("{i}/20");
        assert_eq!(
            command(render, "render", i),
            strings(&[
                "glint",
                "render",
                "/claim/scenes/a b.txt",
                "--tile",
                &tile,
                "--tiles-dir",
                dir,
                "--threads",
                "4"
            ])
        );
    }
    assert_eq!(
        command(render, "tiles-dir", 0),
        strings(&["mkdir", "-p", dir])
    );
    assert_eq!(
        command(merge, "merge", 0),
        strings(&[
            "glint",
            "merge",
            dir,
            "-o",
            "/claim/out/$(JOB_COMPLETION_INDEX) $$HOME.png"
        ])
    );

    // The merge waits until `glint tiles DIR` says every tile is there.
    let wait = command(merge, "wait-for-tiles", 0);
    assert_eq!(wait[..2], strings(&["sh", "-c"]));
    assert_eq!(wait[3..], strings(&["glint", dir]));
    let ran = Command::new("sh")
        .args(["-c", &wait[2], &s.glint(), "a dir's $name"])
        .env("GLINT_TEST_LOG", &s.log)
        .output()
        .unwrap();
    assert!(ran.status.success());
    assert_eq!(
        s.recorded("glint-tiles"),
        strings(&["tiles", "a dir's $name"])
    );
}

#[test]
fn k8s_parallelism_follows_the_tiles_and_the_option() {
    let s = setup();
    let parallelism = |extra: &[&str]| {
        let mut args = vec![
            "k8s", "s.txt", "-o", "o.png", "--image", "i", "--claim", "c",
        ];
        args.extend_from_slice(extra);
        jobs(&s.script(&args))[0].spec.as_ref().unwrap().parallelism
    };
    assert_eq!(parallelism(&["--tiles", "3"]), Some(3));
    assert_eq!(parallelism(&["--tiles", "100"]), Some(16));
    assert_eq!(
        parallelism(&["--tiles", "100", "--parallelism", "40"]),
        Some(40)
    );
}

#[test]
fn a_k8s_pod_runs_what_the_slurm_task_of_its_index_runs() {
    let s = setup();
    let scene = s.scene.to_str().unwrap().to_string();
    let out = s.work.join("o.hdr").to_str().unwrap().to_string();
    let common = [
        scene.as_str(),
        "--tiles",
        "7",
        "-o",
        &out,
        "--width",
        "640",
        "--aov",
        "depth",
        "--photons",
        "pm",
    ];
    let mut slurm = vec!["slurm"];
    slurm.extend(common);
    let glint = s.glint();
    slurm.extend(["--glint", &glint]);
    let script = s.script(&slurm);
    assert!(s.bash(&script, &[]).status.success());
    let render = s.work.join("o.tiles/render.sbatch");

    let mut k8s = vec!["k8s"];
    k8s.extend(common);
    k8s.extend([
        "--image",
        "i",
        "--claim",
        "c",
        "--mount",
        "/elsewhere",
        "--cpus",
        "3",
    ]);
    let yaml = s.script(&k8s);
    for i in [0, 1, 6] {
        let index = i.to_string();
        let task = s.bash(
            &format!("bash {}", shell_quote(render.to_str().unwrap())),
            &[
                ("SLURM_ARRAY_TASK_ID", &index),
                ("SLURM_CPUS_PER_TASK", "3"),
            ],
        );
        assert!(
            task.status.success(),
            "{}",
            String::from_utf8_lossy(&task.stderr)
        );
        let pod = command(&jobs(&yaml)[0], "render", i);
        assert_eq!(pod[0], "glint");
        assert_eq!(pod[1..], s.recorded("glint-render")[..], "index {i}");
    }
}

#[test]
fn parallel_line_renders_every_tile_then_merges() {
    let s = setup();
    std::fs::write(s.work.join("hosts"), ":\n").unwrap();
    let line = s.script(&[
        "parallel",
        "sc ene's.txt",
        "--tiles",
        "5",
        "-o",
        "out.bmp",
        "--glint",
        &s.glint(),
        "--jobs",
        "2",
        "--threads",
        "3",
        "--sshloginfile",
        "hosts",
        "--spp",
        "2",
    ]);
    assert_eq!(line.lines().count(), 1, "{line}");
    let ran = s.bash(&line, &[]);
    assert!(
        ran.status.success(),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    let work = s.work.to_str().unwrap();
    let dir = format!("{work}/out.tiles");
    assert!(Path::new(&dir).is_dir());
    let mut expected = strings(&[
        "--joblog",
        &format!("{dir}/joblog"),
        "--resume-failed",
        "-j",
        "2",
        "--sshloginfile",
        &format!("{work}/hosts"),
        "-q",
        &s.glint(),
        "render",
        s.scene.to_str().unwrap(),
        "--tile",
        "{}/5",
        "--tiles-dir",
        &dir,
        "--spp",
        "2",
        "--threads",
        "3",
        ":::",
    ]);
    expected.extend((0..5).map(|i| i.to_string()));
    assert_eq!(s.recorded("parallel"), expected);
    let out = format!("{work}/out.bmp");
    assert_eq!(
        s.recorded("glint-merge"),
        strings(&["merge", &dir, "-o", &out])
    );

    // A failed tile (parallel's exit code): no merge.
    std::fs::remove_file(s.log.join("glint-merge")).unwrap();
    executable(&s.bin.join("parallel"), "#!/bin/bash\nexit 1\n");
    assert!(!s.bash(&line, &[]).status.success());
    assert!(!s.log.join("glint-merge").exists());
}

/// Runs `glint job ARGS` that must be refused: exit 2, nothing on stdout,
/// and stderr naming `named`.
fn refused<S: AsRef<std::ffi::OsStr> + std::fmt::Debug>(s: &Setup, args: &[S], named: &str) {
    let out = s.job(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    assert!(
        out.stdout.is_empty(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(
        stderr.contains(named),
        "{args:?}: `{named}` not in: {stderr}"
    );
}

#[test]
fn bad_options_are_refused_naming_the_option() {
    let s = setup();
    let k8s = ["--image", "i", "--claim", "c"];
    for engine in ["slurm", "k8s", "parallel"] {
        let extra: &[&str] = if engine == "k8s" { &k8s } else { &[] };
        let with = |args: &[&str]| -> Vec<String> {
            let all = [&[engine][..], args, extra].concat();
            all.into_iter().map(str::to_string).collect()
        };
        let scene = "sc ene's.txt";
        refused(
            &s,
            &with(&[scene, "--tiles", "0", "-o", "o.png"]),
            "--tiles",
        );
        refused(
            &s,
            &with(&[scene, "--tiles", "100001", "-o", "o.png"]),
            "--tiles",
        );
        refused(
            &s,
            &with(&[scene, "--tiles", "two", "-o", "o.png"]),
            "--tiles",
        );
        refused(&s, &with(&[scene, "--tiles", "2", "-o", "o.jpg"]), "-o");
        refused(&s, &with(&[scene, "--tiles", "2"]), "--output");
        refused(
            &s,
            &with(&[scene, "--tiles", "2", "-o", "o.png", "--aov", "nope"]),
            "--aov",
        );
        refused(
            &s,
            &with(&[scene, "--tiles", "2", "-o", "o.png", "--spp", "0"]),
            "--spp",
        );
        let broken = ["--tiles", "2", "-o", "o.png", "--tiles-dir", "a\nb"];
        refused(&s, &with(&[&[scene][..], &broken].concat()), "--tiles-dir");
    }
    for engine in ["slurm", "parallel"] {
        refused(
            &s,
            &[engine, "missing.txt", "--tiles", "2", "-o", "o.png"],
            "missing.txt",
        );
        refused(
            &s,
            &[engine, ".", "--tiles", "2", "-o", "o.png"],
            "not a file",
        );
    }
    let base = ["sc ene's.txt", "--tiles", "2", "-o", "o.png"];
    let k8s_with =
        |extra: &[&str]| -> Vec<String> { strings(&[&["k8s"][..], &base, extra].concat()) };
    refused(&s, &k8s_with(&["--claim", "c"]), "--image");
    refused(&s, &k8s_with(&["--image", "i"]), "--claim");
    refused(
        &s,
        &k8s_with(&[&k8s[..], &["--name", "Not_A_Label"]].concat()),
        "--name",
    );
    refused(
        &s,
        &k8s_with(&[&k8s[..], &["--mount", "data"]].concat()),
        "--mount",
    );
    refused(
        &s,
        &k8s_with(&[&k8s[..], &["--cpus", "0"]].concat()),
        "--cpus",
    );
    let slurm = [&["slurm"][..], &base].concat();
    refused(
        &s,
        &[&slurm[..], &["--tiles-dir", r"a\b"]].concat(),
        "--tiles-dir",
    );
    refused(&s, &[&slurm[..], &["--time", "1\n2"]].concat(), "--time");
    refused(
        &s,
        &[&slurm[..], &["--cpus-per-task", "0"]].concat(),
        "--cpus-per-task",
    );
    let parallel = [&["parallel"][..], &base].concat();
    refused(
        &s,
        &[&parallel[..], &["--tiles-dir", "t{1}"]].concat(),
        "--tiles-dir",
    );
    refused(&s, &[&parallel[..], &["--jobs", "0"]].concat(), "--jobs");
    refused(
        &s,
        &[&parallel[..], &["--threads", "0"]].concat(),
        "--threads",
    );
}

#[test]
fn the_scene_is_not_the_output() {
    let s = setup();
    std::fs::write(s.work.join("s.png"), SCENE).unwrap();
    refused(
        &s,
        &["slurm", "s.png", "--tiles", "2", "-o", "./s.png"],
        "refusing",
    );
}

#[test]
fn slurm_tasks_and_k8s_pods_render_the_very_bytes_of_one_render() {
    let s = setup();
    let glint = env!("CARGO_BIN_EXE_glint");
    // 70 rows: three bands, dealt unevenly to two tiles.
    let options = [
        "--width", "40", "--height", "70", "--seed", "5", "--aov", "depth",
    ];
    let single = Command::new(glint)
        .args(["render", "sc ene's.txt", "-o", "single.png", "--quiet"])
        .args(options)
        .current_dir(&s.work)
        .status()
        .unwrap();
    assert!(single.success());
    let same = |merged: &str| {
        for (a, b) in [
            ("single.png", merged),
            ("single.depth.png", &merged.replace(".png", ".depth.png")),
        ] {
            let a = std::fs::read(s.work.join(a)).unwrap();
            let b = std::fs::read(s.work.join(b)).unwrap();
            assert!(a == b, "{merged}: not the bytes of one render");
        }
    };

    // Slurm: this glint in the batch files, each task run as Slurm runs it.
    let args = [
        &["slurm", "sc ene's.txt", "--tiles", "2", "-o", "slurm.png"][..],
        &options,
    ]
    .concat();
    let ran = s.bash(&s.script(&args), &[]);
    assert!(
        ran.status.success(),
        "{}",
        String::from_utf8_lossy(&ran.stderr)
    );
    for i in ["0", "1"] {
        let task = s.bash(
            "bash slurm.tiles/render.sbatch",
            &[("SLURM_ARRAY_TASK_ID", i)],
        );
        assert!(
            task.status.success(),
            "{}",
            String::from_utf8_lossy(&task.stderr)
        );
    }
    let merge = s.bash("bash slurm.tiles/merge.sbatch", &[]);
    assert!(
        merge.status.success(),
        "{}",
        String::from_utf8_lossy(&merge.stderr)
    );
    same("slurm.png");

    // Kubernetes: the claim mounted where the scene is; each container's
    // command run with JOB_COMPLETION_INDEX, the image's glint this one.
    let mount = s.work.to_str().unwrap();
    let args = [
        &["k8s", "sc ene's.txt", "--tiles", "2", "-o", "k8s.png"][..],
        &["--image", "i", "--claim", "c", "--mount", mount],
        &options,
    ]
    .concat();
    let yaml = s.script(&args);
    let jobs = jobs(&yaml);
    let run = |job: &Job, container: &str, index: u32| {
        let mut words = command(job, container, index);
        if words[0] == "glint" {
            words[0] = glint.to_string();
        }
        let out = Command::new(&words[0]).args(&words[1..]).output().unwrap();
        assert!(
            out.status.success(),
            "{words:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    for i in [1, 0] {
        run(&jobs[0], "tiles-dir", i);
        run(&jobs[0], "render", i);
    }
    run(&jobs[1], "merge", 0);
    same("k8s.png");
}
