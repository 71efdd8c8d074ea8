//! `glint check`: the lints of a scene, without rendering it.

use crate::args::DialectArg;
use crate::{Failure, colour, fail, say_raw, shown};
use glint::{Renderer, Scene};
use std::io::Write;
use std::path::PathBuf;

/// The arguments of `glint check`.
#[derive(clap::Args)]
pub struct Args {
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

/// Prints the findings; a scene that cannot be read is reported, in JSON too.
pub fn exec(args: Args) -> Result<(), Failure> {
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
