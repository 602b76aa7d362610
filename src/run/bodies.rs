//! Running a scene of moving bodies: the system and its integrator
//! ([`BodyIntegrator`]) built from the scene, stepped from t = 0 or
//! restored from a checkpoint, with the series (CSV), the GSD trajectory,
//! the checkpoints and `summary.json` written through the rotors' writers
//! ([`Rows`], [`GsdWriter`], [`super::CheckpointWriter`], the locked
//! [`super::OutputFolder`], the atomic summary) and a restart placed as
//! the rotors' ([`Placement`]). Energies are computed at every sample and
//! every blow-up check; the energy error and the drift follow as for
//! rotors. A blow-up names the step and the bodies (and their sites).

use super::error::RunError;
use super::folder::{GSD_FILE, SUMMARY_FILE};
use super::gsd::{BodyFrame, BodyTypes, GsdBox, GsdWriter};
use super::resume::Placement;
use super::scene_run::{checkpoint_writer, open_folder, read_checkpoint, Outputs, RunResult};
use super::series::{CsvTarget, Rows};
use super::summary::{BodiesSummary, Summary, Threads};
use super::summary_file::{
    in_progress, keep_earlier_summary, placed, record_failure, SummaryAfterCheckpoint,
};
use super::trajectory::GSD_OPEN_MARGIN;
use crate::bodies::{
    BodyIntegrator, BodyQuantity, BodySystem, Evaluation, Overlap, Space, OVERLAP_FRACTION,
};
use crate::integrators::{IntegratorError, NoSquishOptions, Splitting};
use crate::scene::{BodyScene, BodySeries, Scene, SceneError};
use crate::simulation::{
    CheckpointSink, Energies, EnergyHistory, EnergyReference, RunReport, Stop,
};
use crate::units::{quantity_dimension, Dimension, Units};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A GSD trajectory being written.
struct Trajectory {
    every: u64,
    path: PathBuf,
    writer: GsdWriter,
    cell: GsdBox,
}

/// The checkpoints of a run: their interval, and the writer that follows
/// each with the summary in progress.
type BodyCheckpoints = (u64, SummaryAfterCheckpoint);

/// The CSV columns of a series of bodies: `step`, `time`, then the
/// quantities'.
pub(super) fn body_columns(series: &BodySeries) -> Vec<String> {
    ["step", "time"]
        .into_iter()
        .map(String::from)
        .chain(series.quantities.iter().flat_map(|q| q.columns()))
        .collect()
}

/// Runs the scene of bodies `bodies` (the body part of `scene`, whose raw
/// form is `definition`) from t = 0 or from the checkpoint `restart`,
/// continuing the files of the run that wrote it as a run of rotors does
/// ([`Placement`]).
pub(super) fn run_bodies(
    (scene, bodies): (&Scene, &BodyScene),
    definition: serde_json::Value,
    outputs: &Outputs,
    restart: Option<&Path>,
    threads: &Threads,
) -> Result<RunResult, RunError> {
    let mut system = bodies.system()?;
    let thermostat = scene.thermostat.as_ref();
    let mut integrator = BodyIntegrator::new(
        &scene.integrator,
        thermostat,
        &mut system,
        scene.engine_dt(),
    )
    .map_err(|e| SceneError::from(e.at("integrator")))?;
    let (start_step, reference) = match restart {
        Some(path) => {
            let checkpoint = read_checkpoint(scene, path)?;
            integrator
                .restore(&mut system, &checkpoint.state())
                .map_err(|e| RunError::Checkpoint {
                    path: path.display().to_string(),
                    message: match e {
                        IntegratorError::BadCheckpoint(why) => why,
                        other => other.to_string(),
                    },
                })?;
            (checkpoint.step, checkpoint.reference())
        }
        None => (0, None),
    };
    let (_lock, placement, dir) = open_folder(outputs, scene, restart, start_step)?;
    let files = dir.as_deref().zip(placement.as_ref());
    let after = |k: usize| match &placement {
        Some(Placement::Append(after)) => Some(after.series[k]),
        _ => None,
    };
    let mut series = bodies
        .series
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let path = dir.as_ref().map(|d| d.join(format!("{}.csv", s.name)));
            let target = path.as_deref().map(|path| match after(k) {
                Some(after) => CsvTarget::Append { path, after },
                None => CsvTarget::Create(path),
            });
            Rows::open(&s.name, body_columns(s), target, outputs.keep)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut gsd = match (&scene.record.trajectory, &dir) {
        (Some(spec), Some(d)) => Some(trajectory(&system, spec.every, d.join(GSD_FILE))?),
        _ => None,
    };
    keep_earlier_summary(files, start_step)?;
    let mesh = system.mesh_parameters();
    let described = |mut summary: Summary, builds: u64| {
        summary.bodies = Some(BodiesSummary::new(
            &system_counts(bodies),
            bodies,
            builds,
            mesh,
        ));
        summary.units = scene.units.names();
        summary
    };
    let running = match files {
        Some((d, _)) => {
            let start = (start_step, threads);
            let summary = described(in_progress(scene, &definition, None, start), 0);
            Some((d.join(SUMMARY_FILE), placed(summary, files)?))
        }
        None => None,
    };
    let mut checkpoints = scene
        .record
        .checkpoint_every
        .zip(files)
        .map(|(every, (d, _))| {
            let sink = SummaryAfterCheckpoint {
                checkpoint: checkpoint_writer(scene, d),
                summary: running.clone(),
            };
            (every, sink)
        });
    let looped = run_steps(
        (scene, bodies),
        (&mut system, &mut integrator),
        (start_step, reference),
        (&mut series, gsd.as_mut(), checkpoints.as_mut()),
        outputs,
    );
    let report = looped.map_err(|e| {
        let last = checkpoints.and_then(|(_, sink)| sink.summary);
        record_failure(last.or(running), e)
    })?;
    let summary = Summary::new(
        scene,
        definition.clone(),
        None,
        &report,
        (start_step, threads),
    );
    let mut summary = described(summary, system.neighbour_builds());
    if let Stop::BlewUp {
        step,
        rotor,
        reason,
    } = &report.stop
    {
        summary.message = Some(format!("blew up at step {step}, body {rotor}: {reason}"));
    }
    let summary = placed(summary, files)?;
    Ok(RunResult {
        summary,
        series: series.into_iter().filter_map(Rows::into_table).collect(),
        trajectory: None,
        stop: report.stop,
        written: dir.zip(placement),
    })
}

/// The outputs [`run_steps`] writes: the series, the trajectory, the
/// checkpoints.
type Recorders<'a> = (
    &'a mut [Rows],
    Option<&'a mut Trajectory>,
    Option<&'a mut BodyCheckpoints>,
);

/// Steps `system` from `start_step` (0, or a checkpoint's step with the
/// run's energy `reference`) to the end of `scene` (or a blow-up, or a
/// stop request), recording the series and the frames when due, the
/// energies at every sample and blow-up check, and the checkpoints (at
/// their interval and at a stop request, after the step's samples, the
/// series flushed first so their files hold at least what the checkpoint
/// does).
fn run_steps(
    (scene, bodies): (&Scene, &BodyScene),
    (system, integrator): (&mut BodySystem, &mut BodyIntegrator),
    (start_step, reference): (u64, Option<EnergyReference>),
    (series, mut gsd, mut checkpoints): Recorders<'_>,
    outputs: &Outputs,
) -> Result<RunReport, RunError> {
    let started = Instant::now();
    let kinetic = |s: &BodySystem| s.translational_kinetic_energy() + s.rotational_kinetic_energy();
    let mut current = Evaluation::default();
    let reference = match reference {
        Some(r) => r,
        None => {
            let k0 = kinetic(system);
            let v0 = integrator
                .evaluated(system, &mut current)
                .potential_energy();
            EnergyReference::initial(k0, k0 + v0)
        }
    };
    let (mut history, mut last, mut row) = (EnergyHistory::default(), None, Vec::new());
    let mut step = start_step;
    let stop = loop {
        let time = step as f64 * scene.dt;
        let due = |every: u64| step % every == 0;
        let sampled = bodies.series.iter().any(|s| due(s.every));
        let thermostat = integrator.thermostat_energy();
        let evaluation = (sampled || due(scene.record.check_every) || step == scene.steps)
            .then(|| integrator.evaluated(system, &mut current));
        if let Some(e) = evaluation {
            let (k, v) = (kinetic(system), e.potential_energy());
            let total = k + v;
            let conserved = total + thermostat;
            history.push(time, k, conserved);
            let energies = Energies {
                kinetic: k,
                potential: v,
                total,
                conserved,
                error: reference.error(conserved),
            };
            last = Some((step, energies));
            if let Some((body, reason)) = blown_up(system, total) {
                break Stop::BlewUp {
                    step,
                    rotor: body,
                    reason,
                };
            }
        }
        for (rows, spec) in series.iter_mut().zip(&bodies.series) {
            // A series is due only at a sampled step, which has the evaluation.
            if let (true, Some(e)) = (due(spec.every), evaluation) {
                write_row(
                    &spec.quantities,
                    (&*system, e, thermostat),
                    scene.units,
                    &mut row,
                );
                rows.push(step, time, &row)?;
            }
        }
        if let Some(t) = gsd.as_deref_mut().filter(|t| due(t.every)) {
            write_frame(&mut t.writer, system, (step, scene.units), &t.cell)
                .map_err(|e| RunError::io(&t.path, e))?;
        }
        let saved = match checkpoints.as_deref_mut() {
            Some((every, sink)) if step != start_step && due(*every) => {
                save(series, sink, step, integrator.checkpoint(system), reference)?;
                true
            }
            _ => false,
        };
        if step == scene.steps {
            break Stop::Completed;
        }
        if outputs.control.as_ref().is_some_and(|c| c.stop_requested()) {
            let fresh = !saved && step != start_step;
            if let (true, Some((_, sink))) = (fresh, checkpoints.as_deref_mut()) {
                save(series, sink, step, integrator.checkpoint(system), reference)?;
            }
            break Stop::Interrupted { step };
        }
        integrator.step(system);
        step += 1;
        if let Some(control) = &outputs.control {
            control.set_step(step);
        }
    };
    for rows in series.iter_mut() {
        rows.flush()?;
    }
    Ok(RunReport {
        stop,
        last_step: step,
        reference: Some(reference),
        last_energies: last,
        energy_history: history,
        wall_seconds: started.elapsed().as_secs_f64(),
    })
}

/// Writes the checkpoint of `state` at `step` (and the summary in progress
/// after it), the series flushed first.
fn save(
    series: &mut [Rows],
    sink: &mut SummaryAfterCheckpoint,
    step: u64,
    state: Vec<f64>,
    reference: EnergyReference,
) -> Result<(), RunError> {
    for rows in series.iter_mut() {
        rows.flush()?;
    }
    sink.write(step, &state, Some(reference))
}

/// Writes the values of `quantities` for `system` after its evaluation
/// `e` (with the thermostat's share `thermostat` of the conserved energy)
/// into `row`, in `units`.
fn write_row(
    quantities: &[BodyQuantity],
    (system, e, thermostat): (&BodySystem, &Evaluation, f64),
    units: Units,
    row: &mut Vec<f64>,
) {
    row.clear();
    for q in quantities {
        let start = row.len();
        q.write(system, e, thermostat, row);
        let dimension = quantity_dimension(*q);
        for value in &mut row[start..] {
            *value = units.from_internal(*value, dimension);
        }
    }
}

/// What has gone wrong at a blow-up check, naming the bodies: the pair of
/// Lennard-Jones sites of different bodies deepest inside their core
/// (closer than [`OVERLAP_FRACTION`] of their sigma), else the first body
/// whose state is not finite, else a non-finite total energy `total` with
/// the closest pair of sites (body 0 when the sites have no sigma). The
/// pair is that of the last evaluation, which is at the current state.
fn blown_up(system: &BodySystem, total: f64) -> Option<(usize, String)> {
    let pair = |o: &Overlap| {
        let ((a, s), (b, t)) = (o.sites[0], o.sites[1]);
        let reason = format!(
            "site {s} of body {a} and site {t} of body {b} are {:.4} apart, {:.3} of their sigma {}",
            o.distance,
            o.distance / o.sigma,
            o.sigma
        );
        (a, reason)
    };
    let closest = system.closest_pair();
    if let Some(o) = closest.filter(|o| o.distance < OVERLAP_FRACTION * o.sigma) {
        let (body, reason) = pair(&o);
        return Some((
            body,
            format!("{reason} (below {OVERLAP_FRACTION}: far inside their repulsive core)"),
        ));
    }
    let finite = |v: &nalgebra::Vector3<f64>| v.iter().all(|x| x.is_finite());
    let body = system.bodies.iter().position(|b| {
        !(finite(&b.position)
            && finite(&b.velocity)
            && finite(&b.angular_momentum_body)
            && b.orientation.0.iter().all(|x| x.is_finite()))
    });
    if let Some(i) = body {
        return Some((i, "its state is not finite".to_string()));
    }
    if total.is_finite() {
        return None;
    }
    Some(match closest {
        Some(o) => {
            let (body, reason) = pair(&o);
            (
                body,
                format!("the total energy is {total}; the closest {reason}"),
            )
        }
        None => (0, format!("the total energy is {total}")),
    })
}

/// Bodies of each type.
fn system_counts(bodies: &BodyScene) -> Vec<usize> {
    let mut counts = vec![0; bodies.types.len()];
    for b in &bodies.bodies {
        counts[b.kind] += 1;
    }
    counts
}

/// A GSD file at `path` for the bodies of `system`, a frame every `every`
/// steps.
fn trajectory(system: &BodySystem, every: u64, path: PathBuf) -> Result<Trajectory, RunError> {
    let centres: Vec<_> = system.bodies.iter().map(|b| b.position).collect();
    let box_lengths = match system.space {
        Space::Periodic(l) => Some(l),
        Space::Open => None,
    };
    let cell = GsdBox::new(box_lengths, &centres, GSD_OPEN_MARGIN).map_err(SceneError::from)?;
    let types = &system.types;
    let typeid: Vec<u32> = system.bodies.iter().map(|b| b.kind as u32).collect();
    let mass: Vec<f32> = system
        .bodies
        .iter()
        .map(|b| types[b.kind].mass as f32)
        .collect();
    let moment_inertia: Vec<[f32; 3]> = system
        .bodies
        .iter()
        .map(|b| types[b.kind].moments.map(|m| m as f32).into())
        .collect();
    let body_types = BodyTypes {
        types: types.len(),
        typeid: &typeid,
        mass: &mass,
        moment_inertia: &moment_inertia,
    };
    let writer =
        GsdWriter::create_bodies(&path, &cell, &body_types).map_err(|e| RunError::io(&path, e))?;
    Ok(Trajectory {
        every,
        path,
        writer,
        cell,
    })
}
/// Writes the frame of `system` at `step`: centres wrapped into the box
/// with their image counts (open space: the centres as they are, relative
/// to the box of the first frame), HOOMD's centred coordinates; velocities
/// and angular momenta in the scene's `units`.
fn write_frame(
    writer: &mut GsdWriter,
    system: &BodySystem,
    (step, units): (u64, Units),
    cell: &GsdBox,
) -> std::io::Result<()> {
    let rate = |c: f64| units.from_internal(c, Dimension::Rate) as f32;
    let n = system.bodies.len();
    let (mut position, mut orientation) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let (mut velocity, mut angmom, mut image) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for b in &system.bodies {
        let (mut x, mut images) = (b.position, b.image);
        system.space.wrap(&mut x, &mut images);
        let centred = x - cell.corner - cell.lengths * 0.5;
        position.push(centred.map(|c| c as f32).into());
        orientation.push(b.orientation.0.map(|c| c as f32));
        velocity.push(b.velocity.map(rate).into());
        let p = NoSquishOptions::momentum(&b.orientation, &b.angular_momentum_body);
        angmom.push(p.0.map(rate));
        image.push(images.map(|i| i as i32));
    }
    writer.write_bodies(
        step,
        &BodyFrame {
            position: &position,
            orientation: &orientation,
            velocity: &velocity,
            angmom: &angmom,
            image: &image,
        },
    )
}
