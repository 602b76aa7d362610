//! The post-processing of `crate::analysis` and the order observables of
//! `crate::observables` from numpy: `orientational_correlations`,
//! `angular_velocity_correlation`, `order_parameters`, `total_dipole`,
//! `dielectric_constant`, `block_average`. Arguments are any array-like
//! (lists, float32, non-contiguous arrays), converted once to float64;
//! shapes are checked here with messages naming the argument; the
//! computation runs without the GIL; results are dicts of numpy arrays and
//! floats.

use crate::analysis::{
    block_average as block_average_of, dielectric_constant as dielectric_of,
    orientational_correlations as correlations_of, vector_autocorrelation, BlockAverage,
    DielectricBoundary, Frames,
};
use crate::observables::order::{nematic_order, polar_order, space_axes, unit_axis};
use crate::observables::polarization;
use crate::quaternion::Quat;
use nalgebra::{Unit, Vector3};
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{AllowTypeChange, IntoPyArray, PyArrayDyn, PyArrayLikeDyn};
use pyo3::exceptions::{PyRuntimeWarning, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::ffi::CString;

/// A numeric argument converted once to float64, with its shape.
pub(crate) struct Numbers {
    name: &'static str,
    pub(crate) shape: Vec<usize>,
    pub(crate) values: Vec<f64>,
}

impl Numbers {
    /// Converts `arg` (argument `name`): any array-like of numbers.
    pub(crate) fn new(arg: &Bound<'_, PyAny>, name: &'static str) -> PyResult<Self> {
        let array = arg
            .extract::<PyArrayLikeDyn<'_, f64, AllowTypeChange>>()
            .map_err(|_| {
                let kind = arg
                    .get_type()
                    .name()
                    .map_or_else(|_| "?".to_string(), |n| n.to_string());
                PyTypeError::new_err(format!("{name}: expected an array of numbers, got {kind}"))
            })?;
        let view = array.as_array();
        Ok(Numbers {
            name,
            shape: view.shape().to_vec(),
            values: view.iter().copied().collect(),
        })
    }

    /// Items of `W` numbers (the last axis), the array having one of the
    /// leading ranks `ranks` (shape `(..., W)`); `expected` spells the shapes
    /// for the message. Returns the items and the leading shape.
    pub(crate) fn items<const W: usize>(
        &self,
        ranks: &[usize],
        expected: &str,
    ) -> PyResult<(Vec<[f64; W]>, Vec<usize>)> {
        let (last, leading) = self.shape.split_last().unwrap_or((&0, &[]));
        if *last != W || !ranks.contains(&leading.len()) {
            return Err(self.wrong_shape(expected));
        }
        let items = self
            .values
            .chunks_exact(W)
            .map(|c| std::array::from_fn(|k| c[k]))
            .collect();
        Ok((items, leading.to_vec()))
    }

    /// The error for a shape other than `expected`, naming the argument and
    /// the shape found as Python prints it.
    fn wrong_shape(&self, expected: &str) -> PyErr {
        let got: Vec<String> = self.shape.iter().map(usize::to_string).collect();
        let got = match got.len() {
            1 => format!("({},)", got[0]),
            _ => format!("({})", got.join(", ")),
        };
        PyValueError::new_err(format!(
            "{}: expected shape {expected}, got {got}",
            self.name
        ))
    }

    /// A one-dimensional array `(n,)`.
    fn series(self) -> PyResult<Vec<f64>> {
        if self.shape.len() == 1 {
            Ok(self.values)
        } else {
            Err(self.wrong_shape("(n,)"))
        }
    }

    /// A single value of `W` numbers.
    fn single<const W: usize>(&self, expected: &str) -> PyResult<[f64; W]> {
        Ok(self.items::<W>(&[0], expected)?.0[0])
    }
}

/// A numpy array of `shape` from `values` (C order).
pub(crate) fn array<'py>(
    py: Python<'py>,
    shape: &[usize],
    values: Vec<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let a = ArrayD::from_shape_vec(IxDyn(shape), values)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// Orientations `(frames, n, 4)`, or `(frames, 4)` for one rotor, as frames.
fn trajectory(orientations: &Numbers) -> PyResult<(Vec<Quat>, usize)> {
    let (q, leading) = orientations.items::<4>(&[1, 2], "(frames, n, 4) or (frames, 4)")?;
    let rotors = leading.get(1).copied().unwrap_or(1);
    Ok((q.into_iter().map(Quat).collect(), rotors))
}

/// Body axes: None for the three principal axes, `(3,)` for one, `(k, 3)`.
fn body_axes(axes: Option<&Bound<'_, PyAny>>) -> PyResult<(Vec<Vector3<f64>>, bool)> {
    let Some(axes) = axes else {
        return Ok((vec![Vector3::x(), Vector3::y(), Vector3::z()], false));
    };
    let (v, leading) = Numbers::new(axes, "axes")?.items::<3>(&[0, 1], "(3,) or (k, 3)")?;
    Ok((
        v.into_iter().map(Vector3::from).collect(),
        leading.is_empty(),
    ))
}

fn lag_times(dt: f64, lags: usize) -> PyResult<Vec<f64>> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(PyValueError::new_err(format!(
            "dt: must be finite and > 0, got {dt}"
        )));
    }
    Ok((0..lags).map(|k| k as f64 * dt).collect())
}

/// orientational_correlations(orientations, dt, axes=None, max_lag=None) -> dict
///
/// The orientational time-correlation functions `C1(t) = <u(0).u(t)>` and
/// `C2(t) = <P2(u(0).u(t))>`, `P2(x) = (3x^2 - 1)/2`, of body axes `u`
/// averaged over all time origins and rotors (by FFT). `orientations`:
/// `(frames, n, 4)` scalar first (normalised here), frames `dt` apart (the
/// `trajectory["orientations"]` of `quatrot.run`); `axes`: body-frame axes,
/// `(3,)` for one or `(k, 3)` (normalised here; default: the three principal
/// axes); `max_lag`: the largest lag in frames (default: every lag, the
/// last ones averaging few origins). Returns `{"time": (L,), "c1": (k, L),
/// "c2": (k, L)}` (`(L,)` for a single axis).
#[pyfunction]
#[pyo3(signature = (orientations, dt, axes=None, max_lag=None))]
fn orientational_correlations<'py>(
    py: Python<'py>,
    orientations: &Bound<'py, PyAny>,
    dt: f64,
    axes: Option<&Bound<'py, PyAny>>,
    max_lag: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (q, rotors) = trajectory(&Numbers::new(orientations, "orientations")?)?;
    let (axes, single) = body_axes(axes)?;
    let result = py.detach(|| {
        let frames = Frames::new(&q, rotors, "orientations")?;
        correlations_of(&frames, &axes, max_lag)
    })?;
    let lags = result[0].c1.len();
    let out = PyDict::new(py);
    out.set_item("time", array(py, &[lags], lag_times(dt, lags)?)?)?;
    let shape: Vec<usize> = if single {
        vec![lags]
    } else {
        vec![axes.len(), lags]
    };
    let c1 = result.iter().flat_map(|c| c.c1.iter().copied()).collect();
    let c2 = result.iter().flat_map(|c| c.c2.iter().copied()).collect();
    out.set_item("c1", array(py, &shape, c1)?)?;
    out.set_item("c2", array(py, &shape, c2)?)?;
    Ok(out)
}

/// angular_velocity_correlation(omega, dt, max_lag=None) -> dict
///
/// `<w(0).w(t)>` averaged over all time origins and rotors (by FFT), not
/// normalised (lag 0 is `<|w|^2>`), in the frame the vectors are given in
/// (`trajectory["omega_body"]` of `quatrot.run` is body-frame). `omega`:
/// `(frames, n, 3)` or `(frames, 3)`, frames `dt` apart. Returns
/// `{"time": (L,), "c": (L,)}`.
#[pyfunction]
#[pyo3(signature = (omega, dt, max_lag=None))]
fn angular_velocity_correlation<'py>(
    py: Python<'py>,
    omega: &Bound<'py, PyAny>,
    dt: f64,
    max_lag: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let (w, leading) =
        Numbers::new(omega, "omega")?.items::<3>(&[1, 2], "(frames, n, 3) or (frames, 3)")?;
    let rotors = leading.get(1).copied().unwrap_or(1);
    let w: Vec<Vector3<f64>> = w.into_iter().map(Vector3::from).collect();
    let c = py.detach(|| vector_autocorrelation(&Frames::new(&w, rotors, "omega")?, max_lag))?;
    let out = PyDict::new(py);
    out.set_item("time", array(py, &[c.len()], lag_times(dt, c.len())?)?)?;
    out.set_item("c", array(py, &[c.len()], c)?)?;
    Ok(out)
}

fn unit(v: [f64; 3], name: &str) -> PyResult<Unit<Vector3<f64>>> {
    unit_axis(&Vector3::from(v)).ok_or_else(|| {
        PyValueError::new_err(format!(
            "{name}: must be finite and nonzero, got [{}, {}, {}]",
            v[0], v[1], v[2]
        ))
    })
}

/// order_parameters(orientations, axis=(0, 0, 1), direction=None) -> dict
///
/// The orientational order of the body axis `axis` (body frame, normalised)
/// over the rotors: `p2`, the largest eigenvalue of the order tensor
/// `Q = <3/2 u u^T - 1/2 I>` (`q_tensor`), its eigenvector `director`
/// (signed so that `p1 = <u>.director >= 0`), `p1` the polar order along
/// it, `cos_director` each rotor's `u.director`, and with `direction` (a
/// space vector, normalised) `p1_direction = <u>.direction`.
/// `orientations`: `(n, 4)` for one configuration (floats and `(3,)`,
/// `(3, 3)`, `(n,)` arrays), or `(frames, n, 4)` (each result gains a
/// leading frames axis).
#[pyfunction]
#[pyo3(signature = (orientations, axis=None, direction=None))]
fn order_parameters<'py>(
    py: Python<'py>,
    orientations: &Bound<'py, PyAny>,
    axis: Option<&Bound<'py, PyAny>>,
    direction: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (q, leading) = Numbers::new(orientations, "orientations")?
        .items::<4>(&[1, 2], "(n, 4) or (frames, n, 4)")?;
    let axis = match axis {
        Some(a) => unit(Numbers::new(a, "axis")?.single::<3>("(3,)")?, "axis")?,
        None => Vector3::z_axis(),
    };
    let direction = direction
        .map(|d| {
            unit(
                Numbers::new(d, "direction")?.single::<3>("(3,)")?,
                "direction",
            )
        })
        .transpose()?;
    let q: Vec<Quat> = q.into_iter().map(Quat).collect();
    let rotors = *leading.last().unwrap_or(&0);
    if rotors == 0 {
        return Err(PyValueError::new_err(
            "orientations: needs at least one rotor",
        ));
    }
    let frames = Frames::new(&q, rotors, "orientations")?;
    let (mut p2, mut p1, mut p1_direction) = (Vec::new(), Vec::new(), Vec::new());
    let (mut director, mut tensor, mut cosines) = (Vec::new(), Vec::new(), Vec::new());
    for f in 0..frames.frames() {
        let u: Vec<Vector3<f64>> = space_axes(frames.frame(f), &axis).collect();
        let order = nematic_order(&u).ok_or_else(|| PyValueError::new_err("no rotors"))?;
        p2.push(order.p2);
        p1.push(order.p1);
        director.extend(order.director.iter().copied());
        tensor.extend(order.q_tensor.transpose().iter().copied());
        cosines.extend(u.iter().map(|u| u.dot(&order.director)));
        if let Some(n) = &direction {
            p1_direction.extend(polar_order(&u, n));
        }
    }
    let batch: Vec<usize> = leading[..leading.len() - 1].to_vec();
    let shaped = |tail: &[usize]| -> Vec<usize> { batch.iter().chain(tail).copied().collect() };
    let out = PyDict::new(py);
    let scalar_or_array = |values: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        if batch.is_empty() {
            Ok(values[0].into_pyobject(py)?.into_any())
        } else {
            Ok(array(py, &batch, values)?.into_any())
        }
    };
    out.set_item("p2", scalar_or_array(p2)?)?;
    out.set_item("p1", scalar_or_array(p1)?)?;
    out.set_item("director", array(py, &shaped(&[3]), director)?)?;
    out.set_item("q_tensor", array(py, &shaped(&[3, 3]), tensor)?)?;
    out.set_item("cos_director", array(py, &shaped(&[rotors]), cosines)?)?;
    if direction.is_some() {
        out.set_item("p1_direction", scalar_or_array(p1_direction)?)?;
    }
    Ok(out)
}

/// total_dipole(orientations, dipoles_body) -> ndarray
///
/// `M = sum_i R(Q_i) mu_i`, space frame, of body dipoles `dipoles_body`
/// (`(3,)` shared by all rotors, or `(n, 3)`) at `orientations` (`(n, 4)`,
/// normalised here) -> `(3,)`; or `(frames, n, 4)` -> `(frames, 3)`.
/// `|M|^2` is `(M**2).sum(-1)`.
#[pyfunction]
fn total_dipole<'py>(
    py: Python<'py>,
    orientations: &Bound<'py, PyAny>,
    dipoles_body: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (q, leading) = Numbers::new(orientations, "orientations")?
        .items::<4>(&[1, 2], "(n, 4) or (frames, n, 4)")?;
    let rotors = *leading.last().unwrap_or(&0);
    let (mu, mu_leading) =
        Numbers::new(dipoles_body, "dipoles_body")?.items::<3>(&[0, 1], "(3,) or (n, 3)")?;
    let mu: Vec<Vector3<f64>> = match mu_leading.first() {
        None => vec![Vector3::from(mu[0]); rotors],
        Some(&n) if n == rotors => mu.into_iter().map(Vector3::from).collect(),
        Some(&n) => {
            return Err(PyValueError::new_err(format!(
                "dipoles_body: {n} dipoles for {rotors} rotors"
            )))
        }
    };
    let q: Vec<Quat> = q.into_iter().map(Quat).collect();
    let frames = Frames::new(&q, rotors.max(1), "orientations")?;
    let m: Vec<f64> = (0..frames.frames())
        .flat_map(|f| {
            let m = polarization::total_dipole(frames.frame(f), &mu);
            [m.x, m.y, m.z]
        })
        .collect();
    let shape: Vec<usize> = leading[..leading.len() - 1]
        .iter()
        .chain(&[3])
        .copied()
        .collect();
    array(py, &shape, m)
}

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

/// block_average(series) -> dict
///
/// The mean of a correlated series `(n,)` (n >= 2) and its standard error by
/// blocking (Flyvbjerg & Petersen 1989), the level chosen by Jonsson's test
/// (2018) at significance 1 %: `{"mean", "error", "error_of_error",
/// "block_length", "converged", "levels": {"block_length", "blocks",
/// "error", "error_of_error"}}` (every level, for a plot). Warns
/// (`RuntimeWarning`) when no level passes (`converged` False).
#[pyfunction]
fn block_average<'py>(py: Python<'py>, series: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    let x = Numbers::new(series, "series")?.series()?;
    let b = py.detach(|| block_average_of(&x))?;
    warn_unconverged(py, "block_average", &b)?;
    block_dict(py, &b)
}

/// dielectric_constant(dipoles, volume, temperature, boundary="conducting") -> dict
///
/// The static dielectric constant from the fluctuation
/// `F = <|M|^2> - |<M>|^2` of the total dipole series `dipoles` `(frames, 3)`
/// of a box of `volume` at `temperature` (reduced units, 4 pi eps0 = 1,
/// k_B = 1), by the formula of `boundary`: `"conducting"` (Ewald, tin
/// foil): `eps = 1 + 4 pi F / (3 V T)`; `"vacuum"` (Ewald with vacuum
/// surroundings, or a spherical cluster in vacuum): `(eps - 1)/(eps + 2) =
/// 4 pi F / (9 V T)`; `"open"` and `"cutoff"` are refused (no formula
/// applies). Returns `{"epsilon", "error", "mean_squared_dipole",
/// "mean_dipole", "fluctuation" (the block_average dict of F)}`; the error
/// is F's blocking error propagated. Warns when the blocking does not
/// converge.
#[pyfunction]
#[pyo3(signature = (dipoles, volume, temperature, boundary="conducting"))]
fn dielectric_constant<'py>(
    py: Python<'py>,
    dipoles: &Bound<'py, PyAny>,
    volume: f64,
    temperature: f64,
    boundary: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let (m, _) = Numbers::new(dipoles, "dipoles")?.items::<3>(&[1], "(frames, 3)")?;
    let m: Vec<Vector3<f64>> = m.into_iter().map(Vector3::from).collect();
    let boundary: DielectricBoundary = boundary.parse()?;
    let eps = py.detach(|| dielectric_of(&m, volume, temperature, boundary))?;
    warn_unconverged(py, "dielectric_constant", &eps.fluctuation)?;
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

/// Adds the analysis functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(orientational_correlations, m)?)?;
    m.add_function(wrap_pyfunction!(angular_velocity_correlation, m)?)?;
    m.add_function(wrap_pyfunction!(order_parameters, m)?)?;
    m.add_function(wrap_pyfunction!(total_dipole, m)?)?;
    m.add_function(wrap_pyfunction!(block_average, m)?)?;
    m.add_function(wrap_pyfunction!(dielectric_constant, m)?)
}
