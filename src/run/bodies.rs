//! Running a scene of moving bodies: the system and its integrator
//! ([`BodyIntegrator`]) built from the scene, stepped from t = 0 or
//! restored from a checkpoint, with the series (CSV), the GSD trajectory,
//! the checkpoints and `summary.json` written through the rotors' writers
//! ([`Rows`], [`super::gsd::GsdWriter`], [`super::CheckpointWriter`], the locked
//! [`super::OutputFolder`], the atomic summary) and a restart placed as
//! the rotors' ([`super::resume::Placement`]). Energies are computed at every sample and
//! every blow-up check (the other steps evaluate forces and torques only:
//! [`crate::bodies::Scope`]); the energy error and the drift follow as for
//! rotors. A blow-up names the step and the bodies (and their sites).

use super::body_outputs::{open_series, record, trajectory, write_frame, Trajectory};
use super::error::RunError;
use super::folder::{GSD_FILE, SUMMARY_FILE};
use super::scene_run::{checkpoint_writer, open_folder, read_checkpoint, Outputs, RunResult};
use super::series::Rows;
use super::summary::{BodiesSummary, BodyElectrostaticsSummary, Summary, Threads};
use super::summary_file::{
    in_progress, keep_earlier_summary, placed, record_failure, SummaryAfterCheckpoint,
};
use crate::bodies::{BodyIntegrator, BodySystem, Evaluation, Overlap, OVERLAP_FRACTION};
use crate::integrators::IntegratorError;
use crate::scene::{BodyScene, Scene, SceneError};
use crate::simulation::{
    CheckpointSink, Energies, EnergyHistory, EnergyReference, RunReport, Stop,
};
use std::path::Path;
use std::time::Instant;

/// The checkpoints of a run: their interval, and the writer that follows
/// each with the summary in progress.
type BodyCheckpoints = (u64, SummaryAfterCheckpoint);

/// Runs the scene of bodies `bodies` (the body part of `scene`, whose raw
/// form is `definition`) from t = 0 or from the checkpoint `restart`,
/// continuing the files of the run that wrote it as a run of rotors does
/// ([`super::resume::Placement`]).
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
    let (start_step, reference) = restored(scene, restart, &mut system, &mut integrator)?;
    let (_lock, placement, dir) = open_folder(outputs, scene, restart, start_step)?;
    let files = dir.as_deref().zip(placement.as_ref());
    let mut series = open_series(bodies, (dir.as_deref(), placement.as_ref()), outputs)?;
    let mut gsd = match (&scene.record.trajectory, &dir) {
        (Some(spec), Some(d)) => Some(trajectory(&system, spec.every, d.join(GSD_FILE))?),
        _ => None,
    };
    keep_earlier_summary(files, start_step)?;
    let electrostatics = BodyElectrostaticsSummary::new(bodies, system.electrostatic_sum());
    let described = |mut summary: Summary, builds: u64| {
        summary.bodies = Some(BodiesSummary::new(
            &system_counts(bodies),
            bodies,
            builds,
            electrostatics.clone(),
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
    let mut checkpoints = body_checkpoints(scene, files.map(|(d, _)| d), &running);
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
    let summary = with_blow_up(described(summary, system.neighbour_builds()), &report.stop);
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
    let mut current = Evaluation::default();
    let reference = match reference {
        Some(r) => r,
        None => initial_reference(system, integrator, &mut current),
    };
    let (mut history, mut last, mut row) = (EnergyHistory::default(), None, Vec::new());
    let mut step = start_step;
    let evaluated = |step: u64| energies_read((scene, bodies), step);
    let stop = loop {
        let time = step as f64 * scene.dt;
        let due = |every: u64| step % every == 0;
        let thermostat = integrator.thermostat_energy();
        let evaluation = evaluated(step).then(|| integrator.evaluated(system, &mut current));
        if let Some(e) = evaluation {
            let energies = energies(system, e, thermostat, &reference);
            history.push(time, energies.kinetic, energies.conserved);
            last = Some((step, energies));
            if let Some((rotor, reason)) = blown_up(system, e, energies.total) {
                break Stop::BlewUp {
                    step,
                    rotor,
                    reason,
                };
            }
            let at = (step, time);
            record(
                (scene, bodies),
                (&*system, e, thermostat),
                at,
                series,
                &mut row,
            )?;
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
        integrator.step_read(system, evaluated(step + 1));
        step += 1;
        outputs.control.iter().for_each(|c| c.set_step(step));
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

/// Whether the energies are read at `step`: a sample, a blow-up check,
/// the last step.
fn energies_read((scene, bodies): (&Scene, &BodyScene), step: u64) -> bool {
    let due = |every: u64| step % every == 0;
    bodies.series.iter().any(|s| due(s.every))
        || due(scene.record.check_every)
        || step == scene.steps
}

/// The energies of `system` after its evaluation `e`, with the
/// thermostat's share `thermostat` in the conserved energy and its error
/// against `reference`.
fn energies(
    system: &BodySystem,
    e: &Evaluation,
    thermostat: f64,
    reference: &EnergyReference,
) -> Energies {
    let kinetic = system.translational_kinetic_energy() + system.rotational_kinetic_energy();
    let potential = e.potential_energy();
    let total = kinetic + potential;
    let conserved = total + thermostat;
    Energies {
        kinetic,
        potential,
        total,
        conserved,
        error: reference.error(conserved),
    }
}

/// The checkpoints a run writes into the folder `dir` (none without one or
/// without `record.checkpoint_every`), each followed by the summary in
/// progress `running`.
fn body_checkpoints(
    scene: &Scene,
    dir: Option<&Path>,
    running: &Option<(std::path::PathBuf, Summary)>,
) -> Option<BodyCheckpoints> {
    let (every, dir) = scene.record.checkpoint_every.zip(dir)?;
    let checkpoint = checkpoint_writer(scene, dir);
    Some((
        every,
        SummaryAfterCheckpoint {
            checkpoint,
            summary: running.clone(),
        },
    ))
}

/// The step and energy reference a run starts from: 0 and none, or the
/// checkpoint `restart`'s, restoring `system` and `integrator` from it.
fn restored(
    scene: &Scene,
    restart: Option<&Path>,
    system: &mut BodySystem,
    integrator: &mut BodyIntegrator,
) -> Result<(u64, Option<EnergyReference>), RunError> {
    let Some(path) = restart else {
        return Ok((0, None));
    };
    let checkpoint = read_checkpoint(scene, path)?;
    integrator
        .restore(system, &checkpoint.state())
        .map_err(|e| RunError::Checkpoint {
            path: path.display().to_string(),
            message: match e {
                IntegratorError::BadCheckpoint(why) => why,
                other => other.to_string(),
            },
        })?;
    Ok((checkpoint.step, checkpoint.reference()))
}

/// `summary` with the message of a blow-up `stop` (naming the body).
fn with_blow_up(mut summary: Summary, stop: &Stop) -> Summary {
    if let Stop::BlewUp {
        step,
        rotor,
        reason,
    } = stop
    {
        summary.message = Some(format!("blew up at step {step}, body {rotor}: {reason}"));
    }
    summary
}

/// The energy reference of a run from t = 0: the state's kinetic and total
/// energies (evaluated into `scratch` when the integrator has not).
fn initial_reference(
    system: &mut BodySystem,
    integrator: &BodyIntegrator,
    scratch: &mut Evaluation,
) -> EnergyReference {
    let k0 = system.translational_kinetic_energy() + system.rotational_kinetic_energy();
    let v0 = integrator.evaluated(system, scratch).potential_energy();
    EnergyReference::initial(k0, k0 + v0)
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

/// What has gone wrong at a blow-up check, naming the bodies: the pair of
/// Lennard-Jones sites of different bodies deepest inside their core
/// (closer than [`OVERLAP_FRACTION`] of their sigma), else the first body
/// whose state is not finite, else a non-finite total energy `total` with
/// the closest pair of sites (body 0 when the sites have no sigma). The
/// pair is that of the last evaluation `e`, which is at the current state
/// and counted the pairs that may overlap (so that a sound step looks for
/// none).
fn blown_up(system: &BodySystem, e: &Evaluation, total: f64) -> Option<(usize, String)> {
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
    // The pass counted the pairs that may overlap: the closest is looked for only then.
    let overlaps = e.overlaps != Some(0);
    let closest = overlaps.then(|| system.closest_pair()).flatten();
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
    Some(match closest.or_else(|| system.closest_pair()) {
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
