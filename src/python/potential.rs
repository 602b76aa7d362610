//! `quatrot.multipole_evaluate`: the point-multipole potential from numpy arrays.

use crate::potential::{Boundary, ExternalFields, MultipolePotential, PotentialError};
use crate::quaternion::Quat;
use crate::rotor::{Inertia, Rotor};
use nalgebra::{Matrix3, Vector3};
use numpy::{IntoPyArray, PyArray2, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

impl From<PotentialError> for PyErr {
    fn from(e: PotentialError) -> PyErr {
        PyValueError::new_err(e.to_string())
    }
}

/// Checks `shape` against `expected` (`None` = any length), naming the argument.
fn check_shape(name: &str, shape: &[usize], expected: &[Option<usize>]) -> PyResult<()> {
    let fits = shape.len() == expected.len()
        && shape
            .iter()
            .zip(expected)
            .all(|(s, e)| e.is_none_or(|e| e == *s));
    if fits {
        return Ok(());
    }
    let want: Vec<String> = expected
        .iter()
        .map(|e| e.map_or("n".to_string(), |e| e.to_string()))
        .collect();
    Err(PyValueError::new_err(format!(
        "{name}: expected shape ({}), got {shape:?}",
        want.join(", ")
    )))
}

/// Energy, eq 14 gradient `dV/dq` (n, 4) and space-frame torques (n, 3) of
/// point multipoles on fixed `sites` (n, 3) with `orientations` (n, 4,
/// scalar first), body `dipoles_body` (n, 3) and Buckingham
/// `quadrupoles_body` (n, 3, 3, symmetric traceless), each optional (zero
/// rows mean no multipole); optional uniform `field` (3,) and
/// `field_gradient` (3, 3) with `[a, b] = dE_b/dr_a`; open boundaries, or
/// periodic when `box_lengths` (3,) and `cutoff` are given. Reduced units,
/// 4 pi eps0 = 1.
#[pyfunction]
#[pyo3(signature = (sites, orientations, dipoles_body=None, quadrupoles_body=None, field=None, field_gradient=None, box_lengths=None, cutoff=None))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn multipole_evaluate<'py>(
    py: Python<'py>,
    sites: PyReadonlyArrayDyn<'py, f64>,
    orientations: PyReadonlyArrayDyn<'py, f64>,
    dipoles_body: Option<PyReadonlyArrayDyn<'py, f64>>,
    quadrupoles_body: Option<PyReadonlyArrayDyn<'py, f64>>,
    field: Option<PyReadonlyArrayDyn<'py, f64>>,
    field_gradient: Option<PyReadonlyArrayDyn<'py, f64>>,
    box_lengths: Option<PyReadonlyArrayDyn<'py, f64>>,
    cutoff: Option<f64>,
) -> PyResult<(f64, Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
    check_shape("sites", sites.shape(), &[None, Some(3)])?;
    let n = sites.shape()[0];
    check_shape("orientations", orientations.shape(), &[Some(n), Some(4)])?;
    let sites = sites.as_array();
    let orientations = orientations.as_array();
    let mut rotors: Vec<Rotor> = (0..n)
        .map(|i| Rotor {
            site: Vector3::from_fn(|a, _| sites[[i, a]]),
            inertia: Inertia::Spherical(1.0),
            dipole_body: None,
            quadrupole_body: None,
        })
        .collect();
    if let Some(d) = dipoles_body {
        check_shape("dipoles_body", d.shape(), &[Some(n), Some(3)])?;
        let d = d.as_array();
        for (i, r) in rotors.iter_mut().enumerate() {
            r.dipole_body = Some(Vector3::from_fn(|a, _| d[[i, a]]));
        }
    }
    if let Some(t) = quadrupoles_body {
        check_shape("quadrupoles_body", t.shape(), &[Some(n), Some(3), Some(3)])?;
        let t = t.as_array();
        for (i, r) in rotors.iter_mut().enumerate() {
            r.quadrupole_body = Some(Matrix3::from_fn(|a, b| t[[i, a, b]]));
        }
    }
    let field = match field {
        Some(e) => {
            check_shape("field", e.shape(), &[Some(3)])?;
            let e = e.as_array();
            Some(Vector3::from_fn(|a, _| e[a]))
        }
        None => None,
    };
    let field_gradient = match field_gradient {
        Some(g) => {
            check_shape("field_gradient", g.shape(), &[Some(3), Some(3)])?;
            let g = g.as_array();
            Some(Matrix3::from_fn(|a, b| g[[a, b]]))
        }
        None => None,
    };
    let boundary = match (box_lengths, cutoff) {
        (None, None) => Boundary::Open,
        (Some(l), Some(cutoff)) => {
            check_shape("box_lengths", l.shape(), &[Some(3)])?;
            let l = l.as_array();
            Boundary::Periodic {
                box_lengths: Vector3::from_fn(|a, _| l[a]),
                cutoff,
            }
        }
        _ => {
            return Err(PyValueError::new_err(
                "box_lengths, cutoff: give both for periodic boundaries, or neither for open",
            ))
        }
    };
    let q: Vec<Quat> = (0..n)
        .map(|i| {
            Quat::new(
                orientations[[i, 0]],
                orientations[[i, 1]],
                orientations[[i, 2]],
                orientations[[i, 3]],
            )
        })
        .collect();
    let external = ExternalFields {
        field,
        field_gradient,
    };
    let (energy, gradient, torques) = py.detach(|| -> Result<_, PotentialError> {
        let potential = MultipolePotential::new(&rotors, boundary, external)?;
        let mut gradient = vec![Quat::ZERO; n];
        let mut torques = vec![Vector3::zeros(); n];
        let energy = potential.evaluate(&q, Some(&mut gradient), Some(&mut torques));
        Ok((energy, gradient, torques))
    })?;
    let gradient: Vec<f64> = gradient.iter().flat_map(|g| g.0).collect();
    let torques: Vec<f64> = torques.iter().flat_map(|t| [t.x, t.y, t.z]).collect();
    Ok((
        energy,
        gradient.into_pyarray(py).reshape([n, 4])?,
        torques.into_pyarray(py).reshape([n, 3])?,
    ))
}

/// Adds the potential functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(multipole_evaluate, m)?)
}
