//! `glint probe`: the first hit of each ray of a file.

use crate::args::DialectArg;
use crate::{Failure, fail, load_scene};
use glint::{RaysError, Renderer, probe, read_rays};
use std::io::Write;
use std::path::PathBuf;

/// The arguments of `glint probe`.
#[derive(clap::Args)]
pub struct Args {
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

/// Reads every ray (refusing the file at its first bad lines), then prints
/// one answer a ray, in order.
pub fn exec(args: Args) -> Result<(), Failure> {
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
