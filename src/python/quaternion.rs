//! `quatrot.quaternion`: the conventions module (`crate::quaternion`) over
//! numpy arrays. Quaternions are `(n, 4)` scalar first, vectors `(n, 3)`,
//! matrices `(n, 3, 3)`, angles `(n,)` or `(n, 3)`; a single item (`(4,)`,
//! `(3,)`, `(3, 3)`, `()`) gives a single result. Every function converts
//! and delegates to the library.

use nalgebra::{Rotation3, Unit};
use numpy::PyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use super::arrays::{collect, common_len, row_major, Items, Values};
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

/// Hamilton product `p*q` (eq 2, corrected sign).
#[pyfunction]
fn product<'py>(py: Python<'py>, p: &Bound<'py, PyAny>, q: &Bound<'py, PyAny>) -> Array<'py> {
    let (p, q) = (
        Items::new(p, "p", &Q, Values::Quaternions)?,
        Items::new(q, "q", &Q, Values::Quaternions)?,
    );
    collect(py, common_len(&[&p, &q])?, &Q, |i| {
        Ok((p.quat(i) * q.quat(i)).0)
    })
}

/// Conjugate `(q0, -q)` (eq 3).
#[pyfunction]
fn conjugate<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> Array<'py> {
    let q = Items::new(q, "q", &Q, Values::Quaternions)?;
    collect(py, common_len(&[&q])?, &Q, |i| Ok(q.quat(i).conjugate().0))
}

/// Norm `|Q|` (square root of eq 5).
#[pyfunction]
fn norm<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> Array<'py> {
    let q = Items::new(q, "q", &Q, Values::Quaternions)?;
    collect(py, common_len(&[&q])?, &S, |i| Ok([q.quat(i).norm()]))
}

/// `A(Q)` of eq 7, space to body (`r_b = A r_s`).
#[pyfunction]
fn space_to_body_matrix<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> Array<'py> {
    let q = Items::new(q, "q", &Q, Values::Quaternions)?;
    collect(py, common_len(&[&q])?, &M, |i| {
        Ok(row_major(&q.quat(i).space_to_body_matrix()))
    })
}

/// `R(Q) = A(Q)^T`, body to space (`r_s = R r_b`), the active rotation of `Q`.
#[pyfunction]
fn body_to_space_matrix<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> Array<'py> {
    let q = Items::new(q, "q", &Q, Values::Quaternions)?;
    collect(py, common_len(&[&q])?, &M, |i| {
        Ok(row_major(&q.quat(i).body_to_space_matrix()))
    })
}

/// nalgebra's `Rotation3` of `Q` (via `UnitQuaternion`): an independent `R(Q)`
/// for the cross-code checks.
#[pyfunction]
fn nalgebra_body_to_space_matrix<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> Array<'py> {
    let q = Items::new(q, "q", &Q, Values::Quaternions)?;
    collect(py, common_len(&[&q])?, &M, |i| {
        Ok(row_major(Rotation3::from(q.quat(i)).matrix()))
    })
}

/// Body-fixed components `A(Q) v_space` (eq 6).
#[pyfunction]
fn space_to_body<'py>(
    py: Python<'py>,
    q: &Bound<'py, PyAny>,
    v_space: &Bound<'py, PyAny>,
) -> Array<'py> {
    let (q, v) = (
        Items::new(q, "q", &Q, Values::Quaternions)?,
        Items::new(v_space, "v_space", &V, Values::Finite)?,
    );
    collect(py, common_len(&[&q, &v])?, &V, |i| {
        Ok(q.quat(i).space_to_body(&v.vector(i)).into())
    })
}

/// Space-fixed components `R(Q) v_body`.
#[pyfunction]
fn body_to_space<'py>(
    py: Python<'py>,
    q: &Bound<'py, PyAny>,
    v_body: &Bound<'py, PyAny>,
) -> Array<'py> {
    let (q, v) = (
        Items::new(q, "q", &Q, Values::Quaternions)?,
        Items::new(v_body, "v_body", &V, Values::Finite)?,
    );
    collect(py, common_len(&[&q, &v])?, &V, |i| {
        Ok(q.quat(i).body_to_space(&v.vector(i)).into())
    })
}

/// `Q` of y-convention Euler angles `(phi, theta, psi)` in radians (eq 8).
#[pyfunction]
fn from_euler_y<'py>(py: Python<'py>, angles: &Bound<'py, PyAny>) -> Array<'py> {
    let a = Items::new(angles, "angles", &V, Values::Finite)?;
    collect(py, common_len(&[&a])?, &Q, |i| {
        let [phi, theta, psi] = a.vector(i).into();
        Ok(Quat::from_euler_y(phi, theta, psi).0)
    })
}

/// y-convention `(phi, theta, psi)` of unit `Q`: theta in [0, pi], phi, psi in (-pi, pi].
#[pyfunction]
fn to_euler_y<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> Array<'py> {
    let q = Items::new(q, "q", &Q, Values::Quaternions)?;
    collect(py, common_len(&[&q])?, &V, |i| {
        let (phi, theta, psi) = q.quat(i).to_euler_y();
        Ok([phi, theta, psi])
    })
}

/// `Q` of the rotation by `angle` (radians) about `axis` (normalised here; must be nonzero).
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
        let unit = Unit::try_new(axis.vector(i), 0.0)
            .filter(|u| u.iter().all(|x| x.is_finite()))
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "{}: must be a nonzero finite vector",
                    axis.label(i)
                ))
            })?;
        Ok(Quat::from_axis_angle(&unit, angle.scalar(i)).0)
    })
}

/// `(axis, angle)` of unit `Q`, angle in [0, pi]; the axis is `(0, 0, 0)` for angle 0.
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

/// `Q = exp(v)`: the rotation by `|v|` about `v`.
#[pyfunction]
fn exp<'py>(py: Python<'py>, rotvec: &Bound<'py, PyAny>) -> Array<'py> {
    let v = Items::new(rotvec, "rotvec", &V, Values::Finite)?;
    collect(
        py,
        common_len(&[&v])?,
        &Q,
        |i| Ok(Quat::exp(&v.vector(i)).0),
    )
}

/// `ln Q`: the rotation vector of unit `Q`, `|v|` in [0, pi].
#[pyfunction]
fn ln<'py>(py: Python<'py>, q: &Bound<'py, PyAny>) -> Array<'py> {
    let q = Items::new(q, "q", &Q, Values::Quaternions)?;
    collect(py, common_len(&[&q])?, &V, |i| Ok(q.quat(i).ln().into()))
}

/// `Q' = 1/2 Q*(0, w_b)` (eq 10, body form).
#[pyfunction]
fn q_dot_from_omega_body<'py>(
    py: Python<'py>,
    q: &Bound<'py, PyAny>,
    omega_body: &Bound<'py, PyAny>,
) -> Array<'py> {
    let (q, w) = (
        Items::new(q, "q", &Q, Values::Quaternions)?,
        Items::new(omega_body, "omega_body", &V, Values::Finite)?,
    );
    collect(py, common_len(&[&q, &w])?, &Q, |i| {
        Ok(q.quat(i).q_dot_from_omega_body(&w.vector(i)).0)
    })
}

/// `Q' = 1/2 (0, w_s)*Q` (eq 10, space form).
#[pyfunction]
fn q_dot_from_omega_space<'py>(
    py: Python<'py>,
    q: &Bound<'py, PyAny>,
    omega_space: &Bound<'py, PyAny>,
) -> Array<'py> {
    let (q, w) = (
        Items::new(q, "q", &Q, Values::Quaternions)?,
        Items::new(omega_space, "omega_space", &V, Values::Finite)?,
    );
    collect(py, common_len(&[&q, &w])?, &Q, |i| {
        Ok(q.quat(i).q_dot_from_omega_space(&w.vector(i)).0)
    })
}

/// `w_b = 2 vec(Q~*Q')/|Q|^2` (eq 10 inverted; exact for a non-unit `Q` too).
#[pyfunction]
fn omega_body_from_q_dot<'py>(
    py: Python<'py>,
    q: &Bound<'py, PyAny>,
    q_dot: &Bound<'py, PyAny>,
) -> Array<'py> {
    let (q, d) = (
        Items::new(q, "q", &Q, Values::Quaternions)?,
        Items::new(q_dot, "q_dot", &Q, Values::Finite)?,
    );
    collect(py, common_len(&[&q, &d])?, &V, |i| {
        Ok(q.quat(i).omega_body_from_q_dot(&d.quat(i)).into())
    })
}

/// `w_s = 2 vec(Q'*Q~)/|Q|^2` (eq 10 inverted; exact for a non-unit `Q` too).
#[pyfunction]
fn omega_space_from_q_dot<'py>(
    py: Python<'py>,
    q: &Bound<'py, PyAny>,
    q_dot: &Bound<'py, PyAny>,
) -> Array<'py> {
    let (q, d) = (
        Items::new(q, "q", &Q, Values::Quaternions)?,
        Items::new(q_dot, "q_dot", &Q, Values::Finite)?,
    );
    collect(py, common_len(&[&q, &d])?, &V, |i| {
        Ok(q.quat(i).omega_space_from_q_dot(&d.quat(i)).into())
    })
}

/// Unit `Q` (q0 >= 0) of a body-to-space rotation matrix `R`.
#[pyfunction]
fn from_body_to_space_matrix<'py>(py: Python<'py>, r: &Bound<'py, PyAny>) -> Array<'py> {
    let r = Items::new(r, "r", &M, Values::Finite)?;
    collect(py, common_len(&[&r])?, &Q, |i| {
        Ok(checked_rotation(&r, i, false)?.0)
    })
}

/// Unit `Q` (q0 >= 0) of a space-to-body matrix `A` (eq 7).
#[pyfunction]
fn from_space_to_body_matrix<'py>(py: Python<'py>, a: &Bound<'py, PyAny>) -> Array<'py> {
    let a = Items::new(a, "a", &M, Values::Finite)?;
    collect(py, common_len(&[&a])?, &Q, |i| {
        Ok(checked_rotation(&a, i, true)?.0)
    })
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
        PyValueError::new_err(format!(
            "{}: not a proper rotation matrix (needs |M^T M - I| and |det M - 1| <= {ROTATION_TOLERANCE:e})",
            m.label(i)
        ))
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
