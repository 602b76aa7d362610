//! Running a scene of moving bodies: the system and its integrator
//! ([`BodyIntegrator`]) built from the scene, stepped from t = 0 with the
//! series (CSV), the GSD trajectory and `summary.json` written through the
//! rotors' writers ([`Rows`], [`GsdWriter`], the locked [`OutputFolder`],
//! the atomic summary). Energies are computed at every sample and every
//! blow-up check; the energy error and the drift follow as for rotors.

use super::error::RunError;
use super::folder::{OutputFolder, GSD_FILE, SUMMARY_FILE};
use super::gsd::{BodyFrame, BodyTypes, GsdBox, GsdWriter};
use super::resume::Placement;
use super::scene_run::{Outputs, RunResult};
use super::series::{CsvTarget, Rows};
use super::summary::{BodiesSummary, Summary, Threads};
use super::summary_file::{in_progress, placed, record_failure};
use super::trajectory::GSD_OPEN_MARGIN;
use crate::bodies::{BodyIntegrator, BodySystem, Evaluation, Space};
use crate::integrators::{NoSquishOptions, Splitting};
use crate::scene::{BodyScene, Scene, SceneError};
use crate::simulation::{Energies, EnergyHistory, EnergyReference, RunReport, Stop};
use std::path::PathBuf;
use std::time::Instant;

/// A GSD trajectory being written.
struct Trajectory {
    every: u64,
    path: PathBuf,
    writer: GsdWriter,
    cell: GsdBox,
}

/// Runs the scene of bodies `bodies` (the body part of `scene`, whose raw
/// form is `definition`) from t = 0.
pub(super) fn run_bodies(
    scene: &Scene,
    bodies: &BodyScene,
    definition: serde_json::Value,
    outputs: &Outputs,
    threads: &Threads,
) -> Result<RunResult, RunError> {
    let mut system = bodies.system()?;
    let mut integrator = BodyIntegrator::new(&scene.integrator, &mut system, scene.dt)
        .map_err(|e| SceneError::from(e.at("integrator")))?;
    let folder = outputs.dir.as_deref().map(OutputFolder::lock).transpose()?;
    let dir = folder.as_ref().map(|f| f.dir().to_path_buf());
    let files = dir.as_deref().map(|d| (d, &Placement::New));
    let mut series = bodies
        .series
        .iter()
        .map(|s| {
            let path = dir.as_ref().map(|d| d.join(format!("{}.csv", s.name)));
            let columns = ["step", "time"]
                .into_iter()
                .map(String::from)
                .chain(s.quantities.iter().flat_map(|q| q.columns()))
                .collect();
            let target = path.as_deref().map(CsvTarget::Create);
            Rows::open(&s.name, columns, target, outputs.keep)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut gsd = match (&scene.record.trajectory, &dir) {
        (Some(spec), Some(d)) => Some(trajectory(&system, spec.every, d.join(GSD_FILE))?),
        _ => None,
    };
    let mesh = system.mesh_parameters();
    let described = |mut summary: Summary, builds: u64| {
        summary.bodies = Some(BodiesSummary::new(
            &system_counts(bodies),
            bodies,
            builds,
            mesh,
        ));
        summary
    };
    let running = match files {
        Some((d, _)) => {
            let summary = described(in_progress(scene, &definition, None, (0, threads)), 0);
            Some((d.join(SUMMARY_FILE), placed(summary, files)?))
        }
        None => None,
    };
    let looped = run_steps(
        (scene, bodies),
        (&mut system, &mut integrator),
        &mut series,
        gsd.as_mut(),
        outputs,
    );
    let report = looped.map_err(|e| record_failure(running, e))?;
    let summary = Summary::new(scene, definition.clone(), None, &report, (0, threads));
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
        written: dir.map(|d| (d, Placement::New)),
    })
}

/// Steps `system` from t = 0 to the end of `scene` (or a blow-up, or a
/// stop request), recording the series and the frames when due and the
/// energies at every sample and blow-up check.
fn run_steps(
    (scene, bodies): (&Scene, &BodyScene),
    (system, integrator): (&mut BodySystem, &mut BodyIntegrator),
    series: &mut [Rows],
    mut gsd: Option<&mut Trajectory>,
    outputs: &Outputs,
) -> Result<RunReport, RunError> {
    let started = Instant::now();
    let kinetic = |s: &BodySystem| s.translational_kinetic_energy() + s.rotational_kinetic_energy();
    let mut current = Evaluation::default();
    let k0 = kinetic(system);
    let v0 = integrator
        .evaluated(system, &mut current)
        .potential_energy();
    let reference = EnergyReference::initial(k0, k0 + v0);
    let (mut history, mut last, mut row) = (EnergyHistory::default(), None, Vec::new());
    let mut step = 0;
    let stop = loop {
        let time = step as f64 * scene.dt;
        let due = |every: u64| step % every == 0;
        let sampled = bodies.series.iter().any(|s| due(s.every));
        let evaluation = (sampled || due(scene.record.check_every) || step == scene.steps)
            .then(|| integrator.evaluated(system, &mut current));
        if let Some(e) = evaluation {
            let (k, v) = (kinetic(system), e.potential_energy());
            let total = k + v;
            history.push(time, k, total);
            let energies = Energies {
                kinetic: k,
                potential: v,
                total,
                conserved: total,
                error: reference.error(total),
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
                row.clear();
                for q in &spec.quantities {
                    q.write(system, e, &mut row);
                }
                rows.push(step, time, &row)?;
            }
        }
        if let Some(t) = gsd.as_deref_mut().filter(|t| due(t.every)) {
            write_frame(&mut t.writer, system, step, &t.cell)
                .map_err(|e| RunError::io(&t.path, e))?;
        }
        if step == scene.steps {
            break Stop::Completed;
        }
        if outputs.control.as_ref().is_some_and(|c| c.stop_requested()) {
            break Stop::Interrupted { step };
        }
        integrator.step(system);
        step += 1;
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

/// The first body whose state is not finite, or body 0 when the energy
/// `total` is not, with what is wrong.
fn blown_up(system: &BodySystem, total: f64) -> Option<(usize, String)> {
    let finite = |v: &nalgebra::Vector3<f64>| v.iter().all(|x| x.is_finite());
    let body = system.bodies.iter().position(|b| {
        !(finite(&b.position)
            && finite(&b.velocity)
            && finite(&b.angular_momentum_body)
            && b.orientation.0.iter().all(|x| x.is_finite()))
    });
    match body {
        Some(i) => Some((i, "its state is not finite".to_string())),
        None => (!total.is_finite()).then(|| (0, format!("the total energy is {total}"))),
    }
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
/// to the box of the first frame), HOOMD's centred coordinates.
fn write_frame(
    writer: &mut GsdWriter,
    system: &BodySystem,
    step: u64,
    cell: &GsdBox,
) -> std::io::Result<()> {
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
        velocity.push(b.velocity.map(|c| c as f32).into());
        let p = NoSquishOptions::momentum(&b.orientation, &b.angular_momentum_body);
        angmom.push(p.0.map(|c| c as f32));
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
