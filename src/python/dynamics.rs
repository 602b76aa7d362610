//! `quatrot.gear_corrections_table`: the note's experiment
//! ([`crate::experiments::gear_corrections`]) on pinned multipolar rotors
//! given as numpy arrays. Converts and checks the arrays, then delegates.

use super::args::{check_memory, optional_integer};
use super::arrays::{common_len, single, Items, Values};
use super::potential::cutoff_boundary;
use super::rotors::{rotors, states};
use crate::experiments::gear_corrections::{correction_table, Row, Settings, System};
use crate::integrators::setup_checks::{validate_setup, Moments};
use crate::parallel::on_worker;
use crate::potential::{ExternalFields, MultipolePotential};
use crate::rotor::Inertia;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Bytes per energy sample of one run (time, kinetic and total energy, the
/// norm diagnostics), times the experiment's configurations run at once: an
/// upper estimate.
const SAMPLE_BYTES: u64 = 8 * 8 * 8;

/// The note's experiment: scheme A against scheme B with each correction.
///
/// Arrays are float64 for `n` rotors; an item without the leading `n`
/// applies to every rotor.
///
/// Parameters
/// ----------
/// sites : array_like, shape (n, 3)
/// inertia : array_like, shape (n, 3)
///     Principal moments (all equal: spherical tops).
/// orientations : array_like, shape (n, 4)
///     Scalar first.
/// omega_body : array_like, shape (n, 3)
/// dipoles, quadrupoles : array_like, shape (n, 3) and (n, 3, 3), optional
///     Body frame; quadrupoles Buckingham.
/// field : array_like, shape (3,), optional
///     Uniform field.
/// box_lengths : array_like, shape (3,), optional
///     A periodic box, with `cutoff`.
/// cutoff : float, optional
/// dt : float, default 0.02
///     The time step of the energy runs.
/// t_energy, t_error, t_stability : float, default 100, 5, 20
///     Lengths (time units) of the energy runs, the error runs against a
///     reference, and the stability search's runs.
/// sample_every : int, optional
///     Sampling interval of the energy runs.
///
/// Returns
/// -------
/// list of dict
///     One per configuration, with keys `label`, `drift`, `fluctuation`,
///     `global_error`, `order`, `largest_stable_dt`, `max_q_dot_q_dot`,
///     `max_q_dot_force` (the Rust docs of `experiments::gear_corrections`
///     define them).
///
/// Examples
/// --------
/// ```python
///
/// >>> rows = quatrot.gear_corrections_table([[0, 0, 0]], [[0.1] * 3], [[1, 0, 0, 0]],
/// ...     [[0, 0, 0]], dipoles=[[0, 0, 1]], field=[0.5, 0, 1], t_energy=2,
/// ...     t_error=1, t_stability=1)
/// >>> rows[0]["label"]
/// 'A (renormalised)'
/// >>> sorted(rows[0])[:3]
/// ['drift', 'fluctuation', 'global_error']
///
/// ```
#[pyfunction]
#[pyo3(signature = (
    sites, inertia, orientations, omega_body, *, dipoles=None, quadrupoles=None, field=None,
    box_lengths=None, cutoff=None, dt=0.02, t_energy=100.0, t_error=5.0, t_stability=20.0,
    sample_every=None
))]
#[allow(clippy::too_many_arguments)]
fn gear_corrections_table<'py>(
    py: Python<'py>,
    sites: &Bound<'py, PyAny>,
    inertia: &Bound<'py, PyAny>,
    orientations: &Bound<'py, PyAny>,
    omega_body: &Bound<'py, PyAny>,
    dipoles: Option<&Bound<'py, PyAny>>,
    quadrupoles: Option<&Bound<'py, PyAny>>,
    field: Option<&Bound<'py, PyAny>>,
    box_lengths: Option<&Bound<'py, PyAny>>,
    cutoff: Option<f64>,
    dt: f64,
    t_energy: f64,
    t_error: f64,
    t_stability: f64,
    sample_every: Option<&Bound<'py, PyAny>>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let sites = Items::new(sites, "sites", &[3], Values::Finite)?;
    let moments = Items::new(inertia, "inertia", &[3], Values::Finite)?;
    let q = Items::new(orientations, "orientations", &[4], Values::Quaternions)?;
    let w = Items::new(omega_body, "omega_body", &[3], Values::Finite)?;
    let dipoles = Items::optional(dipoles, "dipoles", &[3])?;
    let quadrupoles = Items::optional(quadrupoles, "quadrupoles", &[3, 3])?;
    let mut batch = vec![&sites, &moments, &q, &w];
    batch.extend(dipoles.iter().chain(quadrupoles.iter()));
    let (n, _) = common_len(&batch)?;
    let field = single(field, "field", &[3])?.map(|f| f.vector(0));
    let boundary = cutoff_boundary(box_lengths, cutoff)?;
    let rotors = rotors(
        n,
        &sites,
        Some(&moments),
        dipoles.as_ref(),
        quadrupoles.as_ref(),
    );
    let initial = states(n, &q, &w);
    let external = ExternalFields {
        field,
        field_gradient: None,
    };
    let potential = MultipolePotential::new(&rotors, boundary, external)?;
    let settings = settings(dt, [t_energy, t_error, t_stability], sample_every)?;
    // Validate the rotors and states once, so the experiment itself cannot fail.
    let inertia: Vec<Inertia> = rotors.iter().map(|r| r.inertia).collect();
    let _ = validate_setup(&inertia, &initial, dt, Moments::Positive)?;
    let table = py.detach(|| {
        on_worker(|| {
            let system = System {
                potential: &potential,
                inertia: &inertia,
                initial: &initial,
            };
            correction_table(&system, &settings)
        })
    });
    table.into_iter().map(|row| row_dict(py, row)).collect()
}

/// The experiment's settings from the keywords, checked, with the memory of
/// the energy samples of its longest run (for each configuration) checked.
fn settings(
    dt: f64,
    [t_energy, t_error, t_stability]: [f64; 3],
    sample_every: Option<&Bound<'_, PyAny>>,
) -> PyResult<Settings> {
    let settings = Settings {
        dt,
        t_energy,
        t_error,
        t_stability,
        sample_every: optional_integer(sample_every, "sample_every", 0, u64::MAX)?.unwrap_or(1),
    };
    settings.check()?;
    let samples =
        (t_energy.max(t_error).max(t_stability) / dt / settings.sample_every as f64).ceil();
    let bytes = (samples < 1e18).then(|| samples as u64 * SAMPLE_BYTES);
    check_memory("t_energy, dt, sample_every", bytes)?;
    Ok(settings)
}

/// One row of the table as a dict.
fn row_dict<'py>(py: Python<'py>, row: Row) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("label", row.label)?;
    d.set_item("drift", row.drift)?;
    d.set_item("fluctuation", row.fluctuation)?;
    d.set_item("global_error", row.global_error)?;
    d.set_item("order", row.order)?;
    d.set_item("largest_stable_dt", row.largest_stable_dt)?;
    d.set_item("max_q_dot_q_dot", row.max_norm_velocity)?;
    d.set_item("max_q_dot_force", row.max_norm_force)?;
    Ok(d)
}

/// Adds this submodule's functions to the `quatrot` module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(gear_corrections_table, m)?)
}
