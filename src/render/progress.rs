//! What a render reports as it goes and whether it should stop: the
//! caller's [`Watch`], and the count of camera rays done against the total.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// What the passes report as they go and whether they should stop.
pub(crate) struct Watch<'w> {
    /// Called with (done, total) in units of camera rays.
    pub progress: &'w (dyn Fn(u64, u64) + Sync),
    /// Set by another thread to stop the render.
    pub cancel: Option<&'w AtomicBool>,
}

impl Watch<'_> {
    /// Whether the render was asked to stop.
    pub fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

/// Camera rays done and to do over a region's passes, told to a [`Watch`].
pub(super) struct Progress<'w> {
    watch: &'w Watch<'w>,
    total: AtomicU64,
    done: AtomicU64,
}

impl<'w> Progress<'w> {
    /// `total` camera rays to do, told to `watch`.
    pub fn new(watch: &'w Watch<'w>, total: u64) -> Self {
        Progress {
            watch,
            total: AtomicU64::new(total),
            done: AtomicU64::new(0),
        }
    }

    /// Whether the render was asked to stop.
    pub fn cancelled(&self) -> bool {
        self.watch.cancelled()
    }

    /// `n` more camera rays to do (pass 2's grids, once known).
    pub fn add_total(&self, n: u64) {
        self.total.fetch_add(n, Ordering::Relaxed);
    }

    /// `n` more camera rays done.
    pub fn report(&self, n: u64) {
        let d = self.done.fetch_add(n, Ordering::Relaxed) + n;
        (self.watch.progress)(d, self.total.load(Ordering::Relaxed));
    }
}
