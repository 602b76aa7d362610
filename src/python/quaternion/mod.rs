//! `quatrot.quaternion`: the conventions module (`crate::quaternion`) over
//! numpy arrays. Quaternions are `(n, 4)` scalar first, vectors `(n, 3)`,
//! matrices `(n, 3, 3)`, angles `(n,)` or `(n, 3)`; a single item (`(4,)`,
//! `(3,)`, `(3, 3)`, `()`) gives a single result. Every function converts
//! and delegates to the library.

//!
//! * `rotations`: products, matrices, rotating vectors, Euler angles, and
//!   quaternions from rotation matrices;
//! * `kinematics`: axis and angle, the exponential and logarithm, and the
//!   relations of `Q'` to the angular velocity (eqs 10, 11).

use numpy::PyArrayDyn;
use pyo3::prelude::*;

pub(super) type Array<'py> = PyResult<Bound<'py, PyArrayDyn<f64>>>;
pub(super) type ArrayPair<'py> =
    PyResult<(Bound<'py, PyArrayDyn<f64>>, Bound<'py, PyArrayDyn<f64>>)>;

pub(super) const Q: [usize; 1] = [4];
pub(super) const V: [usize; 1] = [3];
pub(super) const M: [usize; 2] = [3, 3];
pub(super) const S: [usize; 0] = [];

/// A function of `quatrot.quaternion` applied item by item: each argument
/// converted once (its Python name, item shape and value check), the items
/// paired (a single item broadcast), and `body` giving item `i`'s result
/// (of shape `out`).
macro_rules! elementwise {
    ($(#[$doc:meta])* fn $name:ident($($arg:ident: $shape:ident, $values:ident),+) -> $out:ident, |$i:ident| $body:expr) => {
        $(#[$doc])*
        #[pyfunction]
        pub(super) fn $name<'py>(py: Python<'py>, $($arg: &Bound<'py, PyAny>),+) -> Array<'py> {
            $(let $arg = Items::new($arg, stringify!($arg), &$shape, Values::$values)?;)+
            collect(py, common_len(&[$(&$arg),+])?, &$out, |$i| $body)
        }
    };
}

mod kinematics;
mod rotations;

/// Adds the submodule `quatrot._native.quaternion` (importable as such;
/// `quatrot.quaternion` re-exports it).
pub(crate) fn register(parent: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = parent.py();
    let m = PyModule::new(py, "quaternion")?;
    m.add_function(wrap_pyfunction!(rotations::product, &m)?)?;
    m.add_function(wrap_pyfunction!(rotations::conjugate, &m)?)?;
    m.add_function(wrap_pyfunction!(rotations::norm, &m)?)?;
    m.add_function(wrap_pyfunction!(rotations::space_to_body_matrix, &m)?)?;
    m.add_function(wrap_pyfunction!(rotations::body_to_space_matrix, &m)?)?;
    m.add_function(wrap_pyfunction!(
        rotations::nalgebra_body_to_space_matrix,
        &m
    )?)?;
    m.add_function(wrap_pyfunction!(rotations::space_to_body, &m)?)?;
    m.add_function(wrap_pyfunction!(rotations::body_to_space, &m)?)?;
    m.add_function(wrap_pyfunction!(rotations::from_euler_y, &m)?)?;
    m.add_function(wrap_pyfunction!(rotations::to_euler_y, &m)?)?;
    m.add_function(wrap_pyfunction!(kinematics::from_axis_angle, &m)?)?;
    m.add_function(wrap_pyfunction!(kinematics::to_axis_angle, &m)?)?;
    m.add_function(wrap_pyfunction!(kinematics::exp, &m)?)?;
    m.add_function(wrap_pyfunction!(kinematics::ln, &m)?)?;
    m.add_function(wrap_pyfunction!(kinematics::q_dot_from_omega_body, &m)?)?;
    m.add_function(wrap_pyfunction!(kinematics::q_dot_from_omega_space, &m)?)?;
    m.add_function(wrap_pyfunction!(kinematics::omega_body_from_q_dot, &m)?)?;
    m.add_function(wrap_pyfunction!(kinematics::omega_space_from_q_dot, &m)?)?;
    m.add_function(wrap_pyfunction!(rotations::from_body_to_space_matrix, &m)?)?;
    m.add_function(wrap_pyfunction!(rotations::from_space_to_body_matrix, &m)?)?;
    parent.add_submodule(&m)?;
    py.import("sys")?
        .getattr("modules")?
        .set_item("quatrot._native.quaternion", &m)?;
    Ok(())
}
