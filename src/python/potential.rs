//! `quatrot.multipole_evaluate`: the point-multipole potential from numpy arrays.

use super::args::{invalid, optional_text};
use super::arrays::{collect, common_len, overflow, single, Items, Values};
use super::rotors::rotors;
use crate::checks::from_name;
use crate::potential::multipole::mesh_ewald::ForcedMesh;
use crate::potential::{
    Boundary, ExternalFields, MultipolePotential, PotentialError, SumMethod, SumOptions,
};
use crate::quaternion::Quat;
use nalgebra::{Matrix3, Vector3};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use serde::de::DeserializeOwned;

/// The boundary of the keywords: open when `box_lengths` is absent (and
/// none of the sum's options is given); periodic otherwise, in the
/// orthorhombic box `box_lengths` ((3,), or a diagonal (3, 3) matrix),
/// summed as the options say (read by their owner, [`Boundary::periodic`]).
pub(crate) fn boundary(
    box_lengths: Option<&Bound<'_, PyAny>>,
    options: &SumOptions,
) -> PyResult<Boundary> {
    let Some(box_lengths) = box_lengths else {
        if options.cutoff.is_some() {
            return Err(give_both());
        }
        if *options != SumOptions::default() {
            return Err(invalid(
                "box_lengths",
                "required with sum, accuracy or surface (periodic boundaries)",
            ));
        }
        return Ok(Boundary::Open);
    };
    Ok(Boundary::periodic(orthorhombic_box(box_lengths)?, options)?)
}

/// The boundary of `box_lengths` with `cutoff` (both, or neither for open
/// boundaries), for the bindings whose keywords have no Ewald sum.
pub(crate) fn cutoff_boundary(
    box_lengths: Option<&Bound<'_, PyAny>>,
    cutoff: Option<f64>,
) -> PyResult<Boundary> {
    if box_lengths.is_some() != cutoff.is_some() {
        return Err(give_both());
    }
    let options = SumOptions {
        cutoff,
        ..SumOptions::default()
    };
    boundary(box_lengths, &options)
}

/// The error of a cutoff without a box (or, where there is no Ewald sum, a box without a cutoff).
fn give_both() -> PyErr {
    invalid(
        "box_lengths, cutoff",
        "give both for periodic boundaries, or neither for open",
    )
}

/// The options of the sum from the keywords (`sum` and `surface` by name).
fn sum_options(
    sum: Option<&Bound<'_, PyAny>>,
    cutoff: Option<f64>,
    accuracy: Option<f64>,
    surface: Option<&Bound<'_, PyAny>>,
) -> PyResult<SumOptions> {
    Ok(SumOptions {
        sum: by_name(sum, "sum")?,
        cutoff,
        accuracy,
        surface: by_name(surface, "surface")?,
    })
}

/// The mesh counts of the keyword `grid`: one int, or a sequence of them.
fn grid_counts(grid: &Bound<'_, PyAny>) -> PyResult<Vec<i64>> {
    grid.extract::<i64>()
        .map(|k| vec![k])
        .or_else(|_| grid.extract::<Vec<i64>>())
        .map_err(|_| invalid("grid", "expected an int or a sequence of 3 ints"))
}

/// The value named by the optional text `obj` (argument `name`).
fn by_name<T: DeserializeOwned>(obj: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<T>> {
    let Some(text) = optional_text(obj, name)? else {
        return Ok(None);
    };
    Ok(Some(from_name(name, &text)?))
}

/// The box edges of `box_lengths`: a 3-vector, or a 3x3 matrix whose rows
/// are the box vectors, which must be diagonal (orthorhombic).
fn orthorhombic_box(box_lengths: &Bound<'_, PyAny>) -> PyResult<Vector3<f64>> {
    if let Ok(Some(l)) = single(Some(box_lengths), "box_lengths", &[3]) {
        return Ok(l.vector(0));
    }
    let Ok(Some(m)) = single(Some(box_lengths), "box_lengths", &[3, 3]) else {
        return Err(invalid(
            "box_lengths",
            "expected the box edges (3,) or the box vectors (3, 3)",
        ));
    };
    let m = m.matrix(0);
    let off_diagonal = (m - Matrix3::from_diagonal(&m.diagonal())).amax();
    if off_diagonal != 0.0 {
        return Err(invalid(
            "box_lengths",
            format!(
                "the box must be orthorhombic (a diagonal matrix of box vectors), \
                 got off-diagonal entries up to {off_diagonal:e}"
            ),
        ));
    }
    Ok(m.diagonal())
}

/// Energy, eq 14 gradient and torques of point multipoles on fixed sites.
///
/// Reduced units, `4 pi eps0 = 1`. Boundaries: open (no `box_lengths`), or
/// periodic in the box `box_lengths`, summed as a scene's `sum`, `cutoff`,
/// `accuracy` and `surface` say: the Ewald sum by default; every image
/// within `cutoff` (a rotor's own images included) with `sum="cutoff"` or a
/// `cutoff` alone.
///
/// Parameters
/// ----------
/// sites : array_like, shape (n, 3)
///     Fixed positions.
/// orientations : array_like, shape (n, 4)
///     Quaternions, scalar first, body to space.
/// dipoles_body : array_like, shape (n, 3) or (3,), optional
///     Body-frame dipoles (zero rows: no dipole).
/// quadrupoles_body : array_like, shape (n, 3, 3) or (3, 3), optional
///     Body-frame Buckingham quadrupoles, symmetric and traceless.
/// field : array_like, shape (3,), optional
///     Uniform external field.
/// field_gradient : array_like, shape (3, 3), optional
///     Uniform field gradient, `[a, b] = dE_b/dr_a`.
/// box_lengths : array_like, shape (3,) or diagonal (3, 3), optional
///     The periodic box's edges; absent: open boundaries.
/// cutoff : float, optional
///     The truncated periodic sum's cutoff (may exceed half the box).
/// sum : {"ewald", "cutoff"}, optional
///     The periodic sum (default "ewald"; "cutoff" when only `cutoff` is
///     given).
/// accuracy : float, optional
///     The Ewald sum's relative accuracy (default 1e-12).
/// surface : {"conducting", "vacuum"}, optional
///     The Ewald sum's surroundings (default "conducting").
/// method : {"auto", "direct", "lattice_fft", "pme"}, optional
///     "auto" (default): the FFT lattice sum for an Ewald sum on a lattice,
///     on other sites the cheaper of the direct Ewald sum and PME by their
///     cost models (the direct sum for small systems and for accuracies
///     PME cannot reach), the pair sums otherwise; "pme": the smooth
///     particle-mesh Ewald sum (`sum="ewald"` only; accuracy from 1e-10 to
///     1e-2).
/// order : int, optional
///     PME's B-spline order forced, 4 to 8 (`method="pme"` only, as the
///     next three; what is not forced is chosen for `accuracy`).
/// grid : int or sequence of 3 ints, optional
///     PME's mesh points along x, y, z forced (one int: every axis).
/// real_cutoff : float, optional
///     PME's real-space cutoff forced (at most half the shortest box side).
/// alpha : float, optional
///     PME's splitting parameter forced (inverse length).
/// details : bool, default False
///     Also return a dict of how the sum was made.
///
/// Returns
/// -------
/// energy : float
/// gradient : ndarray, shape (n, 4)
///     `dV/dq` (eq 14).
/// torques : ndarray, shape (n, 3)
///     Space-frame torques.
/// details : dict
///     With `details=True` only: the `path` used (`"open_pairs"`,
///     `"cutoff_pairs"`, `"cutoff_lattice_fft"`, `"ewald_direct"`,
///     `"ewald_lattice_fft"`, `"ewald_pme"`), for Ewald sums `alpha`,
///     `real_cutoff`, `reciprocal_cutoff` and the error estimates, for the
///     PME sum `alpha`, `real_cutoff`, `grid`, `order`, `real_estimate` and
///     `mesh_estimate`, for FFT sums `cells` and `basis`; when "auto" chose
///     between the direct sum and PME, `choice`: a dict of each path's
///     estimated `direct_seconds` and `pme_seconds` per evaluation (None
///     when that path cannot be built) and the `reason`.
///
/// Raises
/// ------
/// ValueError
///     For bad shapes, non-finite numbers, coincident sites, a keyword
///     combination that means nothing, sizes beyond the memory limit, or
///     forced PME parameters that do not reach `accuracy` (the message says
///     what they reach).
///
/// Examples
/// --------
/// ```python
///
/// Two dipoles along z one unit apart on the z axis (head to tail: energy -2):
///
/// >>> energy, gradient, torques = quatrot.multipole_evaluate(
/// ...     [[0, 0, 0], [0, 0, 1]], [[1, 0, 0, 0]] * 2, dipoles_body=[0, 0, 1])
/// >>> round(energy, 12)
/// -2.0
/// >>> torques.shape
/// (2, 3)
///
/// ```
#[pyfunction]
#[pyo3(signature = (sites, orientations, dipoles_body=None, quadrupoles_body=None, field=None, field_gradient=None, box_lengths=None, cutoff=None, sum=None, accuracy=None, surface=None, method=None, order=None, grid=None, real_cutoff=None, alpha=None, details=false))]
#[allow(clippy::too_many_arguments)]
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
    sum: Option<&Bound<'py, PyAny>>,
    accuracy: Option<f64>,
    surface: Option<&Bound<'py, PyAny>>,
    method: Option<&Bound<'py, PyAny>>,
    order: Option<i64>,
    grid: Option<&Bound<'py, PyAny>>,
    real_cutoff: Option<f64>,
    alpha: Option<f64>,
    details: bool,
) -> PyResult<Bound<'py, PyTuple>> {
    let sites = Items::new(sites, "sites", &[3], Values::Finite)?;
    let orientations = Items::new(orientations, "orientations", &[4], Values::Quaternions)?;
    let dipoles = Items::optional(dipoles_body, "dipoles_body", &[3])?;
    let quadrupoles = Items::optional(quadrupoles_body, "quadrupoles_body", &[3, 3])?;
    let mut per_rotor = vec![&sites, &orientations];
    per_rotor.extend(dipoles.iter());
    per_rotor.extend(quadrupoles.iter());
    let batch = common_len(&per_rotor)?;
    let n = batch.0;
    let rotors = rotors(n, &sites, None, dipoles.as_ref(), quadrupoles.as_ref());
    let external = ExternalFields {
        field: single(field, "field", &[3])?.map(|e| e.vector(0)),
        field_gradient: single(field_gradient, "field_gradient", &[3, 3])?.map(|g| g.matrix(0)),
    };
    let options = sum_options(sum, cutoff, accuracy, surface)?;
    let boundary = boundary(box_lengths, &options)?;
    let method: SumMethod = by_name(method, "method")?.unwrap_or_default();
    let grid = grid.map(grid_counts).transpose()?;
    let forced = ForcedMesh::new(order, grid.as_deref(), real_cutoff, alpha)?;
    let q: Vec<Quat> = (0..n).map(|i| orientations.quat(i)).collect();
    let (energy, gradient, torques, potential) = py.detach(|| -> Result<_, PotentialError> {
        let potential =
            MultipolePotential::with_forced_mesh(&rotors, boundary, external, method, &forced)?;
        let mut gradient = vec![Quat::ZERO; n];
        let mut torques = vec![Vector3::zeros(); n];
        let energy = potential.evaluate(&q, Some(&mut gradient), Some(&mut torques));
        Ok((energy, gradient, torques, potential))
    })?;
    let values = std::iter::once(energy)
        .chain(gradient.iter().flat_map(|g| g.0))
        .chain(torques.iter().flat_map(|t| [t.x, t.y, t.z]));
    if let Some(x) = values.into_iter().find(|x| !x.is_finite()) {
        return Err(overflow(
            "the energy, gradient or torques of sites, dipoles_body, quadrupoles_body, field \
             and field_gradient",
            x,
        ));
    }
    let gradient = collect(py, batch, &[4], |i| Ok(gradient[i].0))?;
    let torques = collect(py, batch, &[3], |i| Ok(torques[i].into()))?;
    if !details {
        return (energy, gradient, torques).into_pyobject(py);
    }
    (energy, gradient, torques, details_dict(py, &potential)?).into_pyobject(py)
}

/// The `details` of an evaluation: the `path` of the sum, its Ewald or
/// mesh Ewald parameters and error estimates, the lattice of an FFT sum.
fn details_dict<'py>(
    py: Python<'py>,
    potential: &MultipolePotential,
) -> PyResult<Bound<'py, PyDict>> {
    let info = PyDict::new(py);
    info.set_item("path", potential.sum_path().as_str())?;
    if let Some(p) = potential.ewald_parameters() {
        info.set_item("alpha", p.alpha)?;
        info.set_item("real_cutoff", p.real_cutoff)?;
        info.set_item("reciprocal_cutoff", p.reciprocal_cutoff)?;
        info.set_item("real_estimate", p.real_estimate)?;
        info.set_item("reciprocal_estimate", p.reciprocal_estimate)?;
    }
    if let Some((p, e)) = potential.mesh_parameters() {
        info.set_item("alpha", p.alpha)?;
        info.set_item("real_cutoff", p.real_cutoff)?;
        info.set_item("grid", p.grid.to_vec())?;
        info.set_item("order", p.order)?;
        info.set_item("real_estimate", e.real)?;
        info.set_item("mesh_estimate", e.mesh)?;
    }
    if let Some(c) = potential.auto_choice() {
        let choice = PyDict::new(py);
        choice.set_item("direct_seconds", c.direct_seconds)?;
        choice.set_item("pme_seconds", c.pme_seconds)?;
        choice.set_item("reason", &c.reason)?;
        info.set_item("choice", choice)?;
    }
    if let Some(grid) = potential.lattice() {
        info.set_item("cells", grid.cells.to_vec())?;
        info.set_item("basis", grid.basis.len())?;
    }
    Ok(info)
}

/// Adds the potential functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(multipole_evaluate, m)?)
}
