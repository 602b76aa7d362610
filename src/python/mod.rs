//! The Python extension module `quatrot._native` (cargo feature `python`),
//! re-exported whole by the pure-Python package `quatrot`
//! (`src/python/quatrot/__init__.py`). Each submodule converts numpy arrays
//! at the boundary and delegates to the library; one place maps errors to
//! Python exceptions.

use pyo3::prelude::*;

mod arrays;
mod baselines;
mod dynamics;
mod potential;
mod quaternion;
mod run;

/// The `quatrot._native` Python module.
#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    baselines::register(m)?;
    potential::register(m)?;
    dynamics::register(m)?;
    quaternion::register(m)?;
    run::register(m)?;
    Ok(())
}
