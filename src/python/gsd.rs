//! `quatrot.write_gsd`: a GSD trajectory (`crate::run::GsdWriter`) from
//! numpy arrays, e.g. the in-memory trajectory `quatrot.run` returns.

use super::args::{expected, integer, invalid, path_or};
use super::arrays::{Numbers, Values};
use crate::quaternion::Quat;
use crate::run::{GsdBox, GsdWriter, RunError};
use nalgebra::Vector3;
use pyo3::prelude::*;

/// Writes a GSD file (HOOMD-blue's format) of rotors on sites.
///
/// `hoomd` schema 1.4, float32, orientations written normalised. The box is
/// the periodic `[0, box_lengths)` if given, else (an open cluster) the
/// bounding box of the sites grown by `margin` on each side; HOOMD centres its
/// box, so positions are written wrapped into the box and shifted by `-L/2`.
/// Read it with `gsd.hoomd.open(path)`.
///
/// Parameters
/// ----------
/// path : str or path
/// sites : array_like, shape (n, 3)
/// orientations : array_like, shape (frames, n, 4)
///     Scalar first.
/// steps : array_like of int, shape (frames,)
/// box_lengths : array_like, shape (3,), optional
/// margin : float, default 1.0
///
/// Examples
/// --------
/// ```python
///
/// >>> import os, tempfile
/// >>> path = os.path.join(tempfile.mkdtemp(), "rotors.gsd")
/// >>> quatrot.write_gsd(path, [[0, 0, 0], [1, 0, 0]], [[[1, 0, 0, 0]] * 2], [0])
/// >>> os.path.getsize(path) > 0
/// True
///
/// ```
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
    let path = path_or(path, "path", invalid)?;
    let steps = steps
        .try_iter()
        .map_err(|_| expected("steps", "a sequence of integers"))?
        .enumerate()
        .map(|(k, step)| integer(&step?, &format!("steps[{k}]"), 0, u64::MAX))
        .collect::<PyResult<Vec<u64>>>()?;
    let (sites, _) = Numbers::new(sites, "sites", Values::Finite)?.items::<3>(&[1], "(n, 3)")?;
    let sites: Vec<Vector3<f64>> = sites.into_iter().map(Vector3::from).collect();
    if sites.is_empty() {
        return Err(invalid("sites", "needs at least one site"));
    }
    let (q, leading) = Numbers::new(orientations, "orientations", Values::Quaternions)?
        .items::<4>(&[2], "(frames, n, 4)")?;
    if leading[1] != sites.len() {
        return Err(invalid(
            "orientations",
            format!(
                "{} rotors per frame, but sites has {}",
                leading[1],
                sites.len()
            ),
        ));
    }
    if steps.len() != leading[0] {
        return Err(invalid(
            "steps",
            format!("{} steps for {} frames", steps.len(), leading[0]),
        ));
    }
    let box_lengths = box_lengths
        .map(|b| Numbers::new(b, "box_lengths", Values::Finite)?.single::<3>("(3,)"))
        .transpose()?;
    let cell = GsdBox::new(box_lengths.map(Vector3::from), &sites, margin)?;
    let q: Vec<Quat> = q.into_iter().map(Quat).collect();
    py.detach(|| {
        let mut writer = GsdWriter::create(&path, &sites, &cell)?;
        for (frame, step) in q.chunks_exact(sites.len()).zip(&steps) {
            writer.write_frame(*step, frame)?;
        }
        writer.flush()
    })
    .map_err(|e| RunError::io(&path, e))?;
    Ok(())
}

/// Adds `write_gsd` to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(write_gsd, m)?)
}
