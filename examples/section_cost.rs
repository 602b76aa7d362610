//! The cost of one near-empty parallel section in rayon's pool (issue 38).
//!
//! Opens `SECTIONS` sections, each a `par_chunks_mut` over a 2-chunk buffer
//! whose chunks each take `WORK` dependent additions (~24 us on this machine), in a pool of 1
//! and of 2 threads started from a worker (as a run is), and prints the wall
//! time per section. The overhead of a section at 2 threads is its time less
//! half the 1-thread time. With no work per chunk the caller runs both chunks
//! before the other worker steals one, which hides the cost. A measurement,
//! not a test: run it on an idle machine and state the load.
//!
//! `cargo run --release --example section_cost`

use rayon::prelude::*;
use std::time::Instant;

/// Sections per measurement.
const SECTIONS: usize = 5_000;

/// Dependent additions per chunk.
const WORK: u64 = 100_000;

/// Repeats per thread count (the median is printed).
const REPEATS: usize = 7;

/// `WORK` dependent additions the optimiser cannot fold.
fn spin(seed: u64) -> u64 {
    (0..WORK).fold(seed | 1, |a, i| std::hint::black_box(a.wrapping_add(i)))
}

fn per_section_ns(threads: usize) -> f64 {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a pool of 1 or 2 threads");
    pool.install(|| {
        let mut buffer = vec![0u64; 2 * 64];
        let start = Instant::now();
        for _ in 0..SECTIONS {
            buffer
                .par_chunks_mut(64)
                .for_each(|chunk| chunk[0] += spin(chunk[0]));
        }
        let elapsed = start.elapsed().as_secs_f64();
        assert!(buffer[0] > 0);
        elapsed / SECTIONS as f64 * 1e9
    })
}

fn main() {
    for threads in [1, 2] {
        let mut times: Vec<f64> = (0..REPEATS).map(|_| per_section_ns(threads)).collect();
        times.sort_by(f64::total_cmp);
        println!(
            "{threads} thread(s): {:.0} ns per section (median of {REPEATS}, min {:.0}, max {:.0})",
            times[REPEATS / 2],
            times[0],
            times[REPEATS - 1]
        );
    }
}
