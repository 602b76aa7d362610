//! The scalar observables a run can record, each defined once: its name (the
//! scene's and the CSV column's), what it needs from the run loop, and its
//! value at a sample.

use super::observer::{Energies, Needs, Sample};
use crate::observables::{norm_error, norm_velocity};

/// A scalar observable; per-rotor diagnostics are reduced to their largest
/// magnitude over the rotors.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// `K = 1/2 sum w_b . I w_b`.
    KineticEnergy,
    /// `V`.
    PotentialEnergy,
    /// `K + V`.
    TotalEnergy,
    /// `K + V` plus the thermostat's share (the chain's energy, or minus the
    /// heat a stochastic thermostat put in); `K + V` without a thermostat.
    ConservedEnergy,
    /// `(C - C_0) / s` of the conserved energy `C`, with the scale `s` of
    /// the run's [`super::EnergyReference`].
    EnergyError,
    /// Rotational temperature `2 K / (3 n)`.
    Temperature,
    /// `max_i ||Q_i| - 1|`.
    NormError,
    /// `max_i |Q_i . Q_i'|` (zeroth component of eq 15a).
    NormVelocity,
    /// `max_i |Q_i . N_i|` (zeroth component of eq 15b; scheme B only).
    NormForce,
}

/// The largest magnitude of a per-rotor diagnostic (NaN if any is NaN).
fn max_abs(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(
        0.0,
        |m: f64, x| if x.is_nan() { f64::NAN } else { m.max(x.abs()) },
    )
}

impl Quantity {
    /// Every quantity, in the order of [`Quantity::name`]'s documentation.
    pub const ALL: [Quantity; 9] = [
        Quantity::KineticEnergy,
        Quantity::PotentialEnergy,
        Quantity::TotalEnergy,
        Quantity::ConservedEnergy,
        Quantity::EnergyError,
        Quantity::Temperature,
        Quantity::NormError,
        Quantity::NormVelocity,
        Quantity::NormForce,
    ];

    /// The name used in scene files and as the CSV column header.
    pub fn name(&self) -> &'static str {
        match self {
            Quantity::KineticEnergy => "kinetic_energy",
            Quantity::PotentialEnergy => "potential_energy",
            Quantity::TotalEnergy => "total_energy",
            Quantity::ConservedEnergy => "conserved_energy",
            Quantity::EnergyError => "energy_error",
            Quantity::Temperature => "temperature",
            Quantity::NormError => "norm_error",
            Quantity::NormVelocity => "q_dot_q",
            Quantity::NormForce => "q_dot_n",
        }
    }

    /// What the value needs from the run loop.
    pub fn needs(&self) -> Needs {
        match self {
            Quantity::KineticEnergy
            | Quantity::PotentialEnergy
            | Quantity::TotalEnergy
            | Quantity::ConservedEnergy
            | Quantity::EnergyError
            | Quantity::Temperature => Needs {
                energies: true,
                ..Needs::default()
            },
            Quantity::NormError => Needs::default(),
            Quantity::NormVelocity => Needs {
                q_dot: true,
                ..Needs::default()
            },
            Quantity::NormForce => Needs {
                norm_force: true,
                ..Needs::default()
            },
        }
    }

    /// The value at `sample` (NaN when the sample lacks what it needs).
    pub fn value(&self, sample: &Sample<'_>) -> f64 {
        let energy = |f: fn(&Energies) -> f64| sample.energies.as_ref().map_or(f64::NAN, f);
        match self {
            Quantity::KineticEnergy => energy(|e| e.kinetic),
            Quantity::PotentialEnergy => energy(|e| e.potential),
            Quantity::TotalEnergy => energy(|e| e.total),
            Quantity::ConservedEnergy => energy(|e| e.conserved),
            Quantity::EnergyError => energy(|e| e.error),
            // Three rotational degrees of freedom per rotor, k_B = 1.
            Quantity::Temperature => {
                let dof = 3.0 * sample.orientations.len() as f64;
                energy(|e| e.kinetic) * 2.0 / dof
            }
            Quantity::NormError => max_abs(sample.orientations.iter().map(norm_error)),
            Quantity::NormVelocity => sample.q_dot.map_or(f64::NAN, |q_dot| {
                max_abs(
                    sample
                        .orientations
                        .iter()
                        .zip(q_dot)
                        .map(|(q, d)| norm_velocity(q, d)),
                )
            }),
            Quantity::NormForce => sample
                .norm_force
                .map_or(f64::NAN, |qn| max_abs(qn.iter().copied())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quaternion::Quat;

    /// Per-rotor diagnostics reduce to the largest magnitude; a missing part
    /// of the sample gives NaN.
    #[test]
    fn diagnostics_reduce_to_the_largest_magnitude() {
        let q = [Quat::IDENTITY, Quat::IDENTITY * 1.5];
        let sample = Sample {
            step: 0,
            time: 0.0,
            inertia: &[],
            orientations: &q,
            omega_body: None,
            q_dot: None,
            norm_force: Some(&[0.5, -2.0]),
            energies: None,
        };
        assert_eq!(Quantity::NormError.value(&sample), 0.5);
        assert_eq!(Quantity::NormForce.value(&sample), 2.0);
        assert!(Quantity::NormVelocity.value(&sample).is_nan());
        assert!(Quantity::Temperature.value(&sample).is_nan());
    }
}
