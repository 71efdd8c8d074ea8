//! Threads: the one place that knows how many workers a render uses.

/// The most worker threads a render starts: far more than any machine's
/// cores, and each idle one costs time (10 000 took minutes on 2 cores).
pub const MAX_THREADS: usize = 1024;

/// The workers a render of `threads` (`None`: the default pool's) runs on.
pub(crate) fn workers(threads: Option<usize>) -> usize {
    threads.map_or_else(rayon::current_num_threads, |n| n.clamp(1, MAX_THREADS))
}

/// Runs `work` on a pool of `threads` workers (at most [`MAX_THREADS`]);
/// on the default pool for `None`, or when the system refuses to start one.
pub fn with_threads<T: Send>(threads: Option<usize>, work: impl FnOnce() -> T + Send) -> T {
    match threads {
        Some(n) => match rayon::ThreadPoolBuilder::new()
            .num_threads(workers(Some(n)))
            .build()
        {
            Ok(pool) => pool.install(work),
            Err(_) => work(),
        },
        None => work(),
    }
}
