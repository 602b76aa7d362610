//! The total dipole moment of a configuration, `M = sum_i R(Q_i) mu_i` with
//! `mu_i` the body-frame dipole of rotor `i` and `R(Q_i)` body to space
//! (eq 6 inverted; `Q_i` normalised first, so a drifting `|Q|` of the Gear
//! schemes does not scale `M`). Its fluctuation gives the dielectric
//! constant ([`crate::analysis::dielectric`]).

use crate::quaternion::Quat;
use nalgebra::Vector3;

/// `M = sum_i R(Q_i) mu_i`, space frame; `orientations` and `dipoles_body`
/// pair up rotor by rotor (rotors without a dipole have `mu = 0`).
pub fn total_dipole(orientations: &[Quat], dipoles_body: &[Vector3<f64>]) -> Vector3<f64> {
    debug_assert_eq!(orientations.len(), dipoles_body.len());
    orientations
        .iter()
        .zip(dipoles_body)
        .map(|(q, mu)| q.try_normalize().unwrap_or(*q).body_to_space(mu))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two dipoles turned into opposite directions cancel; the norm of `Q`
    /// does not scale M; a rotation of every rotor rotates M.
    #[test]
    fn total_dipole_rotates_with_the_rotors() {
        let mu = [Vector3::new(0.0, 0.0, 1.5), Vector3::new(0.0, 0.0, 1.5)];
        let flip = Quat::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI);
        assert!(total_dipole(&[Quat::IDENTITY, flip], &mu).norm() < 1e-15);
        let q = [
            Quat::new(0.3, -0.5, 0.6, 0.2),
            Quat::new(0.9, 0.1, 0.0, -0.4),
        ];
        let mu = [Vector3::new(0.2, -1.0, 0.4), Vector3::new(1.0, 0.5, 0.0)];
        let m = total_dipole(&q, &mu);
        let scaled = [q[0] * 2.0, q[1] * 0.5];
        assert!((total_dipole(&scaled, &mu) - m).norm() < 1e-14);
        let turn = Quat::from_axis_angle(&Vector3::y_axis(), 0.7);
        let turned = [turn * q[0], turn * q[1]];
        let expected = turn.body_to_space(&m);
        assert!((total_dipole(&turned, &mu) - expected).norm() < 1e-14);
    }
}
