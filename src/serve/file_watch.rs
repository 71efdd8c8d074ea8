//! Noticing saves: the files' modification time, size and inode, polled.
//! Polling survives an editor's rename-on-save (a new inode) and network
//! home folders, where change notifications are unreliable.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// What a file looked like when last polled (`None`: it was not there).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Stamp {
    modified: Option<SystemTime>,
    len: u64,
    inode: u64,
}

/// A set of files and how each looked when first stamped.
#[derive(Clone, Debug, Default)]
pub(crate) struct FileWatch {
    files: Vec<(PathBuf, Option<Stamp>)>,
}

impl FileWatch {
    /// Adds `path`, stamped now (a path already watched keeps its stamp).
    pub fn add(&mut self, path: &Path) {
        if !self.files.iter().any(|(p, _)| p == path) {
            self.files.push((path.to_path_buf(), stamp(path)));
        }
    }

    /// The files watched.
    pub fn paths(&self) -> impl Iterator<Item = &Path> {
        self.files.iter().map(|(p, _)| p.as_path())
    }

    /// Whether any file differs from its stamp (appeared, vanished, was
    /// written or replaced); the stamps are brought up to date.
    pub fn changed(&mut self) -> bool {
        let mut changed = false;
        for (path, old) in &mut self.files {
            let now = stamp(path);
            if now != *old {
                *old = now;
                changed = true;
            }
        }
        changed
    }
}

/// The file's stamp now (`None` when it cannot be read).
fn stamp(path: &Path) -> Option<Stamp> {
    let meta = std::fs::metadata(path).ok()?;
    #[cfg(unix)]
    let inode = {
        use std::os::unix::fs::MetadataExt;
        meta.ino()
    };
    #[cfg(not(unix))]
    let inode = 0;
    Some(Stamp {
        modified: meta.modified().ok(),
        len: meta.len(),
        inode,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_write_a_rename_over_and_a_removal_are_changes() -> std::io::Result<()> {
        let tmp = tempfile::Builder::new().prefix("glint-watch-").tempdir()?;
        let dir = tmp.path();
        let file = dir.join("a.txt");
        std::fs::write(&file, "one")?;
        let mut w = FileWatch::default();
        w.add(&file);
        assert!(!w.changed());
        std::fs::write(&file, "three")?;
        assert!(w.changed());
        assert!(!w.changed());
        // Rename-on-save: same size, a new inode.
        let tmp = dir.join("a.txt.new");
        std::fs::write(&tmp, "three")?;
        std::fs::rename(&tmp, &file)?;
        assert!(w.changed());
        std::fs::remove_file(&file)?;
        assert!(w.changed());
        assert!(!w.changed());
        std::fs::write(&file, "back")?;
        assert!(w.changed());
        Ok(())
    }
}
