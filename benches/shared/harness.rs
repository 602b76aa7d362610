//! What the benches that write raw results share: the quick flag, one
//! thread, the process's CPU time, and where the results go (read by `python -m validation.bench`'s
//! modules).

use serde_json::{json, Value};
use std::path::PathBuf;
use std::time::Instant;

/// Whether `QUATROT_BENCH_QUICK=1` asks for the small sizes.
pub fn quick() -> bool {
    std::env::var("QUATROT_BENCH_QUICK").is_ok_and(|v| v == "1")
}

/// `f` run on one thread (rayon's loops included).
pub fn one_thread<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool")
        .install(f)
}

/// Writes `out`, with the seconds since `started`, as `<QUATROT_BENCH_RAW or
/// target/bench/raw>/<name>`.
pub fn write(name: &str, mut out: Value, started: Instant) {
    let dir = PathBuf::from(
        std::env::var("QUATROT_BENCH_RAW").unwrap_or_else(|_| "target/bench/raw".into()),
    );
    std::fs::create_dir_all(&dir).expect("output folder");
    out["seconds"] = json!(started.elapsed().as_secs_f64());
    std::fs::write(dir.join(name), out.to_string()).expect("write the raw results");
    eprintln!("wrote {}", dir.join(name).display());
}

/// The process's CPU time (all threads) in seconds: less sensitive than
/// the wall time to the other jobs of a shared machine.
pub fn cpu_seconds() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes the timespec it is given.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}
