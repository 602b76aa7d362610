//! Where long computations run: on a worker of rayon's pool.
//!
//! The potential's evaluations split their loops with rayon. Started from a
//! thread outside the pool, every such loop is handed over to the pool and
//! waited for (two context switches each): on the 1000-rotor lattice that is
//! a quarter of a step on one thread. A run started on a worker keeps its
//! loops inside the pool.

/// Runs `op` on a worker of the current rayon pool and returns its result.
pub fn on_worker<R: Send>(op: impl FnOnce() -> R + Send) -> R {
    rayon::scope(|_| op())
}
