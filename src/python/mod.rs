//! The Python extension module `quatrot._native` (cargo feature `python`),
//! re-exported whole by the pure-Python package `quatrot`
//! (`src/python/quatrot/__init__.py`). Each function is a thin wrapper: it
//! converts its arguments once ([`arrays`] for array-likes, [`args`] for
//! text, paths and integers), builds rotors in one place ([`rotors`]) and
//! delegates to a plain function of the library. A fact the library
//! checks is checked there only: its error reaches Python through one
//! `From<...> for PyErr` per error type (here, and for a run's errors in
//! [`run`]); the few errors of the boundary itself (a wrong type, a shape,
//! a keyword combination only Python has) are built by [`args`]' helpers.

use crate::checks::InputError;
use crate::integrators::IntegratorError;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

mod analysis;
mod args;
mod arrays;
mod baselines;
mod bodies;
mod body_analysis;
mod cli;
mod dynamics;
mod fluctuations;
mod gsd;
mod potential;
mod quaternion;
mod rotors;
mod run;
mod run_analysis;
mod scene_dict;

/// Input the library refuses (a potential's sites or multipoles, an
/// analysis' arrays) is a `ValueError` naming the argument.
impl From<InputError> for PyErr {
    fn from(e: InputError) -> PyErr {
        PyValueError::new_err(e.to_string())
    }
}

/// An integrator that cannot run these rotors (a zero moment, a state it
/// cannot start from) is a `ValueError` with the integrator's message.
impl From<IntegratorError> for PyErr {
    fn from(e: IntegratorError) -> PyErr {
        PyValueError::new_err(e.to_string())
    }
}

/// _panic_for_tests(message)
///
/// Panics with `message`: the planted internal error of the test that every
/// panic reaches Python as `quatrot.InternalError` (the package guards every
/// native function). Not part of the API.
#[pyfunction]
fn _panic_for_tests(message: &str) {
    panic!("{message}");
}

/// The `quatrot._native` Python module.
#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(_panic_for_tests, m)?)?;
    baselines::register(m)?;
    bodies::register(m)?;
    potential::register(m)?;
    dynamics::register(m)?;
    quaternion::register(m)?;
    run::register(m)?;
    analysis::register(m)?;
    body_analysis::register(m)?;
    fluctuations::register(m)?;
    gsd::register(m)?;
    cli::register(m)?;
    run_analysis::register(m)?;
    Ok(())
}
