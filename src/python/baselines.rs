//! `quatrot.dlm_dipoles`: quatrot's DLM on dipolar rotors with the multipole
//! potential (open boundaries) and an optional uniform field, sampled every
//! step, for the LAMMPS comparison (`validation/checks/lammps_dipoles.py`).

use crate::integrators::{Dlm, DlmOptions, Integrator, IntegratorError, RotorState, SphericalTops};
use crate::parallel::on_worker;
use crate::potential::{Boundary, ExternalFields, MultipolePotential, Potential};
use crate::quaternion::Quat;
use crate::rotor::{Inertia, Rotor};
use crate::simulation::{self, Needs, Observer, RunOptions, Sample, Scheduled};
use nalgebra::Vector3;
use numpy::ndarray::{Array1, Array3};
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::convert::Infallible;

fn integrator_error(e: IntegratorError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Checks that `array` has shape `(n, width)`.
fn rows(name: &str, array: &PyReadonlyArray2<'_, f64>, n: usize, width: usize) -> PyResult<()> {
    if array.shape() != [n, width] {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape ({n}, {width}), got {:?}",
            array.shape()
        )));
    }
    Ok(())
}

fn vector(a: &PyReadonlyArray2<'_, f64>, i: usize) -> Vector3<f64> {
    let v = a.as_array();
    Vector3::new(v[(i, 0)], v[(i, 1)], v[(i, 2)])
}

/// Runs `steps` DLM steps of `dt` for spherical tops with moments `inertia`
/// (n,) on `sites` (n, 3) carrying `dipoles_body` (n, 3), from `orientations`
/// (n, 4, scalar first, body to space) and `omega_body` (n, 3), in the
/// optional uniform `field` (3,). `split` selects the body-axis sweep for the
/// free rotation (as LAMMPS) instead of the exact spherical-top flow. Returns
/// a dict of per-step samples (index 0 is t = 0): `orientations` (s+1, n, 4),
/// `omega_body` (s+1, n, 3), `potential` (s+1,), `torques_space` (s+1, n, 3).
#[pyfunction]
#[pyo3(signature = (sites, dipoles_body, inertia, orientations, omega_body, field, dt, steps, split))]
#[allow(clippy::too_many_arguments)]
fn dlm_dipoles<'py>(
    py: Python<'py>,
    sites: PyReadonlyArray2<'py, f64>,
    dipoles_body: PyReadonlyArray2<'py, f64>,
    inertia: PyReadonlyArray1<'py, f64>,
    orientations: PyReadonlyArray2<'py, f64>,
    omega_body: PyReadonlyArray2<'py, f64>,
    field: Option<PyReadonlyArray1<'py, f64>>,
    dt: f64,
    steps: usize,
    split: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let n = sites.shape()[0];
    // Sizes before allocation: steps + 1 samples of 11 values per rotor
    // and the energy (in f64, so no count wraps).
    crate::memory::check(
        "steps",
        (steps as f64 + 1.0) * (11.0 * n as f64 + 1.0) * 8.0,
    )?;
    rows("sites", &sites, n, 3)?;
    rows("dipoles_body", &dipoles_body, n, 3)?;
    rows("orientations", &orientations, n, 4)?;
    rows("omega_body", &omega_body, n, 3)?;
    if inertia.shape() != [n] {
        return Err(PyValueError::new_err(format!(
            "inertia: expected shape ({n},), got {:?}",
            inertia.shape()
        )));
    }
    let field = match field {
        Some(f) if f.shape() == [3] => Some(Vector3::from_iterator(f.as_array().iter().copied())),
        Some(f) => {
            return Err(PyValueError::new_err(format!(
                "field: expected shape (3,), got {:?}",
                f.shape()
            )))
        }
        None => None,
    };
    let moments: Vec<Inertia> = inertia
        .as_array()
        .iter()
        .map(|&i| Inertia::Spherical(i))
        .collect();
    let rotors: Vec<Rotor> = (0..n)
        .map(|i| Rotor {
            site: vector(&sites, i),
            inertia: moments[i],
            dipole_body: Some(vector(&dipoles_body, i)),
            quadrupole_body: None,
        })
        .collect();
    let q = orientations.as_array();
    let initial: Vec<RotorState> = (0..n)
        .map(|i| RotorState {
            orientation: Quat([q[(i, 0)], q[(i, 1)], q[(i, 2)], q[(i, 3)]]),
            omega_body: vector(&omega_body, i),
        })
        .collect();
    let external = ExternalFields {
        field,
        field_gradient: None,
    };
    let potential = MultipolePotential::new(&rotors, Boundary::Open, external)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let spherical = if split {
        SphericalTops::Split
    } else {
        SphericalTops::Exact
    };
    let samples = py
        .detach(|| on_worker(|| run(&moments, &potential, &initial, dt, steps, spherical)))
        .map_err(integrator_error)?;
    let out = PyDict::new(py);
    out.set_item("orientations", samples.orientations.into_pyarray(py))?;
    out.set_item("omega_body", samples.omega_body.into_pyarray(py))?;
    out.set_item("potential", samples.energy.into_pyarray(py))?;
    out.set_item("torques_space", samples.torques_space.into_pyarray(py))?;
    Ok(out)
}

/// Per-step samples of a run, recorded as an observer of the run loop: the
/// orientations and angular velocities it samples, the potential energy and
/// the torques evaluated here.
struct Samples<'a> {
    potential: &'a dyn Potential,
    torques: Vec<Vector3<f64>>,
    orientations: Array3<f64>,
    omega_body: Array3<f64>,
    energy: Array1<f64>,
    torques_space: Array3<f64>,
}

impl Observer for Samples<'_> {
    type Error = Infallible;

    fn needs(&self) -> Needs {
        Needs {
            omega_body: true,
            ..Needs::default()
        }
    }

    fn observe(&mut self, sample: &Sample<'_>) -> Result<(), Infallible> {
        let k = sample.step as usize;
        let q = sample.orientations;
        let omega = sample.omega_body.unwrap_or_default();
        self.torques.fill(Vector3::zeros());
        self.potential.accumulate_torques(q, &mut self.torques);
        self.energy[k] = self.potential.energy(q);
        for (i, ((q, w), t)) in q.iter().zip(omega).zip(&self.torques).enumerate() {
            for (c, x) in q.0.iter().enumerate() {
                self.orientations[(k, i, c)] = *x;
            }
            for c in 0..3 {
                self.omega_body[(k, i, c)] = w[c];
                self.torques_space[(k, i, c)] = t[c];
            }
        }
        Ok(())
    }
}

/// Sets DLM up and samples every step of the run loop (no blow-up checks:
/// the arrays are filled to the end).
fn run<'a>(
    inertia: &[Inertia],
    potential: &'a dyn Potential,
    initial: &[RotorState],
    dt: f64,
    steps: usize,
    spherical: SphericalTops,
) -> Result<Samples<'a>, IntegratorError> {
    let n = initial.len();
    let mut dlm = Dlm::new(DlmOptions {
        spherical_tops: spherical,
    });
    dlm.setup(inertia, potential, initial, dt)?;
    let mut samples = Samples {
        potential,
        torques: vec![Vector3::zeros(); n],
        orientations: Array3::zeros((steps + 1, n, 4)),
        omega_body: Array3::zeros((steps + 1, n, 3)),
        energy: Array1::zeros(steps + 1),
        torques_space: Array3::zeros((steps + 1, n, 3)),
    };
    let options = RunOptions {
        dt,
        start_step: 0,
        end_step: steps as u64,
        checks: None,
        reference: None,
        control: None,
    };
    let mut observers = [Scheduled {
        every: 1,
        at_end: false,
        observer: &mut samples,
    }];
    let Ok(_) = simulation::run(&mut dlm, potential, inertia, &mut observers, None, &options);
    Ok(samples)
}

/// Adds the functions of this module to `m`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(dlm_dipoles, m)?)
}
