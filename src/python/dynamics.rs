//! `quatrot.gear_corrections_table`: the note's experiment
//! ([`crate::experiments::gear_corrections`]) on pinned multipolar rotors
//! given as numpy arrays. Converts and checks the arrays, then delegates.

use crate::experiments::gear_corrections::{correction_table, Settings, System};
use crate::integrators::RotorState;
use crate::potential::{Boundary, ExternalFields, MultipolePotential};
use crate::quaternion::Quat;
use crate::rotor::{Inertia, Rotor};
use nalgebra::{Matrix3, Vector3};
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The rows of a `(n, width)` float array, checking its shape.
fn rows(
    name: &str,
    array: &PyReadonlyArray2<f64>,
    n: Option<usize>,
    width: usize,
) -> PyResult<Vec<Vec<f64>>> {
    let shape = array.shape();
    if shape[1] != width || n.is_some_and(|n| shape[0] != n) {
        let expected = n.map_or("n".to_string(), |n| n.to_string());
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape ({expected}, {width}), got {shape:?}"
        )));
    }
    let view = array.as_array();
    Ok(view.outer_iter().map(|r| r.to_vec()).collect())
}

/// A 3-vector from a `(3,)` array.
fn vector(name: &str, array: &PyReadonlyArray1<f64>) -> PyResult<Vector3<f64>> {
    let v = array.as_array();
    if v.len() != 3 {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape (3,), got ({},)",
            v.len()
        )));
    }
    Ok(Vector3::new(v[0], v[1], v[2]))
}

/// The note's experiment: scheme A against scheme B with each correction.
///
/// Arrays (float64): `sites (n, 3)`, `inertia (n, 3)` principal moments (all
/// equal: spherical top), `orientations (n, 4)` scalar first, `omega_body
/// (n, 3)`, optional `dipoles (n, 3)` and `quadrupoles (n, 3, 3)` (body frame,
/// Buckingham), optional uniform `field (3,)`, optional periodic box
/// `box_lengths (3,)` with `cutoff`. Returns one dict per configuration with
/// keys `label, drift, fluctuation, global_error, order, largest_stable_dt,
/// max_q_dot_q_dot, max_q_dot_force` (see the Rust docs for their meaning).
#[pyfunction]
#[pyo3(signature = (
    sites, inertia, orientations, omega_body, *, dipoles=None, quadrupoles=None, field=None,
    box_lengths=None, cutoff=None, dt=0.02, t_energy=100.0, t_error=5.0, t_stability=20.0,
    sample_every=1
))]
#[allow(clippy::too_many_arguments)]
fn gear_corrections_table<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<f64>,
    inertia: PyReadonlyArray2<f64>,
    orientations: PyReadonlyArray2<f64>,
    omega_body: PyReadonlyArray2<f64>,
    dipoles: Option<PyReadonlyArray2<f64>>,
    quadrupoles: Option<PyReadonlyArray3<f64>>,
    field: Option<PyReadonlyArray1<f64>>,
    box_lengths: Option<PyReadonlyArray1<f64>>,
    cutoff: Option<f64>,
    dt: f64,
    t_energy: f64,
    t_error: f64,
    t_stability: f64,
    sample_every: usize,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let sites = rows("sites", &sites, None, 3)?;
    let n = sites.len();
    let moments = rows("inertia", &inertia, Some(n), 3)?;
    let q = rows("orientations", &orientations, Some(n), 4)?;
    let w = rows("omega_body", &omega_body, Some(n), 3)?;
    let dipoles = dipoles
        .map(|d| rows("dipoles", &d, Some(n), 3))
        .transpose()?;
    let quadrupoles = match quadrupoles {
        Some(a) => {
            let shape = a.shape();
            if shape != [n, 3, 3] {
                return Err(PyValueError::new_err(format!(
                    "quadrupoles: expected shape ({n}, 3, 3), got {shape:?}"
                )));
            }
            let view = a.as_array();
            Some(
                (0..n)
                    .map(|i| Matrix3::from_fn(|r, c| view[[i, r, c]]))
                    .collect::<Vec<_>>(),
            )
        }
        None => None,
    };
    let field = field.map(|f| vector("field", &f)).transpose()?;
    let boundary = match (box_lengths, cutoff) {
        (Some(b), Some(cutoff)) => Boundary::Periodic {
            box_lengths: vector("box_lengths", &b)?,
            cutoff,
        },
        (None, None) => Boundary::Open,
        _ => {
            return Err(PyValueError::new_err(
                "box_lengths and cutoff: give both or neither",
            ))
        }
    };
    let rotors: Vec<Rotor> = (0..n)
        .map(|i| {
            let m = Vector3::new(moments[i][0], moments[i][1], moments[i][2]);
            Rotor {
                site: Vector3::new(sites[i][0], sites[i][1], sites[i][2]),
                inertia: if m.x == m.y && m.y == m.z {
                    Inertia::Spherical(m.x)
                } else {
                    Inertia::Principal(m)
                },
                dipole_body: dipoles
                    .as_ref()
                    .map(|d| Vector3::new(d[i][0], d[i][1], d[i][2])),
                quadrupole_body: quadrupoles.as_ref().map(|t| t[i]),
            }
        })
        .collect();
    let initial: Vec<RotorState> = (0..n)
        .map(|i| RotorState {
            orientation: Quat::new(q[i][0], q[i][1], q[i][2], q[i][3]),
            omega_body: Vector3::new(w[i][0], w[i][1], w[i][2]),
        })
        .collect();
    let external = ExternalFields {
        field,
        field_gradient: None,
    };
    let potential = MultipolePotential::new(&rotors, boundary, external)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    for (name, value) in [
        ("dt", dt),
        ("t_energy", t_energy),
        ("t_error", t_error),
        ("t_stability", t_stability),
    ] {
        if !(value.is_finite() && value > 0.0) {
            return Err(PyValueError::new_err(format!(
                "{name}: must be finite and > 0, got {value}"
            )));
        }
    }
    if sample_every == 0 {
        return Err(PyValueError::new_err("sample_every: must be >= 1, got 0"));
    }
    // Validate the rotors and states once, so the experiment itself cannot fail.
    let inertia: Vec<Inertia> = rotors.iter().map(|r| r.inertia).collect();
    crate::integrators::startup::prepare(&inertia, &initial, dt)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let settings = Settings {
        dt,
        t_energy,
        t_error,
        t_stability,
        sample_every,
    };
    let table = py.detach(|| {
        let system = System {
            potential: &potential,
            inertia: &inertia,
            initial: &initial,
        };
        correction_table(&system, &settings)
    });
    table
        .into_iter()
        .map(|row| {
            let d = PyDict::new(py);
            d.set_item("label", row.label)?;
            d.set_item("drift", row.drift)?;
            d.set_item("fluctuation", row.fluctuation)?;
            d.set_item("global_error", row.global_error)?;
            d.set_item("order", row.order)?;
            d.set_item("largest_stable_dt", row.largest_stable_dt)?;
            d.set_item("max_q_dot_q_dot", row.max_q_dot_q_dot)?;
            d.set_item("max_q_dot_force", row.max_q_dot_force)?;
            Ok(d)
        })
        .collect()
}

/// Adds this submodule's functions to the `quatrot` module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(gear_corrections_table, m)?)
}
