//! The one validation path of every integrator's setup: the time step, the
//! moments of inertia and the initial states, checked once, with messages
//! naming the rotor and the value.

use super::{IntegratorError, RotorState};
use crate::checks::{each, finite, orientation};
use crate::rotor::Inertia;
use nalgebra::Vector3;

/// What an integrator requires of the principal moments, beyond being finite
/// and `>= 0` and not all zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Moments {
    /// Zero moments allowed (linear rotors): the baselines skip those axes.
    MayBeZero,
    /// Every moment `> 0`: the Gear schemes divide by each of them.
    Positive,
}

/// The validated setup arguments.
#[derive(Clone, Debug, PartialEq)]
pub struct ValidSetup {
    /// The principal moments `(I1, I2, I3)` of every rotor.
    pub moments: Vec<Vector3<f64>>,
    /// The initial states with unit orientations.
    pub initial: Vec<RotorState>,
}

/// Checks `dt` (finite, > 0), one inertia per initial state, the moments of
/// inertia (finite, >= 0, not all zero, and all > 0 when `required` says so)
/// and the initial states (orientation and angular velocity finite);
/// returns the principal moments and the states with normalised
/// orientations. Errors name the first offending rotor; the check that
/// moments are positive comes after all the others.
pub fn validate_setup(
    inertia: &[Inertia],
    initial: &[RotorState],
    dt: f64,
    required: Moments,
) -> Result<ValidSetup, IntegratorError> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(IntegratorError::BadTimeStep(dt));
    }
    if inertia.len() != initial.len() {
        return Err(IntegratorError::Unsupported {
            rotor: inertia.len().min(initial.len()),
            reason: format!(
                "{} moments of inertia for {} initial states",
                inertia.len(),
                initial.len()
            ),
        });
    }
    let mut moments = Vec::with_capacity(inertia.len());
    let mut unit_initial = Vec::with_capacity(initial.len());
    for (rotor, (inertia, state)) in inertia.iter().zip(initial).enumerate() {
        let m = inertia.principal();
        if m.iter().any(|x| !(x.is_finite() && *x >= 0.0)) || m.iter().all(|x| *x == 0.0) {
            return Err(IntegratorError::Unsupported {
                rotor,
                reason: format!("moments of inertia must be finite, >= 0 and not all 0, got {m:?}"),
            });
        }
        let orientation = orientation(&state.orientation)
            .map_err(|e| e.at("orientation"))
            .and_then(|q| {
                each(state.omega_body.as_slice(), finite).map_err(|e| e.at("omega_body"))?;
                Ok(q)
            })
            .map_err(|e| IntegratorError::Unsupported {
                rotor,
                reason: e.to_string(),
            })?;
        moments.push(m);
        unit_initial.push(RotorState {
            orientation,
            omega_body: state.omega_body,
        });
    }
    if required == Moments::Positive {
        if let Some(rotor) = moments.iter().position(|m| m.iter().any(|x| *x <= 0.0)) {
            return Err(IntegratorError::Unsupported {
                rotor,
                reason: format!(
                    "moments of inertia must all be > 0 for the Gear schemes, got {:?}",
                    moments[rotor].as_slice()
                ),
            });
        }
    }
    Ok(ValidSetup {
        moments,
        initial: unit_initial,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quaternion::Quat;

    /// Zero moments pass for the baselines and are rejected, with the rotor
    /// index, for the Gear schemes.
    #[test]
    fn rejects_non_positive_moments() {
        let inertia = [
            Inertia::Spherical(1.0),
            Inertia::Principal(Vector3::new(1.0, 0.0, 1.0)),
        ];
        let initial = [RotorState {
            orientation: Quat::IDENTITY,
            omega_body: Vector3::zeros(),
        }; 2];
        assert!(validate_setup(&inertia, &initial, 0.1, Moments::MayBeZero).is_ok());
        let err = validate_setup(&inertia, &initial, 0.1, Moments::Positive).unwrap_err();
        assert!(
            matches!(err, IntegratorError::Unsupported { rotor: 1, .. }),
            "{err}"
        );
    }

    /// A negative, infinite or NaN moment is refused, with the rotor index
    /// and the moments, whatever the scheme accepts of zero moments.
    #[test]
    fn rejects_negative_and_non_finite_moments() {
        let initial = [RotorState {
            orientation: Quat::IDENTITY,
            omega_body: Vector3::zeros(),
        }; 2];
        for bad in [-1.0, f64::INFINITY, f64::NAN] {
            let inertia = [
                Inertia::Spherical(1.0),
                Inertia::Principal(Vector3::new(1.0, bad, 1.0)),
            ];
            for moments in [Moments::MayBeZero, Moments::Positive] {
                let err = validate_setup(&inertia, &initial, 0.1, moments).unwrap_err();
                assert!(
                    matches!(err, IntegratorError::Unsupported { rotor: 1, .. }),
                    "{bad}: {err}"
                );
                assert!(err.to_string().contains("finite, >= 0"), "{bad}: {err}");
            }
        }
    }
}
