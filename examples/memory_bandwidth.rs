//! The machine's memory bandwidth at 1 and 2 threads (issue 38): how much a
//! second thread can gain on a step that streams its data.
//!
//! A STREAM-style triad `a = b + 3 c` over three arrays of
//! [`ELEMENTS`] f64 (128 MiB each, far beyond any cache), in a rayon pool of 1
//! and of 2 threads started from a worker (as a run is); each array is
//! first touched by the pool that uses it. Prints one JSON line:
//! `{"gb_per_s_1": ..., "gb_per_s_2": ...}`, the best of [`REPEATS`] sweeps
//! (24 bytes moved per element; write-allocate traffic not counted).
//! `make bench-threads` runs it beside its whole runs: a host whose two
//! threads stream little more than one caps the speed-up of the large
//! lattices, which stream their rotors and grids every pass. A measurement,
//! not a test.
//!
//! `cargo run --release --example memory_bandwidth`

use rayon::prelude::*;
use std::time::Instant;

/// Elements per array: 2^24 f64, 128 MiB.
const ELEMENTS: usize = 1 << 24;

/// Sweeps per thread count (the fastest is kept).
const REPEATS: usize = 10;

/// Elements per rayon task.
const CHUNK: usize = 1 << 16;

fn gb_per_s(threads: usize) -> f64 {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a pool of 1 or 2 threads");
    pool.install(|| {
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
        let mut best = f64::INFINITY;
        for _ in 0..REPEATS {
            let start = Instant::now();
            a.par_chunks_mut(CHUNK)
                .zip(b.par_chunks(CHUNK).zip(c.par_chunks(CHUNK)))
                .for_each(|(a, (b, c))| {
                    for ((a, b), c) in a.iter_mut().zip(b).zip(c) {
                        *a = b + 3.0 * c;
                    }
                });
            best = best.min(start.elapsed().as_secs_f64());
            std::hint::black_box(&a);
        }
        assert!(a.iter().all(|&x| x == 7.0), "the triad's result");
        (3 * 8 * ELEMENTS) as f64 / best / 1e9
    })
}

fn main() {
    println!(
        "{{\"gb_per_s_1\": {:.2}, \"gb_per_s_2\": {:.2}}}",
        gb_per_s(1),
        gb_per_s(2)
    );
}
