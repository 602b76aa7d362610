//! What a second thread adds on this host (issue 38): memory bandwidth and
//! arithmetic throughput at 1 and 2 threads.
//!
//! - *Bandwidth*: a STREAM-style triad `a = b + 3 c` over three arrays of
//!   [`ELEMENTS`] f64 (128 MiB each, far beyond any cache); each array is
//!   first touched by the pool that uses it (24 bytes moved per element;
//!   write-allocate traffic not counted).
//! - *Arithmetic*: each thread updates [`CHAINS`] independent accumulators
//!   held in registers (a multiply and an add each, no memory traffic) for
//!   [`ROUNDS`] rounds. Two virtual CPUs that the hypervisor places on one
//!   physical core's two hardware threads share its floating-point units and
//!   gain little here; on two cores they gain 2x.
//!
//! Each is timed in a rayon pool of 1 and of 2 threads started from a worker
//! (as a run is), the best of [`REPEATS`] sweeps. Prints one JSON line:
//! `{"gb_per_s_1", "gb_per_s_2", "gflops_1", "gflops_2"}`. `make
//! bench-threads` runs it before every pair of its runs. A measurement, not a
//! test.
//!
//! `cargo run --release --example host_probe`

use rayon::prelude::*;
use std::hint::black_box;
use std::time::Instant;

/// Elements per array of the triad: 2^24 f64, 128 MiB.
const ELEMENTS: usize = 1 << 24;

/// Sweeps per measurement and thread count (the fastest is kept).
const REPEATS: usize = 10;

/// Elements per rayon task of the triad.
const CHUNK: usize = 1 << 16;

/// Independent accumulators per thread of the arithmetic probe (enough to
/// cover the latency of the floating-point pipes).
const CHAINS: usize = 24;

/// Rounds of the arithmetic probe per thread and sweep (about 20 ms).
const ROUNDS: usize = 1 << 19;

/// A pool of `threads` threads running `work` from one of its workers.
fn in_pool<R: Send>(threads: usize, work: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a pool of 1 or 2 threads")
        .install(work)
}

/// The fastest of [`REPEATS`] runs of `sweep`, in seconds.
fn fastest(mut sweep: impl FnMut()) -> f64 {
    (0..REPEATS)
        .map(|_| {
            let start = Instant::now();
            sweep();
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn gb_per_s(threads: usize) -> f64 {
    in_pool(threads, || {
        let filled = |value: f64| {
            let mut v = Vec::with_capacity(ELEMENTS);
            v.par_extend(
                (0..ELEMENTS)
                    .into_par_iter()
                    .with_min_len(CHUNK)
                    .map(|_| value),
            );
            v
        };
        let (mut a, b, c) = (filled(0.0), filled(1.0), filled(2.0));
        let best = fastest(|| {
            a.par_chunks_mut(CHUNK)
                .zip(b.par_chunks(CHUNK).zip(c.par_chunks(CHUNK)))
                .for_each(|(a, (b, c))| {
                    for ((a, b), c) in a.iter_mut().zip(b).zip(c) {
                        *a = b + 3.0 * c;
                    }
                });
            black_box(&a);
        });
        assert!(a.iter().all(|&x| x == 7.0), "the triad's result");
        (3 * 8 * ELEMENTS) as f64 / best / 1e9
    })
}

/// One thread's share of the arithmetic probe: its accumulators' sum.
fn chains() -> f64 {
    let mut acc = [1.0f64; CHAINS];
    let (scale, shift) = (black_box(0.999_999), black_box(1e-7));
    for _ in 0..ROUNDS {
        for a in &mut acc {
            *a = *a * scale + shift;
        }
    }
    acc.iter().sum()
}

fn gflops(threads: usize) -> f64 {
    in_pool(threads, || {
        let best = fastest(|| {
            let sums: Vec<f64> = (0..threads).into_par_iter().map(|_| chains()).collect();
            black_box(sums);
        });
        (2 * CHAINS * ROUNDS * threads) as f64 / best / 1e9
    })
}

fn main() {
    println!(
        "{{\"gb_per_s_1\": {:.2}, \"gb_per_s_2\": {:.2}, \"gflops_1\": {:.2}, \"gflops_2\": {:.2}}}",
        gb_per_s(1),
        gb_per_s(2),
        gflops(1),
        gflops(2)
    );
}
