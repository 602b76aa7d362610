//! The analysis of moving bodies from numpy (`crate::analysis`'s
//! `displacement` and `radial`): `mean_squared_displacement` with the
//! self-diffusion coefficient, and `radial_distribution`. Arguments are any
//! array-like, converted once to float64 and shape-checked here; the
//! computation runs without the GIL; results are dicts of numpy arrays.

use super::analysis::lag;
use super::args::{integer, invalid};
use super::arrays::{array, Numbers, Values};
use crate::analysis::{
    lag_times, mean_squared_displacement as msd_of, radial_distribution as rdf_of, self_diffusion,
    unwrapped_positions, Frames,
};
use nalgebra::Vector3;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Vectors `(frames, n, 3)` (or `(n, 3)`, one frame, where `one_frame`) as
/// frame-major vectors and the count per frame.
fn vectors(
    arg: &Bound<'_, PyAny>,
    name: &'static str,
    one_frame: bool,
) -> PyResult<(Vec<Vector3<f64>>, usize)> {
    let (ranks, expected): (&[usize], _) = if one_frame {
        (&[1, 2], "(frames, n, 3) or (n, 3)")
    } else {
        (&[2], "(frames, n, 3)")
    };
    let (v, leading) = Numbers::new(arg, name, Values::Finite)?.items::<3>(ranks, expected)?;
    let per_frame = *leading.last().unwrap_or(&0);
    Ok((v.into_iter().map(Vector3::from).collect(), per_frame))
}

/// The box `(3,)`.
fn box_of(arg: &Bound<'_, PyAny>) -> PyResult<Vector3<f64>> {
    Ok(Vector3::from(
        Numbers::new(arg, "box_lengths", Values::Finite)?.single::<3>("(3,)")?,
    ))
}

/// The mean-squared displacement of body centres, and the self-diffusion
/// coefficient from it.
///
/// `MSD(t) = <|r(t0 + t) - r(t0)|^2>` over all time origins `t0` and bodies
/// (by FFT), of centres unwrapped as `r = x + n L` when the image counts
/// `n` and box `L` are given (a run's GSD frames: `particles.position`,
/// `particles.image`, `configuration.box[:3]`). With `fit_window`, the
/// Einstein relation `D = lim MSD / 6t` as the least-squares slope over
/// the lags in the window, divided by 6.
///
/// Parameters
/// ----------
/// positions : array_like, shape (frames, n, 3)
///     Centres, frames `dt` apart: unwrapped, or wrapped with `images`.
/// dt : float
///     Time between frames.
/// images : array_like, shape (frames, n, 3), optional
///     Image counts (integers); needs `box_lengths`.
/// box_lengths : array_like, shape (3,), optional
///     The periodic box's sides; only with `images`.
/// max_lag : int, optional
///     The largest lag in frames (default: every lag).
/// fit_window : (float, float), optional
///     The times `(start, end)` of the linear regime (at least two lags):
///     after the ballistic start, before the noisy last lags.
///
/// Returns
/// -------
/// dict
///     `{"time": (L,), "msd": (L,)}`, and with `fit_window`, `"diffusion"`:
///     `{"coefficient": D, "slope", "intercept", "points", "window"}`.
///
/// Examples
/// --------
/// ```python
///
/// Two bodies moving at constant velocity through a box of side 2, wrapped:
/// the MSD grows as `|v|^2 t^2`.
///
/// >>> t = np.arange(6)[:, None, None] * 0.5
/// >>> r = np.array([[0.1, 0.0, 0.0], [0.0, 0.2, 0.3]]) + t * [[1.0, 0.0, 0.0], [0.0, 0.0, -2.0]]
/// >>> m = quatrot.mean_squared_displacement(r % 2.0, 0.5, images=r // 2.0, box_lengths=[2, 2, 2])
/// >>> np.allclose(m["msd"], 2.5 * m["time"] ** 2)
/// True
///
/// ```
#[pyfunction]
#[pyo3(signature = (positions, dt, images=None, box_lengths=None, max_lag=None, fit_window=None))]
fn mean_squared_displacement<'py>(
    py: Python<'py>,
    positions: &Bound<'py, PyAny>,
    dt: f64,
    images: Option<&Bound<'py, PyAny>>,
    box_lengths: Option<&Bound<'py, PyAny>>,
    max_lag: Option<&Bound<'py, PyAny>>,
    fit_window: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let max_lag = lag(max_lag)?;
    let (x, bodies) = vectors(positions, "positions", false)?;
    let unwrap = match (images, box_lengths) {
        (Some(images), Some(cell)) => Some((vectors(images, "images", false)?.0, box_of(cell)?)),
        (None, None) => None,
        (Some(_), None) => return Err(invalid("images", "needs box_lengths")),
        (None, Some(_)) => return Err(invalid("box_lengths", "is used only with images")),
    };
    let window = fit_window
        .map(|w| Numbers::new(w, "fit_window", Values::Finite)?.single::<2>("(2,)"))
        .transpose()?;
    let (msd, time, diffusion) = py.detach(|| -> PyResult<_> {
        let wrapped = Frames::new(&x, bodies, "positions")?;
        let unwrapped = match &unwrap {
            Some((n, cell)) => Some(unwrapped_positions(
                &wrapped,
                &Frames::new(n, bodies, "images")?,
                cell,
            )?),
            None => None,
        };
        let centres = match &unwrapped {
            Some(r) => Frames::new(r, bodies, "positions")?,
            None => wrapped,
        };
        let msd = msd_of(&centres, max_lag)?;
        let time = lag_times(dt, msd.len())?;
        let diffusion = window
            .map(|[start, end]| self_diffusion(&time, &msd, (start, end)))
            .transpose()?;
        Ok((msd, time, diffusion))
    })?;
    let out = PyDict::new(py);
    out.set_item("time", array(py, &[time.len()], time)?)?;
    out.set_item("msd", array(py, &[msd.len()], msd)?)?;
    if let (Some(d), Some(w)) = (diffusion, window) {
        let fit = PyDict::new(py);
        fit.set_item("coefficient", d.coefficient)?;
        fit.set_item("slope", d.slope)?;
        fit.set_item("intercept", d.intercept)?;
        fit.set_item("points", d.points)?;
        fit.set_item("window", (w[0], w[1]))?;
        out.set_item("diffusion", fit)?;
    }
    Ok(out)
}

/// The radial distribution function of body centres in a periodic box.
///
/// Pairs at their minimum-image distance below `r_max`, in `bins` shells,
/// over frames; each shell divided by the ideal gas's count for the same
/// `N` bodies (`N - 1` partners each), so uniform random points give 1.
///
/// Parameters
/// ----------
/// positions : array_like, shape (frames, n, 3) or (n, 3)
///     Centres (wrapped or not).
/// box_lengths : array_like, shape (3,)
///     The orthorhombic box's sides.
/// r_max : float, optional
///     Default and largest: half the shortest side.
/// bins : int, default 100
///
/// Returns
/// -------
/// dict
///     `{"r": (bins,), "edges": (bins + 1,), "g": (bins,),
///     "coordination": (bins,)}`: shell mid radii and edges, `g(r)`, and the
///     mean number of neighbours closer than each shell's outer edge.
///
/// Examples
/// --------
/// ```python
///
/// A simple cubic lattice of spacing 1: 6 neighbours at r = 1.
///
/// >>> grid = np.stack(np.meshgrid(*[np.arange(4.0)] * 3), -1).reshape(-1, 3)
/// >>> rdf = quatrot.radial_distribution(grid, [4, 4, 4], r_max=1.2, bins=12)
/// >>> float(rdf["coordination"][-1])
/// 6.0
///
/// ```
#[pyfunction]
#[pyo3(signature = (positions, box_lengths, r_max=None, bins=None))]
fn radial_distribution<'py>(
    py: Python<'py>,
    positions: &Bound<'py, PyAny>,
    box_lengths: &Bound<'py, PyAny>,
    r_max: Option<f64>,
    bins: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let bins = match bins {
        Some(b) => usize::try_from(integer(b, "bins", 1, u64::MAX)?).unwrap_or(usize::MAX),
        None => 100,
    };
    let (x, bodies) = vectors(positions, "positions", true)?;
    let cell = box_of(box_lengths)?;
    let rdf = py.detach(|| rdf_of(&Frames::new(&x, bodies, "positions")?, &cell, r_max, bins))?;
    let out = PyDict::new(py);
    out.set_item("r", array(py, &[bins], rdf.r)?)?;
    out.set_item("edges", array(py, &[bins + 1], rdf.edges)?)?;
    out.set_item("g", array(py, &[bins], rdf.g)?)?;
    out.set_item("coordination", array(py, &[bins], rdf.coordination)?)?;
    Ok(out)
}

/// Adds the analysis of moving bodies to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(mean_squared_displacement, m)?)?;
    m.add_function(wrap_pyfunction!(radial_distribution, m)?)
}
