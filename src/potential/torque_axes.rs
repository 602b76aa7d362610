//! Which body-fixed axes a potential can never exert a torque about, whatever
//! the orientations: a fact about each rotor's multipoles that the global
//! thermostats need (a spin about such an axis of a rotor whose inertia is
//! symmetric about it is conserved by the dynamics, so it is not one of the
//! degrees of freedom the thermostat can thermalise).
//!
//! A rotor's multipoles are symmetric about a body axis `a` when its dipole is
//! along `a` and its quadrupole is `lambda_a a a + lambda_p (I - a a)`; then
//! the energy depends on its orientation only through the space direction of
//! `a`, and every torque on it (`a x dV/da`) is perpendicular to `a`.

use crate::checks::TENSOR_TOLERANCE;
use nalgebra::{Matrix3, Vector3};

/// The directions of the torque a potential exerts on one rotor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TorqueAxes {
    /// Any direction (or nothing known).
    Any,
    /// Always perpendicular to this body-fixed unit axis.
    PerpendicularTo(Vector3<f64>),
    /// Never a torque (the rotor carries no multipole).
    Never,
}

/// The torque directions of a rotor with body dipole `dipole` and body
/// quadrupole `quadrupole` (zero or absent when it has none), symmetry judged
/// within [`crate::rotor::TENSOR_TOLERANCE`] of the largest entry.
pub fn multipole_torque_axes(
    dipole: Option<&Vector3<f64>>,
    quadrupole: Option<&Matrix3<f64>>,
) -> TorqueAxes {
    let dipole = dipole.filter(|d| d.norm() > 0.0);
    let quadrupole = quadrupole.filter(|q| q.amax() > 0.0);
    let axis = match (dipole, quadrupole) {
        (None, None) => return TorqueAxes::Never,
        (Some(d), _) => d.normalize(),
        (None, Some(q)) => match quadrupole_axis(q) {
            Some(a) => a,
            None => return TorqueAxes::Any,
        },
    };
    match quadrupole {
        Some(q) if !symmetric_about(q, &axis) => TorqueAxes::Any,
        _ => TorqueAxes::PerpendicularTo(axis),
    }
}

/// True when `m` is `lambda_a a a + lambda_p (I - a a)` for the unit `a`.
pub fn symmetric_about(m: &Matrix3<f64>, a: &Vector3<f64>) -> bool {
    let along = a.dot(&(m * a));
    let across = 0.5 * (m.trace() - along);
    let axial = a * a.transpose() * along + (Matrix3::identity() - a * a.transpose()) * across;
    (m - axial).amax() <= TENSOR_TOLERANCE * m.amax()
}

/// The axis of an axial symmetric matrix: the eigenvector of its one
/// distinct eigenvalue, if the other two are equal.
fn quadrupole_axis(q: &Matrix3<f64>) -> Option<Vector3<f64>> {
    let eigen = q.symmetric_eigen();
    (0..3)
        .map(|k| eigen.eigenvectors.column(k).into_owned())
        .find(|a| symmetric_about(q, a))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dipole alone, an axial quadrupole alone (along any axis), both along
    /// one axis: perpendicular to it; a quadrupole that is not axial about
    /// the dipole, or not axial at all: any; nothing: never.
    #[test]
    fn axial_multipoles_have_a_torque_free_axis() {
        let d = Vector3::new(0.0, 0.6, 0.8);
        assert_eq!(
            multipole_torque_axes(Some(&(d * 2.0)), None),
            TorqueAxes::PerpendicularTo(d)
        );
        let axial = |a: &Vector3<f64>| (a * a.transpose() * 3.0 - Matrix3::identity()) * 0.5;
        match multipole_torque_axes(None, Some(&axial(&d))) {
            TorqueAxes::PerpendicularTo(a) => assert!((a.dot(&d).abs() - 1.0).abs() < 1e-12),
            other => panic!("{other:?}"),
        }
        assert_eq!(
            multipole_torque_axes(Some(&d), Some(&axial(&d))),
            TorqueAxes::PerpendicularTo(d)
        );
        assert_eq!(
            multipole_torque_axes(Some(&Vector3::x()), Some(&axial(&d))),
            TorqueAxes::Any
        );
        let general = Matrix3::from_diagonal(&Vector3::new(0.3, 0.5, -0.8));
        assert_eq!(multipole_torque_axes(None, Some(&general)), TorqueAxes::Any);
        assert_eq!(
            multipole_torque_axes(Some(&Vector3::zeros()), Some(&Matrix3::zeros())),
            TorqueAxes::Never
        );
    }

    /// Axial symmetry is judged relative to the largest entry, so the verdict
    /// does not depend on the units of the quadrupole: an axial quadrupole
    /// stays axial, and one 1e-6 off axial stays general, from 1e-8 to 1e8.
    #[test]
    fn the_symmetry_verdict_does_not_depend_on_units() {
        let d = Vector3::new(0.0, 0.6, 0.8);
        let axial = (d * d.transpose() * 3.0 - Matrix3::identity()) * 0.5;
        let off = axial + Matrix3::from_diagonal(&Vector3::new(1e-6, -1e-6, 0.0));
        for scale in [1e-8, 1.0, 1e8] {
            assert_eq!(
                multipole_torque_axes(Some(&d), Some(&(axial * scale))),
                TorqueAxes::PerpendicularTo(d),
                "axial at {scale}"
            );
            assert_eq!(
                multipole_torque_axes(Some(&d), Some(&(off * scale))),
                TorqueAxes::Any,
                "off axial at {scale}"
            );
        }
    }
}
