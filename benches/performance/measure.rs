//! One run of a scene, two ways: timed (nothing recorded, the bare loop a
//! user's run does; median of repeats) and observed (energies, norms, the
//! final orientations and the number of torque evaluations).

use crate::counting::Counting;
use quatrot::potential::{Free, Potential};
use quatrot::run::{execute, potential, run_scene, Outputs, RunResult, ScenePotential};
use quatrot::scene::{Record, Scene, Series, TrajectoryFormat, TrajectorySpec};
use quatrot::simulation::{Quantity, Stop};
use quatrot::stats::line_fit;
use serde::Serialize;
use std::error::Error;

/// `scene` with `dt`, a run time rounded to whole steps, and nothing recorded.
pub fn with_step(scene: &Scene, dt: f64, time: f64) -> Scene {
    let mut s = scene.clone();
    s.dt = dt;
    s.steps = ((time / dt).round() as u64).max(1);
    s.record = Record {
        check_every: s.steps,
        ..Record::default()
    };
    s
}

fn outcome(stop: &Stop) -> Option<String> {
    stop.message()
}

/// Wall-clock seconds of the run loop, `repeats` times, nothing recorded.
pub fn timed(scene: &Scene, repeats: usize) -> Result<Vec<f64>, Box<dyn Error + Send + Sync>> {
    (0..repeats)
        .map(|_| {
            let result = execute(
                scene,
                serde_json::Value::Null,
                &Outputs::default(),
                None,
                None,
            )?;
            Ok(result.summary.wall_seconds)
        })
        .collect()
}

/// The median of `values` (NaN when empty).
pub fn median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// What an observed run measured.
#[derive(Clone, Debug, Serialize)]
pub struct Observed {
    /// Torque (gradient) evaluations, start-up included.
    pub torque_evaluations: u64,
    /// `max |E - E_0| / s` over the samples (`s`: initial kinetic energy, or
    /// `|E_0|` for rotors starting at rest).
    pub energy_error_max: f64,
    /// Least-squares slope of `(E - E_0) / s` against time.
    pub energy_drift_per_time: f64,
    /// The relative energy error at the last sample.
    pub energy_error_final: f64,
    /// `max | |Q| - 1 |` over the samples and rotors.
    pub norm_error_max: f64,
    /// Why the run stopped early, if it did.
    pub failure: Option<String>,
    /// The step of the last sample.
    pub last_step: u64,
    /// Orientations at the last step, scalar first (empty if the run stopped early).
    pub final_orientations: Vec<[f64; 4]>,
    /// Loop seconds of this (recording) run.
    pub wall_seconds: f64,
}

/// Runs `scene` (as returned by [`with_step`]) recording energies and norms
/// at `samples` points, the final orientations, and the torque evaluations;
/// stops when `|energy error|` exceeds `threshold` if given.
pub fn observed(
    scene: &Scene,
    samples: u64,
    threshold: Option<f64>,
) -> Result<Observed, Box<dyn Error + Send + Sync>> {
    let mut s = scene.clone();
    let every = (s.steps / samples.max(1)).max(1);
    s.record = Record {
        series: vec![Series {
            name: "energies".into(),
            every,
            quantities: vec![Quantity::EnergyError, Quantity::NormError],
        }],
        trajectory: Some(TrajectorySpec {
            every: s.steps,
            format: TrajectoryFormat::Dcd,
            marker_length: 0.3,
        }),
        checkpoint_every: None,
        energy_error_threshold: threshold,
        check_every: every,
    };
    let (result, evaluations) = match potential(&s)? {
        Some(p) => counted(&s, &p)?,
        None => counted(&s, &Free)?,
    };
    Ok(summarise(&result, s.steps, evaluations))
}

/// Runs `scene` with `potential` (the one `execute` would build) wrapped in
/// a counter: the result and the number of torque evaluations.
fn counted<P: Potential>(
    scene: &Scene,
    potential: &P,
) -> Result<(RunResult, u64), Box<dyn Error + Send + Sync>> {
    let counting = Counting::new(potential);
    let outputs = Outputs {
        dir: None,
        keep: true,
        control: None,
        threads: None,
    };
    let result = run_scene(
        scene,
        serde_json::Value::Null,
        quatrot::dynamics::try_build(&scene.integrator, scene.thermostat.as_ref())?.as_mut(),
        ScenePotential::plain(&counting),
        &outputs,
        None,
        None,
    )?;
    Ok((result, counting.count()))
}

fn summarise(result: &RunResult, steps: u64, torque_evaluations: u64) -> Observed {
    let table = &result.series[0];
    let rows: Vec<&[f64]> = table.values.chunks(table.columns.len()).collect();
    let times: Vec<f64> = rows.iter().map(|r| r[1]).collect();
    let errors: Vec<f64> = rows.iter().map(|r| r[2]).collect();
    let norm_error_max = rows.iter().map(|r| r[3].abs()).fold(0.0, f64::max);
    let energy_error_max =
        errors.iter().map(|e| e.abs()).fold(
            0.0,
            |a: f64, e| {
                if e.is_nan() {
                    f64::NAN
                } else {
                    a.max(e)
                }
            },
        );
    let final_orientations = result
        .trajectory
        .as_ref()
        .filter(|t| t.steps.last() == Some(&steps))
        .map(|t| {
            let n = result.summary.rotors;
            let last = &t.orientations[t.orientations.len() - 4 * n..];
            last.chunks(4).map(|q| [q[0], q[1], q[2], q[3]]).collect()
        })
        .unwrap_or_default();
    Observed {
        torque_evaluations,
        energy_error_max,
        energy_drift_per_time: slope(&times, &errors),
        energy_error_final: errors.last().copied().unwrap_or(f64::NAN),
        norm_error_max,
        failure: outcome(&result.stop),
        last_step: result.summary.last_step,
        final_orientations,
        wall_seconds: result.summary.wall_seconds,
    }
}

/// The least-squares slope of `y` against `x` (NaN for fewer than 2 points).
fn slope(x: &[f64], y: &[f64]) -> f64 {
    if x.len() < 2 {
        return f64::NAN;
    }
    line_fit(x, y).slope
}

/// A rayon pool of `threads` threads for the potential's parallel loops.
pub fn pool(threads: usize) -> Result<rayon::ThreadPool, Box<dyn Error + Send + Sync>> {
    Ok(rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?)
}
