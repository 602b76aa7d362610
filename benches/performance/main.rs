//! The Rust half of `make bench` (`cargo bench --bench performance`): the
//! timed and counted loops (work-precision, stress at a fixed time, scaling),
//! through the same scene -> dispatch -> runner path a user's `quatrot run`
//! takes, written as JSON files (one per section) that `python -m
//! validation.bench` turns into references (scipy, LAMMPS), errors, plots and
//! tables. The scans that are grids of scene runs (largest stable step, long
//! runs, stress at length) run as sweeps from Python (`validation/bench/scans.py`).
//!
//! Environment: `QUATROT_BENCH_RAW` (the output folder, default
//! `target/bench/raw`, one `<section>.json` per section);
//! `QUATROT_BENCH_SECTIONS=a,b` runs only those sections;
//! `QUATROT_BENCH_QUICK=1` shrinks every run to a few steps (to exercise the
//! pipeline, not to measure).

mod counting;
mod measure;
mod scaling;
mod schemes;
mod stress;
mod work_precision;

use serde_json::json;
use std::error::Error;
use std::path::{Path, PathBuf};
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

/// Writes one section's JSON to `<dir>/<name>.json` as soon as it is done
/// (a long benchmark keeps what it finished).
fn write(dir: &Path, name: &str, value: &serde_json::Value) -> Result<(), Box<dyn Error>> {
    std::fs::create_dir_all(dir)?;
    std::fs::write(
        dir.join(format!("{name}.json")),
        serde_json::to_string(value)?,
    )?;
    Ok(())
}

type Section = fn(Effort) -> Result<serde_json::Value, Box<dyn Error + Send + Sync>>;

fn main() -> Result<(), Box<dyn Error>> {
    let effort = Effort {
        quick: std::env::var("QUATROT_BENCH_QUICK").is_ok_and(|v| v == "1"),
    };
    let dir = PathBuf::from(
        std::env::var("QUATROT_BENCH_RAW").unwrap_or_else(|_| "target/bench/raw".into()),
    );
    let only = std::env::var("QUATROT_BENCH_SECTIONS").ok();
    let sections: [(&str, Section); 3] = [
        ("work_precision", work_precision::run),
        ("stress", stress::run),
        ("scaling", scaling::run),
    ];
    let started = Instant::now();
    for (name, section) in sections {
        if only
            .as_deref()
            .is_some_and(|o| !o.split(',').any(|s| s == name))
        {
            continue;
        }
        let t = Instant::now();
        eprintln!("[{:7.1} s] {name}", started.elapsed().as_secs_f64());
        let value = section(effort).map_err(|e| e.to_string())?;
        let seconds = t.elapsed().as_secs_f64();
        write(
            &dir,
            name,
            &json!({"seconds": seconds, "quick": effort.quick, "quatrot": env!("CARGO_PKG_VERSION"), "data": value}),
        )?;
    }
    eprintln!(
        "[{:7.1} s] done; sections in {}",
        started.elapsed().as_secs_f64(),
        dir.display()
    );
    Ok(())
}
