//! Running a validated scene: building the observers and files it asks for,
//! setting up (or restoring) the integrator, running, and summarising.

use super::checkpoint::{Checkpoint, CheckpointWriter};
use super::error::RunError;
use super::observer::{Observer, Scheduled};
use super::runner::{run, RunOptions, Stop};
use super::series::{SeriesObserver, SeriesTable};
use super::summary::Summary;
use super::trajectory::{TrajectoryFiles, TrajectoryFrames, TrajectoryObserver};
use crate::integrators::Integrator;
use crate::potential::Potential;
use crate::rotor::Inertia;
use crate::scene::Scene;
use std::path::{Path, PathBuf};

/// Names of the files written in the output directory.
pub const SUMMARY_FILE: &str = "summary.json";
pub const CHECKPOINT_FILE: &str = "checkpoint.json";
pub const DCD_FILE: &str = "trajectory.dcd";
pub const PDB_FILE: &str = "topology.pdb";

/// Where a run's outputs go.
#[derive(Clone, Debug, Default)]
pub struct Outputs {
    /// Directory for the CSV, DCD, PDB, checkpoint and summary files (created
    /// if missing); `None` writes no file.
    pub dir: Option<PathBuf>,
    /// Keep the series and trajectory in memory (for Python).
    pub keep: bool,
}

/// A progress reporter and its interval in steps.
pub struct Progress<'a> {
    pub every: u64,
    pub observer: &'a mut (dyn Observer + Send),
}

/// Everything a run produced.
#[derive(Clone, Debug)]
pub struct RunResult {
    pub summary: Summary,
    pub series: Vec<SeriesTable>,
    pub trajectory: Option<TrajectoryFrames>,
    pub stop: Stop,
}

/// Runs `scene` with a concrete integrator and potential (both built from
/// the scene by the caller), from t = 0 or from the checkpoint `restart`.
pub fn run_scene(
    scene: &Scene,
    definition: serde_json::Value,
    integrator: &mut dyn Integrator,
    potential: &dyn Potential,
    outputs: &Outputs,
    restart: Option<&Path>,
    progress: Option<Progress<'_>>,
) -> Result<RunResult, RunError> {
    let inertia: Vec<Inertia> = scene.rotors.iter().map(|r| r.inertia).collect();
    integrator.setup(&inertia, potential, &scene.initial, scene.dt)?;
    let checkpoint = restart.map(Checkpoint::read).transpose()?;
    if let (Some(c), Some(path)) = (&checkpoint, restart) {
        c.check(path, integrator.name(), inertia.len(), scene.dt)?;
        if c.step > scene.steps {
            return Err(RunError::Checkpoint {
                path: path.display().to_string(),
                message: format!(
                    "step {} is past the end of the run ({})",
                    c.step, scene.steps
                ),
            });
        }
        integrator.restore(&c.state())?;
    }
    let start_step = checkpoint.as_ref().map_or(0, |c| c.step);
    let dir = outputs.dir.as_deref();
    if let Some(d) = dir {
        std::fs::create_dir_all(d).map_err(|e| RunError::io(d, e))?;
    }
    let file = |name: &str| dir.map(|d| d.join(name));

    let mut series = scene
        .record
        .series
        .iter()
        .map(|s| {
            let path = file(&format!("{}.csv", s.name));
            SeriesObserver::new(s, path.as_deref(), outputs.keep)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let (dcd, pdb) = (file(DCD_FILE), file(PDB_FILE));
    let box_lengths = scene.box_lengths();
    let mut trajectory = scene
        .record
        .trajectory
        .as_ref()
        .map(|spec| {
            let files = dcd
                .as_deref()
                .zip(pdb.as_deref())
                .map(|(dcd, pdb)| TrajectoryFiles {
                    dcd,
                    pdb,
                    box_lengths: box_lengths.as_ref(),
                    first_step: start_step,
                    dt: scene.dt,
                    title: &scene.name,
                });
            let now = integrator.orientations().to_vec();
            TrajectoryObserver::new(spec, &scene.rotors, &now, files, outputs.keep)
        })
        .transpose()?;
    let checkpoint_writer = scene
        .record
        .checkpoint_every
        .zip(file(CHECKPOINT_FILE))
        .map(|(every, path)| {
            (
                every,
                CheckpointWriter {
                    path,
                    scene: scene.name.clone(),
                    integrator: integrator.name().to_string(),
                    rotors: inertia.len(),
                    dt: scene.dt,
                },
            )
        });

    let mut scheduled: Vec<Scheduled<'_>> = Vec::new();
    for (s, spec) in series.iter_mut().zip(&scene.record.series) {
        scheduled.push(Scheduled {
            every: spec.every,
            observer: s,
        });
    }
    if let (Some(t), Some(spec)) = (&mut trajectory, &scene.record.trajectory) {
        scheduled.push(Scheduled {
            every: spec.every,
            observer: t,
        });
    }
    if let Some(p) = progress {
        scheduled.push(Scheduled {
            every: p.every,
            observer: p.observer,
        });
    }
    let options = RunOptions {
        dt: scene.dt,
        start_step,
        end_step: scene.steps,
        check_every: scene.record.check_every,
        energy_error_threshold: scene.record.energy_error_threshold,
        reference: checkpoint.as_ref().and_then(Checkpoint::reference),
    };
    let report = run(
        integrator,
        potential,
        &inertia,
        &mut scheduled,
        checkpoint_writer.as_ref().map(|(every, w)| (*every, w)),
        &options,
    )?;
    drop(scheduled);
    let summary = Summary::new(scene, definition, &report, start_step);
    if let Some(path) = file(SUMMARY_FILE) {
        let text = serde_json::to_string_pretty(&summary).map_err(|e| RunError::io(&path, e))?;
        std::fs::write(&path, text + "\n").map_err(|e| RunError::io(&path, e))?;
    }
    Ok(RunResult {
        summary,
        series: series
            .into_iter()
            .filter_map(SeriesObserver::into_table)
            .collect(),
        trajectory: trajectory.and_then(TrajectoryObserver::into_frames),
        stop: report.stop,
    })
}
