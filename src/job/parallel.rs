//! A GNU parallel line: the tiles rendered on this machine, or over ssh on
//! machines sharing its files, then merged. `--joblog` and `--resume-failed`
//! make running it again render only the tiles that failed.

use super::error::{JobError, unfit};
use super::plan::{TileJob, Word, path_text};
use super::shell::{quote, words};
use std::path::PathBuf;

/// How parallel runs the tasks.
#[derive(Clone, Debug)]
pub struct ParallelOptions {
    /// Tasks at once on each machine (`-j`).
    pub jobs: u32,
    /// The machines to run on, a file as parallel's `--sshloginfile` reads it.
    pub sshloginfile: Option<PathBuf>,
}

/// `mkdir -p DIR && parallel … ::: $(seq 0 N-1) && GLINT merge DIR -o OUT`,
/// a line. parallel is given `-q`, so it passes the command's words as they are.
pub fn parallel_line(job: &TileJob, options: &ParallelOptions) -> Result<String, JobError> {
    for (option, value) in job.values() {
        if let Some(open) = value.find('{')
            && value[open..].contains('}')
        {
            return Err(unfit(
                option,
                value,
                "GNU parallel would read `{…}` in it as a replacement string",
            ));
        }
    }
    let dir = &job.tiles_dir;
    let mut line = format!(
        "mkdir -p {} && parallel --joblog {} --resume-failed -j {}",
        quote(dir),
        quote(&format!("{dir}/joblog")),
        options.jobs
    );
    if let Some(file) = &options.sshloginfile {
        line.push_str(&format!(
            " --sshloginfile {}",
            quote(&path_text("--sshloginfile", file)?)
        ));
    }
    line.push_str(" -q");
    let tile = Word::Engine(format!("{{}}/{}", job.tiles));
    line.push_str(&words(&job.render_command(tile, None)));
    line.push_str(&format!(" ::: $(seq 0 {}) &&", job.tiles - 1));
    line.push_str(&words(&job.merge_command()));
    line.push('\n');
    Ok(line)
}
