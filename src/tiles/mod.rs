//! Renders split over machines (Slurm job arrays, Kubernetes Indexed Jobs,
//! GNU parallel): each part's films in one checked file (`file`) carrying
//! what it was rendered from (`fingerprint`), and a folder of them read,
//! checked and merged into the very film of one render (`folder`), its
//! gaps named as a scheduler's index list (`indices`).

mod file;
mod fingerprint;
mod folder;
mod indices;

pub use file::{ReadError, TILE_FORMAT, TileError, TileFile};
pub use fingerprint::{Fingerprint, FingerprintError};
pub use folder::{Folder, FolderError, MergeError, Merged, TileState};
pub use indices::index_list;
