//! The post-processing of `crate::analysis` and the order observables of
//! `crate::observables` from numpy: `orientational_correlations`,
//! `angular_velocity_correlation`, `order_parameters`, `total_dipole`
//! (`block_average` and `dielectric_constant`: `super::fluctuations`). Arguments are any array-like
//! (lists, float32, non-contiguous arrays), converted once to float64;
//! shapes are checked here with messages naming the argument; the
//! computation runs without the GIL; results are dicts of numpy arrays and
//! floats.

use super::args::{invalid, optional_integer};
use super::arrays::{array, Numbers, Values};
use crate::analysis::{
    lag_times, order_parameters as order_of, orientational_correlations as correlations_of,
    vector_autocorrelation, FrameOrder, Frames,
};
use crate::checks::InputError;
use crate::observables::order::checked_unit_axis;
use crate::observables::polarization;
use crate::quaternion::Quat;
use nalgebra::{Unit, Vector3};
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;

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
    let (v, leading) =
        Numbers::new(axes, "axes", Values::Finite)?.items::<3>(&[0, 1], "(3,) or (k, 3)")?;
    if v.is_empty() {
        return Err(invalid("axes", "needs at least one axis, got shape (0, 3)"));
    }
    Ok((
        v.into_iter().map(Vector3::from).collect(),
        leading.is_empty(),
    ))
}

/// The optional `max_lag` argument (frames).
pub(super) fn lag(max_lag: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    Ok(optional_integer(max_lag, "max_lag", 0, u64::MAX)?
        .map(|m| usize::try_from(m).unwrap_or(usize::MAX)))
}

/// Orientational time-correlation functions C1 and C2 of body axes.
///
/// `C1(t) = <u(0).u(t)>` and `C2(t) = <P2(u(0).u(t))>`, `P2(x) = (3x^2 - 1)/2`,
/// averaged over all time origins and rotors (by FFT).
///
/// Parameters
/// ----------
/// orientations : array_like, shape (frames, n, 4)
///     Scalar first (normalised here), frames `dt` apart (the
///     `trajectory["orientations"]` of `quatrot.run`).
/// dt : float
///     Time between frames.
/// axes : array_like, shape (3,) or (k, 3), optional
///     Body-frame axes (normalised here); default the three principal axes.
/// max_lag : int, optional
///     The largest lag in frames (default: every lag, the last ones
///     averaging few origins).
///
/// Returns
/// -------
/// dict
///     `{"time": (L,), "c1": (k, L), "c2": (k, L)}`, `(L,)` for a single axis.
///
/// Examples
/// --------
/// ```python
///
/// A rotor spinning about z at 1 rad per unit time: its x axis has
/// `C1(t) = cos t`.
///
/// >>> t = np.arange(4) * 0.5
/// >>> q = quaternion.exp(np.outer(t, [0, 0, 1]))[:, None, :]
/// >>> c = quatrot.orientational_correlations(q, 0.5, axes=[1, 0, 0])
/// >>> np.allclose(c["c1"], np.cos(c["time"]))
/// True
///
/// ```
#[pyfunction]
#[pyo3(signature = (orientations, dt, axes=None, max_lag=None))]
fn orientational_correlations<'py>(
    py: Python<'py>,
    orientations: &Bound<'py, PyAny>,
    dt: f64,
    axes: Option<&Bound<'py, PyAny>>,
    max_lag: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let max_lag = lag(max_lag)?;
    let (q, rotors) = trajectory(&Numbers::new(
        orientations,
        "orientations",
        Values::Quaternions,
    )?)?;
    let (axes, single) = body_axes(axes)?;
    let result = py
        .detach(|| {
            let frames = Frames::new(&q, rotors, "orientations")?;
            correlations_of(&frames, &axes, max_lag)
        })
        .map_err(|e| match e.path.strip_prefix("axes_body") {
            // The library's `axes_body` is this function's `axes`.
            Some(rest) => InputError {
                // One axis given as (3,): no index.
                path: format!(
                    "axes{}",
                    if single && rest.starts_with('[') {
                        ""
                    } else {
                        rest
                    }
                ),
                ..e
            },
            None => e,
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

/// The angular-velocity autocorrelation `<w(0).w(t)>`.
///
/// Averaged over all time origins and rotors (by FFT), not normalised (lag 0
/// is `<|w|^2>`), in the frame the vectors are given in.
///
/// Parameters
/// ----------
/// omega : array_like, shape (frames, n, 3) or (frames, 3)
///     Angular velocities, frames `dt` apart (`trajectory["omega_body"]` of
///     `quatrot.run` is body-frame).
/// dt : float
///     Time between frames.
/// max_lag : int, optional
///     The largest lag in frames (default: every lag).
///
/// Returns
/// -------
/// dict
///     `{"time": (L,), "c": (L,)}`.
///
/// Examples
/// --------
/// ```python
///
/// >>> c = quatrot.angular_velocity_correlation(np.tile([0.0, 0.0, 2.0], (5, 1)), 0.1)
/// >>> c["c"]
/// array([4., 4., 4., 4., 4.])
///
/// ```
#[pyfunction]
#[pyo3(signature = (omega, dt, max_lag=None))]
fn angular_velocity_correlation<'py>(
    py: Python<'py>,
    omega: &Bound<'py, PyAny>,
    dt: f64,
    max_lag: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let max_lag = lag(max_lag)?;
    let (w, leading) = Numbers::new(omega, "omega", Values::Finite)?
        .items::<3>(&[1, 2], "(frames, n, 3) or (frames, 3)")?;
    let rotors = leading.get(1).copied().unwrap_or(1);
    let w: Vec<Vector3<f64>> = w.into_iter().map(Vector3::from).collect();
    let c = py.detach(|| vector_autocorrelation(&Frames::new(&w, rotors, "omega")?, max_lag))?;
    let out = PyDict::new(py);
    out.set_item("time", array(py, &[c.len()], lag_times(dt, c.len())?)?)?;
    out.set_item("c", array(py, &[c.len()], c)?)?;
    Ok(out)
}

/// The axis `name` (one 3-vector), normalised.
fn unit(axis: &Bound<'_, PyAny>, name: &'static str) -> PyResult<Unit<Vector3<f64>>> {
    let v = Numbers::new(axis, name, Values::Finite)?.single::<3>("(3,)")?;
    Ok(checked_unit_axis(name, &Vector3::from(v))?)
}

/// The orientational order of a body axis over the rotors.
///
/// Parameters
/// ----------
/// orientations : array_like, shape (n, 4) or (frames, n, 4)
///     Scalar first; with frames, each result gains a leading frames axis.
/// axis : array_like, shape (3,), default (0, 0, 1)
///     The body axis `u` (normalised here).
/// direction : array_like, shape (3,), optional
///     A space vector (normalised here) for the polar order along it.
///
/// Returns
/// -------
/// dict
///     `p2`, the largest eigenvalue of the order tensor
///     `Q = <3/2 u u^T - 1/2 I>` (`q_tensor`, (3, 3)); its eigenvector
///     `director` (signed so that `p1 = <u>.director >= 0`); `p1`, the polar
///     order along it; `cos_director` (n,), each rotor's `u.director`; with
///     `direction`, `p1_direction = <u>.direction` and `cos_direction` (n,).
///
/// Examples
/// --------
/// ```python
///
/// Two rotors with their z axes along +z and -z: nematic, not polar.
///
/// >>> flipped = quaternion.from_axis_angle([1, 0, 0], np.pi)
/// >>> order = quatrot.order_parameters([[1, 0, 0, 0], flipped])
/// >>> round(float(order["p2"]), 12), round(float(order["p1"]), 12)
/// (1.0, 0.0)
///
/// ```
#[pyfunction]
#[pyo3(signature = (orientations, axis=None, direction=None))]
fn order_parameters<'py>(
    py: Python<'py>,
    orientations: &Bound<'py, PyAny>,
    axis: Option<&Bound<'py, PyAny>>,
    direction: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (q, leading) = Numbers::new(orientations, "orientations", Values::Quaternions)?
        .items::<4>(&[1, 2], "(n, 4) or (frames, n, 4)")?;
    let axis = match axis {
        Some(a) => unit(a, "axis")?,
        None => Vector3::z_axis(),
    };
    let direction = direction.map(|d| unit(d, "direction")).transpose()?;
    let q: Vec<Quat> = q.into_iter().map(Quat).collect();
    let rotors = *leading.last().unwrap_or(&0);
    let frames = Frames::new(&q, rotors, "orientations")?;
    let order = py.detach(|| order_of(&frames, &axis, direction.as_ref()));
    let batch: Vec<usize> = leading[..leading.len() - 1].to_vec();
    let shaped = |tail: &[usize]| -> Vec<usize> { batch.iter().chain(tail).copied().collect() };
    let scalar_or_array = |values: Vec<f64>| -> PyResult<Bound<'py, PyAny>> {
        if batch.is_empty() {
            Ok(values[0].into_pyobject(py)?.into_any())
        } else {
            Ok(array(py, &batch, values)?.into_any())
        }
    };
    let gather = |f: fn(&FrameOrder) -> &[f64]| -> Vec<f64> {
        order.iter().flat_map(|o| f(o).iter().copied()).collect()
    };
    let out = PyDict::new(py);
    out.set_item(
        "p2",
        scalar_or_array(gather(|o| std::slice::from_ref(&o.p2)))?,
    )?;
    out.set_item(
        "p1",
        scalar_or_array(gather(|o| std::slice::from_ref(&o.p1)))?,
    )?;
    out.set_item(
        "director",
        array(py, &shaped(&[3]), gather(|o| o.director.as_slice()))?,
    )?;
    let tensor = order
        .iter()
        .flat_map(|o| o.q_tensor.transpose().iter().copied().collect::<Vec<_>>())
        .collect();
    out.set_item("q_tensor", array(py, &shaped(&[3, 3]), tensor)?)?;
    out.set_item(
        "cos_director",
        array(py, &shaped(&[rotors]), gather(|o| &o.cos_director))?,
    )?;
    if direction.is_some() {
        let p1 = order.iter().filter_map(|o| o.p1_direction).collect();
        out.set_item("p1_direction", scalar_or_array(p1)?)?;
        out.set_item(
            "cos_direction",
            array(py, &shaped(&[rotors]), gather(|o| &o.cos_direction))?,
        )?;
    }
    Ok(out)
}

/// The total dipole `M = sum_i R(Q_i) mu_i` in the space frame.
///
/// Parameters
/// ----------
/// orientations : array_like, shape (n, 4) or (frames, n, 4)
///     Scalar first (normalised here).
/// dipoles_body : array_like, shape (3,) or (n, 3)
///     Body-frame dipoles (one shared by all rotors, or one each).
///
/// Returns
/// -------
/// ndarray, shape (3,) or (frames, 3)
///     `|M|^2` is `(M**2).sum(-1)`.
///
/// Examples
/// --------
/// ```python
///
/// >>> quatrot.total_dipole([[1, 0, 0, 0], quaternion.from_axis_angle([1, 0, 0], np.pi / 2)], [0, 0, 1])
/// array([ 0., -1.,  1.])
///
/// ```
#[pyfunction]
fn total_dipole<'py>(
    py: Python<'py>,
    orientations: &Bound<'py, PyAny>,
    dipoles_body: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (q, leading) = Numbers::new(orientations, "orientations", Values::Quaternions)?
        .items::<4>(&[1, 2], "(n, 4) or (frames, n, 4)")?;
    let rotors = *leading.last().unwrap_or(&0);
    let (mu, mu_leading) = Numbers::new(dipoles_body, "dipoles_body", Values::Finite)?
        .items::<3>(&[0, 1], "(3,) or (n, 3)")?;
    let mu: Vec<Vector3<f64>> = match mu_leading.first() {
        None => vec![Vector3::from(mu[0]); rotors],
        Some(&n) if n == rotors => mu.into_iter().map(Vector3::from).collect(),
        Some(&n) => {
            return Err(invalid(
                "dipoles_body",
                format!("{n} dipoles for {rotors} rotors"),
            ))
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

/// Adds the analysis functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(orientational_correlations, m)?)?;
    m.add_function(wrap_pyfunction!(angular_velocity_correlation, m)?)?;
    m.add_function(wrap_pyfunction!(order_parameters, m)?)?;
    m.add_function(wrap_pyfunction!(total_dipole, m)?)
}
