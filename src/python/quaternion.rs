//! `quatrot.quaternion`: the conventions module (`crate::quaternion`) over
//! numpy arrays. Quaternions are `(n, 4)` scalar first, vectors `(n, 3)`,
//! matrices `(n, 3, 3)`, angles `(n,)` or `(n, 3)`; a single item (`(4,)`,
//! `(3,)`, `(3, 3)`, `()`) gives a single result. Every function converts
//! and delegates to the library.

use nalgebra::Rotation3;
use numpy::PyArrayDyn;
use pyo3::prelude::*;

use super::args::invalid;
use super::arrays::{collect, common_len, row_major, Items, Values};
use crate::observables::order::checked_unit_axis;
use crate::Quat;

/// Largest `|R^T R - I|` and `|det R - 1|` accepted by the matrix conversions:
/// a rotation written with about 12 significant digits.
const ROTATION_TOLERANCE: f64 = 1e-9;

type Array<'py> = PyResult<Bound<'py, PyArrayDyn<f64>>>;
type ArrayPair<'py> = PyResult<(Bound<'py, PyArrayDyn<f64>>, Bound<'py, PyArrayDyn<f64>>)>;

const Q: [usize; 1] = [4];
const V: [usize; 1] = [3];
const M: [usize; 2] = [3, 3];
const S: [usize; 0] = [];

/// A function of `quatrot.quaternion` applied item by item: each argument
/// converted once (its Python name, item shape and value check), the items
/// paired (a single item broadcast), and `body` giving item `i`'s result
/// (of shape `out`).
macro_rules! elementwise {
    ($(#[$doc:meta])* fn $name:ident($($arg:ident: $shape:ident, $values:ident),+) -> $out:ident, |$i:ident| $body:expr) => {
        $(#[$doc])*
        #[pyfunction]
        fn $name<'py>(py: Python<'py>, $($arg: &Bound<'py, PyAny>),+) -> Array<'py> {
            $(let $arg = Items::new($arg, stringify!($arg), &$shape, Values::$values)?;)+
            collect(py, common_len(&[$(&$arg),+])?, &$out, |$i| $body)
        }
    };
}

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
fn from_axis_angle<'py>(
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
fn to_axis_angle<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> ArrayPair<'py> {
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

/// Adds the submodule `quatrot._native.quaternion` (importable as such;
/// `quatrot.quaternion` re-exports it).
pub(crate) fn register(parent: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = parent.py();
    let m = PyModule::new(py, "quaternion")?;
    m.add_function(wrap_pyfunction!(product, &m)?)?;
    m.add_function(wrap_pyfunction!(conjugate, &m)?)?;
    m.add_function(wrap_pyfunction!(norm, &m)?)?;
    m.add_function(wrap_pyfunction!(space_to_body_matrix, &m)?)?;
    m.add_function(wrap_pyfunction!(body_to_space_matrix, &m)?)?;
    m.add_function(wrap_pyfunction!(nalgebra_body_to_space_matrix, &m)?)?;
    m.add_function(wrap_pyfunction!(space_to_body, &m)?)?;
    m.add_function(wrap_pyfunction!(body_to_space, &m)?)?;
    m.add_function(wrap_pyfunction!(from_euler_y, &m)?)?;
    m.add_function(wrap_pyfunction!(to_euler_y, &m)?)?;
    m.add_function(wrap_pyfunction!(from_axis_angle, &m)?)?;
    m.add_function(wrap_pyfunction!(to_axis_angle, &m)?)?;
    m.add_function(wrap_pyfunction!(exp, &m)?)?;
    m.add_function(wrap_pyfunction!(ln, &m)?)?;
    m.add_function(wrap_pyfunction!(q_dot_from_omega_body, &m)?)?;
    m.add_function(wrap_pyfunction!(q_dot_from_omega_space, &m)?)?;
    m.add_function(wrap_pyfunction!(omega_body_from_q_dot, &m)?)?;
    m.add_function(wrap_pyfunction!(omega_space_from_q_dot, &m)?)?;
    m.add_function(wrap_pyfunction!(from_body_to_space_matrix, &m)?)?;
    m.add_function(wrap_pyfunction!(from_space_to_body_matrix, &m)?)?;
    parent.add_submodule(&m)?;
    py.import("sys")?
        .getattr("modules")?
        .set_item("quatrot._native.quaternion", &m)?;
    Ok(())
}
