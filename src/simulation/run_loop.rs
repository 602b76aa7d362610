//! The run loop. Between two events the loop is the bare
//! `integrator.step(potential)`; at an event step (a multiple of some
//! observer's interval, of the check interval or of the checkpoint interval)
//! it computes only what is due then: the observers' [`Needs`], the blow-up
//! checks, a checkpoint.

use super::control::Control;
use super::energy::{EnergyHistory, EnergyReference};
use super::observer::{Checkpoints, Energies, Needs, Sample, Scheduled};
use super::stop::{blow_up, BlowUpChecks, Stop};
use crate::integrators::Integrator;
use crate::observables::total_kinetic_energy;
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;
use std::sync::Arc;
use std::time::Instant;

/// How long to run and what to guard.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Step the integrator is at (0, or a checkpoint's step).
    pub start_step: u64,
    /// Last step.
    pub end_step: u64,
    /// The blow-up guard (`None`: the run never stops early).
    pub checks: Option<BlowUpChecks>,
    /// The reference energy carried over from a checkpoint.
    pub reference: Option<EnergyReference>,
    /// Polled after every step: a stop request ends the run there
    /// ([`Stop::Interrupted`]), after the samples due at that step, with a
    /// checkpoint if checkpoints are written; the step reached is recorded
    /// in it.
    pub control: Option<Arc<Control>>,
}

/// What the run did.
#[derive(Clone, Debug)]
pub struct RunReport {
    /// Why the run ended.
    pub stop: Stop,
    /// The step the run ended at.
    pub last_step: u64,
    /// The energy reference of the run, if energies were computed.
    pub reference: Option<EnergyReference>,
    /// The last energies computed, and their step.
    pub last_energies: Option<(u64, Energies)>,
    /// The energies at every step where they were computed.
    pub energy_history: EnergyHistory,
    /// Wall-clock seconds spent in the loop.
    pub wall_seconds: f64,
}

/// Runs `integrator` (already set up, or restored at `options.start_step`)
/// from `start_step` to `end_step`, feeding the observers at their intervals
/// and writing checkpoints (the observers flushed first, so that their files
/// hold at least what the checkpoint does). A stop requested through
/// `options.control` ends the run at the end of the current step, with a
/// checkpoint there when checkpoints are written. Observers are finished in
/// every case; the first error of an observer or of the checkpoint sink ends
/// the run.
pub fn run<E>(
    integrator: &mut dyn Integrator,
    potential: &dyn Potential,
    inertia: &[Inertia],
    observers: &mut [Scheduled<'_, E>],
    checkpoints: Option<Checkpoints<'_, E>>,
    options: &RunOptions,
) -> Result<RunReport, E> {
    let started = Instant::now();
    let mut run = Loop {
        integrator,
        potential,
        inertia,
        checkpoints,
        options,
        buffers: Buffers::new(inertia.len()),
        due: vec![false; observers.len()],
        wants_energies: options
            .checks
            .is_some_and(|c| c.energy_error_threshold.is_some())
            || observers.iter().any(|s| s.observer.needs().energies),
        report: RunReport {
            stop: Stop::Completed,
            last_step: options.start_step,
            reference: options.reference,
            last_energies: None,
            energy_history: EnergyHistory::default(),
            wall_seconds: 0.0,
        },
    };
    let result = run.steps(observers);
    let finished: Result<(), E> = observers.iter_mut().try_for_each(|s| s.observer.finish());
    result?;
    finished?;
    let mut report = run.report;
    report.wall_seconds = started.elapsed().as_secs_f64();
    Ok(report)
}

/// Scratch buffers of the sampling steps, sized once.
struct Buffers {
    omega_body: Vec<Vector3<f64>>,
    q_dot: Vec<Quat>,
    norm_force: Vec<f64>,
}

impl Buffers {
    fn new(n: usize) -> Self {
        Buffers {
            omega_body: vec![Vector3::zeros(); n],
            q_dot: vec![Quat::ZERO; n],
            norm_force: vec![0.0; n],
        }
    }
}

/// The first multiple of `every` after `step`.
fn next_multiple(step: u64, every: u64) -> u64 {
    (step / every + 1).saturating_mul(every)
}

/// The energies from the kinetic and potential energy and the thermostat's
/// share of the conserved energy, the error of the conserved energy measured
/// from `reference` (set from these energies if there is none yet).
fn energies(
    kinetic: f64,
    potential: f64,
    thermostat: f64,
    reference: &mut Option<EnergyReference>,
) -> Energies {
    let total = kinetic + potential;
    let conserved = total + thermostat;
    let reference = *reference.get_or_insert_with(|| EnergyReference::initial(kinetic, conserved));
    Energies {
        kinetic,
        potential,
        total,
        conserved,
        error: reference.error(conserved),
    }
}

/// One run in progress.
struct Loop<'a, 'c, E> {
    integrator: &'a mut dyn Integrator,
    potential: &'a dyn Potential,
    inertia: &'a [Inertia],
    checkpoints: Option<Checkpoints<'c, E>>,
    options: &'a RunOptions,
    buffers: Buffers,
    /// Which observers sample at the current step.
    due: Vec<bool>,
    /// Whether energies are computed at all (then also at the start, for the
    /// reference).
    wants_energies: bool,
    report: RunReport,
}

impl<E> Loop<'_, '_, E> {
    /// Steps from the start to the end (or a blow-up), handling each event.
    fn steps(&mut self, observers: &mut [Scheduled<'_, E>]) -> Result<(), E> {
        let mut step = self.options.start_step;
        loop {
            self.report.last_step = step;
            self.sample(step, observers)?;
            if self.report.stop != Stop::Completed {
                return Ok(());
            }
            self.checkpoint(step, observers, false)?;
            if step >= self.options.end_step {
                return Ok(());
            }
            let control = self.options.control.as_deref();
            if control.is_some_and(Control::stop_requested) {
                self.report.stop = Stop::Interrupted { step };
                return self.checkpoint(step, observers, true);
            }
            let next = self.next_event(step, observers);
            // A stop between two events ends the run at the end of the
            // step in progress; one at an event step is seen above, after
            // that step's samples.
            let first = step;
            let mut go_on = |taken: u64| match control {
                Some(control) => {
                    control.set_step(first + taken);
                    !control.stop_requested()
                }
                None => true,
            };
            step += self
                .integrator
                .steps(self.potential, next - step, &mut go_on);
            if let Some(control) = control {
                control.set_step(step);
                if step < next {
                    self.report.last_step = step;
                    self.report.stop = Stop::Interrupted { step };
                    return self.checkpoint(step, observers, true);
                }
            }
        }
    }

    /// The observers due at `step` (marked in `self.due`) and what they need.
    fn due_at(&mut self, step: u64, observers: &[Scheduled<'_, E>]) -> Needs {
        let mut needs = Needs::default();
        for (d, s) in self.due.iter_mut().zip(observers) {
            *d = step % s.every.max(1) == 0 || (s.at_end && step == self.options.end_step);
            if *d {
                needs = needs.union(s.observer.needs());
            }
        }
        needs
    }

    /// At `step`: computes what the due observers and the checks need, feeds
    /// the observers, and applies the blow-up checks (to `self.report.stop`).
    fn sample(&mut self, step: u64, observers: &mut [Scheduled<'_, E>]) -> Result<(), E> {
        let options = self.options;
        let mut needs = self.due_at(step, observers);
        let any_due = self.due.iter().any(|&d| d);
        let is_check = options
            .checks
            .is_some_and(|c| step % c.every.max(1) == 0 || step == options.end_step);
        let threshold = options.checks.and_then(|c| c.energy_error_threshold);
        if is_check || any_due {
            needs.omega_body = true;
        }
        if (is_check && threshold.is_some())
            || (step == options.start_step
                && self.wants_energies
                && self.report.reference.is_none())
        {
            needs.energies = true;
        }
        if !(is_check || any_due || needs.energies) {
            return Ok(());
        }
        let orientations = self.integrator.orientations();
        let buffers = &mut self.buffers;
        if needs.omega_body || needs.energies {
            self.integrator.omega_body(&mut buffers.omega_body);
        }
        if needs.q_dot {
            self.integrator.q_dot(&mut buffers.q_dot);
        }
        let norm_force = needs.norm_force && self.integrator.norm_force(&mut buffers.norm_force);
        let energies = needs.energies.then(|| {
            let kinetic = total_kinetic_energy(self.inertia, &buffers.omega_body);
            energies(
                kinetic,
                self.potential.energy(orientations),
                self.integrator.thermostat_energy(),
                &mut self.report.reference,
            )
        });
        let time = step as f64 * self.integrator.dt();
        if let Some(e) = energies {
            self.report.last_energies = Some((step, e));
            self.report
                .energy_history
                .push(time, e.kinetic, e.conserved);
        }
        let sample = Sample {
            step,
            time,
            inertia: self.inertia,
            orientations,
            omega_body: needs.omega_body.then_some(&buffers.omega_body[..]),
            q_dot: needs.q_dot.then_some(&buffers.q_dot[..]),
            norm_force: norm_force.then_some(&buffers.norm_force[..]),
            energies,
        };
        for (s, _) in observers.iter_mut().zip(&self.due).filter(|(_, &d)| d) {
            s.observer.observe(&sample)?;
        }
        if let Some(checks) = &options.checks {
            self.report.stop = blow_up(&sample, &buffers.omega_body, checks);
        }
        Ok(())
    }

    /// Writes a checkpoint when one is due at `step`, or at once when
    /// `now` (never at the start), after flushing the observers.
    fn checkpoint(
        &mut self,
        step: u64,
        observers: &mut [Scheduled<'_, E>],
        now: bool,
    ) -> Result<(), E> {
        if let Some(c) = &mut self.checkpoints {
            if step != self.options.start_step && (now || step % c.every.max(1) == 0) {
                for s in observers.iter_mut() {
                    s.observer.flush()?;
                }
                c.sink
                    .write(step, &self.integrator.checkpoint(), self.report.reference)?;
            }
        }
        Ok(())
    }

    /// The next step with an event after `step` (at most the end).
    fn next_event(&self, step: u64, observers: &[Scheduled<'_, E>]) -> u64 {
        let mut next = self.options.end_step;
        if let Some(c) = &self.options.checks {
            next = next.min(next_multiple(step, c.every.max(1)));
        }
        for s in observers {
            next = next.min(next_multiple(step, s.every.max(1)));
        }
        if let Some(c) = &self.checkpoints {
            next = next.min(next_multiple(step, c.every.max(1)));
        }
        next
    }
}
