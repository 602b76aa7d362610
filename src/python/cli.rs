//! `quatrot._native.cli_main(argv)`: the `quatrot` command line inside the
//! Python module, for `python -m quatrot` (`quatrot/__main__.py`): the same
//! Rust entry point as the `quatrot` binary, not a reimplementation.

use pyo3::prelude::*;
use std::ffi::OsString;

/// cli_main(argv) -> int
///
/// Runs the command line `argv` (the program name first, as `sys.argv`)
/// and returns its exit code. The GIL is released while it runs.
#[pyfunction]
fn cli_main(py: Python<'_>, argv: Vec<OsString>) -> i32 {
    py.detach(|| crate::cli::main_from(argv))
}

/// Adds `cli_main` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(cli_main, m)?)
}
