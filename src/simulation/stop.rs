//! Why a run stops early: the blow-up guard.

use super::observer::Sample;
use crate::observables::kinetic_energy;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;

/// The blow-up guard: at every sample and every `every` steps (and at the
/// last step) all orientations and angular velocities must be finite, and
/// the energy, when computed, finite and within the threshold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlowUpChecks {
    /// The interval of the checks in steps (>= 1).
    pub every: u64,
    /// Stop when `|energy error|` exceeds this (the energy is then computed
    /// at every check).
    pub energy_error_threshold: Option<f64>,
}

/// Why the run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Stop {
    /// All steps were done.
    Completed,
    /// A non-finite value or an energy error above the threshold.
    BlewUp {
        /// The step of the check that failed.
        step: u64,
        /// The rotor blamed.
        rotor: usize,
        /// What was wrong.
        reason: String,
    },
    /// A stop was requested through the run's [`super::Control`] (a
    /// signal, Ctrl-C); the run ended at the end of this step.
    Interrupted {
        /// The last step done.
        step: u64,
    },
}

impl Stop {
    /// The message of a blow-up (naming the step and the rotor) or of an
    /// interrupt.
    pub fn message(&self) -> Option<String> {
        match self {
            Stop::Completed => None,
            Stop::Interrupted { step } => Some(format!("interrupted at step {step}")),
            Stop::BlewUp {
                step,
                rotor,
                reason,
            } => Some(format!("blew up at step {step}, rotor {rotor}: {reason}")),
        }
    }
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

/// The blow-up test of a sample (with its angular velocities).
pub(super) fn blow_up(
    sample: &Sample<'_>,
    omega_body: &[Vector3<f64>],
    checks: &BlowUpChecks,
) -> Stop {
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
        if !(e.conserved.is_finite() && e.error.is_finite()) {
            return Stop::BlewUp {
                step: sample.step,
                rotor: hottest(sample.inertia, omega_body),
                reason: format!(
                    "the conserved energy is not finite ({}): the thermostat's energy overflowed",
                    e.conserved
                ),
            };
        }
        if let Some(threshold) = checks.energy_error_threshold {
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
