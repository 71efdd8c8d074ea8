//! `glint tiles`: which tiles of a folder are done, missing, corrupt or of
//! another render, the missing ones as an array list, and how to render them.

use crate::{Failure, fail};
use glint::tiles::{Folder, TileState, index_list};
use std::path::PathBuf;

/// The arguments of `glint tiles`.
#[derive(clap::Args)]
pub struct Args {
    /// The folder of tile files (tile-I-of-N.glt).
    dir: PathBuf,
    /// Also write a picture of which part rendered which band: the pixels
    /// tinted with their part's colour, bands not done black.
    #[arg(long, value_name = "OUT")]
    picture: Option<PathBuf>,
}

/// Prints the folder's state: exit 0 when every tile is done, 3 when not.
pub fn exec(args: Args) -> Result<(), Failure> {
    let folder = Folder::read(&args.dir).map_err(|e| fail(format!("error: {e}")))?;
    let report = report(&folder);
    println!("{report}");
    if let Some(out) = &args.picture {
        let Some(picture) = folder.picture() else {
            return Err(fail(format!(
                "error: {}: no tile is done, so there is no picture to draw",
                args.dir.display()
            )));
        };
        picture
            .save(out)
            .map_err(|e| fail(format!("error: cannot write the picture: {e}")))?;
    }
    if report.complete {
        Ok(())
    } else {
        Err(Failure::Status(3))
    }
}

/// What a folder holds, as people read it.
pub struct Report {
    /// Tiles in all.
    pub count: u32,
    /// Whether every tile is done.
    pub complete: bool,
    lines: Vec<String>,
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.lines.join("\n"))
    }
}

/// The report of `folder`: a line a tile not done, the counts, the
/// indices to render again as an array list and the command that does.
pub fn report(folder: &Folder) -> Report {
    let n = folder.count;
    let mut lines = Vec::new();
    let of = |want: fn(&TileState) -> bool| -> Vec<u32> {
        (0..n)
            .filter(|&i| want(&folder.states[i as usize]))
            .collect()
    };
    for (i, state) in folder.states.iter().enumerate() {
        match state {
            TileState::Done => {}
            TileState::Missing => lines.push(format!("tile {i} of {n}: missing")),
            TileState::Corrupt(why) => lines.push(format!("tile {i} of {n}: corrupt: {why}")),
            TileState::Foreign(why) => lines.push(format!("tile {i} of {n}: foreign: {why}")),
        }
    }
    for (name, count) in &folder.others {
        lines.push(format!(
            "{name}: a tile of a render cut into {count} parts, not {n}: ignored"
        ));
    }
    let done = of(|s| *s == TileState::Done);
    let missing = of(|s| *s == TileState::Missing);
    let corrupt = of(|s| matches!(s, TileState::Corrupt(_)));
    let foreign = of(|s| matches!(s, TileState::Foreign(_)));
    for (what, list) in [
        ("done", &done),
        ("missing", &missing),
        ("corrupt", &corrupt),
        ("foreign", &foreign),
    ] {
        lines.push(format!("{what}: {} ({})", list.len(), index_list(list)));
    }
    let redo = folder.not_done();
    if !redo.is_empty() {
        lines.push(format!("to render again: {}", index_list(&redo)));
        lines.push(format!("rerun: {}", folder.rerun(&redo)));
    }
    Report {
        count: n,
        complete: redo.is_empty(),
        lines,
    }
}
