//! Writing a file atomically: a uniquely named temporary file beside it,
//! synced and renamed into place, safe on a folder several hosts share.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// Writes `bytes` to a hidden temporary file beside `path`, syncs it and
/// renames it over `path`; the temporary file is removed on failure, and
/// when `cancel` is set before the rename (an `Interrupted` error).
pub fn write_atomically(path: &Path, bytes: &[u8], cancel: &AtomicBool) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let tmp = dir.join(temporary_name(path));
    let result = (|| {
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        if cancel.load(Ordering::Relaxed) {
            return Err(std::io::Error::from(std::io::ErrorKind::Interrupted));
        }
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// `.glint-<16 hex digits>.tmp` (27 bytes, so any legal output name has a
/// legal temporary name): a hash of the output path, the host name, the
/// process, the time and a per-process counter, unique across the hosts
/// that share a folder.
pub(super) fn temporary_name(path: &Path) -> String {
    use std::hash::{BuildHasher, Hash, Hasher};
    use std::sync::atomic::AtomicU64;
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    // RandomState is seeded from the system's randomness.
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    path.hash(&mut h);
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .or_else(|_| std::env::var("HOSTNAME"))
        .unwrap_or_default()
        .hash(&mut h);
    std::process::id().hash(&mut h);
    COUNTER.fetch_add(1, Ordering::Relaxed).hash(&mut h);
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or_default()
        .hash(&mut h);
    format!(".glint-{:016x}.tmp", h.finish())
}
