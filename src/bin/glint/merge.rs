//! `glint merge`: the tiles of a folder checked and merged into the
//! picture (and AOVs) one render writes, byte for byte.

use crate::tiles::{Report, report};
use crate::{Failure, check_interrupt, fail, say};
use glint::Format;
use glint::tiles::{Folder, MergeError};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// The arguments of `glint merge`.
#[derive(clap::Args)]
pub struct Args {
    /// The folder of tile files (tile-I-of-N.glt) that `glint render --tile` wrote.
    dir: PathBuf,
    /// The picture to write (.png, .bmp, .exr or .hdr); AOVs are written as `render` writes them.
    #[arg(short, long)]
    output: PathBuf,
    /// No summary line.
    #[arg(short, long)]
    quiet: bool,
}

/// Merges the folder's tiles into the output, or names every tile that is
/// not done (exit 3) and how to render them again.
pub fn exec(args: Args, interrupt: &AtomicBool) -> Result<(), Failure> {
    Format::from_path(&args.output).map_err(|e| fail(format!("error: {e}")))?;
    let folder = Folder::read(&args.dir).map_err(|e| fail(format!("error: {e}")))?;
    let hint = report(&folder);
    let merged = match folder.merge() {
        Ok(merged) => merged,
        Err(MergeError::Incomplete { .. }) => {
            say(&hint.to_string());
            say(&format!(
                "error: nothing written to {}",
                args.output.display()
            ));
            return Err(Failure::Status(3));
        }
        Err(e @ MergeError::Assemble(_)) => {
            say(&format!(
                "error: {}: {e}; nothing written",
                args.dir.display()
            ));
            return Err(Failure::Status(3));
        }
    };
    check_interrupt(interrupt)?;
    let table = || merged.table.clone();
    let saved = glint::save_film(
        &merged.film,
        &args.output,
        table,
        merged.scene_file.as_deref(),
        interrupt,
    );
    check_interrupt(interrupt)?;
    saved.map_err(|e| fail(format!("error: cannot write the image: {e}")))?;
    if !args.quiet {
        let Report { count, .. } = hint;
        let (w, h) = merged.film.frame_size();
        say(&format!(
            "{}: {w}x{h} from {count} tiles of {}",
            args.output.display(),
            args.dir.display()
        ));
    }
    Ok(())
}
