//! Observables of a rotor system as pure functions of its state (the
//! sampling runner calls them; potential and total energy use
//! [`Potential::energy`]). The orientational order and the total dipole are
//! in [`order`] and [`polarization`]; the body axes along which rotors carry
//! their multipoles, whose order is measured, in [`multipole_axes`].

pub mod multipole_axes;
pub mod order;
pub mod polarization;

use crate::potential::Potential;
use crate::quaternion::Quat;
use crate::rotor::Inertia;
use nalgebra::Vector3;

/// Kinetic energy of a spherical top from `Q'` alone: `2 I |Q'|^2` (the
/// note's identity, equal to `1/2 I w^2` for unit `Q` with `Q.Q' = 0`).
pub fn kinetic_energy_spherical(moment: f64, q_dot: &Quat) -> f64 {
    2.0 * moment * q_dot.norm_squared()
}

/// Kinetic energy `1/2 w_b . I w_b` of one rotor.
pub fn kinetic_energy(inertia: &Inertia, omega_body: &Vector3<f64>) -> f64 {
    0.5 * omega_body.dot(&inertia.principal().component_mul(omega_body))
}

/// Total kinetic energy of all rotors.
pub fn total_kinetic_energy(inertia: &[Inertia], omega_body: &[Vector3<f64>]) -> f64 {
    inertia
        .iter()
        .zip(omega_body)
        .map(|(i, w)| kinetic_energy(i, w))
        .sum()
}

/// Total energy: kinetic plus `Potential::energy` at the orientations.
pub fn total_energy<P: Potential>(
    potential: &P,
    inertia: &[Inertia],
    orientations: &[Quat],
    omega_body: &[Vector3<f64>],
) -> f64 {
    total_kinetic_energy(inertia, omega_body) + potential.energy(orientations)
}

/// The norm error `|Q| - 1`.
pub fn norm_error(q: &Quat) -> f64 {
    q.norm() - 1.0
}

/// `Q.Q'`, the zeroth component of `Q~*Q'`: half the time derivative of
/// `|Q|^2` (eq 15a), zero on the exact motion.
pub fn norm_velocity(q: &Quat, q_dot: &Quat) -> f64 {
    q.dot(q_dot)
}

/// `Q.N`, the zeroth component of `Q~*N` (eq 15b): twice the body-frame norm
/// component `(N_b)_0` of the quaternion force, zero after the projection.
pub fn norm_force(q: &Quat, force: &Quat) -> f64 {
    q.dot(force)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The angular velocities of eq 10 inverted are exact for a non-unit `Q`
    /// (scaling `Q` and `Q'` together leaves them unchanged), and body and
    /// space forms are related by the rotation of `Q` (eq 6).
    #[test]
    fn angular_velocities_are_scale_invariant_and_related_by_the_rotation() {
        let q = Quat::new(0.3, -0.5, 0.6, 0.2).try_normalize().unwrap();
        let w_b = Vector3::new(0.7, -1.1, 0.9);
        let q_dot = q.q_dot_from_omega_body(&w_b);
        assert!(((q * 1.3).omega_body_from_q_dot(&(q_dot * 1.3)) - w_b).norm() < 1e-15);
        assert!((q.omega_space_from_q_dot(&q_dot) - q.body_to_space(&w_b)).norm() < 1e-15);
        assert!(norm_velocity(&q, &q_dot).abs() < 1e-16);
        assert!((norm_error(&(q * 1.5)) - 0.5).abs() < 1e-15);
    }

    /// `1/2 w.Iw` for a general top, and the total adds the potential.
    #[test]
    fn kinetic_and_total_energy() {
        let inertia = [
            Inertia::Principal(Vector3::new(1.0, 2.0, 3.0)),
            Inertia::Spherical(2.0),
        ];
        let w = [Vector3::new(1.0, 1.0, 1.0), Vector3::new(0.0, 0.0, 1.0)];
        assert_eq!(total_kinetic_energy(&inertia, &w), 3.0 + 1.0);
        let q = [Quat::IDENTITY; 2];
        assert_eq!(total_energy(&crate::potential::Free, &inertia, &q, &w), 4.0);
        assert_eq!(
            norm_force(&Quat::IDENTITY, &Quat::new(2.0, 1.0, 0.0, 0.0)),
            2.0
        );
    }
}
