//! Axis and angle, the exponential and logarithm of quaternions, and the
//! relations between `Q'` and the angular velocity (eqs 10, 11).

use pyo3::prelude::*;

use super::{Array, ArrayPair, Q, S, V};
use crate::observables::order::checked_unit_axis;
use crate::python::arrays::{collect, common_len, Items, Values};
use crate::Quat;

/// `Q` of the rotation by `angle` (radians) about `axis`.
///
/// Parameters
/// ----------
/// axis : array_like, shape (3,) or (m, 3)
///     Normalised here; must be nonzero.
/// angle : float or array_like, shape (m,)
///
/// Returns
/// -------
/// ndarray, shape (4,) or (m, 4)
///
/// Examples
/// --------
/// ```python
///
/// >>> quaternion.from_axis_angle([0, 0, 2], np.pi)
/// array([0., 0., 0., 1.])
///
/// ```
#[pyfunction]
pub(super) fn from_axis_angle<'py>(
    py: Python<'py>,
    axis: &Bound<'py, PyAny>,
    angle: &Bound<'py, PyAny>,
) -> Array<'py> {
    let (axis, angle) = (
        Items::new(axis, "axis", &V, Values::Finite)?,
        Items::new(angle, "angle", &S, Values::Finite)?,
    );
    collect(py, common_len(&[&axis, &angle])?, &Q, |i| {
        let unit = checked_unit_axis(&axis.label(i), &axis.vector(i))?;
        Ok(Quat::from_axis_angle(&unit, angle.scalar(i)).0)
    })
}

/// `(axis, angle)` of unit `Q`, angle in [0, pi].
///
/// Parameters
/// ----------
/// q : array_like, shape (4,) or (m, 4)
///     Quaternions, scalar first.
///
/// Returns
/// -------
/// axis : ndarray, shape (3,) or (m, 3)
///     `(0, 0, 0)` for angle 0.
/// angle : float or ndarray, shape (m,)
///
/// Examples
/// --------
/// ```python
///
/// >>> axis, angle = quaternion.to_axis_angle([0, 0, 0, 1])
/// >>> axis, float(angle) == np.pi
/// (array([0., 0., 1.]), True)
///
/// ```
#[pyfunction]
pub(super) fn to_axis_angle<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> ArrayPair<'py> {
    let q = Items::new(q, "q", &Q, Values::Quaternions)?;
    let n = common_len(&[&q])?;
    let axis = collect(py, n, &V, |i| {
        Ok(q.quat(i)
            .to_axis_angle()
            .0
            .map_or([0.0; 3], |a| a.into_inner().into()))
    })?;
    let angle = collect(py, n, &S, |i| Ok([q.quat(i).to_axis_angle().1]))?;
    Ok((axis, angle))
}

elementwise! {
    /// `Q = exp(v)`: the rotation by `|v|` about `v`.
    ///
    /// Parameters
    /// ----------
    /// rotvec : array_like, shape (3,) or (m, 3)
    ///
    /// Returns
    /// -------
    /// ndarray, shape (4,) or (m, 4)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.exp([np.pi, 0, 0])
    /// array([0., 1., 0., 0.])
    ///
    /// ```
    fn exp(rotvec: V, Finite) -> Q, |i| Ok(Quat::exp(&rotvec.vector(i)).0)
}

elementwise! {
    /// `ln Q`: the rotation vector of unit `Q`, `|v|` in [0, pi].
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    ///
    /// Returns
    /// -------
    /// ndarray, shape (3,) or (m, 3)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.ln(quaternion.exp([0.1, 0.2, -0.3]))
    /// array([ 0.1,  0.2, -0.3])
    /// >>> quaternion.ln([-1, 0, 0, 0])  # the double cover: -Q is Q
    /// array([0., 0., 0.])
    ///
    /// ```
    fn ln(q: Q, Quaternions) -> V, |i| Ok(q.quat(i).ln().into())
}

elementwise! {
    /// `Q' = 1/2 Q*(0, w_b)` (eq 10, body form).
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    /// omega_body : array_like, shape (3,) or (m, 3)
    ///
    /// Returns
    /// -------
    /// ndarray, shape (4,) or (m, 4)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.q_dot_from_omega_body([1, 0, 0, 0], [0, 0, 2])
    /// array([0., 0., 0., 1.])
    ///
    /// ```
    fn q_dot_from_omega_body(q: Q, Quaternions, omega_body: V, Finite) -> Q, |i| Ok(q.quat(i).q_dot_from_omega_body(&omega_body.vector(i)).0)
}

elementwise! {
    /// `Q' = 1/2 (0, w_s)*Q` (eq 10, space form).
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    /// omega_space : array_like, shape (3,) or (m, 3)
    ///
    /// Returns
    /// -------
    /// ndarray, shape (4,) or (m, 4)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> quaternion.q_dot_from_omega_space([1, 0, 0, 0], [0, 0, 2])
    /// array([0., 0., 0., 1.])
    ///
    /// ```
    fn q_dot_from_omega_space(q: Q, Quaternions, omega_space: V, Finite) -> Q, |i| Ok(q.quat(i).q_dot_from_omega_space(&omega_space.vector(i)).0)
}

elementwise! {
    /// `w_b = 2 vec(Q~*Q')/|Q|^2` (eq 10 inverted; exact for a non-unit `Q` too).
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    /// q_dot : array_like, shape (4,) or (m, 4)
    ///
    /// Returns
    /// -------
    /// ndarray, shape (3,) or (m, 3)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> q = quaternion.exp([0.3, 0.2, 0.1])
    /// >>> quaternion.omega_body_from_q_dot(q, quaternion.q_dot_from_omega_body(q, [1, 2, 3]))
    /// array([1., 2., 3.])
    ///
    /// ```
    fn omega_body_from_q_dot(q: Q, Quaternions, q_dot: Q, Finite) -> V, |i| Ok(q.quat(i).omega_body_from_q_dot(&q_dot.quat(i)).into())
}

elementwise! {
    /// `w_s = 2 vec(Q'*Q~)/|Q|^2` (eq 10 inverted; exact for a non-unit `Q` too).
    ///
    /// Parameters
    /// ----------
    /// q : array_like, shape (4,) or (m, 4)
    ///     Quaternions, scalar first.
    /// q_dot : array_like, shape (4,) or (m, 4)
    ///
    /// Returns
    /// -------
    /// ndarray, shape (3,) or (m, 3)
    ///
    /// Examples
    /// --------
    /// ```python
    ///
    /// >>> q = quaternion.exp([0.3, 0.2, 0.1])
    /// >>> quaternion.omega_space_from_q_dot(q, quaternion.q_dot_from_omega_space(q, [1, 2, 3]))
    /// array([1., 2., 3.])
    ///
    /// ```
    fn omega_space_from_q_dot(q: Q, Quaternions, q_dot: Q, Finite) -> V, |i| Ok(q.quat(i).omega_space_from_q_dot(&q_dot.quat(i)).into())
}
