//! The Python extension module `quatrot` (cargo feature `python`). Each
//! submodule converts numpy arrays at the boundary and delegates to the
//! library; one place maps errors to Python exceptions.

use crate::checks::InputError;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

mod analysis;
mod arrays;
mod baselines;
mod dynamics;
mod gsd;
mod potential;
mod quaternion;
mod run;

/// Input the library refuses (a potential's sites or multipoles, an
/// analysis' arrays) is a `ValueError` naming the argument.
impl From<InputError> for PyErr {
    fn from(e: InputError) -> PyErr {
        PyValueError::new_err(e.to_string())
    }
}

/// The `quatrot` Python module.
#[pymodule]
fn quatrot(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    baselines::register(m)?;
    potential::register(m)?;
    dynamics::register(m)?;
    quaternion::register(m)?;
    run::register(m)?;
    analysis::register(m)?;
    gsd::register(m)?;
    Ok(())
}
