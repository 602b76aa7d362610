//! What a run of a scene will hold and write, checked before it starts (by
//! `run` and by `check`): the memory of what grows with the run's length
//! (the energy history, and the series and frames kept for Python) against
//! [`crate::memory`], and the ranges of the trajectory's file formats (DCD
//! counts in 32 bits; PDB columns hold coordinates from -999.999 to
//! 9999.999). Errors name the scene field.

use crate::memory;
use crate::scene::{Scene, SceneError, TrajectoryFormat, TrajectorySpec};

/// Bytes per sample of the energy history (time, kinetic and total energy).
const HISTORY_BYTES: f64 = 24.0;
/// The coordinates the PDB's `%8.3f` columns hold, rounded to three decimals.
const PDB_RANGE: (f64, f64) = (-999.9995, 9999.9995);

/// An upper bound on the samples at every multiple of `every` in `0..=steps`.
fn samples(steps: u64, every: u64) -> f64 {
    (steps / every.max(1)) as f64 + 2.0
}

/// Checks the sizes and ranges of a run of `scene` (series and frames kept
/// in memory when `keep`).
pub fn check_run_limits(scene: &Scene, keep: bool) -> Result<(), SceneError> {
    let record = &scene.record;
    let memory = |path: &str, what: String, bytes: f64| {
        memory::check(path, bytes)
            .map_err(|e| SceneError::field(e.path, format!("{what}: {}", e.message)))
    };
    let energy_every = record
        .series
        .iter()
        .filter(|s| s.quantities.iter().any(|q| q.needs().energies))
        .map(|s| s.every)
        .chain(record.energy_error_threshold.map(|_| record.check_every))
        .min();
    if let Some(every) = energy_every {
        let n = samples(scene.steps, every);
        memory(
            "run.steps",
            format!("the energy history of {n:.2e} samples (energies every {every} steps)"),
            n * HISTORY_BYTES,
        )?;
    }
    if keep {
        for (k, s) in record.series.iter().enumerate() {
            let row = 8.0 * (2 + s.quantities.len()) as f64;
            let n = samples(scene.steps, s.every);
            memory(
                &format!("record.series[{k}].every"),
                format!("{n:.2e} rows kept in memory"),
                n * row,
            )?;
        }
        if let Some(t) = &record.trajectory {
            let frame = 8.0 * (7 * scene.rotors.len() + 2) as f64;
            let n = samples(scene.steps, t.every);
            memory(
                "record.trajectory.every",
                format!("{n:.2e} frames kept in memory"),
                n * frame,
            )?;
        }
    }
    match &record.trajectory {
        Some(t) if t.format == TrajectoryFormat::Dcd => check_dcd(scene, t),
        _ => Ok(()),
    }
}

/// Checks the ranges of a DCD trajectory and its PDB topology (a GSD
/// counts steps in 64 bits and its writer checks its coordinates).
fn check_dcd(scene: &Scene, t: &TrajectorySpec) -> Result<(), SceneError> {
    let limit = i32::MAX as u64;
    if scene.steps > limit || t.every > limit {
        return Err(SceneError::field(
            "record.trajectory",
            format!(
                "the DCD trajectory counts steps in 32 bits: run.steps ({}) and every ({}) must be at most {limit}",
                scene.steps, t.every
            ),
        ));
    }
    let reach = scene
        .rotors
        .iter()
        .flat_map(|r| r.site.iter().copied())
        .fold((0.0f64, 0.0f64), |(lo, hi), x| (lo.min(x), hi.max(x)));
    let (lo, hi) = (reach.0 - t.marker_length, reach.1 + t.marker_length);
    if lo <= PDB_RANGE.0 || hi >= PDB_RANGE.1 {
        return Err(SceneError::field(
            "record.trajectory",
            format!(
                "the sites and markers reach coordinates from {} to {}, beyond the PDB topology's columns (-999.999 to 9999.999): \
                 readers could not load the trajectory; move the sites nearer the origin or record no trajectory",
                crate::checks::num(lo),
                crate::checks::num(hi)
            ),
        ));
    }
    Ok(())
}
