//! The body axes along which rotors carry their multipoles, whose space
//! directions the order parameters of [`super::order`] average: the unit
//! direction of a dipole, `e = mu_b / |mu_b|`, and the axis of a quadrupole,
//! the principal axis of its eigenvalue largest in magnitude (the symmetry
//! axis of a linear quadrupole `Theta = Theta_zz (3 e e - I) / 2`; for any
//! traceless `Theta`, the axis it is most elongated or flattened along). A
//! quadrupole's axis has no sign (`Theta` is even in `e`), so only its
//! nematic order means something. Rotors whose multipole vanishes carry no
//! axis and are left out of the averages.

use crate::checks::{InputError, TENSOR_TOLERANCE};
use crate::quaternion::Quat;
use crate::rotor::Rotor;
use nalgebra::{Matrix3, Unit, Vector3};

use super::order::unit_axis;

/// The axis of the traceless symmetric quadrupole `theta`: the unit
/// eigenvector of its eigenvalue largest in magnitude (sign: its first
/// nonzero component positive); `Ok(None)` for a zero quadrupole; an error
/// when two eigenvalues share the largest magnitude to within
/// [`crate::rotor::TENSOR_TOLERANCE`] of it (`diag(1, -1, 0)`: no axis stands out), with
/// the eigenvalues in the message.
pub fn quadrupole_axis(theta: &Matrix3<f64>) -> Result<Option<Unit<Vector3<f64>>>, InputError> {
    let eigen = theta.symmetric_eigen();
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| {
        eigen.eigenvalues[b]
            .abs()
            .total_cmp(&eigen.eigenvalues[a].abs())
    });
    let (largest, second) = (
        eigen.eigenvalues[order[0]].abs(),
        eigen.eigenvalues[order[1]].abs(),
    );
    if largest == 0.0 {
        return Ok(None);
    }
    if largest - second <= TENSOR_TOLERANCE * largest {
        let mut values: Vec<f64> = eigen.eigenvalues.iter().copied().collect();
        values.sort_by(|a, b| b.total_cmp(a));
        let [a, b, c] = [values[0], values[1], values[2]];
        return Err(InputError::new(
            "",
            format!(
                "has no single axis: two of its eigenvalues ({a}, {b}, {c}) share the largest magnitude"
            ),
        ));
    }
    let axis = eigen.eigenvectors.column(order[0]).into_owned();
    let first = axis.iter().copied().find(|x| *x != 0.0).unwrap_or(1.0);
    Ok(unit_axis(&(axis * first.signum())))
}

/// One body axis per rotor that carries a given multipole.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CarriedAxes {
    /// The rotors carrying an axis, in order.
    rotors: Vec<usize>,
    /// Their body axes.
    axes_body: Vec<Unit<Vector3<f64>>>,
}

impl CarriedAxes {
    /// The dipole directions of the rotors with a nonzero dipole.
    pub fn of_dipoles(rotors: &[Rotor]) -> CarriedAxes {
        let mut out = CarriedAxes::default();
        for (i, r) in rotors.iter().enumerate() {
            if let Some(axis) = r.dipole_body.as_ref().and_then(unit_axis) {
                out.rotors.push(i);
                out.axes_body.push(axis);
            }
        }
        out
    }

    /// The quadrupole axes ([`quadrupole_axis`]) of the rotors with a
    /// nonzero quadrupole; an error names the first rotor whose quadrupole
    /// has no single axis (`rotors[i].quadrupole_body`).
    pub fn of_quadrupoles(rotors: &[Rotor]) -> Result<CarriedAxes, InputError> {
        let mut out = CarriedAxes::default();
        for (i, r) in rotors.iter().enumerate() {
            let Some(theta) = &r.quadrupole_body else {
                continue;
            };
            let axis = quadrupole_axis(theta)
                .map_err(|e| e.at(&format!("rotors[{i}].quadrupole_body")))?;
            if let Some(axis) = axis {
                out.rotors.push(i);
                out.axes_body.push(axis);
            }
        }
        Ok(out)
    }

    /// The number of rotors carrying an axis.
    pub fn len(&self) -> usize {
        self.rotors.len()
    }

    /// True when no rotor carries an axis.
    pub fn is_empty(&self) -> bool {
        self.rotors.is_empty()
    }

    /// The space directions `u = R(Q) e` of the axes at `orientations` (one
    /// per rotor of the system, normalised first) into `out` (cleared).
    pub fn space_axes(&self, orientations: &[Quat], out: &mut Vec<Vector3<f64>>) {
        out.clear();
        out.extend(self.rotors.iter().zip(&self.axes_body).map(|(&i, e)| {
            let q = orientations[i];
            q.try_normalize().unwrap_or(q).body_to_space(e)
        }));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotor::Inertia;

    fn rotor(dipole: Option<Vector3<f64>>, quadrupole: Option<Matrix3<f64>>) -> Rotor {
        Rotor {
            site: Vector3::zeros(),
            inertia: Inertia::Spherical(1.0),
            dipole_body: dipole,
            quadrupole_body: quadrupole,
        }
    }

    /// A linear quadrupole's axis is its symmetry axis whether it is
    /// prolate or oblate, also when turned; `diag(1, -1, 0)` has none; a
    /// zero quadrupole carries no axis.
    #[test]
    fn quadrupole_axes() {
        let e = Vector3::new(1.0, 2.0, -2.0) / 3.0;
        let linear = (e * e.transpose() * 3.0 - Matrix3::identity()) * 0.5;
        for theta in [linear, -linear * 0.3] {
            let axis = quadrupole_axis(&theta).unwrap().unwrap();
            assert!((axis.into_inner() - e).norm() < 1e-14, "{axis:?}");
        }
        let tie = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 0.0));
        assert_eq!(
            quadrupole_axis(&tie).unwrap_err().message,
            "has no single axis: two of its eigenvalues (1, 0, -1) share the largest magnitude"
        );
        assert_eq!(quadrupole_axis(&Matrix3::zeros()), Ok(None));
    }

    /// A tie is judged relative to the largest eigenvalue, so the verdict
    /// does not depend on units: a linear quadrupole has its axis and a
    /// tie is refused at scales 1e-8 to 1e8.
    #[test]
    fn the_axis_verdict_does_not_depend_on_units() {
        let e = Vector3::new(1.0, 2.0, -2.0) / 3.0;
        let linear = (e * e.transpose() * 3.0 - Matrix3::identity()) * 0.5;
        let tie = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 0.0));
        for scale in [1e-8, 1.0, 1e8] {
            let axis = quadrupole_axis(&(linear * scale)).unwrap().unwrap();
            assert!((axis.into_inner() - e).norm() < 1e-14, "at {scale}");
            assert!(quadrupole_axis(&(tie * scale)).is_err(), "tie at {scale}");
        }
    }

    /// Only rotors with a nonzero multipole carry an axis; the space axes
    /// follow their rotors' orientations (not scaled by |Q|).
    #[test]
    fn carried_axes_skip_rotors_without_the_multipole() {
        let axial = Matrix3::from_diagonal(&Vector3::new(-0.5, -0.5, 1.0));
        let rotors = [
            rotor(Some(Vector3::new(0.0, 0.0, 2.0)), None),
            rotor(None, Some(axial)),
            rotor(Some(Vector3::zeros()), Some(Matrix3::zeros())),
            rotor(Some(Vector3::new(0.0, 3.0, 0.0)), Some(axial)),
        ];
        let dipoles = CarriedAxes::of_dipoles(&rotors);
        assert_eq!(dipoles.rotors, [0, 3]);
        assert_eq!((dipoles.len(), dipoles.is_empty()), (2, false));
        let none = CarriedAxes::of_dipoles(&rotors[1..3]);
        assert_eq!((none.len(), none.is_empty()), (0, true));
        let quadrupoles = CarriedAxes::of_quadrupoles(&rotors).unwrap();
        assert_eq!(quadrupoles.rotors, [1, 3]);
        let turn = Quat::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
        let q = [turn * 2.0, Quat::IDENTITY, Quat::IDENTITY, turn];
        let mut u = Vec::new();
        dipoles.space_axes(&q, &mut u);
        assert!((u[0] + Vector3::y()).norm() < 1e-15);
        assert!((u[1] - Vector3::z()).norm() < 1e-15);
        let mut tie = rotors.to_vec();
        tie[3].quadrupole_body = Some(Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 0.0)));
        assert_eq!(
            CarriedAxes::of_quadrupoles(&tie).unwrap_err().path,
            "rotors[3].quadrupole_body"
        );
    }
}
