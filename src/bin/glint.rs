//! The `glint` command line: argument parsing, progress and reporting only.

use clap::{Args, Parser, Subcommand};
use glint::{
    Aov, Control, Dialect, Film, Format, MAX_THREADS, PhotonFilter, PhotonMode, PhotonOptions,
    RaysError, Region, RenderError, RenderOptions, Renderer, Scene, probe, read_rays,
};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// glint: a fast, exact ray tracer for the teaching framework's scene files.
#[derive(Parser)]
#[command(name = "glint", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene file to an image (.png, .bmp, .exr or .hdr).
    Render(RenderArgs),
    /// Print the first hit of each ray of a file (one `ox oy oz dx dy dz` per line).
    Probe(ProbeArgs),
    /// Explain one pixel: its ray tree as `render` traces it, its bytes and why.
    Explain(ExplainArgs),
    /// Lint a scene without rendering it: findings with file:line, what is
    /// wrong and what to change (exit 0; 1 with --deny-warnings when there
    /// are any; 2 when the scene cannot be read).
    Check(CheckArgs),
    /// Compare your own render with glint's: a heat map, and the differing
    /// pixels grouped by the primitive glint sees there, worst first.
    Compare(CompareArgs),
    /// A live page of the scene, rendered again on every save of it or of
    /// a texture or mesh it uses; hover and click explain pixels.
    Serve(ServeArgs),
}

#[derive(Args)]
struct ServeArgs {
    /// The scene file.
    scene: PathBuf,
    /// The port to listen on (0: a free one).
    #[arg(long, default_value_t = 0)]
    port: u16,
    /// The address to listen on. Anything but a loopback address lets
    /// anyone who can reach it and knows the token read the scene.
    #[arg(long, default_value = "127.0.0.1")]
    bind: std::net::IpAddr,
    /// Open the page in the desktop's browser (xdg-open or open).
    #[arg(long)]
    open: bool,
    /// Your own render of the scene (.bmp or .png) to compare with, on a slider.
    #[arg(long)]
    compare: Option<PathBuf>,
    /// Worker threads, as for `render`.
    #[arg(long, value_parser = thread_count)]
    threads: Option<usize>,
    #[command(flatten)]
    pixels: PixelArgs,
    #[command(flatten)]
    dialect: DialectArg,
    #[command(flatten)]
    photons: PhotonArgs,
}

#[derive(Args)]
struct CompareArgs {
    /// The scene file.
    scene: PathBuf,
    /// Your render of it (.bmp or .png), the scene's size.
    theirs: PathBuf,
    /// Write the heat map here (.png or .bmp): glint's picture dimmed, the
    /// differing pixels from red to white.
    #[arg(short, long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    pixels: PixelArgs,
    /// A pixel differs when a channel is off by more than this (8-bit steps).
    #[arg(long, default_value_t = glint::DEFAULT_THRESHOLD)]
    threshold: u8,
    /// One JSON object on stdout (schema: docs/debugging.md).
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    dialect: DialectArg,
}

#[derive(Args)]
struct CheckArgs {
    /// The scene file.
    scene: PathBuf,
    /// Exit with status 1 when there is any warning (the reader's or a finding).
    #[arg(long)]
    deny_warnings: bool,
    /// One JSON object on stdout (schema: docs/debugging.md).
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    dialect: DialectArg,
}

#[derive(Args)]
struct ExplainArgs {
    /// The scene file.
    scene: PathBuf,
    /// The pixel, `X,Y` (column, row from the top, from 0).
    #[arg(long, value_parser = pixel)]
    pixel: (u32, u32),
    #[command(flatten)]
    pixels: PixelArgs,
    /// List every ray of glossy fans and every sample, instead of summing them up.
    #[arg(long)]
    expand: bool,
    /// One JSON object (schema: docs/debugging.md).
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    dialect: DialectArg,
    #[command(flatten)]
    photons: PhotonArgs,
}

/// Parses `--pixel X,Y`.
fn pixel(s: &str) -> Result<(u32, u32), String> {
    let (x, y) = s
        .split_once(',')
        .ok_or_else(|| "expected `X,Y`, e.g. `--pixel 412,300`".to_string())?;
    let n = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|e| format!("`{}` is not a pixel coordinate: {e}", v.trim()))
    };
    Ok((n(x)?, n(y)?))
}

/// What decides a picture's pixels beside the scene: its size, samples and seed.
#[derive(Args)]
struct PixelArgs {
    /// Image width in pixels, overriding the scene's image_W= (the lens stays as the scene sets it).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels, overriding the scene's image_H=.
    #[arg(long)]
    height: Option<u32>,
    /// Seed of the random streams (same scene and seed: same bytes, whatever the threads).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Stratified samples per pixel instead of the framework's adaptive anti-aliasing
    /// (at least 1; 1: exactly one ray through each pixel's centre).
    #[arg(long, value_parser = at_least_one::<u32>)]
    spp: Option<u32>,
}

impl PixelArgs {
    /// The render options they set, the rest as `base` has them.
    fn apply(&self, base: RenderOptions) -> RenderOptions {
        RenderOptions {
            width: self.width,
            height: self.height,
            seed: self.seed,
            spp: self.spp,
            ..base
        }
    }
}

#[derive(Args)]
struct RenderArgs {
    /// The scene file.
    scene: PathBuf,
    /// Output image; the format follows the extension [default: the scene's name with .png]
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Worker threads, 1 to 1024 [default: one per core]
    #[arg(long, value_parser = thread_count)]
    threads: Option<usize>,
    #[command(flatten)]
    pixels: PixelArgs,
    /// No progress bar, no summary (warnings and errors are still printed).
    #[arg(short, long)]
    quiet: bool,
    /// Also print notes (where textures were found) and a breakdown of the rays.
    #[arg(short, long)]
    verbose: bool,
    /// AOVs (arbitrary output values) to write beside the picture,
    /// comma-separated: normal, depth, position, uv, primitive, albedo, rays,
    /// light:N, shade, why, clamp, cost, photons (layers of an .exr; else
    /// OUT.AOV.EXT files).
    #[arg(long)]
    aov: Option<String>,
    /// Render only columns X0..X1 and rows Y0..Y1 (ends excluded, rows from
    /// the top): `X0,Y0,X1,Y1`; its pixels are those of the whole render.
    #[arg(long, value_parser = region)]
    region: Option<Region>,
    /// PPM and SPPM: write the picture every N iterations (atomically; Ctrl-C
    /// writes the last complete iteration).
    #[arg(long, default_value_t = 10, value_parser = at_least_one::<u64>)]
    checkpoint: u64,
    #[command(flatten)]
    dialect: DialectArg,
    #[command(flatten)]
    photons: PhotonArgs,
}

/// Parses `--region X0,Y0,X1,Y1` (ends excluded).
fn region(s: &str) -> Result<Region, String> {
    let n: Vec<u32> = s
        .split(',')
        .map(|v| {
            v.trim()
                .parse::<u32>()
                .map_err(|e| format!("`{}` is not a pixel coordinate: {e}", v.trim()))
        })
        .collect::<Result<_, _>>()?;
    let [x0, y0, x1, y1] = n[..] else {
        return Err("expected `X0,Y0,X1,Y1`, e.g. `--region 0,0,64,48`".to_string());
    };
    if x1 <= x0 || y1 <= y0 {
        return Err(format!(
            "the region is empty: X1 must exceed X0 and Y1 exceed Y0 (got {s})"
        ));
    }
    Ok(Region {
        x: x0,
        y: y0,
        width: x1 - x0,
        height: y1 - y0,
    })
}

#[derive(Args)]
struct ProbeArgs {
    /// The scene file.
    scene: PathBuf,
    /// File of rays, one `ox oy oz dx dy dz` per line (`-` for standard input).
    #[arg(long)]
    rays: PathBuf,
    /// One JSON object per line: {"hit":true,"t":..,"point":[..],"normal":[..],"front":..,"primitive":K,"uv":[u,v]}.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    dialect: DialectArg,
}

/// The photon options of `render` and `explain`.
#[derive(Args)]
struct PhotonArgs {
    /// Photon mapping: pm, ppm, sppm or off [default: as the file's dialect and `algorithm=` say]
    #[arg(long)]
    photons: Option<PhotonMode>,
    /// PPM and SPPM iterations, overriding the camera's `iterations=` (at least 1).
    #[arg(long, value_parser = at_least_one::<u64>)]
    iterations: Option<u64>,
    /// Photons emitted per pass, overriding the camera's `emit_photons=` (at least 1).
    #[arg(long, value_parser = at_least_one::<u64>)]
    emit: Option<u64>,
    /// How gathered photons are weighted by distance: box or cone (Jensen's).
    #[arg(long, default_value_t)]
    photon_filter: PhotonFilter,
}

impl PhotonArgs {
    fn options(&self) -> PhotonOptions {
        PhotonOptions {
            mode: self.photons,
            iterations: self.iterations,
            emit: self.emit,
            filter: self.photon_filter,
        }
    }
}

/// `--dialect`, shared by every command that reads a scene.
#[derive(Args)]
struct DialectArg {
    /// The lineage whose renderer's model draws the file: f, z14, pm3, v or w
    /// (or a repository's name) [default: chosen by the file's markers]
    #[arg(long, value_parser = dialect)]
    dialect: Option<Dialect>,
}

/// Parses `--dialect NAME`.
fn dialect(s: &str) -> Result<Dialect, String> {
    Dialect::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = Dialect::ALL.iter().map(|d| d.name()).collect();
        format!(
            "unknown dialect `{s}`: expected one of {}",
            names.join(", ")
        )
    })
}

/// Parses a whole number that must be at least 1 (`--spp`, `--threads`);
/// clap reports a refusal as an argument error with exit code 2.
fn at_least_one<T>(s: &str) -> Result<T, String>
where
    T: std::str::FromStr + PartialOrd + From<u8>,
    T::Err: std::fmt::Display,
{
    let n: T = s.trim().parse().map_err(|e| format!("{e}"))?;
    if n < T::from(1) {
        return Err("must be at least 1".to_string());
    }
    Ok(n)
}

/// Parses `--threads`: 1 to [`MAX_THREADS`].
fn thread_count(s: &str) -> Result<usize, String> {
    let n = at_least_one::<usize>(s)?;
    if n > MAX_THREADS {
        return Err(format!("must be at most {MAX_THREADS}"));
    }
    Ok(n)
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
    let result = match cli.command {
        // Only a render watches for signals (a probe ends at the first).
        Command::Render(args) => run_render(args, &interrupt_flag()),
        Command::Probe(args) => run_probe(args),
        Command::Explain(args) => run_explain(args),
        Command::Check(args) => run_check(args),
        Command::Compare(args) => run_compare(args, &interrupt_flag()),
        Command::Serve(args) => run_serve(args, &interrupt_flag()),
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

fn run_serve(args: ServeArgs, interrupt: &AtomicBool) -> Result<(), Failure> {
    let options = glint::serve::ServeOptions {
        scene: args.scene.clone(),
        bind: args.bind,
        port: args.port,
        render: args.pixels.apply(RenderOptions {
            threads: args.threads,
            photons: args.photons.options(),
            ..RenderOptions::default()
        }),
        dialect: args.dialect.dialect,
        compare: args.compare.clone(),
    };
    let server = glint::serve::Server::start(options).map_err(|e| fail(format!("error: {e}")))?;
    let addr = server.address();
    if !addr.ip().is_loopback() {
        say(&format!(
            "warning: listening on {}: anyone who can reach this address and knows the token \
             can read the scene and the files it uses (the default, 127.0.0.1, keeps it on this machine)",
            addr.ip()
        ));
    }
    let url = server.url();
    // One line on stdout, for people and scripts; the rest on stderr.
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{url}");
    let _ = out.flush();
    drop(out);
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_string())
        .ok()
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "THIS-MACHINE".to_string());
    // The tunnel's far end: the address listened on (loopback for 0.0.0.0 or ::).
    let target = if addr.ip().is_unspecified() {
        "127.0.0.1".to_string()
    } else {
        match addr.ip() {
            std::net::IpAddr::V6(ip) => format!("[{ip}]"),
            ip => ip.to_string(),
        }
    };
    say(&format!(
        "from another machine: ssh -L {port}:{target}:{port} {host}   then open http://127.0.0.1:{port}/?token={token}",
        port = addr.port(),
        token = server.token()
    ));
    if args.open {
        for opener in ["xdg-open", "open"] {
            let started = std::process::Command::new(opener)
                .arg(&url)
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::null())
                .spawn();
            if started.is_ok() {
                break;
            }
        }
    }
    server.serve_until(interrupt);
    Err(Failure::Interrupted)
}

fn run_compare(args: CompareArgs, interrupt: &AtomicBool) -> Result<(), Failure> {
    if let Some(out) = &args.output {
        refuse_scene_as_output(&args.scene, out)?;
        refuse_scene_as_output(&args.theirs, out)?;
        Format::from_path(out).map_err(|e| fail(format!("error: -o: {e}")))?;
    }
    let scene = load_scene(&args.scene, args.dialect.dialect, true)?;
    let (theirs, size) =
        glint::read_picture(&args.theirs).map_err(|e| fail(format!("error: {e}")))?;
    let renderer = Renderer::new(scene);
    let options = args.pixels.apply(RenderOptions::default());
    let c = glint::compare(&renderer, &theirs, size, args.threshold, &options).map_err(
        |e| match e {
            glint::CompareError::Size { .. } => {
                fail(format!("error: {}: {e}", args.theirs.display()))
            }
            glint::CompareError::Render(r) => render_failure(r),
        },
    )?;
    check_interrupt(interrupt)?;
    if let Some(out) = &args.output {
        let saved = c.heat.save_unless(out, interrupt);
        check_interrupt(interrupt)?;
        saved.map_err(|e| fail(format!("error: cannot write the heat map: {e}")))?;
    }
    let text = if args.json {
        format!("{}\n", c.to_json())
    } else {
        shown(&c.to_text()).into_owned()
    };
    let _ = std::io::stdout().write_all(text.as_bytes());
    Ok(())
}

fn run_check(args: CheckArgs) -> Result<(), Failure> {
    let colour = colour();
    let file = Some(args.scene.display().to_string());
    let out = |text: String| {
        let _ = std::io::stdout().write_all(text.as_bytes());
    };
    // The reader's diagnostics go to stderr as `render` prints them.
    let scene = match Scene::from_file_as(&args.scene, args.dialect.dialect) {
        Ok(scene) => scene,
        Err(e) => {
            say_raw(&e.render(colour));
            if args.json {
                let report = glint::CheckReport::unreadable(file, &e.diagnostics);
                out(format!("{}\n", report.to_json()));
            }
            return Err(fail(""));
        }
    };
    for w in scene.warnings() {
        say_raw(&format!("{}\n", w.render(colour)));
    }
    let report = glint::check(&Renderer::new(scene));
    if args.json {
        out(format!("{}\n", report.to_json()));
    } else {
        out(shown(&report.to_text()).into_owned());
    }
    if args.deny_warnings && report.warnings() > 0 {
        return Err(Failure::Status(1));
    }
    Ok(())
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

fn run_render(args: RenderArgs, interrupt: &AtomicBool) -> Result<(), Failure> {
    let start = Instant::now();
    let output = args.output.clone().unwrap_or_else(|| {
        let stem = args.scene.file_stem().unwrap_or_default();
        PathBuf::from(stem).with_extension("png")
    });
    // Fail on the output path before spending the render time.
    refuse_scene_as_output(&args.scene, &output)?;
    let scene = load_scene(&args.scene, args.dialect.dialect, !args.quiet)?;
    Format::from_path(&output).map_err(|e| fail(format!("error: {e}")))?;
    if args.verbose {
        for note in scene.notes() {
            say(&format!("note: {note}"));
        }
    }
    let options = args.pixels.apply(RenderOptions {
        threads: args.threads,
        region: args.region,
        aovs: match &args.aov {
            Some(list) => Aov::parse_list(list).map_err(|e| fail(format!("error: --aov: {e}")))?,
            None => Vec::new(),
        },
        photons: args.photons.options(),
        ..RenderOptions::default()
    });
    check_interrupt(interrupt)?;
    let renderer = Renderer::new(scene);
    if !args.quiet {
        for note in renderer.photon_notes(&options) {
            say(&format!("{}: {note}", args.scene.display()));
        }
    }
    let (w, h) = renderer.frame_size(&options).map_err(render_failure)?;
    check_memory(&renderer, &options, args.verbose)?;
    warn_if_slow(&renderer, &options, &args.scene)?;
    check_interrupt(interrupt)?;

    let bar = if args.quiet || !std::io::stderr().is_terminal() {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::with_draw_target(Some(1), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] [{wide_bar}] {percent:>3}% ETA {eta}",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar
    };
    let progress = |done, total| {
        bar.set_length(total);
        bar.set_position(done);
    };
    // PPM and SPPM checkpoints: the picture so far, written atomically
    // (AOVs and EXR layers are written at the end only).
    let never = AtomicBool::new(false);
    let checkpoint = |_: u64, film: &Film| {
        if let Err(e) = film.image().save_unless(&output, &never) {
            bar.suspend(|| say(&format!("warning: cannot write the checkpoint: {e}")));
        }
    };
    let control = Control {
        progress: Some(&progress),
        cancel: Some(interrupt),
        checkpoint: Some(&checkpoint),
        checkpoint_every: args.checkpoint,
    };
    let rendered = renderer.render_with(&options, control);
    bar.finish_and_clear();
    let (film, stats) = rendered.map_err(render_failure)?;
    if interrupt.load(Ordering::Relaxed) && stats.photons.iterations > 0 {
        // Stopped between iterations: the last complete one is the picture.
        film.image()
            .save_unless(&output, &never)
            .map_err(|e| fail(format!("error: cannot write the image: {e}")))?;
        say(&format!(
            "{}: interrupted: wrote iteration {} of {}",
            output.display(),
            stats.photons.iterations,
            stats.photons.planned
        ));
        return Err(Failure::Interrupted);
    }
    let cannot = |e: glint::SaveError| fail(format!("error: cannot write the image: {e}"));
    let exr = Format::from_path(&output).is_ok_and(|f| f == Format::Exr);
    if exr && !options.aovs.is_empty() {
        let saved = glint::save_exr_layers(&film, &output, interrupt);
        check_interrupt(interrupt)?;
        saved.map_err(cannot)?;
    } else {
        let saved = film.image().save_unless(&output, interrupt);
        check_interrupt(interrupt)?;
        saved.map_err(cannot)?;
        if !options.aovs.is_empty() {
            let table = renderer.primitive_table();
            let file = renderer.scene_file();
            let saved = glint::save_aov_images(&film, &output, &table, file.as_deref(), interrupt);
            check_interrupt(interrupt)?;
            saved.map_err(cannot)?;
        }
    }
    if !args.quiet {
        let r = stats.rays;
        say(&format!(
            "{}: {}x{}, {:.3} s wall ({:.3} s render, {:.3} s BVH), {:.1} M rays, {:.1} Mrays/s",
            output.display(),
            w,
            h,
            start.elapsed().as_secs_f64(),
            (stats.elapsed + stats.build).as_secs_f64(),
            stats.build.as_secs_f64(),
            r.total() as f64 / 1e6,
            stats.mrays_per_sec()
        ));
        if args.verbose {
            say(&format!(
                "rays: camera {}, reflected {}, refracted {}, shadow {}; {} pixels anti-aliased",
                r.camera, r.reflected, r.refracted, r.shadow, stats.refined_pixels
            ));
        }
    }
    Ok(())
}

/// A render that could not start: a size option out of range names its option.
fn render_failure(e: RenderError) -> Failure {
    match e {
        RenderError::Cancelled => Failure::Interrupted,
        RenderError::Side { .. } | RenderError::Samples { .. } => fail(format!("error: --{e}")),
        _ => fail(format!("error: {e}")),
    }
}

/// Rays past which a render is said, before it starts, to take over a
/// minute (at about 10 Mrays/s).
const SLOW_RAYS: u64 = 600_000_000;

/// Warns before a render that will take long, naming what drives its cost.
fn warn_if_slow(renderer: &Renderer, options: &RenderOptions, scene: &Path) -> Result<(), Failure> {
    let work = renderer.estimate(options).map_err(render_failure)?;
    if work.rays > SLOW_RAYS {
        say(&format!(
            "warning: {}: this render traces about {:.1e} rays, {} at 10 Mrays/s; \
             driven by {}\n",
            scene.display(),
            work.rays as f64,
            duration(work.rays as f64 / 1e7),
            work.drivers
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    Ok(())
}

/// Seconds as people say them: "3 minutes", "2.5 hours".
fn duration(seconds: f64) -> String {
    match seconds {
        s if s < 120.0 => format!("about {s:.0} s"),
        s if s < 7200.0 => format!("about {:.0} minutes", s / 60.0),
        s if s < 172_800.0 => format!("about {:.1} hours", s / 3600.0),
        s => format!("about {:.0} days", s / 86400.0),
    }
}

/// Refuses a render whose buffers would not fit in the memory available
/// now; with `verbose`, says the bound.
fn check_memory(
    renderer: &Renderer,
    options: &RenderOptions,
    verbose: bool,
) -> Result<(), Failure> {
    let need = renderer.memory_needed(options).map_err(render_failure)?;
    let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
    if verbose && let Some(held) = memory_held() {
        say(&format!(
            "note: memory: at most {:.1} MiB at the peak ({:.1} MiB held now, at most {:.1} MiB more for the render)",
            mib(held.saturating_add(need)),
            mib(held),
            mib(need)
        ));
    }
    let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
    match memory_available() {
        Some(avail) if need > avail => {
            let (w, h) = renderer.frame_size(options).map_err(render_failure)?;
            Err(fail(format!(
                "error: a {w}x{h} render needs up to {:.1} GiB of memory, but only {:.1} GiB is available: render smaller, with fewer AOVs, or (photon mapping) fewer photons (`--emit`) or hit points (`max_hitpoints=`)",
                gib(need),
                gib(avail),
            )))
        }
        _ => Ok(()),
    }
}

fn run_explain(args: ExplainArgs) -> Result<(), Failure> {
    let scene = load_scene(&args.scene, args.dialect.dialect, true)?;
    let options = args.pixels.apply(RenderOptions {
        threads: Some(1),
        photons: args.photons.options(),
        ..RenderOptions::default()
    });
    let renderer = Renderer::new(scene);
    let (x, y) = args.pixel;
    let e = renderer.explain(&options, x, y).map_err(render_failure)?;
    // JSON escapes what it must itself; text goes through `shown`, which
    // escapes what a terminal would obey in the file name.
    let text = if args.json {
        format!("{}\n", e.to_json(args.expand))
    } else {
        shown(&e.to_text(args.expand)).into_owned()
    };
    let _ = std::io::stdout().write_all(text.as_bytes());
    Ok(())
}

/// The resident memory of this process now (VmRSS), where known.
fn memory_held() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    proc_field(&status, "VmRSS:", 1024)
}

/// The number after `key` on its line of `text` (a /proc file), times `unit`.
fn proc_field(text: &str, key: &str, unit: u64) -> Option<u64> {
    text.lines()
        .find_map(|l| l.strip_prefix(key))
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse::<u64>().ok())
        .map(|n| n.saturating_mul(unit))
}

/// The memory this process may still take, where known: what the system
/// has available, within the address-space limit (RLIMIT_AS, less what is
/// mapped now) and the cgroup's `memory.max` (less its `memory.current`).
fn memory_available() -> Option<u64> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let system = read("/proc/meminfo").and_then(|m| proc_field(&m, "MemAvailable:", 1024));
    let mapped = read("/proc/self/status").and_then(|s| proc_field(&s, "VmSize:", 1024));
    let address_space = read("/proc/self/limits")
        .and_then(|l| proc_field(&l, "Max address space", 1))
        .map(|limit| limit.saturating_sub(mapped.unwrap_or(0)));
    let group = read("/proc/self/cgroup")
        .and_then(|c| {
            c.lines()
                .find_map(|l| l.strip_prefix("0::").map(str::to_string))
        })
        .unwrap_or_default();
    let cgroup = [
        format!("/sys/fs/cgroup{group}"),
        "/sys/fs/cgroup".to_string(),
    ]
    .iter()
    .find_map(|dir| {
        let max = read(&format!("{dir}/memory.max"))?
            .trim()
            .parse::<u64>()
            .ok()?;
        let current = read(&format!("{dir}/memory.current"))
            .and_then(|c| c.trim().parse::<u64>().ok())
            .unwrap_or(0);
        Some(max.saturating_sub(current))
    });
    [system, address_space, cgroup].into_iter().flatten().min()
}

fn run_probe(args: ProbeArgs) -> Result<(), Failure> {
    let scene = load_scene(&args.scene, args.dialect.dialect, false)?;
    let name = args.rays.display().to_string();
    let cannot_read =
        |e: &dyn std::fmt::Display| fail(format!("error: cannot read the rays from {name}: {e}"));
    // Every line is checked before anything is printed.
    let read = if name == "-" {
        read_rays(std::io::stdin().lock())
    } else {
        let file = std::fs::File::open(&args.rays).map_err(|e| cannot_read(&e))?;
        read_rays(file)
    };
    let rays = match read {
        Ok(rays) => rays,
        Err(RaysError::Read(e)) => return Err(cannot_read(&e)),
        Err(RaysError::Lines(errors, more)) => {
            let mut lines: Vec<String> = errors
                .iter()
                .map(|(n, e)| format!("error: {name}:{n}:{}: {}", e.column, e.message))
                .collect();
            if more > 0 {
                lines.push(format!("… and {more} more bad lines"));
            }
            return Err(fail(lines.join("\n")));
        }
    };

    let prober = Renderer::new(scene);
    let lines: Vec<String> = {
        use rayon::prelude::*;
        rays.par_chunks(4096)
            .map(|chunk| {
                let mut s = String::with_capacity(chunk.len() * 160);
                for &(o, d) in chunk {
                    let hit = prober.probe(o, d);
                    if args.json {
                        s.push_str(&probe::to_json(hit.as_ref()));
                    } else {
                        s.push_str(&probe::to_text(hit.as_ref()));
                    }
                    s.push('\n');
                }
                s
            })
            .collect()
    };
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let written = lines
        .iter()
        .try_for_each(|chunk| out.write_all(chunk.as_bytes()))
        .and_then(|()| out.flush());
    match written {
        // The reader went away (e.g. `| head`): nothing more to say.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(fail(format!("error: cannot write the probe answers: {e}"))),
        Ok(()) => Ok(()),
    }
}
