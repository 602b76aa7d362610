//! `quatrot.run_dielectric_constant`: the dielectric constant of a run
//! (`crate::run::dielectric_of_run`), from the dict `quatrot.run` returns or
//! from a run's output directory.

use super::args::{expected, invalid, optional_text, path_or};
use super::fluctuations::dielectric_dict;
use crate::run::{dielectric_of_run, dipole_series, read_run, InteractionsSummary, SeriesTable};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

/// The `interactions` of a run's summary dict and its series, from the dict
/// `quatrot.run` returns.
fn from_result(
    py: Python<'_>,
    result: &Bound<'_, PyDict>,
) -> PyResult<(Option<InteractionsSummary>, Vec<SeriesTable>)> {
    let missing = |key: &str| invalid("run", format!("no \"{key}\" in the dict"));
    let summary = result
        .get_item("summary")?
        .ok_or_else(|| missing("summary"))?;
    let interactions = summary
        .cast::<PyDict>()
        .map_err(|_| expected("run[\"summary\"]", "a dict"))?
        .get_item("interactions")?;
    let text: String = py
        .import("json")?
        .call_method1("dumps", (interactions,))?
        .extract()?;
    let interactions: Option<InteractionsSummary> = serde_json::from_str(&text)
        .map_err(|e| invalid("run[\"summary\"][\"interactions\"]", e.to_string()))?;
    let series = result
        .get_item("series")?
        .ok_or_else(|| missing("series"))?;
    let series = series
        .cast::<PyDict>()
        .map_err(|_| expected("run[\"series\"]", "a dict"))?;
    let mut tables = Vec::new();
    for (name, columns) in series.iter() {
        let name: String = name.extract()?;
        let columns = columns
            .cast::<PyDict>()
            .map_err(|_| expected(&format!("run[\"series\"][\"{name}\"]"), "a dict"))?;
        let mut names = Vec::new();
        let mut data: Vec<Vec<f64>> = Vec::new();
        for (column, values) in columns.iter() {
            names.push(column.extract::<String>()?);
            data.push(values.extract::<Vec<f64>>().map_err(|_| {
                let column = &names[names.len() - 1];
                expected(
                    &format!("run[\"series\"][\"{name}\"][\"{column}\"]"),
                    "numbers",
                )
            })?);
        }
        let rows = data.first().map_or(0, Vec::len);
        if data.iter().any(|d| d.len() != rows) {
            return Err(invalid(
                &format!("run[\"series\"][\"{name}\"]"),
                "columns of different lengths",
            ));
        }
        let values = (0..rows)
            .flat_map(|r| data.iter().map(move |d| d[r]))
            .collect();
        tables.push(SeriesTable {
            name,
            columns: names,
            values,
        });
    }
    Ok((interactions, tables))
}

/// The static dielectric constant of a run, by the formula of its boundary.
///
/// From `summary["interactions"]`: an Ewald sum with conducting surroundings,
/// `eps = 1 + 4 pi F / (3 V T)`, or vacuum surroundings,
/// `(eps - 1)/(eps + 2) = 4 pi F / (9 V T)`, with `F = <|M|^2> - |<M>|^2` and
/// `V` the box; a truncated sum, an open cluster or a run without
/// interactions are refused.
///
/// Parameters
/// ----------
/// run : dict or path
///     The dict `quatrot.run` returns, or a run's output directory (its
///     `summary.json` and CSV files).
/// series : str, optional
///     The series recording `"M"` (default: the only one that does).
/// temperature : float, optional
///     Default: the mean of the `"temperature"` column of that series.
///
/// Returns
/// -------
/// dict
///     As `dielectric_constant` returns (`epsilon`, `error`, ...).
///
/// Raises
/// ------
/// ValueError
///     For a boundary with no formula, or no series with `M`.
///
/// Examples
/// --------
/// ```python
///
/// A 3 x 3 x 3 dipole lattice (Ewald sum, conducting) at T = 1, its total
/// dipole and temperature recorded every step:
///
/// >>> scene = {"version": 1, "name": "eps",
/// ...     "rotors": {"kind": "lattice", "lattice": "simple_cubic", "cells": 3, "spacing": 1.0,
/// ...                "default": {"inertia": 0.1, "dipole": [0, 0, 0.5]}},
/// ...     "interactions": {"terms": ["dipole_dipole"], "boundary": {"kind": "periodic"}},
/// ...     "initial": {"kind": "random", "seed": 1, "temperature": 1.0},
/// ...     "integrator": {"kind": "dlm"}, "run": {"dt": 0.002, "steps": 300},
/// ...     "record": {"series": [{"name": "s", "every": 1, "quantities": ["M", "temperature"]}]}}
/// >>> result = quatrot.run(scene)
/// >>> eps = quatrot.run_dielectric_constant(result)
/// >>> s = result["series"]["s"]
/// >>> by_hand = quatrot.dielectric_constant(np.stack([s["M_x"], s["M_y"], s["M_z"]], 1), 27.0, s["temperature"].mean())
/// >>> bool(np.isclose(eps["epsilon"], by_hand["epsilon"], rtol=1e-12, atol=0))
/// True
///
/// ```
#[pyfunction]
#[pyo3(signature = (run, *, series=None, temperature=None))]
fn run_dielectric_constant<'py>(
    py: Python<'py>,
    run: &Bound<'py, PyAny>,
    series: Option<&Bound<'py, PyAny>>,
    temperature: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let series = optional_text(series, "series")?;
    let (interactions, tables) = if let Ok(result) = run.cast::<PyDict>() {
        from_result(py, result)?
    } else if run.is_instance_of::<PyString>() || run.hasattr("__fspath__")? {
        read_run(&path_or(run, "run", invalid)?)?
    } else {
        return Err(expected(
            "run",
            "the dict quatrot.run returns or a run's output directory",
        ));
    };
    let table = dipole_series(&tables, series.as_deref())?;
    let eps = py.detach(|| dielectric_of_run(interactions.as_ref(), table, temperature))?;
    dielectric_dict(py, "run_dielectric_constant", &eps)
}

/// Adds `run_dielectric_constant` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run_dielectric_constant, m)?)
}
