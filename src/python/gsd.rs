//! `quatrot.write_gsd`: a GSD trajectory (`crate::run::GsdWriter`) from
//! numpy arrays, e.g. the in-memory trajectory `quatrot.run` returns.

use super::args::{integer, path_or};
use super::arrays::{Numbers, Values};
use crate::quaternion::Quat;
use crate::run::{GsdBox, GsdWriter};
use nalgebra::Vector3;
use pyo3::exceptions::{PyOSError, PyTypeError, PyValueError};
use pyo3::prelude::*;

/// write_gsd(path, sites, orientations, steps, box_lengths=None, margin=1.0)
///
/// Writes a GSD file (HOOMD-blue's format, `hoomd` schema 1.4, float32) of
/// rotors on `sites` `(n, 3)` with `orientations` `(frames, n, 4)` (scalar
/// first, written normalised) at integer `steps` `(frames,)`. The box is the
/// periodic `[0, box_lengths)` if given, else (an open cluster) the bounding
/// box of the sites grown by `margin` on each side; HOOMD centres its box,
/// so positions are written wrapped into the box and shifted by `-L/2`.
/// Read it with `gsd.hoomd.open(path)`.
#[pyfunction]
#[pyo3(signature = (path, sites, orientations, steps, box_lengths=None, margin=1.0))]
fn write_gsd(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    sites: &Bound<'_, PyAny>,
    orientations: &Bound<'_, PyAny>,
    steps: &Bound<'_, PyAny>,
    box_lengths: Option<&Bound<'_, PyAny>>,
    margin: f64,
) -> PyResult<()> {
    let path = path_or(path, "path", PyValueError::new_err)?;
    let steps = steps
        .try_iter()
        .map_err(|_| PyTypeError::new_err("steps: expected a sequence of integers"))?
        .enumerate()
        .map(|(k, step)| integer(&step?, &format!("steps[{k}]"), 0, u64::MAX))
        .collect::<PyResult<Vec<u64>>>()?;
    let (sites, _) = Numbers::new(sites, "sites", Values::Finite)?.items::<3>(&[1], "(n, 3)")?;
    let sites: Vec<Vector3<f64>> = sites.into_iter().map(Vector3::from).collect();
    if sites.is_empty() {
        return Err(PyValueError::new_err("sites: needs at least one site"));
    }
    let (q, leading) = Numbers::new(orientations, "orientations", Values::Quaternions)?
        .items::<4>(&[2], "(frames, n, 4)")?;
    if leading[1] != sites.len() {
        return Err(PyValueError::new_err(format!(
            "orientations: {} rotors per frame, but sites has {}",
            leading[1],
            sites.len()
        )));
    }
    if steps.len() != leading[0] {
        return Err(PyValueError::new_err(format!(
            "steps: {} steps for {} frames",
            steps.len(),
            leading[0]
        )));
    }
    let cell = match box_lengths {
        Some(b) => {
            let (l, _) =
                Numbers::new(b, "box_lengths", Values::Finite)?.items::<3>(&[0], "(3,)")?;
            let l = Vector3::from(l[0]);
            if !l.iter().all(|x| x.is_finite() && *x > 0.0) {
                return Err(PyValueError::new_err(format!(
                    "box_lengths: must be finite and > 0, got [{}, {}, {}]",
                    l.x, l.y, l.z
                )));
            }
            GsdBox::periodic(l)
        }
        None if margin.is_finite() && margin > 0.0 => GsdBox::enclosing(&sites, margin),
        None => {
            return Err(PyValueError::new_err(format!(
                "margin: must be finite and > 0, got {margin}"
            )))
        }
    };
    let q: Vec<Quat> = q.into_iter().map(Quat).collect();
    let io_error = |e: std::io::Error| PyOSError::new_err(format!("{}: {e}", path.display()));
    py.detach(|| {
        let mut writer = GsdWriter::create(&path, &sites, &cell)?;
        for (frame, step) in q.chunks_exact(sites.len()).zip(&steps) {
            writer.write_frame(*step, frame)?;
        }
        writer.flush()
    })
    .map_err(io_error)
}

/// Adds `write_gsd` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(write_gsd, m)?)
}
