//! The `glint` command line: argument parsing, progress and reporting only.

use clap::{Args, Parser, Subcommand};
use glint::{
    Aov, Control, Format, MAX_THREADS, Region, RenderError, RenderOptions, Renderer, Scene,
    memory_needed, parse_ray, to_json, to_text,
};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::{BufRead, IsTerminal, Read, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
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
}

#[derive(Args)]
struct ExplainArgs {
    /// The scene file.
    scene: PathBuf,
    /// The pixel, `X,Y` (column, row from the top, from 0).
    #[arg(long, value_parser = pixel)]
    pixel: (u32, u32),
    /// Image width in pixels, as for `render`.
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels, as for `render`.
    #[arg(long)]
    height: Option<u32>,
    /// Seed of the random streams, as for `render`.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Stratified samples per pixel, as for `render` (default: adaptive anti-aliasing).
    #[arg(long, value_parser = at_least_one::<u32>)]
    spp: Option<u32>,
    /// List every ray of glossy fans and every sample, instead of summing them up.
    #[arg(long)]
    expand: bool,
    /// One JSON object (schema: docs/debugging.md).
    #[arg(long)]
    json: bool,
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

#[derive(Args)]
struct RenderArgs {
    /// The scene file.
    scene: PathBuf,
    /// Output image; the format follows the extension [default: the scene's name with .png]
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Image width in pixels, overriding the scene's image_W= (the lens stays as the scene sets it).
    #[arg(long)]
    width: Option<u32>,
    /// Image height in pixels, overriding the scene's image_H=.
    #[arg(long)]
    height: Option<u32>,
    /// Worker threads, 1 to 1024 [default: one per core]
    #[arg(long, value_parser = thread_count)]
    threads: Option<usize>,
    /// Seed of the random streams (same scene and seed: same bytes, whatever the threads).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Stratified samples per pixel instead of the framework's adaptive anti-aliasing
    /// (at least 1; 1: exactly one ray through each pixel's centre).
    #[arg(long, value_parser = at_least_one::<u32>)]
    spp: Option<u32>,
    /// No progress bar, no summary (warnings and errors are still printed).
    #[arg(short, long)]
    quiet: bool,
    /// Also print notes (where textures were found) and a breakdown of the rays.
    #[arg(short, long)]
    verbose: bool,
    /// Passes to write beside the picture, comma-separated: normal, depth,
    /// position, uv, primitive, albedo, rays (layers of an .exr; else OUT.PASS.EXT files).
    #[arg(long)]
    aov: Option<String>,
    /// Render only columns X0..X1 and rows Y0..Y1 (ends excluded, rows from
    /// the top): `X0,Y0,X1,Y1`; its pixels are those of the whole render.
    #[arg(long, value_parser = region)]
    region: Option<Region>,
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

/// A failure to report: the message, printed escaped (if not empty), and exit code 2.
struct Failure(String);

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => run_render(args),
        Command::Probe(args) => run_probe(args),
        Command::Explain(args) => run_explain(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure(message)) => {
            if !message.is_empty() {
                eprintln!("{}", shown(&message));
            }
            ExitCode::from(2)
        }
    }
}

/// Reads a scene, printing its warnings, or its errors (already escaped, so
/// printed here, perhaps in colour) and a [`Failure`] with nothing left to say.
fn load_scene(path: &Path) -> Result<Scene, Failure> {
    let colour = colour();
    let scene = Scene::from_file(path).map_err(|e| {
        eprintln!("{}", e.render(colour));
        Failure(String::new())
    })?;
    for w in scene.warnings() {
        eprintln!("{}\n", w.render(colour));
    }
    Ok(scene)
}

fn run_render(args: RenderArgs) -> Result<(), Failure> {
    let start = Instant::now();
    let scene = load_scene(&args.scene)?;
    let output = args.output.clone().unwrap_or_else(|| {
        let stem = args.scene.file_stem().unwrap_or_default();
        PathBuf::from(stem).with_extension("png")
    });
    // Fail on the output path before spending the render time.
    Format::from_path(&output).map_err(|e| Failure(format!("error: {e}")))?;
    if args.verbose {
        for note in scene.notes() {
            eprintln!("note: {}", shown(note));
        }
    }
    let options = RenderOptions {
        threads: args.threads,
        seed: args.seed,
        spp: args.spp,
        width: args.width,
        height: args.height,
        region: args.region,
        aovs: match &args.aov {
            Some(list) => {
                Aov::parse_list(list).map_err(|e| Failure(format!("error: --aov: {e}")))?
            }
            None => Vec::new(),
        },
    };
    let renderer = Renderer::new(scene);
    let (w, h) = renderer.frame_size(&options).map_err(render_failure)?;
    check_memory(w, h)?;

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
    let control = Control {
        progress: Some(&progress),
        cancel: None,
    };
    let (film, stats) = renderer
        .render_with(&options, control)
        .map_err(render_failure)?;
    bar.finish_and_clear();
    let cannot = |e: glint::SaveError| Failure(format!("error: cannot write the image: {e}"));
    let exr = Format::from_path(&output).is_ok_and(|f| f == Format::Exr);
    if exr && !options.aovs.is_empty() {
        glint::save_exr_layers(&film, &output).map_err(cannot)?;
    } else {
        film.image().save(&output).map_err(cannot)?;
        if !options.aovs.is_empty() {
            let table = renderer.primitive_table();
            let file = renderer.scene_file();
            glint::save_pass_images(&film, &output, &table, file.as_deref()).map_err(cannot)?;
        }
    }
    if !args.quiet {
        let r = stats.rays;
        eprintln!(
            "{}: {}x{}, {:.3} s wall ({:.3} s render, {:.3} s BVH), {:.1} M rays, {:.1} Mrays/s",
            output.display(),
            w,
            h,
            start.elapsed().as_secs_f64(),
            (stats.elapsed + stats.build).as_secs_f64(),
            stats.build.as_secs_f64(),
            r.total() as f64 / 1e6,
            stats.mrays_per_sec()
        );
        if args.verbose {
            eprintln!(
                "rays: camera {}, reflected {}, refracted {}, shadow {}; {} pixels anti-aliased",
                r.camera, r.reflected, r.refracted, r.shadow, stats.refined_pixels
            );
        }
    }
    Ok(())
}

/// A render that could not start: a size option out of range names its option.
fn render_failure(e: RenderError) -> Failure {
    match e {
        RenderError::Side { .. } | RenderError::Samples { .. } => Failure(format!("error: --{e}")),
        _ => Failure(format!("error: {e}")),
    }
}

/// Refuses a size whose buffers would not fit in the memory available now.
fn check_memory(w: u32, h: u32) -> Result<(), Failure> {
    let need = memory_needed(w, h);
    let available = std::fs::read_to_string("/proc/meminfo").ok().and_then(|m| {
        m.lines()
            .find(|l| l.starts_with("MemAvailable:"))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|kb| kb.parse::<u64>().ok())
            .map(|kb| kb * 1024)
    });
    match available {
        Some(avail) if need > avail => Err(Failure(format!(
            "error: a {w}x{h} image needs about {:.1} GiB of memory, but only {:.1} GiB is available",
            need as f64 / (1u64 << 30) as f64,
            avail as f64 / (1u64 << 30) as f64
        ))),
        _ => Ok(()),
    }
}

fn run_explain(args: ExplainArgs) -> Result<(), Failure> {
    let scene = load_scene(&args.scene)?;
    let options = RenderOptions {
        threads: Some(1),
        seed: args.seed,
        spp: args.spp,
        width: args.width,
        height: args.height,
        region: None,
        aovs: Vec::new(),
    };
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

fn run_probe(args: ProbeArgs) -> Result<(), Failure> {
    let scene = load_scene(&args.scene)?;
    let name = args.rays.display().to_string();
    let mut text = String::new();
    let read = if name == "-" {
        std::io::stdin().lock().read_to_string(&mut text)
    } else {
        std::fs::File::open(&args.rays).and_then(|mut f| f.read_to_string(&mut text))
    };
    read.map_err(|e| Failure(format!("error: cannot read the rays from {name}: {e}")))?;

    // Validate every line before printing anything.
    let mut rays = Vec::new();
    let mut errors = Vec::new();
    for (n, line) in text.as_bytes().lines().enumerate() {
        let line = line.unwrap_or_default();
        let body = line.split('#').next().unwrap_or("");
        if body.trim().is_empty() {
            continue;
        }
        match parse_ray(body) {
            Ok(r) => rays.push(r),
            Err(e) => errors.push(format!(
                "error: {name}:{}:{}: {}",
                n + 1,
                e.column,
                e.message
            )),
        }
    }
    if !errors.is_empty() {
        return Err(Failure(errors.join("\n")));
    }

    let prober = Renderer::new(scene);
    let lines: Vec<String> = {
        use rayon::prelude::*;
        rays.par_chunks(4096)
            .map(|chunk| {
                let mut s = String::with_capacity(chunk.len() * 160);
                for &(o, d) in chunk {
                    let hit = prober.probe(o, d);
                    if args.json {
                        s.push_str(&to_json(hit.as_ref()));
                    } else {
                        s.push_str(&to_text(hit.as_ref()));
                    }
                    s.push('\n');
                }
                s
            })
            .collect()
    };
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    for chunk in lines {
        if out.write_all(chunk.as_bytes()).is_err() {
            return Ok(()); // the reader went away (e.g. `| head`)
        }
    }
    let _ = out.flush();
    Ok(())
}
