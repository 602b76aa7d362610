//! Where long computations run: on a worker of rayon's pool.
//!
//! The potential's evaluations split their loops with rayon. Started from a
//! thread outside the pool, every such loop is handed over to the pool and
//! waited for (two context switches each): on the 1000-rotor lattice that is
//! a quarter of a step on one thread. A run started on a worker keeps its
//! loops inside the pool.
//!
//! The periodic pair loop sums its per-thread blocks in an order that
//! depends on the pool's size, so a run's last bits depend on it too:
//! [`in_pool`] fixes the size (a sweep's runs then give the same numbers on
//! any machine).

use std::num::NonZeroUsize;

/// The most threads a pool may have (checked where a count is given): more
/// than the hardware threads of any node (a few hundred), few enough that a
/// pool starts at once. A larger count is refused rather than spawned until
/// the system says no.
pub const MAX_THREADS: usize = 1024;

/// Runs `op` on a worker of the current rayon pool and returns its result.
pub fn on_worker<R: Send>(op: impl FnOnce() -> R + Send) -> R {
    rayon::scope(|_| op())
}

/// Runs `op` on a worker of a new rayon pool of `threads` threads (built for
/// this call and dropped after it) and returns its result.
pub fn in_pool<R: Send>(
    threads: NonZeroUsize,
    op: impl FnOnce() -> R + Send,
) -> Result<R, rayon::ThreadPoolBuildError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.get())
        .build()?;
    Ok(pool.install(op))
}
