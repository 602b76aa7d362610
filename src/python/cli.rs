//! `quatrot._native.cli_main(argv)`: the `quatrot` command line inside the
//! Python module, for `python -m quatrot` (`quatrot/__main__.py`): the same
//! Rust entry point as the `quatrot` binary, not a reimplementation.

use pyo3::prelude::*;
use std::ffi::OsString;

/// Runs the command line `argv` and returns its exit code.
///
/// The entry point of `python -m quatrot` and of the `quatrot` script; the
/// GIL is released while it runs. Exit codes: 0 completed, 2 error, 3 blew
/// up, 130 interrupted.
///
/// Parameters
/// ----------
/// argv : list of str
///     The program name first, as `sys.argv`.
///
/// Returns
/// -------
/// int
///
/// Examples
/// --------
/// ```python
///
/// >>> quatrot.cli_main(["quatrot", "check", "dipole_in_field"])
/// 0
///
/// ```
#[pyfunction]
fn cli_main(py: Python<'_>, argv: Vec<OsString>) -> i32 {
    py.detach(|| crate::cli::main_from(argv))
}

/// Adds `cli_main` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(cli_main, m)?)
}
