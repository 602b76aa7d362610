//! `quatrot.multipole_evaluate`: the point-multipole potential from numpy arrays.

use super::arrays::{collect, common_len, single, Items};
use crate::potential::{Boundary, ExternalFields, MultipolePotential, PotentialError};
use crate::quaternion::Quat;
use crate::rotor::{Inertia, Rotor};
use nalgebra::Vector3;
use numpy::PyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

impl From<PotentialError> for PyErr {
    fn from(e: PotentialError) -> PyErr {
        PyValueError::new_err(e.to_string())
    }
}

/// Periodic boundaries when both `box_lengths` (a single 3-vector) and
/// `cutoff` are given (the lattice sum over every image inside the cutoff,
/// which may exceed half the box: see [`Boundary::Periodic`]), open when
/// neither is.
pub(crate) fn boundary(
    box_lengths: Option<&Bound<'_, PyAny>>,
    cutoff: Option<f64>,
) -> PyResult<Boundary> {
    match (single(box_lengths, "box_lengths", &[3])?, cutoff) {
        (None, None) => Ok(Boundary::Open),
        (Some(l), Some(cutoff)) => Ok(Boundary::periodic_cutoff(l.vector(0), cutoff)),
        _ => Err(PyValueError::new_err(
            "box_lengths, cutoff: give both for periodic boundaries, or neither for open",
        )),
    }
}

/// Energy, eq 14 gradient `dV/dq` (n, 4) and space-frame torques (n, 3) of
/// point multipoles on fixed `sites` (n, 3) with `orientations` (n, 4,
/// scalar first), body `dipoles_body` (n, 3) and Buckingham
/// `quadrupoles_body` (n, 3, 3, symmetric traceless), each optional (zero
/// rows mean no multipole); optional uniform `field` (3,) and
/// `field_gradient` (3, 3) with `[a, b] = dE_b/dr_a`; open boundaries, or
/// periodic when `box_lengths` (3,) and `cutoff` are given (every image
/// within the cutoff, a rotor's own images included). Reduced units,
/// 4 pi eps0 = 1.
#[pyfunction]
#[pyo3(signature = (sites, orientations, dipoles_body=None, quadrupoles_body=None, field=None, field_gradient=None, box_lengths=None, cutoff=None))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn multipole_evaluate<'py>(
    py: Python<'py>,
    sites: &Bound<'py, PyAny>,
    orientations: &Bound<'py, PyAny>,
    dipoles_body: Option<&Bound<'py, PyAny>>,
    quadrupoles_body: Option<&Bound<'py, PyAny>>,
    field: Option<&Bound<'py, PyAny>>,
    field_gradient: Option<&Bound<'py, PyAny>>,
    box_lengths: Option<&Bound<'py, PyAny>>,
    cutoff: Option<f64>,
) -> PyResult<(
    f64,
    Bound<'py, PyArrayDyn<f64>>,
    Bound<'py, PyArrayDyn<f64>>,
)> {
    let sites = Items::new(sites, "sites", &[3])?;
    let orientations = Items::new(orientations, "orientations", &[4])?;
    let dipoles = dipoles_body
        .map(|d| Items::new(d, "dipoles_body", &[3]))
        .transpose()?;
    let quadrupoles = quadrupoles_body
        .map(|t| Items::new(t, "quadrupoles_body", &[3, 3]))
        .transpose()?;
    let mut per_rotor = vec![&sites, &orientations];
    per_rotor.extend(dipoles.iter());
    per_rotor.extend(quadrupoles.iter());
    let batch = common_len(&per_rotor)?;
    let n = batch.0;
    let rotors: Vec<Rotor> = (0..n)
        .map(|i| Rotor {
            site: sites.vector(i),
            inertia: Inertia::Spherical(1.0),
            dipole_body: dipoles.as_ref().map(|d| d.vector(i)),
            quadrupole_body: quadrupoles.as_ref().map(|t| t.matrix(i)),
        })
        .collect();
    let external = ExternalFields {
        field: single(field, "field", &[3])?.map(|e| e.vector(0)),
        field_gradient: single(field_gradient, "field_gradient", &[3, 3])?.map(|g| g.matrix(0)),
    };
    let boundary = boundary(box_lengths, cutoff)?;
    let q: Vec<Quat> = (0..n).map(|i| orientations.quat(i)).collect();
    let (energy, gradient, torques) = py.detach(|| -> Result<_, PotentialError> {
        let potential = MultipolePotential::new(&rotors, boundary, external)?;
        let mut gradient = vec![Quat::ZERO; n];
        let mut torques = vec![Vector3::zeros(); n];
        let energy = potential.evaluate(&q, Some(&mut gradient), Some(&mut torques));
        Ok((energy, gradient, torques))
    })?;
    Ok((
        energy,
        collect(py, batch, &[4], |i| Ok(gradient[i].0))?,
        collect(py, batch, &[3], |i| Ok(torques[i].into()))?,
    ))
}

/// Adds the potential functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(multipole_evaluate, m)?)
}
