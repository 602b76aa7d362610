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

#[cfg(test)]
mod tests {
    use super::*;

    /// `A(Q/|Q|) n_s` for a non-unit `Q`: the same body components as for
    /// the unit `Q` of the same rotation, and the torque's length kept.
    #[test]
    fn body_components_do_not_depend_on_the_norm_of_q() {
        let unit = Quat::new(0.3, -0.5, 0.6, 0.2).try_normalize().unwrap();
        let n_s = Vector3::new(0.4, -1.3, 0.7);
        let reference = torque_body(&unit, &n_s);
        assert!((reference.norm() - n_s.norm()).abs() < 1e-15);
        for scale in [0.8, 1.3] {
            let d = torque_body(&(unit * scale), &n_s) - reference;
            assert!(d.norm() < 1e-15, "|Q| = {scale}: {d:?}");
        }
    }
}
