//! The statistics of recorded series from numpy: `block_average` (the mean
//! of a correlated series and its error) and `dielectric_constant` (from
//! the fluctuation of the total dipole), with a `RuntimeWarning` when the
//! blocking finds no plateau.

use super::args::text;
use super::arrays::{array, Numbers, Values};
use crate::analysis::{
    block_average as block_average_of, dielectric_constant as dielectric_of, BlockAverage,
    DielectricBoundary, DielectricConstant,
};
use crate::checks::from_name;
use nalgebra::Vector3;
use pyo3::exceptions::{PyRuntimeWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::ffi::CString;

/// A `RuntimeWarning` when the blocking found no plateau.
fn warn_unconverged(py: Python<'_>, what: &str, b: &BlockAverage) -> PyResult<()> {
    if b.converged {
        return Ok(());
    }
    let message = CString::new(format!(
        "{what}: no blocking level passed the test for uncorrelated blocks; the series is \
         too short for its correlation time and the error (at blocks of {}) is a lower bound",
        b.block_length
    ))
    .map_err(|e| PyValueError::new_err(e.to_string()))?;
    PyErr::warn(py, &py.get_type::<PyRuntimeWarning>(), &message, 1)
}

fn block_dict<'py>(py: Python<'py>, b: &BlockAverage) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("mean", b.mean)?;
    out.set_item("error", b.error)?;
    out.set_item("error_of_error", b.error_of_error)?;
    out.set_item("block_length", b.block_length)?;
    out.set_item("converged", b.converged)?;
    let levels = PyDict::new(py);
    let column = |f: fn(&crate::analysis::BlockLevel) -> f64| -> Vec<f64> {
        b.levels.iter().map(f).collect()
    };
    let n = b.levels.len();
    levels.set_item(
        "block_length",
        array(py, &[n], column(|l| l.block_length as f64))?,
    )?;
    levels.set_item("blocks", array(py, &[n], column(|l| l.blocks as f64))?)?;
    levels.set_item("error", array(py, &[n], column(|l| l.error))?)?;
    levels.set_item(
        "error_of_error",
        array(py, &[n], column(|l| l.error_of_error))?,
    )?;
    out.set_item("levels", levels)?;
    Ok(out)
}

/// The mean of a correlated series and its standard error by blocking.
///
/// Flyvbjerg and Petersen's blocking (1989), the level chosen by Jonsson's
/// test (2018) at significance 1 %.
///
/// Parameters
/// ----------
/// series : array_like, shape (n,)
///     At least 2 values.
///
/// Returns
/// -------
/// dict
///     `mean`, `error`, `error_of_error`, `block_length`, `converged`, and
///     `levels` (`block_length`, `blocks`, `error`, `error_of_error` of every
///     level, for a plot).
///
/// Warns
/// -----
/// RuntimeWarning
///     When no level passes the test (`converged` False).
///
/// Examples
/// --------
/// ```python
///
/// >>> rng = np.random.default_rng(1)
/// >>> b = quatrot.block_average(rng.normal(size=4096))
/// >>> abs(b["mean"]) < 4 * b["error"], 0.01 < b["error"] < 0.02
/// (True, True)
///
/// ```
#[pyfunction]
fn block_average<'py>(py: Python<'py>, series: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    let x = Numbers::new(series, "series", Values::Finite)?.series()?;
    let b = py.detach(|| block_average_of(&x))?;
    warn_unconverged(py, "block_average", &b)?;
    block_dict(py, &b)
}

/// The static dielectric constant from the fluctuation of the total dipole.
///
/// `F = <|M|^2> - |<M>|^2` of a box of volume `V` at temperature `T`
/// (reduced units, 4 pi eps0 = 1, k_B = 1), by the formula of `boundary`:
/// `"conducting"` (Ewald, tin foil): `eps = 1 + 4 pi F / (3 V T)`;
/// `"vacuum"` (Ewald with vacuum surroundings, or a spherical cluster in
/// vacuum): `(eps - 1)/(eps + 2) = 4 pi F / (9 V T)`.
///
/// Parameters
/// ----------
/// dipoles : array_like, shape (frames, 3)
///     The total dipole series `M`.
/// volume : float
///     The box volume.
/// temperature : float
/// boundary : {"conducting", "vacuum"}, default "conducting"
///     `"open"` and `"cutoff"` are refused: no formula applies.
///
/// Returns
/// -------
/// dict
///     `epsilon`, `error` (F's blocking error propagated),
///     `mean_squared_dipole`, `mean_dipole`, `fluctuation` (the
///     `block_average` dict of F).
///
/// Raises
/// ------
/// ValueError
///     For a boundary with no formula.
///
/// Warns
/// -----
/// RuntimeWarning
///     When the blocking does not converge.
///
/// Examples
/// --------
/// ```python
///
/// >>> rng = np.random.default_rng(2)
/// >>> eps = quatrot.dielectric_constant(rng.normal(size=(4096, 3)), 100.0, 1.0)
/// >>> round(eps["epsilon"], 1)  # 1 + 4 pi 3 / 300
/// 1.1
///
/// ```
#[pyfunction]
#[pyo3(signature = (dipoles, volume, temperature, boundary=None))]
fn dielectric_constant<'py>(
    py: Python<'py>,
    dipoles: &Bound<'py, PyAny>,
    volume: f64,
    temperature: f64,
    boundary: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (m, _) =
        Numbers::new(dipoles, "dipoles", Values::Finite)?.items::<3>(&[1], "(frames, 3)")?;
    let m: Vec<Vector3<f64>> = m.into_iter().map(Vector3::from).collect();
    let boundary: DielectricBoundary = match boundary {
        Some(b) => from_name("boundary", &text(b, "boundary")?)?,
        None => DielectricBoundary::Conducting,
    };
    let eps = py.detach(|| dielectric_of(&m, volume, temperature, boundary))?;
    dielectric_dict(py, "dielectric_constant", &eps)
}

/// The dict of a dielectric constant (see `dielectric_constant`), warning
/// in the name of `function` when the blocking does not converge.
pub(crate) fn dielectric_dict<'py>(
    py: Python<'py>,
    function: &str,
    eps: &DielectricConstant,
) -> PyResult<Bound<'py, PyDict>> {
    warn_unconverged(py, function, &eps.fluctuation)?;
    let out = PyDict::new(py);
    out.set_item("epsilon", eps.epsilon)?;
    out.set_item("error", eps.error)?;
    out.set_item("mean_squared_dipole", eps.mean_squared_dipole)?;
    out.set_item(
        "mean_dipole",
        array(py, &[3], eps.mean_dipole.iter().copied().collect())?,
    )?;
    out.set_item("fluctuation", block_dict(py, &eps.fluctuation)?)?;
    Ok(out)
}

/// Adds the statistics functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(block_average, m)?)?;
    m.add_function(wrap_pyfunction!(dielectric_constant, m)?)
}
