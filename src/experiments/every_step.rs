//! A run that records every step: the orientations, angular velocities,
//! potential energy and space-frame torques at t = 0 and after each step,
//! for comparisons step by step with another code (LAMMPS' dipole
//! integrator in the validation suite). Runs through the one run loop.

use crate::integrators::{Integrator, IntegratorError, RotorState};
use crate::potential::Potential;
use crate::rotor::Inertia;
use crate::simulation::{self, Needs, Observer, RunOptions, Sample, Scheduled};
use nalgebra::Vector3;
use std::convert::Infallible;

/// Numbers stored per rotor and sample: orientation (4), angular velocity
/// (3), torque (3).
const PER_ROTOR: u64 = 10;

/// The samples of a run of `steps` steps on `rotors` rotors, in C order:
/// `orientations` `(steps + 1, rotors, 4)` scalar first, `omega_body`
/// `(steps + 1, rotors, 3)`, `energy` `(steps + 1,)`, `torques_space`
/// `(steps + 1, rotors, 3)`; sample 0 is the initial state.
#[derive(Clone, Debug, PartialEq)]
pub struct EveryStep {
    /// Orientations, `(steps + 1, rotors, 4)`.
    pub orientations: Vec<f64>,
    /// Body-frame angular velocities, `(steps + 1, rotors, 3)`.
    pub omega_body: Vec<f64>,
    /// Potential energies, `(steps + 1,)`.
    pub energy: Vec<f64>,
    /// Space-frame torques, `(steps + 1, rotors, 3)`.
    pub torques_space: Vec<f64>,
}

impl EveryStep {
    /// The bytes the samples of `steps` steps on `rotors` rotors take, or
    /// `None` when the count overflows (checked before anything is allocated).
    pub fn bytes(rotors: usize, steps: u64) -> Option<u64> {
        let samples = steps.checked_add(1)?;
        let per_sample = (rotors as u64).checked_mul(PER_ROTOR)?.checked_add(1)?;
        samples.checked_mul(per_sample)?.checked_mul(8)
    }
}

/// The recorder: an observer of every step of the run loop.
struct Recorder<'a> {
    potential: &'a dyn Potential,
    torques: Vec<Vector3<f64>>,
    samples: EveryStep,
}

impl Observer for Recorder<'_> {
    type Error = Infallible;

    fn needs(&self) -> Needs {
        Needs {
            omega_body: true,
            ..Needs::default()
        }
    }

    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), Infallible> {
        let q = sample.orientations;
        let omega = sample.omega_body.unwrap_or_default();
        self.torques.fill(Vector3::zeros());
        self.potential.accumulate_torques(q, &mut self.torques);
        let s = &mut self.samples;
        s.energy.push(self.potential.energy(q));
        for ((q, w), t) in q.iter().zip(omega).zip(&self.torques) {
            s.orientations.extend_from_slice(&q.0);
            s.omega_body.extend_from_slice(w.as_slice());
            s.torques_space.extend_from_slice(t.as_slice());
        }
        Ok(())
    }
}

/// Sets `integrator` up on `initial` with steps of `dt` and records every
/// one of `steps` steps (no blow-up checks: the samples go to the end).
/// The caller checks [`EveryStep::bytes`] first.
pub fn every_step(
    integrator: &mut dyn Integrator,
    inertia: &[Inertia],
    potential: &dyn Potential,
    initial: &[RotorState],
    dt: f64,
    steps: u64,
) -> Result<EveryStep, IntegratorError> {
    integrator.setup(inertia, potential, initial, dt)?;
    let n = initial.len();
    let samples = usize::try_from(steps.saturating_add(1)).unwrap_or(usize::MAX);
    let mut recorder = Recorder {
        potential,
        torques: vec![Vector3::zeros(); n],
        samples: EveryStep {
            orientations: Vec::with_capacity(samples * n * 4),
            omega_body: Vec::with_capacity(samples * n * 3),
            energy: Vec::with_capacity(samples),
            torques_space: Vec::with_capacity(samples * n * 3),
        },
    };
    let options = RunOptions {
        start_step: 0,
        end_step: steps,
        checks: None,
        reference: None,
        control: None,
    };
    let mut observers = [Scheduled {
        every: 1,
        at_end: false,
        observer: &mut recorder,
    }];
    let Ok(_) = simulation::run(
        integrator,
        potential,
        inertia,
        &mut observers,
        None,
        &options,
    );
    Ok(recorder.samples)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::{DlmOptions, IntegratorSpec};
    use crate::potential::Free;
    use crate::quaternion::Quat;

    /// A free spherical top under DLM's exact flow follows the closed form
    /// `Q(t) = Q0 * exp(w_b t)` (body-fixed constant `w_b`), sampled at
    /// every step, with the sizes `bytes` promises.
    #[test]
    fn free_spherical_top_is_sampled_every_step_on_the_closed_form() {
        let omega = Vector3::new(0.3, -0.2, 0.5);
        let initial = [RotorState {
            orientation: Quat::IDENTITY,
            omega_body: omega,
        }];
        let mut dlm = IntegratorSpec::Dlm(DlmOptions::default()).build();
        let s = every_step(
            dlm.as_mut(),
            &[Inertia::Spherical(0.1)],
            &Free,
            &initial,
            0.01,
            10,
        )
        .expect("a valid setup");
        assert_eq!(s.energy.len(), 11);
        assert_eq!(s.orientations.len(), 44);
        let stored = 8
            * (s.orientations.len() + s.omega_body.len() + s.energy.len() + s.torques_space.len());
        assert_eq!(EveryStep::bytes(1, 10), Some(stored as u64));
        let exact = Quat::exp(&(omega * 0.1)).0;
        let last = &s.orientations[40..44];
        let error = last
            .iter()
            .zip(exact)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(error < 1e-14, "error {error}"); // ten unit products: round-off
    }

    /// Sizes that overflow are `None`, never a wrapped count.
    #[test]
    fn sizes_that_overflow_are_refused() {
        assert_eq!(EveryStep::bytes(1, u64::MAX), None);
        assert_eq!(EveryStep::bytes(usize::MAX, 1), None);
    }
}
