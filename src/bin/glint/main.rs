//! The `glint` command line: argument parsing, progress and reporting only.
//! One file a subcommand, as cargo lays out its commands: its arguments
//! (`Args`) and `exec`, which turns them into the library's options and
//! calls it; this file holds what they share (reporting, exit codes, signals).

mod args;
mod check;
mod compare;
mod explain;
mod huge_pages;
mod job;
mod memory;
mod merge;
mod probe;
mod render;
mod serve;
mod tile;
mod tiles;

use clap::{Parser, Subcommand};
use glint::{Dialect, RenderError, Scene};
use std::io::{IsTerminal, Write};
use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Large blocks in huge pages: fewer page faults reading and building a
/// big scene.
#[global_allocator]
static ALLOCATOR: huge_pages::HugePages = huge_pages::HugePages;

/// glint: a fast, exact ray tracer for the teaching framework's scene files.
#[derive(Parser)]
#[command(
    name = "glint",
    version,
    about,
    long_about = None,
    after_help = "Environment: GLINT_SIMD=baseline|avx2|avx512|neon picks the instruction set \
                  the ray queries run in (by default AVX2 where the CPU has it); every one \
                  draws the same bytes."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file to an image (.png, .bmp, .exr or .hdr).
    Render(render::Args),
    /// Print the first hit of each ray of a file (one `ox oy oz dx dy dz` per line).
    Probe(probe::Args),
    /// Explain one pixel: its ray tree as `render` traces it, its bytes and why.
    Explain(explain::Args),
    /// Lint a scene without rendering it: findings with file:line, what is
    /// wrong and what to change (exit 0; 1 with --deny-warnings when there
    /// are any; 2 when the scene cannot be read).
    Check(check::Args),
    /// Compare your own render with glint's: a heat map, and the differing
    /// pixels grouped by the primitive glint sees there, worst first.
    Compare(compare::Args),
    /// Merge the tiles of `render --tile I/N --tiles-dir DIR` into the
    /// picture one render writes, byte for byte (exit 3 naming the tiles not done).
    Merge(merge::Args),
    /// List the tiles of a folder: done, missing, corrupt or of another
    /// render, and how to render the missing ones (exit 0 when all are done, 3 when not).
    Tiles(tiles::Args),
    /// A live page of the scene, rendered again on every save of it or of
    /// a texture or mesh it uses; hover and click explain pixels.
    Serve(serve::Args),
    /// Write the job that renders a scene as tiles on Slurm, Kubernetes or
    /// GNU parallel and merges them (printed; nothing is submitted).
    Job(job::Args),
}

/// Text from a scene or a path made safe for a terminal: each line through
/// [`glint::scene::escaped`] (an escape sequence could recolour or clear the
/// screen, an override turn the text around), the line breaks kept.
fn shown(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.contains('\n') {
        return glint::scene::escaped(text);
    }
    let lines: Vec<_> = text.split('\n').map(glint::scene::escaped).collect();
    lines.join("\n").into()
}

/// Whether scene diagnostics are printed in colour: only to a terminal, and
/// not when `NO_COLOR` is set to anything but the empty string.
fn colour() -> bool {
    std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
}

/// Writes text that is already safe for a terminal (rendered diagnostics) and
/// a line break to stderr; a stderr that cannot be written is ignored, as
/// there is nowhere left to report it, and the exit code still tells.
fn say_raw(text: &str) {
    let _ = writeln!(std::io::stderr().lock(), "{text}");
}

/// Writes a message to stderr escaped through [`shown`] (see [`say_raw`]).
fn say(text: &str) {
    say_raw(&shown(text));
}

/// Why the command stops early.
enum Failure {
    /// A message, printed escaped (if not empty), and exit code 2.
    Error(String),
    /// SIGINT or SIGTERM arrived: "interrupted", exit code 130.
    Interrupted,
    /// Nothing more to say, and this exit code (`check --deny-warnings`: 1).
    Status(u8),
}

/// A [`Failure::Error`] with the message `message`.
fn fail(message: impl Into<String>) -> Failure {
    Failure::Error(message.into())
}

/// Set by SIGINT and SIGTERM: the render stops, nothing is written. A second
/// signal ends the process at once.
fn interrupt_flag() -> Arc<AtomicBool> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let flag = Arc::new(AtomicBool::new(false));
    for signal in [SIGINT, SIGTERM] {
        // Registering fails only for signals that cannot be caught; then the
        // default action (ending the process) stays, which is safe.
        let _ = signal_hook::flag::register_conditional_shutdown(signal, 130, flag.clone());
        let _ = signal_hook::flag::register(signal, flag.clone());
    }
    flag
}

/// `Err(Interrupted)` once a signal has arrived.
fn check_interrupt(flag: &AtomicBool) -> Result<(), Failure> {
    if flag.load(Ordering::Relaxed) {
        return Err(Failure::Interrupted);
    }
    Ok(())
}

/// Applies `GLINT_SIMD`, the instruction set asked for the ray queries
/// (the same pictures in every one), if it is set.
fn choose_isa() -> Result<(), String> {
    let Some(name) = std::env::var_os("GLINT_SIMD").filter(|v| !v.is_empty()) else {
        return Ok(());
    };
    let name = name.to_string_lossy();
    match glint::Isa::named(&name) {
        Some(Ok(isa)) => {
            isa.choose();
            Ok(())
        }
        Some(Err(why)) => Err(format!("error: GLINT_SIMD={}: {why}", shown(&name))),
        None => Err(format!(
            "error: GLINT_SIMD={}: expected best, {}",
            shown(&name),
            glint::Isa::NAMES.join(", ")
        )),
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            // Argument errors quote the arguments: escape them like the rest.
            let _ = write!(std::io::stderr().lock(), "{}", shown(&e.to_string()));
            return ExitCode::from(2);
        }
        Err(e) => {
            // --help and --version go to stdout.
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
    };
    if let Err(message) = choose_isa() {
        say(&message);
        return ExitCode::from(2);
    }
    let result = match cli.command {
        // Only a render watches for signals (a probe ends at the first).
        Command::Render(args) => render::exec(args, &interrupt_flag()),
        Command::Probe(args) => probe::exec(args),
        Command::Explain(args) => explain::exec(args),
        Command::Check(args) => check::exec(args),
        Command::Compare(args) => compare::exec(args, &interrupt_flag()),
        Command::Serve(args) => serve::exec(args, &interrupt_flag()),
        Command::Merge(args) => merge::exec(args, &interrupt_flag()),
        Command::Tiles(args) => tiles::exec(args),
        Command::Job(args) => job::exec(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Error(message)) => {
            if !message.is_empty() {
                say(&message);
            }
            ExitCode::from(2)
        }
        Err(Failure::Interrupted) => {
            say("interrupted");
            ExitCode::from(130)
        }
        Err(Failure::Status(code)) => ExitCode::from(code),
    }
}

/// A render that could not start: a size option out of range names its option.
fn render_failure(e: RenderError) -> Failure {
    match e {
        RenderError::Cancelled => Failure::Interrupted,
        RenderError::Side { .. } | RenderError::Samples { .. } => fail(format!("error: --{e}")),
        _ => fail(format!("error: {e}")),
    }
}

/// Reads a scene, printing its warnings, or its errors (already escaped, so
/// printed here, perhaps in colour) and a [`Failure`] with nothing left to say.
fn load_scene(path: &Path, dialect: Option<Dialect>, announce: bool) -> Result<Scene, Failure> {
    let colour = colour();
    let scene = Scene::from_file_as(path, dialect).map_err(|e| {
        say_raw(&e.render(colour));
        fail("")
    })?;
    for w in scene.warnings() {
        say_raw(&format!("{}\n", w.render(colour)));
    }
    if announce {
        say(&scene.dialect().to_string());
    }
    Ok(scene)
}

/// Refuses an output that is the scene file itself (the same file by device
/// and inode, whatever the names: `a.png -o ./a.png`, a hard link).
fn refuse_scene_as_output(scene: &Path, output: &Path) -> Result<(), Failure> {
    let (Ok(s), Ok(o)) = (std::fs::metadata(scene), std::fs::metadata(output)) else {
        return Ok(()); // no output file yet (or no scene, reported when read)
    };
    #[cfg(unix)]
    let same = {
        use std::os::unix::fs::MetadataExt;
        (s.dev(), s.ino()) == (o.dev(), o.ino())
    };
    #[cfg(not(unix))]
    let same = {
        let _ = (s, o);
        std::fs::canonicalize(scene).ok() == std::fs::canonicalize(output).ok()
    };
    if same {
        return Err(fail(format!(
            "error: the output {} is the scene file {}: refusing to write over it (choose another name with -o)",
            output.display(),
            scene.display()
        )));
    }
    Ok(())
}
