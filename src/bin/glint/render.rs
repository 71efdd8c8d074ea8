//! `glint render`: a scene to an image, with a progress bar and a summary.

use crate::args::{DialectArg, PhotonArgs, PictureArgs, PixelArgs, at_least_one, thread_count};
use crate::memory::{memory_available, memory_held};
use crate::tile;
use crate::{
    Failure, check_interrupt, fail, load_scene, refuse_scene_as_output, render_failure, say,
};
use glint::{Control, Film, Format, RenderOptions, Renderer, Tile};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// The arguments of `glint render`.
#[derive(clap::Args)]
pub struct Args {
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
    #[command(flatten)]
    picture: PictureArgs,
    /// PPM and SPPM: write the picture every N iterations (atomically; Ctrl-C
    /// writes the last complete iteration).
    #[arg(long, default_value_t = 10, value_parser = at_least_one::<u64>)]
    checkpoint: u64,
    #[command(flatten)]
    dialect: DialectArg,
    #[command(flatten)]
    photons: PhotonArgs,
    /// Render only part I of N (I from 0 to N-1: full-width bands of 32
    /// rows, band b to part b mod N) into DIR/tile-I-of-N.glt, for `glint merge`.
    #[arg(
        long,
        value_name = "I/N",
        requires = "tiles_dir",
        conflicts_with = "output"
    )]
    tile: Option<Tile>,
    /// The folder the part's file is written to (with --tile).
    #[arg(long, value_name = "DIR", requires = "tile")]
    tiles_dir: Option<PathBuf>,
    /// With --tile: leave a valid tile of the same render in the folder alone.
    #[arg(long, requires = "tile")]
    skip_existing: bool,
}

/// Renders, writing the picture (and its AOVs), checkpoints of PPM and
/// SPPM on the way, and the summary unless quiet.
pub fn exec(args: Args, interrupt: &AtomicBool) -> Result<(), Failure> {
    let start = Instant::now();
    if let Some(dir) = &args.tiles_dir {
        tile::check_folder(dir)?;
    }
    let output = args.output.clone().unwrap_or_else(|| {
        let stem = args.scene.file_stem().unwrap_or_default();
        PathBuf::from(stem).with_extension("png")
    });
    // Fail on the output path before spending the render time.
    if args.tile.is_none() {
        refuse_scene_as_output(&args.scene, &output)?;
    }
    // Read and build the tree on the render's threads (one pool for both):
    // the reader and the builder work at once when there are two, and the
    // tree is the same on any number.
    let (format, options, read, renderer) = glint::with_threads(args.threads, || {
        let scene = load_scene(&args.scene, args.dialect.dialect, !args.quiet)?;
        // A part of a render writes its tile, not the picture.
        let format = match args.tile {
            None => Some(Format::from_path(&output).map_err(|e| fail(format!("error: {e}")))?),
            Some(_) => None,
        };
        if args.verbose {
            for note in scene.notes() {
                say(&format!("note: {note}"));
            }
        }
        let options = args.pixels.apply(RenderOptions {
            threads: args.threads,
            region: args.picture.region(),
            aovs: args
                .picture
                .aovs()
                .map_err(|e| fail(format!("error: {e}")))?,
            photons: args.photons.options(),
            tile: args.tile,
            ..RenderOptions::default()
        });
        check_interrupt(interrupt)?;
        let read = start.elapsed();
        Ok::<_, Failure>((format, options, read, Renderer::new(scene)))
    })?;
    if !args.quiet {
        for note in renderer.photon_notes(&options) {
            say(&format!("{}: {note}", args.scene.display()));
        }
    }
    let (w, h) = renderer.frame_size(&options).map_err(render_failure)?;
    check_memory(&renderer, &options, format, args.verbose)?;
    warn_if_slow(&renderer, &options, &args.scene)?;
    check_interrupt(interrupt)?;

    let bar = progress_bar(args.quiet);
    let progress = |done, total| {
        bar.set_length(total);
        bar.set_position(done);
    };
    if let (Some(tile), Some(dir)) = (args.tile, &args.tiles_dir) {
        let part = tile::Part {
            renderer: &renderer,
            options: &options,
            tile,
            dir,
            skip_existing: args.skip_existing,
        };
        let rendered = part.render(&progress, interrupt);
        bar.finish_and_clear();
        let (path, stats) = match rendered? {
            Some(done) => done,
            None => return Ok(()),
        };
        if !args.quiet {
            let times = tile::Times {
                read,
                wall: start.elapsed(),
            };
            say(&tile::summary(
                &path, tile, &options, &renderer, &stats, times,
            ));
        }
        return Ok(());
    }

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
    if let Some(warning) = renderer.photon_cap_warning(&stats.photons) {
        say(&format!("{}: {warning}", args.scene.display()));
    }
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
    let file = renderer.scene_file();
    let table = || renderer.primitive_table();
    let saved = glint::save_film(&film, &output, table, file.as_deref(), interrupt);
    check_interrupt(interrupt)?;
    saved.map_err(cannot)?;
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
            let sets: Vec<&str> = glint::Isa::available().iter().map(|i| i.name()).collect();
            say(&format!(
                "ray queries in {} (GLINT_SIMD picks one of: {})",
                glint::Isa::chosen().name(),
                sets.join(", ")
            ));
            let p = &stats.photons;
            if p.emitted > 0 {
                let passes = if p.planned > 0 {
                    format!("{} of {} passes", p.iterations, p.planned)
                } else {
                    "one map".to_string()
                };
                say(&format!(
                    "photons: {passes} of {} emitted, {} stored in the last (of {} traced), {} hit points, {:.3} s, {:.1} M photon rays",
                    p.emitted,
                    p.stored,
                    p.stored + p.thinned,
                    p.hit_points,
                    p.elapsed.as_secs_f64(),
                    p.rays as f64 / 1e6
                ));
            }
        }
    }
    Ok(())
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
/// now, saying what would make it fit; with `verbose`, says the estimate.
fn check_memory(
    renderer: &Renderer,
    options: &RenderOptions,
    format: Option<Format>,
    verbose: bool,
) -> Result<(), Failure> {
    let mut need = renderer.memory_needed(options).map_err(render_failure)?;
    if let Some(format) = format {
        need = need.with_encoding(format.encoding());
    }
    let mib = |b: u64| b as f64 / (1u64 << 20) as f64;
    if verbose && let Some(held) = memory_held() {
        say(&format!(
            "note: memory: at most {:.1} MiB at the peak ({:.1} MiB held now, at most {:.1} MiB more for the render)",
            mib(held.saturating_add(need.bytes)),
            mib(held),
            mib(need.bytes)
        ));
    }
    let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
    match memory_available() {
        Some(avail) if need.bytes > avail => {
            let (w, h) = renderer.frame_size(options).map_err(render_failure)?;
            let fits: Vec<String> = need.fits(avail).iter().map(|f| f.to_string()).collect();
            let advice = if fits.is_empty() {
                "nothing alone would make it fit".to_string()
            } else {
                format!("it would fit with {}", fits.join(", or "))
            };
            Err(fail(format!(
                "error: a {w}x{h} render needs up to {:.1} GiB of memory, but only {:.1} GiB is available: {advice}",
                gib(need.bytes),
                gib(avail),
            )))
        }
        _ => Ok(()),
    }
}

/// The progress bar: on a terminal, unless quiet.
fn progress_bar(quiet: bool) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(1), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(
        "{spinner} [{elapsed_precise}] [{wide_bar}] {percent:>3}% ETA {eta}",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}
