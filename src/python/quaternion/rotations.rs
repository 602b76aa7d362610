//! Products, rotation matrices, rotating vectors and Euler angles of
//! quaternions (eqs 2-8), and quaternions from rotation matrices.

use nalgebra::Rotation3;
use pyo3::prelude::*;

use super::{Array, M, Q, S, V};
use crate::python::args::invalid;
use crate::python::arrays::{collect, common_len, row_major, Items, Values};
use crate::Quat;

/// Largest `|R^T R - I|` and `|det R - 1|` accepted by the matrix conversions:
/// a rotation written with about 12 significant digits.
const ROTATION_TOLERANCE: f64 = 1e-9;

elementwise! {
    /// Hamilton product `p*q` (eq 2, corrected sign).
    ///
    /// Parameters
    /// ----------
    /// p : array_like, shape (4,) or (m, 4)
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    ///
    /// Returns
    /// -------
    /// ndarray, shape (4,) or (m, 4)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.product([0, 1, 0, 0], [0, 0, 1, 0])  # i j = k
    /// array([0., 0., 0., 1.])
    ///
    /// ```
    fn product(p: Q, Quaternions, q: Q, Quaternions) -> Q, |i| Ok((p.quat(i) * q.quat(i)).0)
}

elementwise! {
    /// Conjugate `(q0, -q)` (eq 3).
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    ///
    /// Returns
    /// -------
    /// ndarray, shape (4,) or (m, 4)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.conjugate([1, 2, 3, 4])
    /// array([ 1., -2., -3., -4.])
    ///
    /// ```
    fn conjugate(q: Q, Quaternions) -> Q, |i| Ok(q.quat(i).conjugate().0)
}

elementwise! {
    /// Norm `|Q|` (square root of eq 5).
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    ///
    /// Returns
    /// -------
    /// float or ndarray, shape (m,)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> float(quaternion.norm([1, 1, 1, 1]))
    /// 2.0
    ///
    /// ```
    fn norm(q: Q, Quaternions) -> S, |i| Ok([q.quat(i).norm()])
}

elementwise! {
    /// `A(Q)` of eq 7, space to body (`r_b = A r_s`).
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    ///
    /// Returns
    /// -------
    /// ndarray, shape (3, 3) or (m, 3, 3)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.space_to_body_matrix(quaternion.from_axis_angle([0, 0, 1], np.pi / 2))
    /// array([[ 0.,  1.,  0.],
    ///        [-1.,  0.,  0.],
    ///        [ 0.,  0.,  1.]])
    ///
    /// ```
    fn space_to_body_matrix(q: Q, Quaternions) -> M, |i| Ok(row_major(&q.quat(i).space_to_body_matrix()))
}

elementwise! {
    /// `R(Q) = A(Q)^T`, body to space (`r_s = R r_b`), the active rotation of `Q`.
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    ///
    /// Returns
    /// -------
    /// ndarray, shape (3, 3) or (m, 3, 3)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.body_to_space_matrix(quaternion.from_axis_angle([0, 0, 1], np.pi / 2))
    /// array([[ 0., -1.,  0.],
    ///        [ 1.,  0.,  0.],
    ///        [ 0.,  0.,  1.]])
    ///
    /// ```
    fn body_to_space_matrix(q: Q, Quaternions) -> M, |i| Ok(row_major(&q.quat(i).body_to_space_matrix()))
}

elementwise! {
    /// nalgebra's `Rotation3` of `Q` (via `UnitQuaternion`).
    ///
    /// An independent `R(Q)` for the cross-code checks.
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    ///
    /// Returns
    /// -------
    /// ndarray, shape (3, 3) or (m, 3, 3)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> q = quaternion.exp([0.1, -0.2, 0.3])
    /// >>> np.allclose(quaternion.nalgebra_body_to_space_matrix(q), quaternion.body_to_space_matrix(q))
    /// True
    ///
    /// ```
    fn nalgebra_body_to_space_matrix(q: Q, Quaternions) -> M, |i| Ok(row_major(Rotation3::from(q.quat(i)).matrix()))
}

elementwise! {
    /// Body-fixed components `A(Q) v_space` (eq 6).
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    /// v_space : array_like, shape (3,) or (m, 3)
    ///
    /// Returns
    /// -------
    /// ndarray, shape (3,) or (m, 3)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.space_to_body(quaternion.from_axis_angle([0, 0, 1], np.pi / 2), [1, 0, 0])
    /// array([ 0., -1.,  0.])
    ///
    /// ```
    fn space_to_body(q: Q, Quaternions, v_space: V, Finite) -> V, |i| Ok(q.quat(i).space_to_body(&v_space.vector(i)).into())
}

elementwise! {
    /// Space-fixed components `R(Q) v_body`.
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    /// v_body : array_like, shape (3,) or (m, 3)
    ///
    /// Returns
    /// -------
    /// ndarray, shape (3,) or (m, 3)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.body_to_space(quaternion.from_axis_angle([0, 0, 1], np.pi / 2), [1, 0, 0])
    /// array([0., 1., 0.])
    ///
    /// ```
    fn body_to_space(q: Q, Quaternions, v_body: V, Finite) -> V, |i| Ok(q.quat(i).body_to_space(&v_body.vector(i)).into())
}

elementwise! {
    /// `Q` of y-convention Euler angles `(phi, theta, psi)` in radians (eq 8).
    ///
    /// Parameters
    /// ----------
    /// angles : array_like, shape (3,) or (m, 3)
    ///
    /// Returns
    /// -------
    /// ndarray, shape (4,) or (m, 4)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.from_euler_y([0, np.pi / 2, 0])  # theta: 90 degrees about y
    /// array([0.707107, 0.      , 0.707107, 0.      ])
    ///
    /// ```
    fn from_euler_y(angles: V, Finite) -> Q, |i| {
        let [phi, theta, psi] = angles.vector(i).into();
        Ok(Quat::from_euler_y(phi, theta, psi).0)
    }
}

elementwise! {
    /// y-convention `(phi, theta, psi)` of unit `Q`.
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    ///
    /// Returns
    /// -------
    /// ndarray, shape (3,) or (m, 3)
    ///     theta in [0, pi], phi and psi in (-pi, pi].
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> angles = quaternion.to_euler_y(quaternion.from_euler_y([0.3, 1.2, -0.5]))
    /// >>> np.allclose(angles, [0.3, 1.2, -0.5])
    /// True
    ///
    /// ```
    fn to_euler_y(q: Q, Quaternions) -> V, |i| {
        let (phi, theta, psi) = q.quat(i).to_euler_y();
        Ok([phi, theta, psi])
    }
}
elementwise! {
    /// Unit `Q` (q0 >= 0) of a body-to-space rotation matrix `R`.
    ///
    /// Raises `ValueError` for a matrix that is not a rotation.
    ///
    /// Parameters
    /// ----------
    /// r : array_like, shape (3, 3) or (m, 3, 3)
    ///     A rotation (orthonormal, det 1, to about 1e-9).
    ///
    /// Returns
    /// -------
    /// ndarray, shape (4,) or (m, 4)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.from_body_to_space_matrix(np.diag([1.0, -1.0, -1.0]))
    /// array([0., 1., 0., 0.])
    ///
    /// ```
    fn from_body_to_space_matrix(r: M, Finite) -> Q, |i| Ok(checked_rotation(&r, i, false)?.0)
}

elementwise! {
    /// Unit `Q` (q0 >= 0) of a space-to-body matrix `A` (eq 7).
    ///
    /// Raises `ValueError` for a matrix that is not a rotation.
    ///
    /// Parameters
    /// ----------
    /// a : array_like, shape (3, 3) or (m, 3, 3)
    ///     A rotation (orthonormal, det 1, to about 1e-9).
    ///
    /// Returns
    /// -------
    /// ndarray, shape (4,) or (m, 4)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> q = quaternion.exp([0.1, 0.2, 0.3])
    /// >>> np.allclose(quaternion.from_space_to_body_matrix(quaternion.space_to_body_matrix(q)), q)
    /// True
    ///
    /// ```
    fn from_space_to_body_matrix(a: M, Finite) -> Q, |i| Ok(checked_rotation(&a, i, true)?.0)
}

/// Item `i` of `m` (transposed first if `transpose`) as a quaternion, or a
/// `ValueError` naming the item when it is not a proper rotation.
fn checked_rotation(m: &Items<'_>, i: usize, transpose: bool) -> PyResult<Quat> {
    let matrix = if transpose {
        m.matrix(i).transpose()
    } else {
        m.matrix(i)
    };
    Quat::from_body_to_space_matrix(&matrix, ROTATION_TOLERANCE).ok_or_else(|| {
        invalid(
            &m.label(i),
            format!(
                "not a proper rotation matrix (needs |M^T M - I| and |det M - 1| <= {ROTATION_TOLERANCE:e})"
            ),
        )
    })
}
