//! `glint job slurm|k8s|parallel`: the script that renders a scene as tiles
//! on an engine and merges them, printed to stdout; nothing is submitted.

use crate::args::{DialectArg, PhotonArgs, PictureArgs, PixelArgs, at_least_one, thread_count};
use crate::{Failure, fail, refuse_scene_as_output};
use glint::Format;
use glint::job::{JobPaths, K8sOptions, ParallelOptions, SlurmOptions, TileJob, default_tiles_dir};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The arguments of `glint job`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    engine: Engine,
}

/// The engines a job is written for.
#[derive(clap::Subcommand)]
enum Engine {
    /// A bash script for a Slurm login node: it writes DIR/render.sbatch (an
    /// array job, a task a tile) and DIR/merge.sbatch, submits both with
    /// $GLINT_SBATCH (default sbatch; the merge after every task has
    /// succeeded) and prints their job IDs.
    Slurm(SlurmArgs),
    /// Kubernetes YAML: an Indexed Job rendering the tiles, and a Job that
    /// waits for them and merges them (`kubectl apply -f`).
    K8s(K8sArgs),
    /// A GNU parallel line rendering the tiles here or over ssh, then merging;
    /// run again, it renders only the tiles that failed.
    Parallel(ParallelArgs),
}

/// What every engine's job is: the scene, its tiles, the output, and the
/// render options each task passes on.
#[derive(clap::Args)]
struct TileArgs {
    /// The scene file.
    scene: PathBuf,
    /// Tiles to split the render into (tasks), 1 to 100000.
    #[arg(long, value_name = "N")]
    tiles: u32,
    /// The merged image; the format follows the extension (.png, .bmp, .exr or .hdr).
    #[arg(short, long)]
    output: PathBuf,
    /// The folder of the tiles [default: OUT with its extension replaced by .tiles]
    #[arg(long)]
    tiles_dir: Option<PathBuf>,
    /// The glint the tasks run, as given [default: this glint's absolute path; k8s: glint]
    #[arg(long)]
    glint: Option<PathBuf>,
    /// Each task leaves a valid tile of the same render alone (`render --skip-existing`).
    #[arg(long)]
    skip_existing: bool,
    #[command(flatten)]
    pixels: PixelArgs,
    #[command(flatten)]
    picture: PictureArgs,
    #[command(flatten)]
    dialect: DialectArg,
    #[command(flatten)]
    photons: PhotonArgs,
}

/// The arguments of `glint job slurm`.
#[derive(clap::Args)]
struct SlurmArgs {
    #[command(flatten)]
    tiles: TileArgs,
    /// The render tasks' job name [default: glint-STEM, STEM the output's]; the merge's adds -merge.
    #[arg(long)]
    job_name: Option<String>,
    /// Each task's time limit, as sbatch takes it (`2:00:00`).
    #[arg(long)]
    time: Option<String>,
    /// CPUs of each render task, and so its threads [default: 1].
    #[arg(long, value_parser = at_least_one::<u32>)]
    cpus_per_task: Option<u32>,
    /// The partition to run in.
    #[arg(long)]
    partition: Option<String>,
    /// The account to charge.
    #[arg(long)]
    account: Option<String>,
    /// Each task's memory, as sbatch takes it (`4G`).
    #[arg(long)]
    mem: Option<String>,
}

/// The arguments of `glint job k8s`.
#[derive(clap::Args)]
struct K8sArgs {
    #[command(flatten)]
    tiles: TileArgs,
    /// The container image; glint on its PATH (or --glint) and a POSIX shell.
    #[arg(long)]
    image: String,
    /// The PersistentVolumeClaim (ReadWriteMany) holding the scene, its files, the tiles and the output.
    #[arg(long)]
    claim: String,
    /// Where every pod mounts the claim; relative paths are taken from it.
    #[arg(long, default_value = "/data")]
    mount: String,
    /// The render Job's name, a DNS label [default: glint-STEM made one]; the merge's adds -merge.
    #[arg(long)]
    name: Option<String>,
    /// Pods rendering at once [default: 16, or the tile count when fewer].
    #[arg(long, value_parser = at_least_one::<u32>)]
    parallelism: Option<u32>,
    /// CPUs each pod asks for, and so each render's threads.
    #[arg(long, default_value_t = 1, value_parser = at_least_one::<u32>)]
    cpus: u32,
    /// Memory each pod asks for, a Kubernetes quantity (`4Gi`).
    #[arg(long)]
    mem: Option<String>,
}

/// The arguments of `glint job parallel`.
#[derive(clap::Args)]
struct ParallelArgs {
    #[command(flatten)]
    tiles: TileArgs,
    /// Renders at once on each machine (parallel's -j).
    #[arg(short, long, default_value_t = 1, value_parser = at_least_one::<u32>)]
    jobs: u32,
    /// The machines to run on (parallel's --sshloginfile); they must see this
    /// machine's files at the same paths.
    #[arg(long)]
    sshloginfile: Option<PathBuf>,
    /// Each render's threads [default: one per core of its machine].
    #[arg(long, value_parser = thread_count)]
    threads: Option<usize>,
}

/// Prints the engine's script (nothing when an option is wrong: exit 2).
pub fn exec(args: Args) -> Result<(), Failure> {
    let text = match args.engine {
        Engine::Slurm(a) => {
            let job = local_job(&a.tiles, Vec::new())?;
            let options = SlurmOptions {
                job_name: a.job_name,
                time: a.time,
                cpus_per_task: a.cpus_per_task,
                partition: a.partition,
                account: a.account,
                mem: a.mem,
            };
            glint::job::slurm_script(&job, &options)
        }
        Engine::K8s(a) => {
            let job = claim_job(&a.tiles, Path::new(&a.mount))?;
            let options = K8sOptions {
                image: a.image,
                claim: a.claim,
                mount: a.mount,
                name: a.name,
                parallelism: a.parallelism,
                cpus: a.cpus,
                memory: a.mem,
            };
            glint::job::k8s_manifests(&job, &options)
        }
        Engine::Parallel(a) => {
            let threads = a
                .threads
                .map(|t| vec!["--threads".to_string(), t.to_string()]);
            let job = local_job(&a.tiles, threads.unwrap_or_default())?;
            let options = ParallelOptions {
                jobs: a.jobs,
                sshloginfile: a
                    .sshloginfile
                    .map(|f| current_dir().map(|here| here.join(f)))
                    .transpose()?,
            };
            glint::job::parallel_line(&job, &options)
        }
    }
    .map_err(|e| fail(format!("error: {e}")))?;
    std::io::stdout()
        .write_all(text.as_bytes())
        .map_err(|e| fail(format!("error: cannot write the job to stdout: {e}")))
}

/// A job whose tasks see this machine's files (Slurm, parallel): every path
/// made absolute, the scene checked, `extra` render options after the others.
fn local_job(args: &TileArgs, extra: Vec<String>) -> Result<TileJob, Failure> {
    let scene = args.scene.display();
    match std::fs::metadata(&args.scene) {
        Ok(m) if m.is_file() => {}
        Ok(_) => return Err(fail(format!("error: the scene {scene} is not a file"))),
        Err(e) => return Err(fail(format!("error: cannot read the scene {scene}: {e}"))),
    }
    refuse_scene_as_output(&args.scene, &args.output)?;
    let glint = match &args.glint {
        Some(glint) => glint.clone(),
        None => std::env::current_exe().map_err(|e| {
            fail(format!(
                "error: --glint: cannot find this glint's path: {e}"
            ))
        })?,
    };
    tile_job(args, &glint, &current_dir()?, extra)
}

/// The folder glint runs in, which relative paths are taken from.
fn current_dir() -> Result<PathBuf, Failure> {
    std::env::current_dir().map_err(|e| fail(format!("error: cannot read the current folder: {e}")))
}

/// A job whose tasks run in pods (k8s): paths as given, relative ones taken
/// from the claim's `mount`; glint as the image has it unless told.
fn claim_job(args: &TileArgs, mount: &Path) -> Result<TileJob, Failure> {
    let glint = args.glint.clone().unwrap_or_else(|| PathBuf::from("glint"));
    tile_job(args, &glint, mount, Vec::new())
}

/// The job of `args`: paths taken from `base`, the output's format and the
/// render options checked, `extra` render options after the others.
fn tile_job(
    args: &TileArgs,
    glint: &Path,
    base: &Path,
    extra: Vec<String>,
) -> Result<TileJob, Failure> {
    Format::from_path(&args.output).map_err(|e| fail(format!("error: -o: {e}")))?;
    args.picture
        .aovs()
        .map_err(|e| fail(format!("error: {e}")))?;
    let output = base.join(&args.output);
    let tiles_dir = match &args.tiles_dir {
        Some(dir) => base.join(dir),
        None => default_tiles_dir(&output),
    };
    let paths = JobPaths {
        glint,
        scene: &base.join(&args.scene),
        output: &output,
        tiles_dir: &tiles_dir,
    };
    let mut options = args.pixels.to_args();
    options.extend(args.picture.to_args());
    options.extend(args.dialect.to_args());
    options.extend(args.photons.to_args());
    if args.skip_existing {
        options.push("--skip-existing".to_string());
    }
    options.extend(extra);
    TileJob::new(paths, args.tiles, options).map_err(|e| fail(format!("error: {e}")))
}
