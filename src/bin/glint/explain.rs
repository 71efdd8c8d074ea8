//! `glint explain`: one pixel's ray tree.

use crate::args::{DialectArg, PhotonArgs, PixelArgs};
use crate::{Failure, load_scene, render_failure, shown};
use glint::{RenderOptions, Renderer};
use std::io::Write;
use std::path::PathBuf;

/// The arguments of `glint explain`.
#[derive(clap::Args)]
pub struct Args {
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

/// Prints the pixel's report, as text or JSON.
pub fn exec(args: Args) -> Result<(), Failure> {
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
