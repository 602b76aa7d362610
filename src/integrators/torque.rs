//! Torques on all rotors, evaluated into a buffer the integrator owns (sized
//! once at setup), and their body-fixed components. (The baselines keep unit
//! orientations and apply `A(Q)` of eq 7 directly in their kicks.)

use crate::potential::Potential;
use crate::quaternion::Quat;
use nalgebra::Vector3;

/// Overwrites `torque_space` with the space-fixed torques at `orientations`.
pub fn evaluate_torques(
    potential: &dyn Potential,
    orientations: &[Quat],
    torque_space: &mut [Vector3<f64>],
) {
    torque_space.fill(Vector3::zeros());
    potential.accumulate_torques(orientations, torque_space);
}

/// Body-fixed components of a space-fixed torque with the rotation of `Q`,
/// `A(Q/|Q|) n_s` (eq 6), exact for a slightly non-unit predicted `Q`.
pub fn torque_body(q: &Quat, torque_space: &Vector3<f64>) -> Vector3<f64> {
    q.space_to_body(torque_space) / q.norm_squared()
}
