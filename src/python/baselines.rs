//! `quatrot.dlm_dipoles`: quatrot's DLM on dipolar rotors with the multipole
//! potential (open boundaries) and an optional uniform field, sampled every
//! step ([`crate::experiments::every_step`]), for the LAMMPS comparison
//! (`validation/checks/lammps_dipoles.py`). Converts, checks and delegates.

use super::args::{check_memory, integer};
use super::arrays::{array, common_len, single, Items, Values};
use super::rotors::{rotors, states};
use crate::experiments::every_step::{every_step, EveryStep};
use crate::integrators::{DlmOptions, IntegratorSpec, SphericalTops};
use crate::parallel::on_worker;
use crate::potential::{Boundary, ExternalFields, MultipolePotential};
use crate::rotor::Inertia;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Runs DLM steps for dipolar spherical tops on fixed sites.
///
/// The Dullweber-Leimkuhler-McLachlan splitting as LAMMPS `fix nve/sphere
/// update dipole/dlm` integrates it, for the side-by-side comparison with
/// LAMMPS.
///
/// Parameters
/// ----------
/// sites : array_like, shape (n, 3)
///     Fixed positions (reduced length units).
/// dipoles_body : array_like, shape (n, 3)
///     Body-frame dipoles.
/// inertia : array_like, shape (n,)
///     Moments of inertia (> 0), one per spherical top.
/// orientations : array_like, shape (n, 4)
///     Initial quaternions, scalar first, body to space.
/// omega_body : array_like, shape (n, 3)
///     Initial body-frame angular velocities.
/// field : array_like, shape (3,) or None
///     Optional uniform field.
/// dt : float
///     Time step (> 0).
/// steps : int
///     Number of steps.
/// split : bool
///     True: the body-axis sweep for the free rotation (as LAMMPS); False:
///     the exact spherical-top flow.
///
/// Returns
/// -------
/// dict
///     Per-step samples, index 0 at t = 0: `orientations` (s+1, n, 4),
///     `omega_body` (s+1, n, 3), `potential` (s+1,), `torques_space`
///     (s+1, n, 3).
///
/// Raises
/// ------
/// ValueError
///     For a bad shape, a non-finite number or a zero quaternion (the message
///     names the argument).
///
/// Examples
/// --------
/// ```python
///
/// >>> out = quatrot.dlm_dipoles([[0, 0, 0]], [[0, 0, 1]], [0.1], [[1, 0, 0, 0]],
/// ...                           [[1.0, 0, 0]], [0, 0, 1.0], 0.01, 10, False)
/// >>> out["orientations"].shape
/// (11, 1, 4)
///
/// ```
#[pyfunction]
#[pyo3(signature = (sites, dipoles_body, inertia, orientations, omega_body, field, dt, steps, split))]
#[allow(clippy::too_many_arguments)]
fn dlm_dipoles<'py>(
    py: Python<'py>,
    sites: &Bound<'py, PyAny>,
    dipoles_body: &Bound<'py, PyAny>,
    inertia: &Bound<'py, PyAny>,
    orientations: &Bound<'py, PyAny>,
    omega_body: &Bound<'py, PyAny>,
    field: Option<&Bound<'py, PyAny>>,
    dt: f64,
    steps: &Bound<'py, PyAny>,
    split: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let sites = Items::new(sites, "sites", &[3], Values::Finite)?;
    let dipoles = Items::new(dipoles_body, "dipoles_body", &[3], Values::Finite)?;
    let moments = Items::new(inertia, "inertia", &[], Values::Finite)?;
    let q = Items::new(orientations, "orientations", &[4], Values::Quaternions)?;
    let w = Items::new(omega_body, "omega_body", &[3], Values::Finite)?;
    let (n, _) = common_len(&[&sites, &dipoles, &moments, &q, &w])?;
    let steps = integer(steps, "steps", 0, u64::MAX)?;
    check_memory("steps", EveryStep::bytes(n, steps))?;
    let rotors = rotors(n, &sites, Some(&moments), Some(&dipoles), None);
    let initial = states(n, &q, &w);
    let external = ExternalFields {
        field: single(field, "field", &[3])?.map(|f| f.vector(0)),
        field_gradient: None,
    };
    let potential = MultipolePotential::new(&rotors, Boundary::Open, external)?;
    let inertia: Vec<Inertia> = rotors.iter().map(|r| r.inertia).collect();
    let spherical_tops = if split {
        SphericalTops::Split
    } else {
        SphericalTops::Exact
    };
    let mut dlm = IntegratorSpec::Dlm(DlmOptions { spherical_tops }).build();
    let samples = py.detach(|| {
        on_worker(|| every_step(dlm.as_mut(), &inertia, &potential, &initial, dt, steps))
    })?;
    let s = samples.energy.len();
    let out = PyDict::new(py);
    out.set_item("orientations", array(py, &[s, n, 4], samples.orientations)?)?;
    out.set_item("omega_body", array(py, &[s, n, 3], samples.omega_body)?)?;
    out.set_item("potential", array(py, &[s], samples.energy)?)?;
    out.set_item(
        "torques_space",
        array(py, &[s, n, 3], samples.torques_space)?,
    )?;
    Ok(out)
}

/// Adds the functions of this module to `m`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(dlm_dipoles, m)?)
}
