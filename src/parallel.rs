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

use crate::checks::{at_least_one, InputError};
use std::num::NonZeroUsize;

/// The most threads a pool may have: more than the hardware threads of any
/// node (a few hundred), few enough that a pool starts at once. A larger
/// count is refused rather than spawned until the system says no.
pub const MAX_THREADS: usize = 1024;

/// The size of a pool of `n` threads: from 1 to [`MAX_THREADS`].
pub fn thread_count(n: i64) -> Result<NonZeroUsize, InputError> {
    let n = at_least_one(n)?;
    usize::try_from(n)
        .ok()
        .filter(|&n| n <= MAX_THREADS)
        .and_then(NonZeroUsize::new)
        .ok_or_else(|| InputError::new("", format!("must be at most {MAX_THREADS}, got {n}")))
}

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

#[cfg(test)]
mod tests {
    use super::*;

    /// A pool has from one to `MAX_THREADS` threads; sizes outside are
    /// refused with the value.
    #[test]
    fn thread_counts_are_at_least_one_and_at_most_the_limit() {
        assert_eq!(thread_count(1024).map(NonZeroUsize::get), Ok(1024));
        assert_eq!(
            thread_count(1025).unwrap_err().message,
            "must be at most 1024, got 1025"
        );
        assert_eq!(
            thread_count(1_000_000_000).unwrap_err().message,
            "must be at most 1024, got 1000000000"
        );
        assert_eq!(thread_count(3).map(NonZeroUsize::get), Ok(3));
        assert_eq!(
            thread_count(0).unwrap_err().at("threads").to_string(),
            "threads: must be >= 1, got 0"
        );
        assert_eq!(
            thread_count(-1).unwrap_err().message,
            "must be >= 1, got -1"
        );
    }
}
