//! Threads: the one place that knows how many workers a render uses.

/// The most worker threads a render starts: far more than any machine's
/// cores, and each idle one costs time (10 000 took minutes on 2 cores).
pub const MAX_THREADS: usize = 1024;

/// Runs `work` on a pool of `threads` workers (at most [`MAX_THREADS`]);
/// on the default pool for `None`, or when the system refuses to start one.
pub(crate) fn with_threads<T: Send>(threads: Option<usize>, work: impl FnOnce() -> T + Send) -> T {
    match threads {
        Some(n) => match rayon::ThreadPoolBuilder::new()
            .num_threads(n.clamp(1, MAX_THREADS))
            .build()
        {
            Ok(pool) => pool.install(work),
            Err(_) => work(),
        },
        None => work(),
    }
}
