//! Pieces shared by the kick-based baselines (NO_SQUISH, DLM, Richardson):
//! validation of the setup arguments, the torque evaluation into a reused
//! buffer, and the flat checkpoint layout.

use super::{IntegratorError, RotorState};
use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;

/// Checks `dt`, the moments of inertia (finite, >= 0, not all zero) and the
/// orientations (finite, non-zero; they are normalised by the caller), and
/// returns the principal moments per rotor.
pub fn validate_setup(
    inertia: &[Inertia],
    initial: &[RotorState],
    dt: f64,
) -> Result<Vec<Vector3<f64>>, IntegratorError> {
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
    for (rotor, (inertia, state)) in inertia.iter().zip(initial).enumerate() {
        let m = inertia.principal();
        if m.iter().any(|x| !(x.is_finite() && *x >= 0.0)) || m.iter().all(|x| *x == 0.0) {
            return Err(IntegratorError::Unsupported {
                rotor,
                reason: format!("moments of inertia must be finite, >= 0 and not all 0, got {m:?}"),
            });
        }
        if state.orientation.try_normalize().is_none()
            || !state.omega_body.iter().all(|x| x.is_finite())
        {
            return Err(IntegratorError::Unsupported {
                rotor,
                reason: "orientation must be finite and non-zero, angular velocity finite".into(),
            });
        }
        moments.push(m);
    }
    Ok(moments)
}

/// The unit orientation of a validated state.
pub fn unit_orientation(state: &RotorState) -> Quat {
    state.orientation.try_normalize().unwrap_or(Quat::IDENTITY)
}

/// Overwrites `torques_space` with the space-fixed torques at `orientations`.
pub fn evaluate_torques<P: Potential>(
    potential: &P,
    orientations: &[Quat],
    torques_space: &mut [Vector3<f64>],
) {
    torques_space.fill(Vector3::zeros());
    potential.accumulate_torques(orientations, torques_space);
}

/// Checks that a checkpoint has `rotors * per_rotor` values.
pub fn check_length(state: &[f64], rotors: usize, per_rotor: usize) -> Result<(), IntegratorError> {
    if state.len() != rotors * per_rotor || state.iter().any(|x| !x.is_finite()) {
        return Err(IntegratorError::BadCheckpoint(format!(
            "expected {} finite values ({rotors} rotors x {per_rotor}), got {}",
            rotors * per_rotor,
            state.len()
        )));
    }
    Ok(())
}

/// Flattens quaternions.
pub fn quats_flat(q: &[Quat]) -> impl Iterator<Item = f64> + '_ {
    q.iter().flat_map(|q| q.0)
}

/// Flattens 3-vectors.
pub fn vectors_flat(v: &[Vector3<f64>]) -> impl Iterator<Item = f64> + '_ {
    v.iter().flat_map(|v| [v.x, v.y, v.z])
}

/// Reads `out.len()` quaternions from the front of `state`, returning the rest.
pub fn read_quats<'a>(state: &'a [f64], out: &mut [Quat]) -> &'a [f64] {
    let (head, rest) = state.split_at(4 * out.len());
    for (q, c) in out.iter_mut().zip(head.chunks_exact(4)) {
        *q = Quat([c[0], c[1], c[2], c[3]]);
    }
    rest
}

/// Reads `out.len()` 3-vectors from the front of `state`, returning the rest.
pub fn read_vectors<'a>(state: &'a [f64], out: &mut [Vector3<f64>]) -> &'a [f64] {
    let (head, rest) = state.split_at(3 * out.len());
    for (v, c) in out.iter_mut().zip(head.chunks_exact(3)) {
        *v = Vector3::new(c[0], c[1], c[2]);
    }
    rest
}
