//! The harness of `tests/cluster.rs`: whether a real Slurm answers (else the
//! test says it was skipped, or fails where `GLINT_REQUIRE_SLURM=1`), a
//! scratch folder whose Slurm jobs are cancelled before it is removed,
//! commands run with a time limit, array jobs submitted and waited for, and
//! folders compared byte for byte.

use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::OnceLock;
use std::sync::mpsc::{Receiver, channel};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The glint binary under test.
pub const GLINT: &str = env!("CARGO_BIN_EXE_glint");

/// A generous bound on any one wait (the machine may be busy): not a speed check.
pub const WAIT: Duration = Duration::from_secs(180);

/// Says on stderr that `test` was skipped and why (straight to stderr: the
/// harness captures `eprintln!`), or fails when the variable `require` is `1`.
pub fn skip(test: &str, require: &str, why: &str) {
    if std::env::var(require).as_deref() == Ok("1") {
        panic!("{test}: {require}=1 but {why}");
    }
    let _ = writeln!(std::io::stderr(), "skipped: {test}: {why}");
}

/// Whether `tool` is an executable file in a folder of `PATH`.
pub fn on_path(tool: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|path| {
        std::env::split_paths(&path).any(|dir| {
            std::fs::metadata(dir.join(tool)).is_ok_and(|m| {
                m.is_file() && {
                    use std::os::unix::fs::PermissionsExt;
                    m.permissions().mode() & 0o111 != 0
                }
            })
        })
    })
}

/// Why no Slurm cluster can run these tests' jobs, or `None` when one answers.
fn slurm_missing() -> Option<String> {
    const START: &str = "scripts/slurm-local.sh start, then source the env file it names";
    for tool in ["sbatch", "sinfo", "squeue", "scontrol", "scancel"] {
        if !on_path(tool) {
            return Some(format!(
                "no `{tool}` on PATH (Debian's slurm-client: {START})"
            ));
        }
    }
    let Some(conf) = std::env::var_os("SLURM_CONF") else {
        return Some(format!("SLURM_CONF is not set ({START})"));
    };
    let conf = PathBuf::from(conf);
    let out = match spawn(Command::new("sinfo").args(["-h", "-o", "%T"])).try_finish(WAIT / 6) {
        Ok(out) => out,
        Err(e) => return Some(format!("sinfo: {e}")),
    };
    let states = String::from_utf8_lossy(&out.stdout);
    // A node that takes jobs (busy with other tests' too); a `*` suffix: not responding.
    let up = states.lines().any(|s| {
        let state = s.trim_end_matches(|c: char| !c.is_ascii_alphabetic());
        let taking = ["idle", "mixed", "allocated", "completing", "planned"];
        !s.ends_with('*') && taking.contains(&state)
    });
    if !out.status.success() || !up {
        return Some(format!(
            "the cluster of SLURM_CONF={} does not answer or has no node up (sinfo: {} {})",
            conf.display(),
            states.trim(),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    None
}

/// Whether a real Slurm answers (asked once a test binary); if not, says
/// that `test` was skipped and why, or fails where `GLINT_REQUIRE_SLURM=1`
/// (as in `.ci/run`).
pub fn slurm_ready(test: &str) -> bool {
    static MISSING: OnceLock<Option<String>> = OnceLock::new();
    match MISSING.get_or_init(slurm_missing) {
        None => true,
        Some(why) => {
            skip(test, "GLINT_REQUIRE_SLURM", why);
            false
        }
    }
}

/// A child process whose output is read as it comes; killed if dropped
/// before it ends (a failing test leaves no process behind).
pub struct Running {
    child: Child,
    what: String,
    lines: Receiver<Vec<u8>>,
    stdout: Vec<u8>,
    stdout_reader: Option<JoinHandle<()>>,
    stderr_reader: Option<JoinHandle<Vec<u8>>>,
}

/// Starts `cmd` with its output piped (stdin empty).
pub fn spawn(cmd: &mut Command) -> Running {
    let what = format!("{cmd:?}");
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot run {what}: {e}"));
    let (send, lines) = channel();
    // Both pipes exist: they were asked for just above.
    let out = child.stdout.take().expect("piped stdout");
    let stdout_reader = std::thread::spawn(move || {
        for line in BufReader::new(out).split(b'\n') {
            let Ok(line) = line else { break };
            if send.send(line).is_err() {
                break;
            }
        }
    });
    let mut err = child.stderr.take().expect("piped stderr");
    let stderr_reader = std::thread::spawn(move || {
        let mut buf = Vec::new();
        let _ = err.read_to_end(&mut buf);
        buf
    });
    Running {
        child,
        what,
        lines,
        stdout: Vec::new(),
        stdout_reader: Some(stdout_reader),
        stderr_reader: Some(stderr_reader),
    }
}

/// Runs `cmd` to its end (at most [`WAIT`]) and returns its output.
pub fn run(cmd: &mut Command) -> Output {
    spawn(cmd).finish(WAIT)
}

impl Running {
    /// The next line of its stdout, waiting at most `limit`.
    pub fn line(&mut self, limit: Duration) -> String {
        let line = self
            .lines
            .recv_timeout(limit)
            .unwrap_or_else(|_| panic!("{}: no line on stdout after {limit:?}", self.what));
        self.stdout.extend_from_slice(&line);
        self.stdout.push(b'\n');
        String::from_utf8_lossy(&line).into_owned()
    }

    /// Waits for it to end, at most `limit` (then kills it and fails).
    pub fn finish(self, limit: Duration) -> Output {
        self.try_finish(limit).unwrap_or_else(|e| panic!("{e}"))
    }

    /// Waits for it to end, at most `limit` (then kills it: an error).
    pub fn try_finish(mut self, limit: Duration) -> Result<Output, String> {
        let start = Instant::now();
        let status = loop {
            match self.child.try_wait() {
                Ok(Some(status)) => break status,
                Ok(None) if start.elapsed() < limit => {
                    std::thread::sleep(Duration::from_millis(20))
                }
                _ => {
                    let _ = self.child.kill();
                    let _ = self.child.wait();
                    return Err(format!("{} still ran after {limit:?}: killed", self.what));
                }
            }
        };
        if let Some(reader) = self.stdout_reader.take() {
            let _ = reader.join();
        }
        for line in self.lines.try_iter() {
            self.stdout.extend_from_slice(&line);
            self.stdout.push(b'\n');
        }
        let stderr = self
            .stderr_reader
            .take()
            .and_then(|r| r.join().ok())
            .unwrap_or_default();
        Ok(Output {
            status,
            stdout: std::mem::take(&mut self.stdout),
            stderr,
        })
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

/// `glint ARGS`, run to its end.
pub fn glint(args: &[&str]) -> Output {
    run(Command::new(GLINT).args(args))
}

/// Fails with the command's stderr unless it exited 0.
pub fn assert_ok(out: &Output, what: &str) {
    assert!(
        out.status.success(),
        "{what}: {}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `s` quoted for bash.
pub fn sh_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// A path as a `&str` (the scratch folders are ASCII: temp dir plus a name).
pub fn text(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}

/// `squeue`'s state of job (or array task) `id`, empty once it has left the queue.
pub fn job_state(id: &str) -> String {
    let out = run(Command::new("squeue").args(["-h", "-j", id, "-o", "%T"]));
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// How long [`requeue`] waits for the task to run again.
pub const REQUEUE_WAIT: Duration = Duration::from_secs(360);

/// `scontrol requeue TASK`, then waits until `done` holds: the task is
/// killed and queued again, and starts again once its begin time comes
/// (twice the credential lifetime and a little more: 25 s with
/// scripts/slurm-local.sh's `cred_expire=10`, about 4 minutes with Slurm's
/// default 120 s, so up to [`REQUEUE_WAIT`]). It is not released sooner:
/// a task started again within the second its first attempt ended has its
/// launch refused ("credential revoked") and fails, as it did in CI. What
/// the task leaves behind, not squeue, says it ran again. On a timeout it
/// fails with the states squeue showed, `scontrol show job` and `why()`.
pub fn requeue(task: &str, done: impl Fn() -> bool, why: impl Fn() -> String) {
    let o = run(Command::new("scontrol").args(["requeue", task]));
    assert_ok(&o, &format!("scontrol requeue {task}"));
    let start = Instant::now();
    let mut seen = Vec::new();
    while !done() {
        let state = job_state(task);
        if seen.last() != Some(&state) {
            seen.push(state);
        }
        if start.elapsed() > REQUEUE_WAIT {
            let show = run(Command::new("scontrol").args(["show", "job", task]));
            panic!(
                "{task} did not finish again within {REQUEUE_WAIT:?}; squeue said {seen:?}\n\
                 scontrol show job {task}:\n{}{}\n{}",
                String::from_utf8_lossy(&show.stdout),
                String::from_utf8_lossy(&show.stderr),
                why()
            );
        }
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// A test's scratch folder, removed when dropped (a failing test's too),
/// after every Slurm job that runs a script or works in it is cancelled and
/// gone, so that no task writes into a removed folder or outlives the test.
pub struct Scratch {
    dir: tempfile::TempDir,
    slurm: bool,
}

impl Scratch {
    /// A fresh folder for test `name` that submits no job.
    pub fn new(name: &str) -> Scratch {
        let dir = tempfile::Builder::new()
            .prefix(&format!("glint-cluster-{name}-"))
            .tempdir()
            .expect("a scratch folder in the temporary folder");
        Scratch { dir, slurm: false }
    }

    /// A fresh folder for test `name`, whose Slurm jobs are cancelled when dropped.
    pub fn for_slurm(name: &str) -> Scratch {
        let mut s = Scratch::new(name);
        s.slurm = true;
        s
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        self.dir.path()
    }

    /// `sub` of the folder, created.
    pub fn sub(&self, sub: &str) -> PathBuf {
        let p = self.path().join(sub);
        std::fs::create_dir_all(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        p
    }

    /// Writes `name` in the folder, returning its path.
    pub fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.path().join(name);
        std::fs::write(&p, text).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        p
    }

    /// Writes `path`, a batch script of array tasks, each rendering its part
    /// of `n` into `tiles` (`glint render SCENE --tile "$SLURM_ARRAY_TASK_ID/n"
    /// --tiles-dir TILES --quiet ARGS`) after the shell lines `before`.
    pub fn task_script(
        &self,
        path: &Path,
        before: &str,
        scene: &Path,
        n: usize,
        tiles: &Path,
        args: &[&str],
    ) {
        let args: Vec<String> = args.iter().map(|a| sh_quote(a)).collect();
        let script = format!(
            "#!/bin/bash\nset -eu\n{before}exec {} render {} --tile \"$SLURM_ARRAY_TASK_ID/{n}\" --tiles-dir {} --quiet {}\n",
            sh_quote(GLINT),
            sh_quote(text(scene)),
            sh_quote(text(tiles)),
            args.join(" ")
        );
        std::fs::write(path, script).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }

    /// `sbatch --wait --array=INDICES SCRIPT` started: the tasks' output in
    /// `logs/`, a limit of 5 minutes a task. Returns the waiting sbatch and
    /// the job's ID (printed at once; `sbatch --wait` then exits with the
    /// highest exit code of the tasks).
    pub fn submit(&self, script: &Path, indices: &str) -> (Running, String) {
        assert!(self.slurm, "a Scratch::for_slurm submits jobs");
        let logs = self.sub("logs");
        let mut sbatch = spawn(
            Command::new("sbatch")
                .args(["--parsable", "--wait", "--time=5", "--cpus-per-task=1"])
                .arg(format!("--array={indices}"))
                .arg(format!("--chdir={}", text(self.path())))
                .arg(format!("--output={}/%x-%A_%a.out", text(&logs)))
                .arg(script),
        );
        let line = sbatch.line(WAIT / 6);
        let job = line
            .split(';')
            .next()
            .unwrap_or_default()
            .trim()
            .to_string();
        assert!(
            !job.is_empty() && job.bytes().all(|b| b.is_ascii_digit()),
            "sbatch --parsable printed {line:?}"
        );
        (sbatch, job)
    }

    /// Submits each `(script, indices)` at once and waits for them all;
    /// fails (with the tasks' logs) unless every task exited 0.
    pub fn arrays(&self, jobs: &[(&Path, &str)]) {
        let started: Vec<_> = jobs
            .iter()
            .map(|(s, i)| (self.submit(s, i), s, i))
            .collect();
        for ((sbatch, job), script, indices) in started {
            let out = sbatch.finish(WAIT);
            assert!(
                out.status.success(),
                "job {job} (sbatch --array={indices} --wait {}): {}\n{}\ntask logs:\n{}",
                script.display(),
                out.status,
                String::from_utf8_lossy(&out.stderr),
                self.logs()
            );
        }
    }

    /// Slurm's task logs so far (the `*.out` files anywhere in the folder),
    /// each named: for failure messages.
    pub fn logs(&self) -> String {
        let mut all = String::new();
        let mut folders = vec![self.path().to_path_buf()];
        while let Some(dir) = folders.pop() {
            let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
                .into_iter()
                .flatten()
                .flatten()
                .map(|e| e.path())
                .collect();
            files.sort();
            for f in files {
                if f.is_dir() {
                    folders.push(f);
                } else if f.extension().is_some_and(|x| x == "out") {
                    let text = std::fs::read_to_string(&f).unwrap_or_default();
                    all += &format!("== {}\n{text}", f.display());
                }
            }
        }
        all
    }

    /// The IDs of the jobs (arrays by their array ID) whose script or
    /// working folder is in this folder.
    pub fn jobs(&self) -> Vec<String> {
        let Ok(out) =
            spawn(Command::new("squeue").args(["-h", "-o", "%F\t%Z\t%o"])).try_finish(WAIT / 6)
        else {
            return Vec::new();
        };
        let mine = |p: &str| Path::new(p).starts_with(self.path());
        let mut ids: Vec<String> = String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter_map(|l| {
                let mut f = l.split('\t');
                let (id, dir, script) = (f.next()?, f.next()?, f.next()?);
                (mine(dir) || mine(script)).then(|| id.to_string())
            })
            .collect();
        ids.sort();
        ids.dedup();
        ids
    }

    /// Waits until no job of this folder is in the queue (at most [`WAIT`]),
    /// returning every job ID seen.
    pub fn wait_for_jobs(&self) -> Vec<String> {
        let start = Instant::now();
        let mut seen = Vec::new();
        loop {
            let now = self.jobs();
            if now.is_empty() {
                return seen;
            }
            assert!(
                start.elapsed() < WAIT,
                "jobs {now:?} still queued after {WAIT:?}; task logs:\n{}",
                self.logs()
            );
            for id in now {
                if !seen.contains(&id) {
                    seen.push(id);
                }
            }
            std::thread::sleep(Duration::from_millis(250));
        }
    }
}

impl Drop for Scratch {
    /// Cancels this folder's jobs and waits (up to 30 s) until they are gone.
    fn drop(&mut self) {
        if !self.slurm {
            return;
        }
        let start = Instant::now();
        loop {
            let ids = self.jobs();
            if ids.is_empty() || start.elapsed() > Duration::from_secs(30) {
                break;
            }
            let _ = spawn(Command::new("scancel").args(&ids)).try_finish(WAIT / 6);
            std::thread::sleep(Duration::from_millis(250));
        }
    }
}

/// Fails unless folders `a` and `b` hold the same file names with the same
/// bytes (a picture and the files beside it: AOVs, their ranges).
pub fn assert_same_files(a: &Path, b: &Path, what: &str) {
    let names = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap_or_else(|e| panic!("{}: {e}", d.display()))
            .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
            .collect();
        v.sort();
        v
    };
    let (na, nb) = (names(a), names(b));
    assert_eq!(
        na,
        nb,
        "{what}: the files of {} and {}",
        a.display(),
        b.display()
    );
    assert!(!na.is_empty(), "{what}: {} is empty", a.display());
    for name in na {
        assert_same_bytes(&a.join(&name), &b.join(&name), what);
    }
}

/// Fails unless files `a` and `b` hold the same bytes.
pub fn assert_same_bytes(a: &Path, b: &Path, what: &str) {
    let (x, y) = (read(a), read(b));
    if x != y {
        let at = x
            .iter()
            .zip(&y)
            .position(|(p, q)| p != q)
            .unwrap_or(x.len().min(y.len()));
        panic!(
            "{what}: {} ({} bytes) and {} ({} bytes) differ from byte {at}",
            a.display(),
            x.len(),
            b.display(),
            y.len()
        );
    }
}

/// The bytes of `p`.
pub fn read(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}
