//! Running a validated scene: setting up (or restoring) the integrator,
//! opening the outputs the scene asks for, running the one loop of
//! [`crate::simulation`], and summarising.

use super::checkpoint::{Checkpoint, CheckpointWriter, Identity};
use super::error::RunError;
use super::execute::choose_threads;
use super::folder::{OutputFolder, CHECKPOINT_FILE, DCD_FILE, GSD_FILE, PDB_FILE};
use super::resume::{plan, Placement};
use super::series::{CsvTarget, SeriesObserver, SeriesTable};
use super::summary::{InteractionsSummary, Summary, Threads};
use super::summary_file::{
    keep_earlier_summary, placed, record_failure, running_summary, SummaryAfterCheckpoint,
};
use super::trajectory::{TrajectoryFiles, TrajectoryFrames, TrajectoryObserver};
use crate::integrators::Integrator;
use crate::potential::Potential;
use crate::rotor::Inertia;
use crate::scene::Scene;
use crate::simulation::{
    run, BlowUpChecks, Checkpoints, Control, EnergyReference, Observer, RunOptions, Scheduled, Stop,
};
use std::num::NonZeroUsize;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where a run's outputs go.
#[derive(Clone, Debug, Default)]
pub struct Outputs {
    /// Directory for the CSV, DCD, PDB, checkpoint and summary files
    /// (created if missing, locked for the run: see [`super::OutputFolder`]);
    /// `None` writes no file.
    pub dir: Option<PathBuf>,
    /// Keep the series and trajectory in memory (for Python).
    pub keep: bool,
    /// Stops the run from another thread (a signal handler, Ctrl-C in
    /// Python) at the end of a step.
    pub control: Option<Arc<Control>>,
    /// The threads of the run, overriding the scene's `run.threads`
    /// (`None`: the scene's, else `RAYON_NUM_THREADS` if set, else
    /// [`crate::parallel::automatic_threads`]; see [`super::execute()`]).
    pub threads: Option<NonZeroUsize>,
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
    /// The summary (also written to [`super::SUMMARY_FILE`]).
    pub summary: Summary,
    /// The series kept in memory.
    pub series: Vec<SeriesTable>,
    /// The trajectory kept in memory.
    pub trajectory: Option<TrajectoryFrames>,
    /// Why the run ended.
    pub stop: Stop,
    /// Where the files went and how (`None` when no file was written).
    pub written: Option<(PathBuf, Placement)>,
}

/// Runs `scene` with an integrator and a potential (both built from the
/// scene by the caller, possibly wrapped), from t = 0 or from the checkpoint
/// `restart`. The output folder is locked for the run; a restart keeps the
/// files an earlier run left there (see [`Placement`]). The summary records
/// the size of the rayon pool it runs in and why (`choose_threads`).
pub fn run_scene(
    scene: &Scene,
    definition: serde_json::Value,
    integrator: &mut dyn Integrator,
    potential: ScenePotential<'_>,
    outputs: &Outputs,
    restart: Option<&Path>,
    progress: Option<Progress<'_>>,
) -> Result<RunResult, RunError> {
    let threads = &thread_record(scene, outputs);
    let ScenePotential {
        potential,
        interactions,
    } = potential;
    let inertia = scene.inertia();
    let (start_step, reference) = set_up(integrator, scene, potential, &inertia, restart)?;
    let (_lock, placement, dir) = open_folder(outputs, scene, restart, start_step)?;
    let files = dir.as_deref().zip(placement.as_ref());
    let Recorders {
        mut series,
        mut trajectory,
        checkpoints,
    } = Recorders::open(scene, integrator, files, outputs.keep, start_step)?;
    keep_earlier_summary(files, start_step)?;
    let running = running_summary(
        scene,
        &definition,
        interactions,
        (start_step, threads),
        files,
    )?;
    let mut checkpoints = checkpoints.map(|(every, checkpoint)| {
        let summary = running.clone();
        (
            every,
            SummaryAfterCheckpoint {
                checkpoint,
                summary,
            },
        )
    });
    let options = run_options(scene, outputs, start_step, reference);
    let mut scheduled = scheduled(scene, &mut series, &mut trajectory, progress);
    let report = run(
        integrator,
        potential,
        &inertia,
        &mut scheduled,
        checkpoints.as_mut().map(|(every, sink)| Checkpoints {
            every: *every,
            sink,
        }),
        &options,
    );
    drop(scheduled);
    let report = report.map_err(|e| {
        let last = checkpoints.and_then(|(_, sink)| sink.summary);
        record_failure(last.or(running), e)
    })?;
    let summary = Summary::new(
        scene,
        definition,
        interactions.cloned(),
        &report,
        (start_step, threads),
    );
    let summary = placed(summary, files)?;
    Ok(RunResult {
        summary,
        series: series
            .into_iter()
            .filter_map(SeriesObserver::into_table)
            .collect(),
        trajectory: trajectory.and_then(TrajectoryObserver::into_frames),
        stop: report.stop,
        written: dir.zip(placement),
    })
}

/// Sets `integrator` up for `scene` and, for a restart, restores it from
/// the checkpoint at `restart`: the step it starts at and the run's energy
/// reference.
fn set_up(
    integrator: &mut dyn Integrator,
    scene: &Scene,
    potential: &dyn Potential,
    inertia: &[Inertia],
    restart: Option<&Path>,
) -> Result<(u64, Option<EnergyReference>), RunError> {
    integrator.setup(inertia, potential, &scene.initial, scene.dt)?;
    match restart {
        Some(path) => restore(integrator, scene, path),
        None => Ok((0, None)),
    }
}

/// The thread record of a run of `scene`: the size of the rayon pool it
/// runs in, who chose it and why (`choose_threads`).
pub(super) fn thread_record(scene: &Scene, outputs: &Outputs) -> Threads {
    let (_, chosen, reason) = choose_threads(scene, outputs.threads);
    Threads {
        count: rayon::current_num_threads(),
        chosen,
        reason,
    }
}

/// The loop's options for a run of `scene` from `start_step` (its blow-up
/// checks, the energy reference of a restart, the control of `outputs`).
fn run_options(
    scene: &Scene,
    outputs: &Outputs,
    start_step: u64,
    reference: Option<EnergyReference>,
) -> RunOptions {
    RunOptions {
        start_step,
        end_step: scene.steps,
        checks: Some(BlowUpChecks {
            every: scene.record.check_every,
            energy_error_threshold: scene.record.energy_error_threshold,
        }),
        reference,
        control: outputs.control.clone(),
    }
}

/// The locked output folder of a run, where its files go and the folder
/// they are written to (all `None` without outputs).
pub(super) type OpenedFolder = (Option<OutputFolder>, Option<Placement>, Option<PathBuf>);

/// Locks the output folder of a run, plans where its files go ([`plan`] for
/// a restart) and creates the folder they are written to when it is new.
pub(super) fn open_folder(
    outputs: &Outputs,
    scene: &Scene,
    restart: Option<&Path>,
    start_step: u64,
) -> Result<OpenedFolder, RunError> {
    let folder = outputs.dir.as_deref().map(OutputFolder::lock).transpose()?;
    let placement = folder.as_ref().map(|f| match restart {
        Some(_) => plan(f.dir(), scene, start_step),
        None => Placement::New,
    });
    let dir = match (&folder, &placement) {
        (Some(_), Some(Placement::NewFolder { dir, .. })) => {
            std::fs::create_dir(dir).map_err(|e| RunError::io(dir, e))?;
            Some(dir.clone())
        }
        (Some(f), _) => Some(f.dir().to_path_buf()),
        (None, _) => None,
    };
    Ok((folder, placement, dir))
}

/// Restores `integrator` (set up for `scene`) from the checkpoint at `path`:
/// the step it is at and the run's energy reference.
fn restore(
    integrator: &mut dyn Integrator,
    scene: &Scene,
    path: &Path,
) -> Result<(u64, Option<EnergyReference>), RunError> {
    let checkpoint = read_checkpoint(scene, path)?;
    integrator.restore(&checkpoint.state())?;
    Ok((checkpoint.step, checkpoint.reference()))
}

/// The checkpoint at `path`, read and checked: intact, of a run of
/// `scene`, at a step within its length.
pub(super) fn read_checkpoint(scene: &Scene, path: &Path) -> Result<Checkpoint, RunError> {
    let checkpoint = Checkpoint::read(path)?;
    checkpoint.check(path, scene)?;
    if checkpoint.step > scene.steps {
        return Err(RunError::Checkpoint {
            path: path.display().to_string(),
            message: format!(
                "step {} is past the end of the run ({})",
                checkpoint.step, scene.steps
            ),
        });
    }
    Ok(checkpoint)
}

/// The outputs a scene records: its series, its trajectory, its checkpoints.
struct Recorders {
    series: Vec<SeriesObserver>,
    trajectory: Option<TrajectoryObserver>,
    checkpoints: Option<(u64, CheckpointWriter)>,
}

/// The first multiple of `every` at or after `step`.
fn first_sample(step: u64, every: u64) -> u64 {
    step.div_ceil(every).saturating_mul(every)
}

impl Recorders {
    /// Opens the files of `scene`'s record section in `files` (a folder and
    /// how to write there; the CSV headers and the PDB of new files are
    /// written now), for a run from `start_step`.
    fn open(
        scene: &Scene,
        integrator: &dyn Integrator,
        files: Option<(&Path, &Placement)>,
        keep: bool,
        start_step: u64,
    ) -> Result<Self, RunError> {
        let record = &scene.record;
        let append = match files {
            Some((_, Placement::Append(after))) => Some(after),
            _ => None,
        };
        let series = record
            .series
            .iter()
            .enumerate()
            .map(|(k, s)| {
                let path = files.map(|(dir, _)| dir.join(format!("{}.csv", s.name)));
                let target = path.as_deref().map(|path| match append {
                    Some(after) => CsvTarget::Append {
                        path,
                        after: after.series[k],
                    },
                    None => CsvTarget::Create(path),
                });
                SeriesObserver::new(s, &scene.rotors, target, keep)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let box_lengths = scene.box_lengths();
        let trajectory = record
            .trajectory
            .as_ref()
            .map(|spec| {
                let paths = files
                    .map(|(dir, _)| (dir.join(DCD_FILE), dir.join(PDB_FILE), dir.join(GSD_FILE)));
                let files = paths.as_ref().map(|(dcd, pdb, gsd)| TrajectoryFiles {
                    dcd,
                    pdb,
                    gsd,
                    box_lengths: box_lengths.as_ref(),
                    first_step: first_sample(start_step, spec.every),
                    dt: integrator.dt(),
                    title: &scene.name,
                    append: append.and_then(|a| a.trajectory),
                });
                let now = integrator.orientations();
                TrajectoryObserver::new(spec, &scene.rotors, now, files, keep)
            })
            .transpose()?;
        let checkpoints = record
            .checkpoint_every
            .zip(files)
            .map(|(every, (dir, _))| (every, checkpoint_writer(scene, dir)));
        Ok(Recorders {
            series,
            trajectory,
            checkpoints,
        })
    }
}

/// The writer of the checkpoints of a run of `scene` in the folder `dir`.
pub(super) fn checkpoint_writer(scene: &Scene, dir: &Path) -> CheckpointWriter {
    CheckpointWriter {
        path: dir.join(CHECKPOINT_FILE),
        scene: scene.name.clone(),
        identity: Identity::of(scene),
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
