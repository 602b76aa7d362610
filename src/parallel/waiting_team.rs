//! The workers of a run's pool wait for work actively while the run goes on.
//!
//! A rayon worker that finds no work yields about 32 times, then sleeps on
//! a futex, and the thread that next offers work has to wake it. On the
//! project's 2-core Intel Xeon guest a wake-up took 10-70 us (median).
//! That is longer than the parallel sections of a 1,000-rotor lattice step
//! (10-40 us of work each; benchmarks/RESULTS.md, issue 38). A worker that
//! finished its share early went to sleep, and the next section waited for
//! its wake-up. The cutoff lattice slept 7,000 times in 4,000 steps.
//!
//! While its run goes on, a run's pool keeps its other workers polling
//! instead, as OpenMP's active wait does (`OMP_WAIT_POLICY=active`). Each
//! worker runs a waiter that takes jobs with `rayon::yield_now` and spins
//! between polls (the `pause` instruction, which leaves a hyper-threaded
//! core's other thread its resources: a `sched_yield` between every two
//! polls made the 1,000-rotor cutoff lattice 20 % slower on the Xeon); every
//! [`YIELD_EVERY`] it yields its core to any other thread that wants it
//! (`sched_yield`). After [`SPIN_FOR`] without a job it polls every
//! [`POLL_EVERY`] and sleeps in between, so a long serial stretch (the
//! outputs, the set-up) holds no core. A yield returns within 5 us on an
//! idle core; one that takes over [`CONTENDED_YIELD`] gave the core to
//! another thread. A waiter that has lost more than [`GIVE_UP_AFTER`] and
//! more than [`CONTENDED_SHARE`] of its time that way shares its core with
//! another process: it stops waiting actively, and its worker waits as
//! rayon's do. Two runs of 2 threads side by side on 2 cores were up to
//! 30 % slower with waiters that never stopped; on the idle machine a few
//! yields of a run take 1-3 ms each (the kernel's writeback of the outputs,
//! the hypervisor), up to 5 % of a short run, which must not stop them
//! (issue 38, benchmarks/RESULTS.md).
//!
//! Which worker runs which job changes no value: every pass computes in an
//! order fixed by its cuts. So a fixed thread count gives the same bits with
//! or without waiters. A team waits actively only if its threads fit in the
//! cores together with the teams already waiting in the process (tests and
//! sweeps run pools side by side). Otherwise it waits as rayon does, never
//! spinning against another team's work.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// How long a waiter spins without finding a job before it starts sleeping
/// between polls: longer than any serial stretch inside a step, and short
/// against the outputs' stretches and the set-up.
pub const SPIN_FOR: Duration = Duration::from_millis(1);

/// How often a spinning waiter offers its core to other threads.
pub const YIELD_EVERY: Duration = Duration::from_micros(50);

/// The sleep between polls after [`SPIN_FOR`] without a job.
pub const POLL_EVERY: Duration = Duration::from_micros(50);

/// A yield that took longer than this gave the core to another thread.
/// Measured on the idle 2-core Xeon (a 1,000-rotor lattice, 4,000 steps):
/// 21 of 379,000 yields took 20-100 us, one over 1 ms; with a second run
/// side by side, 170 of 3,700 took over 100 us, 140 of them over 1 ms.
pub const CONTENDED_YIELD: Duration = Duration::from_micros(100);

/// The time a waiter may lose to other threads in contended yields before it
/// stops waiting actively: a few of the scheduler's time slices.
pub const GIVE_UP_AFTER: Duration = Duration::from_millis(10);

/// The share of its waiting time a waiter may lose to other threads (once
/// past [`GIVE_UP_AFTER`]): a second process on the core takes about half,
/// the idle machine's occasional slow yields under 5 %.
pub const CONTENDED_SHARE: f64 = 0.25;

/// The threads of the teams now waiting actively in this process.
static WAITING_THREADS: AtomicUsize = AtomicUsize::new(0);

/// Runs `op` on the current worker of a pool of `threads` threads, the
/// pool's other `threads - 1` workers waiting actively until `op` returns
/// (or panics). If this team and the teams already waiting do not fit in
/// `cores` (or `threads` is 1), runs `op` with rayon's own waiting.
///
/// The caller must be a worker of a pool of exactly `threads` threads with
/// nothing else to do: each waiter holds one worker until `op` returns.
pub fn run_with_waiters<R: Send>(threads: usize, cores: usize, op: impl FnOnce() -> R + Send) -> R {
    match Claim::take(&WAITING_THREADS, threads, cores) {
        Some(_claim) => place(threads - 1, &Flags::default(), op),
        None => op(),
    }
}

/// A team's share of the waiting threads' count, given back on drop.
struct Claim<'a> {
    count: &'a AtomicUsize,
    threads: usize,
}

impl<'a> Claim<'a> {
    /// Adds `threads` to `count` if the sum stays within `cores`.
    fn take(count: &'a AtomicUsize, threads: usize, cores: usize) -> Option<Self> {
        if threads < 2 {
            return None;
        }
        let before = count.fetch_add(threads, Ordering::SeqCst);
        let claim = Claim { count, threads };
        (before + threads <= cores).then_some(claim)
    }
}

impl Drop for Claim<'_> {
    fn drop(&mut self) {
        let _before = self.count.fetch_sub(self.threads, Ordering::SeqCst);
    }
}

/// `started`: `op` runs (every waiter has its worker); `finished`: `op`
/// has returned or panicked.
#[derive(Default)]
struct Flags {
    started: AtomicBool,
    finished: AtomicBool,
}

/// Sets `finished` when dropped, so a panicking `op` releases its waiters.
struct Finish<'a>(&'a AtomicBool);

impl Drop for Finish<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

/// Puts `waiters` waiters on as many workers, then runs `op` on the next.
/// Each join's second half is taken by an idle worker, because the first
/// half's waiter takes no job until `op` has started.
fn place<R: Send>(waiters: usize, flags: &Flags, op: impl FnOnce() -> R + Send) -> R {
    if waiters == 0 {
        let _finish = Finish(&flags.finished);
        flags.started.store(true, Ordering::Release);
        return op();
    }
    rayon::join(|| wait(flags), || place(waiters - 1, flags, op)).1
}

/// One worker's active wait: runs the jobs it finds until `op` finishes,
/// or until it shares its core with another process ([`contended`]).
fn wait(flags: &Flags) {
    while !flags.started.load(Ordering::Acquire) {
        std::hint::spin_loop();
    }
    let start = Instant::now();
    let (mut last_job, mut last_yield, mut lost) = (start, start, Duration::ZERO);
    while !flags.finished.load(Ordering::Acquire) && !contended(lost, start.elapsed()) {
        match rayon::yield_now() {
            Some(rayon::Yield::Executed) => last_job = Instant::now(),
            _ if last_job.elapsed() < SPIN_FOR => {
                std::hint::spin_loop();
                if last_yield.elapsed() >= YIELD_EVERY {
                    lost += contended_yield();
                    last_yield = Instant::now();
                }
            }
            _ => std::thread::sleep(POLL_EVERY),
        }
    }
}

/// Whether a waiter that has lost `lost` of `waited` to other threads in
/// its yields shares its core: over [`GIVE_UP_AFTER`] and
/// [`CONTENDED_SHARE`] of the time.
fn contended(lost: Duration, waited: Duration) -> bool {
    lost > GIVE_UP_AFTER && lost.as_secs_f64() > CONTENDED_SHARE * waited.as_secs_f64()
}

/// Yields the core; returns the time the yield took if another thread took
/// the core meanwhile (over [`CONTENDED_YIELD`]), else zero.
fn contended_yield() -> Duration {
    let start = Instant::now();
    std::thread::yield_now();
    Some(start.elapsed())
        .filter(|took| *took > CONTENDED_YIELD)
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pool(threads: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
    }

    /// The worker `install` runs on, the worker `op` runs on, and the count
    /// of jobs `op` offered that ran, for a pool of `threads` threads.
    fn placement(threads: usize) -> (Option<usize>, Option<usize>, usize) {
        let ran = AtomicUsize::new(0);
        let (outer, inner) = pool(threads).install(|| {
            let outer = rayon::current_thread_index();
            // Cores enough for any other test's teams at the same time.
            let inner = run_with_waiters(threads, 1000, || {
                rayon::scope(|s| {
                    for _ in 0..64 {
                        s.spawn(|_| {
                            let _ = ran.fetch_add(1, Ordering::Relaxed);
                        });
                    }
                });
                rayon::current_thread_index()
            });
            (outer, inner)
        });
        (outer, inner, ran.into_inner())
    }

    #[test]
    fn the_waiters_hold_the_other_workers_and_op_runs_its_jobs() {
        // With 2 threads the waiter holds the worker `install` started on,
        // so op runs on the other; without waiters op runs where it was
        // called. Every job op offers runs either way.
        let (outer, inner, ran) = placement(2);
        assert!(outer.is_some() && inner.is_some());
        assert_ne!(outer, inner, "op ran on the waiter's worker");
        assert_eq!(ran, 64);
        let (outer, inner, ran) = placement(1);
        assert_eq!(outer, inner, "one thread has no waiter");
        assert_eq!(ran, 64);
    }

    #[test]
    fn a_team_that_does_not_fit_the_cores_waits_as_rayon_does() {
        let count = AtomicUsize::new(0);
        assert!(
            Claim::take(&count, 1, 8).is_none(),
            "one thread has no one to wait"
        );
        assert!(Claim::take(&count, 3, 2).is_none(), "3 threads on 2 cores");
        assert_eq!(
            count.load(Ordering::SeqCst),
            0,
            "a refused claim takes nothing"
        );
        let first = Claim::take(&count, 2, 3).expect("2 threads fit 3 cores");
        assert!(
            Claim::take(&count, 2, 3).is_none(),
            "a second team of 2 does not fit"
        );
        assert_eq!(count.load(Ordering::SeqCst), 2);
        drop(first);
        assert_eq!(
            count.load(Ordering::SeqCst),
            0,
            "the first team gave its cores back"
        );
        assert!(Claim::take(&count, 2, 4).is_some(), "2 threads fit 4 cores");
    }

    #[test]
    fn a_waiter_stops_when_another_process_takes_a_share_of_its_core() {
        let ms = Duration::from_millis;
        assert!(!contended(ms(9), ms(10)), "under the absolute threshold");
        assert!(!contended(ms(11), ms(100)), "11 % of the time: hiccups");
        assert!(contended(ms(30), ms(100)), "30 % of the time");
        assert!(contended(ms(11), ms(40)));
    }

    #[test]
    fn a_panicking_run_releases_its_waiters() {
        let outcome = pool(2).install(|| {
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                run_with_waiters(2, 2, || panic!("the run failed"))
            }))
        });
        assert!(outcome.is_err());
    }
}
