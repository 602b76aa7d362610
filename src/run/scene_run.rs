//! Running a validated scene: setting up (or restoring) the integrator,
//! opening the outputs the scene asks for, running the one loop of
//! [`crate::simulation`], and summarising.

use super::checkpoint::{Checkpoint, CheckpointWriter};
use super::error::RunError;
use super::series::{SeriesObserver, SeriesTable};
use super::summary::{InteractionsSummary, Summary};
use super::trajectory::{TrajectoryFiles, TrajectoryFrames, TrajectoryObserver};
use crate::integrators::Integrator;
use crate::potential::Potential;
use crate::scene::Scene;
use crate::simulation::{
    run, BlowUpChecks, Checkpoints, Control, EnergyReference, Observer, RunOptions, Scheduled, Stop,
};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Name of the summary file in the output directory.
pub const SUMMARY_FILE: &str = "summary.json";
/// Name of the checkpoint file in the output directory.
pub const CHECKPOINT_FILE: &str = "checkpoint.json";
/// Name of the trajectory file in the output directory.
pub const DCD_FILE: &str = "trajectory.dcd";
/// Name of the trajectory's topology file in the output directory.
pub const PDB_FILE: &str = "topology.pdb";
/// Name of the GSD trajectory file in the output directory.
pub const GSD_FILE: &str = "trajectory.gsd";

/// Where a run's outputs go.
#[derive(Clone, Debug, Default)]
pub struct Outputs {
    /// Directory for the CSV, DCD, PDB, checkpoint and summary files (created
    /// if missing); `None` writes no file.
    pub dir: Option<PathBuf>,
    /// Keep the series and trajectory in memory (for Python).
    pub keep: bool,
    /// Stops the run from another thread (Ctrl-C in Python) at the end of
    /// a step.
    pub control: Option<Arc<Control>>,
}

impl Outputs {
    /// The path of file `name` in the output directory, if there is one.
    fn file(&self, name: &str) -> Option<PathBuf> {
        self.dir.as_deref().map(|d| d.join(name))
    }
}

/// A progress reporter and its interval in steps.
pub struct Progress<'a> {
    /// The interval in steps.
    pub every: u64,
    /// The reporter.
    pub observer: &'a mut (dyn Observer<Error = RunError> + Send),
}

/// The potential a scene runs with, and how it sums the pair interactions
/// (for the summary).
#[derive(Clone, Copy)]
pub struct ScenePotential<'a> {
    /// The potential.
    pub potential: &'a dyn Potential,
    /// How it sums the pair interactions (`None`: none, or not recorded).
    pub interactions: Option<&'a InteractionsSummary>,
}

impl<'a> ScenePotential<'a> {
    /// A potential with nothing to record about its sums (free rotors, a
    /// wrapped potential in a test).
    pub fn plain(potential: &'a dyn Potential) -> Self {
        ScenePotential {
            potential,
            interactions: None,
        }
    }
}

/// Everything a run produced.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// The summary (also written to [`SUMMARY_FILE`]).
    pub summary: Summary,
    /// The series kept in memory.
    pub series: Vec<SeriesTable>,
    /// The trajectory kept in memory.
    pub trajectory: Option<TrajectoryFrames>,
    /// Why the run ended.
    pub stop: Stop,
}

/// Runs `scene` with an integrator and a potential (both built from the
/// scene by the caller, possibly wrapped), from t = 0 or from the checkpoint
/// `restart`.
pub fn run_scene(
    scene: &Scene,
    definition: serde_json::Value,
    integrator: &mut dyn Integrator,
    potential: ScenePotential<'_>,
    outputs: &Outputs,
    restart: Option<&Path>,
    progress: Option<Progress<'_>>,
) -> Result<RunResult, RunError> {
    let ScenePotential {
        potential,
        interactions,
    } = potential;
    let inertia = scene.inertia();
    integrator.setup(&inertia, potential, &scene.initial, scene.dt)?;
    let (start_step, reference) = match restart {
        Some(path) => restore(integrator, scene, path)?,
        None => (0, None),
    };
    if let Some(d) = &outputs.dir {
        std::fs::create_dir_all(d).map_err(|e| RunError::io(d, e))?;
    }
    let Recorders {
        mut series,
        mut trajectory,
        mut checkpoints,
    } = Recorders::open(scene, integrator, outputs, start_step)?;
    let options = RunOptions {
        dt: scene.dt,
        start_step,
        end_step: scene.steps,
        checks: Some(BlowUpChecks {
            every: scene.record.check_every,
            energy_error_threshold: scene.record.energy_error_threshold,
        }),
        reference,
        control: outputs.control.clone(),
    };
    let mut scheduled = scheduled(scene, &mut series, &mut trajectory, progress);
    let checkpoints = checkpoints.as_mut().map(|(every, sink)| Checkpoints {
        every: *every,
        sink,
    });
    let report = run(
        integrator,
        potential,
        &inertia,
        &mut scheduled,
        checkpoints,
        &options,
    )?;
    drop(scheduled);
    let summary = Summary::new(
        scene,
        definition,
        interactions.cloned(),
        &report,
        start_step,
    );
    if let Some(path) = outputs.file(SUMMARY_FILE) {
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

/// Restores `integrator` (set up for `scene`) from the checkpoint at `path`:
/// the step it is at and the run's energy reference.
fn restore(
    integrator: &mut dyn Integrator,
    scene: &Scene,
    path: &Path,
) -> Result<(u64, Option<EnergyReference>), RunError> {
    let checkpoint = Checkpoint::read(path)?;
    checkpoint.check(
        path,
        integrator.name(),
        scene.thermostat.as_ref().map(|t| t.name()),
        scene.rotors.len(),
        scene.dt,
    )?;
    if checkpoint.step > scene.steps {
        return Err(RunError::Checkpoint {
            path: path.display().to_string(),
            message: format!(
                "step {} is past the end of the run ({})",
                checkpoint.step, scene.steps
            ),
        });
    }
    integrator.restore(&checkpoint.state())?;
    Ok((checkpoint.step, checkpoint.reference()))
}

/// The outputs a scene records: its series, its trajectory, its checkpoints.
struct Recorders {
    series: Vec<SeriesObserver>,
    trajectory: Option<TrajectoryObserver>,
    checkpoints: Option<(u64, CheckpointWriter)>,
}

impl Recorders {
    /// Opens the files of `scene`'s record section in `outputs` (the CSV
    /// headers and the PDB are written now), for a run from `start_step`.
    fn open(
        scene: &Scene,
        integrator: &dyn Integrator,
        outputs: &Outputs,
        start_step: u64,
    ) -> Result<Self, RunError> {
        let record = &scene.record;
        let series = record
            .series
            .iter()
            .map(|s| {
                let path = outputs.file(&format!("{}.csv", s.name));
                SeriesObserver::new(s, &scene.rotors, path.as_deref(), outputs.keep)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let (dcd, pdb, gsd) = (
            outputs.file(DCD_FILE),
            outputs.file(PDB_FILE),
            outputs.file(GSD_FILE),
        );
        let box_lengths = scene.box_lengths();
        let trajectory = record
            .trajectory
            .as_ref()
            .map(|spec| {
                let files = dcd.as_deref().zip(pdb.as_deref()).zip(gsd.as_deref()).map(
                    |((dcd, pdb), gsd)| TrajectoryFiles {
                        dcd,
                        pdb,
                        gsd,
                        box_lengths: box_lengths.as_ref(),
                        first_step: start_step,
                        dt: scene.dt,
                        title: &scene.name,
                    },
                );
                let now = integrator.orientations();
                TrajectoryObserver::new(spec, &scene.rotors, now, files, outputs.keep)
            })
            .transpose()?;
        let checkpoints = record
            .checkpoint_every
            .zip(outputs.file(CHECKPOINT_FILE))
            .map(|(every, path)| {
                let writer = CheckpointWriter {
                    path,
                    scene: scene.name.clone(),
                    integrator: integrator.name().to_string(),
                    thermostat: scene.thermostat.as_ref().map(|t| t.name().to_string()),
                    rotors: scene.rotors.len(),
                    dt: scene.dt,
                };
                (every, writer)
            });
        Ok(Recorders {
            series,
            trajectory,
            checkpoints,
        })
    }
}

/// The observers with their intervals: the series, the trajectory, then the
/// progress reporter.
fn scheduled<'a, 'p: 'a>(
    scene: &Scene,
    series: &'a mut [SeriesObserver],
    trajectory: &'a mut Option<TrajectoryObserver>,
    progress: Option<Progress<'p>>,
) -> Vec<Scheduled<'a, RunError>> {
    let mut scheduled: Vec<Scheduled<'a, RunError>> = Vec::new();
    for (s, spec) in series.iter_mut().zip(&scene.record.series) {
        scheduled.push(Scheduled {
            every: spec.every,
            at_end: false,
            observer: s,
        });
    }
    if let (Some(t), Some(spec)) = (trajectory, &scene.record.trajectory) {
        scheduled.push(Scheduled {
            every: spec.every,
            at_end: false,
            observer: t,
        });
    }
    if let Some(p) = progress {
        scheduled.push(Scheduled {
            every: p.every,
            at_end: false,
            observer: p.observer,
        });
    }
    scheduled
}
