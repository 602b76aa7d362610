//! The Rust half of `make bench` (`cargo bench --bench performance`): every
//! heavy loop, through the same scene -> dispatch -> runner path a user's
//! `quatrot run` takes, written as one JSON file that
//! `python -m validation.bench` turns into references (scipy, LAMMPS),
//! errors, plots and tables.
//!
//! Environment: `QUATROT_BENCH_RAW` (the output file, default
//! `target/bench/raw.json`); `QUATROT_BENCH_QUICK=1` shrinks every run to a
//! few steps (to exercise the pipeline, not to measure).

mod counting;
mod measure;
mod scaling;
mod schemes;
mod stability;
mod stress;
mod work_precision;

use serde_json::json;
use std::error::Error;
use std::path::PathBuf;
use std::time::Instant;

/// How much to run: the full benchmark or the pipeline smoke test.
#[derive(Clone, Copy, Debug)]
pub struct Effort {
    pub quick: bool,
}

impl Effort {
    /// `full` in the real benchmark, `quick` in the smoke test.
    pub fn pick<T>(&self, full: T, quick: T) -> T {
        if self.quick {
            quick
        } else {
            full
        }
    }
}

fn main() -> Result<(), Box<dyn Error + Send + Sync>> {
    let effort = Effort {
        quick: std::env::var("QUATROT_BENCH_QUICK").is_ok_and(|v| v == "1"),
    };
    let out = PathBuf::from(
        std::env::var("QUATROT_BENCH_RAW").unwrap_or_else(|_| "target/bench/raw.json".into()),
    );
    let started = Instant::now();
    let section = |name: &str| eprintln!("[{:7.1} s] {name}", started.elapsed().as_secs_f64());
    section("work-precision");
    let work_precision = work_precision::run(effort)?;
    section("stability");
    let stability = stability::run(effort)?;
    section("long runs");
    let long_runs = stability::long_runs(effort)?;
    section("stress cases");
    let stress = stress::run(effort)?;
    section("scaling");
    let scaling = scaling::run(effort)?;
    section("done");
    let result = json!({
        "quatrot": env!("CARGO_PKG_VERSION"),
        "quick": effort.quick,
        "seconds": started.elapsed().as_secs_f64(),
        "work_precision": work_precision,
        "stability": stability,
        "long_runs": long_runs,
        "stress": stress,
        "scaling": scaling,
    });
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(&out, serde_json::to_string(&result)?)?;
    eprintln!("wrote {}", out.display());
    Ok(())
}
