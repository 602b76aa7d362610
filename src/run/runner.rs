//! The run loop, generic over the integrator and the potential so that the
//! stepping is monomorphised. Between two events the loop is the bare
//! `integrator.step(potential)`; at an event step (a multiple of some
//! observer's interval, of the check interval or of the checkpoint interval)
//! it computes only what is due then.

use super::checkpoint::CheckpointWriter;
use super::error::RunError;
use super::observer::{Energies, Needs, Sample, Scheduled};
use crate::integrators::Integrator;
use crate::observables::{kinetic_energy, total_kinetic_energy};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The energy the error is measured from: `error = (E - total) / scale`.
/// `scale` is the initial kinetic energy, or `|E_0|` when the rotors start at
/// rest, or 1 when both vanish.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnergyReference {
    pub total: f64,
    pub scale: f64,
}

impl EnergyReference {
    /// The reference of a run starting with these energies.
    pub fn initial(kinetic: f64, total: f64) -> Self {
        let scale = if kinetic > 0.0 {
            kinetic
        } else if total != 0.0 {
            total.abs()
        } else {
            1.0
        };
        EnergyReference { total, scale }
    }

    /// The relative energy error of `total`.
    pub fn error(&self, total: f64) -> f64 {
        (total - self.total) / self.scale
    }
}

/// How long to run and what to guard.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Time step (the integrator was set up with it).
    pub dt: f64,
    /// Step the integrator is at (0, or a checkpoint's step).
    pub start_step: u64,
    /// Last step.
    pub end_step: u64,
    /// Interval of the blow-up checks (finite orientations and angular
    /// velocities, and the energy threshold if any); also checked at every
    /// sample and at the last step.
    pub check_every: u64,
    /// Stop when `|energy error|` exceeds this.
    pub energy_error_threshold: Option<f64>,
    /// The reference energy carried over from a checkpoint.
    pub reference: Option<EnergyReference>,
}

/// Why the run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Stop {
    /// All steps were done.
    Completed,
    /// A non-finite value or an energy error above the threshold.
    BlewUp {
        step: u64,
        rotor: usize,
        reason: String,
    },
}

impl Stop {
    /// The message of a blow-up, naming the step and the rotor.
    pub fn message(&self) -> Option<String> {
        match self {
            Stop::Completed => None,
            Stop::BlewUp {
                step,
                rotor,
                reason,
            } => Some(format!("blew up at step {step}, rotor {rotor}: {reason}")),
        }
    }
}

/// What the run did.
#[derive(Clone, Debug)]
pub struct RunReport {
    pub stop: Stop,
    /// The step the run ended at.
    pub last_step: u64,
    pub reference: Option<EnergyReference>,
    /// The last energies computed, and their step.
    pub last_energies: Option<(u64, Energies)>,
    /// `(time, kinetic, total)` at every step where energies were computed.
    pub energy_history: Vec<[f64; 3]>,
    /// Wall-clock seconds spent in the loop.
    pub wall_seconds: f64,
}

/// Scratch buffers of the sampling steps, sized once.
struct Buffers {
    omega_body: Vec<Vector3<f64>>,
    q_dot: Vec<Quat>,
    q_dot_n: Vec<f64>,
}

/// The first multiple of `every` after `step`.
fn next_multiple(step: u64, every: u64) -> u64 {
    (step / every + 1).saturating_mul(every)
}

/// The first rotor whose orientation or angular velocity is not finite.
fn first_non_finite(orientations: &[Quat], omega_body: &[Vector3<f64>]) -> Option<usize> {
    orientations
        .iter()
        .zip(omega_body)
        .position(|(q, w)| !q.is_finite() || !w.iter().all(|x| x.is_finite()))
}

/// The rotor with the largest kinetic energy (blamed for an energy blow-up).
fn hottest(inertia: &[Inertia], omega_body: &[Vector3<f64>]) -> usize {
    inertia
        .iter()
        .zip(omega_body)
        .map(|(i, w)| kinetic_energy(i, w))
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |best, (k, e)| {
            if e > best.1 || e.is_nan() {
                (k, e)
            } else {
                best
            }
        })
        .0
}

/// Runs `integrator` (already set up, or restored at `options.start_step`)
/// from `start_step` to `end_step`, feeding the observers at their intervals
/// and writing checkpoints. Observers are finished in every case.
pub fn run(
    integrator: &mut dyn Integrator,
    potential: &dyn Potential,
    inertia: &[Inertia],
    observers: &mut [Scheduled<'_>],
    checkpoints: Option<(u64, &CheckpointWriter)>,
    options: &RunOptions,
) -> Result<RunReport, RunError> {
    let started = Instant::now();
    let result = run_loop(
        integrator,
        potential,
        inertia,
        observers,
        checkpoints,
        options,
    );
    let finished: Result<(), RunError> = observers.iter_mut().try_for_each(|s| s.observer.finish());
    let mut report = result?;
    finished?;
    report.wall_seconds = started.elapsed().as_secs_f64();
    Ok(report)
}

fn run_loop(
    integrator: &mut dyn Integrator,
    potential: &dyn Potential,
    inertia: &[Inertia],
    observers: &mut [Scheduled<'_>],
    checkpoints: Option<(u64, &CheckpointWriter)>,
    options: &RunOptions,
) -> Result<RunReport, RunError> {
    let n = inertia.len();
    let mut buffers = Buffers {
        omega_body: vec![Vector3::zeros(); n],
        q_dot: vec![Quat::ZERO; n],
        q_dot_n: vec![0.0; n],
    };
    let check_every = options.check_every.max(1);
    let wants_energies = options.energy_error_threshold.is_some()
        || observers.iter().any(|s| s.observer.needs().energies);
    let mut report = RunReport {
        stop: Stop::Completed,
        last_step: options.start_step,
        reference: options.reference,
        last_energies: None,
        energy_history: Vec::new(),
        wall_seconds: 0.0,
    };
    let mut due = vec![false; observers.len()];
    let mut step = options.start_step;
    loop {
        let is_check = step % check_every == 0 || step == options.end_step;
        let mut needs = Needs::default();
        for (d, s) in due.iter_mut().zip(observers.iter()) {
            *d = step % s.every.max(1) == 0;
            if *d {
                needs = needs.union(s.observer.needs());
            }
        }
        let any_due = due.iter().any(|&d| d);
        let first = step == options.start_step;
        if is_check || any_due {
            needs.omega_body = true;
        }
        if (is_check && options.energy_error_threshold.is_some())
            || (first && wants_energies && report.reference.is_none())
        {
            needs.energies = true;
        }
        if is_check || any_due || needs.energies {
            let orientations = integrator.orientations();
            if needs.omega_body || needs.energies {
                integrator.omega_body(&mut buffers.omega_body);
            }
            if needs.q_dot {
                integrator.q_dot(&mut buffers.q_dot);
            }
            let q_dot_n = needs.q_dot_n && integrator.norm_force(&mut buffers.q_dot_n);
            let energies = needs.energies.then(|| {
                let kinetic = total_kinetic_energy(inertia, &buffers.omega_body);
                let total = kinetic + potential.energy(orientations);
                let reference = *report
                    .reference
                    .get_or_insert_with(|| EnergyReference::initial(kinetic, total));
                Energies {
                    kinetic,
                    potential: total - kinetic,
                    total,
                    error: reference.error(total),
                }
            });
            if let Some(e) = energies {
                report.last_energies = Some((step, e));
                report
                    .energy_history
                    .push([step as f64 * options.dt, e.kinetic, e.total]);
            }
            let sample = Sample {
                step,
                time: step as f64 * options.dt,
                inertia,
                orientations,
                omega_body: needs.omega_body.then_some(&buffers.omega_body[..]),
                q_dot: needs.q_dot.then_some(&buffers.q_dot[..]),
                q_dot_n: q_dot_n.then_some(&buffers.q_dot_n[..]),
                energies,
            };
            for (s, _) in observers.iter_mut().zip(&due).filter(|(_, &d)| d) {
                s.observer.observe(&sample)?;
            }
            report.stop = blow_up(&sample, &buffers.omega_body, options);
            report.last_step = step;
            if report.stop != Stop::Completed {
                return Ok(report);
            }
        }
        if let Some((every, writer)) = checkpoints {
            if step != options.start_step && step % every.max(1) == 0 {
                writer.write(step, &integrator.checkpoint(), report.reference)?;
            }
        }
        if step >= options.end_step {
            report.last_step = step;
            return Ok(report);
        }
        let mut next = next_multiple(step, check_every).min(options.end_step);
        for s in observers.iter() {
            next = next.min(next_multiple(step, s.every.max(1)));
        }
        if let Some((every, _)) = checkpoints {
            next = next.min(next_multiple(step, every.max(1)));
        }
        for _ in step..next {
            integrator.step(potential);
        }
        step = next;
    }
}

/// The blow-up test of a sample (angular velocities always present).
fn blow_up(sample: &Sample<'_>, omega_body: &[Vector3<f64>], options: &RunOptions) -> Stop {
    if let Some(rotor) = first_non_finite(sample.orientations, omega_body) {
        return Stop::BlewUp {
            step: sample.step,
            rotor,
            reason: "orientation or angular velocity is not finite".to_string(),
        };
    }
    if let Some(e) = sample.energies {
        if !e.total.is_finite() {
            return Stop::BlewUp {
                step: sample.step,
                rotor: hottest(sample.inertia, omega_body),
                reason: format!("energy is not finite ({})", e.total),
            };
        }
        if let Some(threshold) = options.energy_error_threshold {
            if e.error.abs() > threshold {
                return Stop::BlewUp {
                    step: sample.step,
                    rotor: hottest(sample.inertia, omega_body),
                    reason: format!(
                        "energy error {:e} exceeds the threshold {threshold:e} (rotor with the largest kinetic energy)",
                        e.error
                    ),
                };
            }
        }
    }
    Stop::Completed
}
