//! A bash script for a Slurm login node: it writes `DIR/render.sbatch` (an
//! array job, one task a tile) and `DIR/merge.sbatch`, submits the first,
//! then the second to run once every task has succeeded.

use super::error::{JobError, unfit};
use super::plan::{TileJob, Word, default_name, text};
use super::shell::{quote, words};

/// The `#SBATCH` settings beside the array, each passed to sbatch as given.
#[derive(Clone, Debug, Default)]
pub struct SlurmOptions {
    /// `--job-name` [default: [`default_name`] of the output]; the merge's is this and `-merge`.
    pub job_name: Option<String>,
    /// `--time`: each task's (and the merge's) wall-clock limit.
    pub time: Option<String>,
    /// `--cpus-per-task`: each render task's CPUs, and so its threads.
    pub cpus_per_task: Option<u32>,
    /// `--partition`.
    pub partition: Option<String>,
    /// `--account`.
    pub account: Option<String>,
    /// `--mem`: each task's memory (and the merge's).
    pub mem: Option<String>,
}

/// Ends each batch script written by a here-document (no line of theirs is this).
const END: &str = "GLINT_END";

/// The script: `set -euo pipefail`, the folders, the two batch scripts,
/// `$GLINT_SBATCH` (default `sbatch`) run on each, and a line naming both jobs.
pub fn slurm_script(job: &TileJob, options: &SlurmOptions) -> Result<String, JobError> {
    if job.tiles_dir.contains('\\') {
        // A backslash in an --output name turns off Slurm's %A and %a.
        return Err(unfit(
            "--tiles-dir",
            &job.tiles_dir,
            "Slurm reads a backslash in a log file's name as `expand no %A or %a`",
        ));
    }
    let name = match &options.job_name {
        Some(name) => text("--job-name", name)?.to_string(),
        None => default_name(job.output.as_ref()),
    };
    let mut shared = Vec::new();
    let settings = [
        ("--time", &options.time),
        ("--partition", &options.partition),
        ("--account", &options.account),
        ("--mem", &options.mem),
    ];
    for (option, value) in settings {
        if let Some(value) = value {
            shared.push(format!("{option}={}", directive(text(option, value)?)));
        }
    }
    let dir = &job.tiles_dir;
    // The logs folder in sbatch's file name patterns, where `%%` is a `%`.
    let logs = format!("{}/logs", dir.replace('%', "%%"));
    let render = format!("{dir}/render.sbatch");
    let merge = format!("{dir}/merge.sbatch");

    let mut render_settings = vec![
        format!("--job-name={}", directive(&name)),
        format!("--array=0-{}", job.tiles - 1),
        format!(
            "--output={}",
            directive(&format!("{logs}/render-%A_%a.out"))
        ),
    ];
    if let Some(cpus) = options.cpus_per_task {
        render_settings.push(format!("--cpus-per-task={cpus}"));
    }
    render_settings.extend(shared.iter().cloned());
    let tile = Word::Engine(format!("\"$SLURM_ARRAY_TASK_ID/{}\"", job.tiles));
    let threads = Word::Engine("\"${SLURM_CPUS_PER_TASK:-1}\"".to_string());
    let render_task = job.render_command(tile, Some(threads));

    let mut merge_settings = vec![
        format!("--job-name={}", directive(&format!("{name}-merge"))),
        format!("--output={}", directive(&format!("{logs}/merge-%j.out"))),
        // A failed render task cancels the merge instead of leaving it pending.
        "--kill-on-invalid-dep=yes".to_string(),
    ];
    merge_settings.extend(shared);

    let out = &job.output;
    let n = job.tiles;
    let mut s = String::new();
    s.push_str("#!/bin/bash\n");
    s.push_str(&format!(
        "# Written by `glint job slurm`: run it on the login node. It renders\n\
         #   {}\n\
         # in {n} tiles (an array job), then merges them into\n\
         #   {out}\n\
         # once every task has succeeded. GLINT_SBATCH names the sbatch command\n\
         # to run (default: sbatch).\n",
        job.scene
    ));
    s.push_str("set -euo pipefail\n");
    s.push_str(&format!("mkdir -p {}\n", quote(&format!("{dir}/logs"))));
    s.push_str(&batch_file(&render, &render_settings, &render_task));
    s.push_str(&batch_file(&merge, &merge_settings, &job.merge_command()));
    s.push_str("sbatch=${GLINT_SBATCH:-sbatch}\n");
    s.push_str(&format!(
        "job=$(\"$sbatch\" --parsable {})\njob=${{job%%;*}}\n",
        quote(&render)
    ));
    s.push_str(&format!(
        "merge=$(\"$sbatch\" --parsable --dependency=\"afterok:$job\" {})\nmerge=${{merge%%;*}}\n",
        quote(&merge)
    ));
    s.push_str(&format!(
        "printf 'render job %s ({n} tasks), merge job %s -> %s\\n' \"$job\" \"$merge\" {}\n",
        quote(out)
    ));
    Ok(s)
}

/// `cat > PATH <<'END'`, a batch script with these `#SBATCH` settings that
/// runs `command`, and `END`.
fn batch_file(path: &str, settings: &[String], command: &[Word]) -> String {
    let mut s = format!("cat > {} <<'{END}'\n#!/bin/bash\n", quote(path));
    for setting in settings {
        s.push_str(&format!("#SBATCH {setting}\n"));
    }
    s.push_str(&format!(
        "set -euo pipefail\nexec{}\n{END}\n",
        words(command)
    ));
    s
}

/// A value as sbatch reads it from an `#SBATCH` line: as it is when plain,
/// else in double quotes with `\` and `"` escaped (sbatch's own quoting).
fn directive(value: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_@%+:,./=-".contains(c);
    if !value.is_empty() && value.chars().all(plain) {
        return value.to_string();
    }
    format!("\"{}\"", value.replace('\\', r"\\").replace('"', "\\\""))
}
