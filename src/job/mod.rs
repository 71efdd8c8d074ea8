//! Job scripts that split a render into tiles on an existing engine: a
//! Slurm array job (`slurm`), a Kubernetes Indexed Job (`k8s`) or a GNU
//! parallel line (`parallel`). Each runs the same `glint render --tile I/N`
//! for every index (`plan`), then `glint merge`; they submit nothing
//! themselves. `shell` quotes words for bash, `error` says what a script
//! cannot carry.

mod error;
mod k8s;
mod parallel;
mod plan;
mod shell;
mod slurm;

pub use error::JobError;
pub use k8s::{K8sOptions, k8s_manifests};
pub use parallel::{ParallelOptions, parallel_line};
pub use plan::{JobPaths, MAX_JOB_TILES, TileJob, default_name, default_tiles_dir};
pub(crate) use shell::quote;
pub use slurm::{SlurmOptions, slurm_script};
