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
//! any machine). A run whose count is not fixed takes
//! [`automatic_threads`].
//!
//! # The parallel step
//!
//! A step opens few parallel sections, each over all rotors or all grid
//! lines, with no serial work between them that grows with the number of
//! rotors. A kick-based step (NO_SQUISH, DLM, Richardson) opens:
//!
//! 1. the first half kick and the free flow, one pass over chunks of rotors
//!    (`integrators::rotor_chunks`, two loops per chunk);
//! 2. the space-frame multipoles, one pass over the rotors;
//! 3. the pair fields: one section for a cutoff sum (blocks of rows), five
//!    for the FFT lattice sum (passes over grid lines, the scatter and
//!    gather fused into the first and last; `fft3::RealFft3::convolve_into`),
//!    one plus the reciprocal passes for a direct Ewald sum;
//! 4. the external fields, gradient and torques, one pass over the rotors;
//! 5. the second half kick, one pass over chunks of rotors.
//!
//! The Gear schemes open the same sections with the corrector in place of
//! 5 and the predictor of the next step at the end of its pass (when the
//! run loop takes several steps in one `Integrator::steps` call), so no
//! section in place of 1. The Langevin thermostat draws its noise (one
//! random stream, in rotor order) on one thread during pass 1. A new
//! per-rotor or per-body pass (the
//! moving bodies, another sum) joins the pass of the same kind: work on one
//! rotor or body goes into the per-rotor pass that reads the same inputs
//! (as the external fields joined the torque pass), work on the grid into
//! the grid passes of `convolve_into`; a pass of its own only where it needs the
//! results of all rotors of the previous one. Each pass computes every
//! rotor's or grid line's values in the same order whatever the cuts, so
//! results depend on the thread count only where the pair loop's blocks do.
//!
//! Between and inside these sections a run's pool keeps its idle workers
//! polling for work instead of sleeping ([`waiting_team`]): a sleeping
//! worker's wake-up cost more than a small lattice's whole section.

mod waiting_team;

use std::num::NonZeroUsize;
use waiting_team::run_with_waiters;

/// The most threads a pool may have (checked where a count is given): more
/// than the hardware threads of any node (a few hundred), few enough that a
/// pool starts at once. A larger count is refused rather than spawned until
/// the system says no.
pub const MAX_THREADS: usize = 1024;

/// A run's thread count as a scene gives it (`run.threads`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ThreadCount {
    /// Not fixed (`"auto"`, the default): `RAYON_NUM_THREADS` if set, else
    /// [`automatic_threads`].
    #[default]
    Automatic,
    /// This many threads (1 to `MAX_THREADS`, 1024).
    Fixed(NonZeroUsize),
}

/// `count` as a fixed thread count: `None` unless 1 to `MAX_THREADS` (1024).
///
/// ```
/// use quatrot::internals::fixed_threads;
/// assert_eq!(fixed_threads(2).map(|n| n.get()), Some(2));
/// assert_eq!(fixed_threads(1024).map(|n| n.get()), Some(1024));
/// assert_eq!(fixed_threads(0), None);
/// assert_eq!(fixed_threads(-1), None);
/// assert_eq!(fixed_threads(1025), None);
/// ```
pub fn fixed_threads(count: i64) -> Option<NonZeroUsize> {
    usize::try_from(count)
        .ok()
        .filter(|&n| n <= MAX_THREADS)
        .and_then(NonZeroUsize::new)
}

/// Runs `op` on a worker of the current rayon pool and returns its result.
pub fn on_worker<R: Send>(op: impl FnOnce() -> R + Send) -> R {
    rayon::scope(|_| op())
}

/// Runs `op` on a worker of a new rayon pool of `threads` threads (built for
/// this call and dropped after it) and returns its result. The pool's other
/// workers wait for `op`'s work actively when the pool fits in the machine's
/// cores ([`waiting_team`]).
pub fn in_pool<R: Send>(
    threads: NonZeroUsize,
    op: impl FnOnce() -> R + Send,
) -> Result<R, rayon::ThreadPoolBuildError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.get())
        .build()?;
    let cores = std::thread::available_parallelism().map_or(1, NonZeroUsize::get);
    Ok(pool.install(|| run_with_waiters(threads.get(), cores, op)))
}

/// Rotors per thread of the automatic count: a run takes one thread per
/// this many rotors (at least one, at most the cores). From `make
/// bench-threads` on an idle 2-core machine (2026-11-28,
/// benchmarks/RESULTS.md): with the parallel step, a second thread paid at
/// every size measured, from 1.05x to 1.16x at 1,000 rotors (dipole
/// lattices) and 1.68x at 864 (quadrupoles) to 1.96x (multipole tops), so
/// two threads from 1,000 rotors; smaller systems were not measured.
pub const ROTORS_PER_THREAD: usize = 500;

/// Sites of moving bodies per thread of the automatic count. Whole runs
/// through the CLI, 1 against 2 threads, 3 alternating pairs on an idle
/// 2-core AMD EPYC (2026-12-03, benchmarks/RESULTS.md, moving bodies): the
/// second thread's loop speed-up was 0.90-1.23x on the 256-site Stockmayer
/// fluid, 1.27-1.48x on 500 Stockmayer sites and 0.97-1.32x on 864,
/// 1.08-1.59x on o-terphenyl's 768 and 1.43-1.52x on 512 SPC/E molecules'
/// 1,536: two threads from 500 sites.
pub const SITES_PER_THREAD: usize = 250;

/// The thread count of a run whose count is not fixed, for `size` units of
/// work (rotors, or sites of moving bodies) at `per_thread` units a thread,
/// on a machine with `cores` hardware threads: `size / per_thread`, at
/// least 1 and at most `cores`.
///
/// ```
/// use quatrot::internals::{automatic_threads, ROTORS_PER_THREAD, SITES_PER_THREAD};
/// assert_eq!(automatic_threads(1, ROTORS_PER_THREAD, 8).get(), 1);
/// assert_eq!(automatic_threads(999, ROTORS_PER_THREAD, 2).get(), 1);
/// assert_eq!(automatic_threads(1000, ROTORS_PER_THREAD, 2).get(), 2);
/// assert_eq!(automatic_threads(8000, ROTORS_PER_THREAD, 2).get(), 2);
/// assert_eq!(automatic_threads(1_000_000, ROTORS_PER_THREAD, 8).get(), 8);
/// assert_eq!(automatic_threads(1000, ROTORS_PER_THREAD, 0).get(), 1);
/// assert_eq!(automatic_threads(256, SITES_PER_THREAD, 2).get(), 1);
/// assert_eq!(automatic_threads(500, SITES_PER_THREAD, 2).get(), 2);
/// ```
pub fn automatic_threads(size: usize, per_thread: usize, cores: usize) -> NonZeroUsize {
    let count = (size / per_thread.max(1)).clamp(1, cores.max(1));
    NonZeroUsize::new(count).unwrap_or(NonZeroUsize::MIN)
}
