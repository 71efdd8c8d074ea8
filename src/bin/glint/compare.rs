//! `glint compare`: a student's picture against glint's.

use crate::args::{DialectArg, PhotonArgs, PixelArgs};
use crate::{
    Failure, check_interrupt, fail, load_scene, refuse_scene_as_output, render_failure, shown,
};
use glint::{Format, RenderOptions, Renderer};
use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// The arguments of `glint compare`.
#[derive(clap::Args)]
pub struct Args {
    /// The scene file.
    scene: PathBuf,
    /// Your render of it (.bmp or .png), the scene's size.
    theirs: PathBuf,
    /// Write the heat map here (.png or .bmp): glint's picture dimmed, the
    /// differing pixels from red to white.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also write glint's render that was compared here (.png, .bmp, .exr or .hdr).
    #[arg(long)]
    ours: Option<PathBuf>,
    #[command(flatten)]
    pixels: PixelArgs,
    #[command(flatten)]
    photons: PhotonArgs,
    /// A pixel differs when a channel is off by more than this (8-bit steps).
    #[arg(long, default_value_t = glint::DEFAULT_THRESHOLD)]
    threshold: u8,
    /// One JSON object on stdout (schema: docs/debugging.md).
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    dialect: DialectArg,
}

/// Compares, writes the heat map when asked and prints the report.
pub fn exec(args: Args, interrupt: &AtomicBool) -> Result<(), Failure> {
    for (out, flag) in [(&args.output, "-o"), (&args.ours, "--ours")] {
        if let Some(out) = out {
            refuse_scene_as_output(&args.scene, out)?;
            refuse_scene_as_output(&args.theirs, out)?;
            Format::from_path(out).map_err(|e| fail(format!("error: {flag}: {e}")))?;
        }
    }
    let scene = load_scene(&args.scene, args.dialect.dialect, true)?;
    let (theirs, size) =
        glint::read_picture(&args.theirs).map_err(|e| fail(format!("error: {e}")))?;
    let renderer = Renderer::new(scene);
    let options = RenderOptions {
        photons: args.photons.options(),
        ..args.pixels.apply(RenderOptions::default())
    };
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
    if let Some(out) = &args.ours {
        let saved = c.picture.save_unless(out, interrupt);
        check_interrupt(interrupt)?;
        saved.map_err(|e| fail(format!("error: cannot write glint's render: {e}")))?;
    }
    let text = if args.json {
        format!("{}\n", c.to_json())
    } else {
        shown(&c.to_text()).into_owned()
    };
    let _ = std::io::stdout().write_all(text.as_bytes());
    Ok(())
}
