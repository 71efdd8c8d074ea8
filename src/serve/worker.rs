//! What a save sets off. A watcher thread polls the scene file and every
//! file it read; on a change it cancels the running render at once and
//! wakes the worker, which reads the scene again and renders it in stages
//! (coarse preview, full image, AOVs, comparison: see [`Version`]),
//! publishing each as it is ready. A broken file leaves the last good
//! picture in place.

use super::file_watch::FileWatch;
use super::state::{Phase, Shared};
use super::version::{Version, file_error};
use crate::scene::{Diagnostic, Dialect};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// How often the files are polled.
pub(crate) const POLL: Duration = Duration::from_millis(25);

/// A pending save, handed from the watcher to the worker.
struct Pending {
    /// A save was noticed (at this instant) and not yet read.
    noticed: Option<Instant>,
    /// The running render's flag: set by the next save.
    cancel: Arc<AtomicBool>,
}

/// The hand-off between the watcher and the worker.
pub(crate) struct Trigger {
    pending: Mutex<Pending>,
    wake: Condvar,
}

impl Trigger {
    /// A trigger with a save pending (the first read).
    pub fn new() -> Trigger {
        Trigger {
            pending: Mutex::new(Pending {
                noticed: Some(Instant::now()),
                cancel: Arc::new(AtomicBool::new(false)),
            }),
            wake: Condvar::new(),
        }
    }

    /// A save was noticed: the running render stops, the worker wakes.
    pub fn fire(&self) {
        let mut p = self.pending.lock().unwrap_or_else(|e| e.into_inner());
        p.noticed.get_or_insert_with(Instant::now);
        p.cancel.store(true, Ordering::Relaxed);
        self.wake.notify_all();
    }

    /// Waits for a save; returns when it was noticed and the flag of the
    /// render it starts.
    fn next(&self) -> (Instant, Arc<AtomicBool>) {
        let mut p = self.pending.lock().unwrap_or_else(|e| e.into_inner());
        loop {
            if let Some(at) = p.noticed.take() {
                p.cancel = Arc::new(AtomicBool::new(false));
                return (at, p.cancel.clone());
            }
            p = self.wake.wait(p).unwrap_or_else(|e| e.into_inner());
        }
    }
}

/// What the worker needs besides the shared state.
pub(crate) struct Config {
    /// The lineage to read the file as (`None`: by its markers).
    pub dialect: Option<Dialect>,
    /// Their picture, 8-bit RGB, and its size (`--compare`).
    pub theirs: Option<(Vec<u8>, (u32, u32))>,
}

/// Polls the files of `watch` for ever, firing `trigger` on a change.
pub(crate) fn watch_loop(watch: &Mutex<FileWatch>, trigger: &Trigger) {
    loop {
        std::thread::sleep(POLL);
        let changed = watch.lock().unwrap_or_else(|e| e.into_inner()).changed();
        if changed {
            trigger.fire();
        }
    }
}

/// Renders every save for ever.
pub(crate) fn work_loop(
    shared: &Shared,
    config: &Config,
    watch: &Mutex<FileWatch>,
    trigger: &Trigger,
) {
    let mut number = 0;
    loop {
        let (noticed, cancel) = trigger.next();
        number += 1;
        let version = Version {
            shared,
            number,
            noticed,
            cancel: &cancel,
        };
        let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            version.render(config.dialect, watch, config.theirs.as_ref())
        }));
        if run.is_err() {
            // A bug, not the user's: say so on the page, keep serving.
            shared.update(|s| {
                s.phase = Phase::Broken;
                s.diagnostics = vec![internal_error(&shared.scene)];
            });
        }
    }
}

/// A diagnostic for a render that panicked.
fn internal_error(scene: &Path) -> Diagnostic {
    file_error(
        scene,
        "glint failed while rendering this version (a bug in glint: please report it); \
         the last good picture stays"
            .to_string(),
    )
}
