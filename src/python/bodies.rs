//! `quatrot.bodies_evaluate`: the state of a system of moving rigid bodies
//! at one configuration, without running it.

use super::args::invalid;
use super::arrays::{array, collect, common_len, row_major, single, Items, Values};
use super::scene_dict::{scene_error, to_toml};
use crate::bodies::{
    Body, BodySystem, ElectrostaticTruncation, ElectrostaticsOptions, Evaluation,
    InteractionOptions, LennardJonesOptions, Mixing, Space, Truncation,
};
use crate::checks::{from_name, InputError};
use crate::scene::{body_electrostatics, body_types};
use crate::units::{Dimension, Units};
use nalgebra::Vector3;
use numpy::PyArrayDyn;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The library's path of a body's value as the argument that holds it
/// (`bodies[3].orientation` is `orientations[3]`; `electrostatics.cutoff`
/// is `electrostatic_cutoff` unless the `electrostatics` table was given).
fn argument_path(e: InputError, table: bool) -> PyErr {
    if e.path == "lennard_jones.cutoff" {
        return invalid("lj_cutoff", e.message);
    }
    if e.path.starts_with("electrostatics") && !table {
        return invalid("electrostatic_cutoff", e.message);
    }
    let renamed = [
        ("kind", "kinds"),
        ("position", "positions"),
        ("orientation", "orientations"),
        ("velocity", "velocities"),
    ]
    .iter()
    .find_map(|(field, argument)| {
        let rest = e.path.strip_prefix("bodies[")?;
        let (index, tail) = rest.split_once(']')?;
        let tail = tail.strip_prefix('.')?.strip_prefix(field)?;
        Some(format!("{argument}[{index}]{tail}"))
    });
    invalid(&renamed.unwrap_or(e.path), e.message)
}

/// Energies by term, forces and torques per body, site forces and the
/// virial of rigid bodies at one configuration.
///
/// In `units`: reduced (`4 pi eps0 = 1`, `k_B = 1`), or real (Angstrom,
/// g/mol, kcal/mol, fs, e, Debye, atm, as LAMMPS `units real`). Sites of different bodies
/// interact (never within one): Lennard-Jones truncated at `lj_cutoff`,
/// charges and point dipoles truncated at `electrostatic_cutoff` as LAMMPS
/// `pair_style lj/cut/dipole/cut` (bare pair energies, no shift; the
/// `electrostatics` table may ask for shifted force). Each body
/// type's frame is rotated to its principal axes: an orientation here is
/// that of the principal frame.
///
/// Parameters
/// ----------
/// body_types : list of dict
///     Each ``{"sites": [...], "mass": m, "inertia": [[...]] * 3}`` (mass
///     and inertia default to those of the site masses); each site
///     ``{"position": [x, y, z], "mass": m, "lennard_jones": {"epsilon":
///     e, "sigma": s}, "charge": q, "dipole": [...]}``, all but the
///     position optional.
/// positions : array_like, shape (n, 3)
///     Body centres.
/// orientations : array_like, shape (n, 4)
///     Quaternions, scalar first, principal body frame to space.
/// kinds : sequence of int, shape (n,), optional
///     Each body's index in `body_types` (default all 0).
/// velocities : array_like, shape (n, 3), optional
///     Centre velocities, for the kinetic part of the pressure (default 0).
/// box_lengths : array_like, shape (3,), optional
///     The periodic orthorhombic box; absent: open space.
/// lj_cutoff : float, optional
///     Lennard-Jones cutoff (required when a site has Lennard-Jones).
/// truncation : {"plain", "shifted", "force_shifted"}, default "plain"
///     The Lennard-Jones truncation (tail corrections for "plain" in a box).
/// mixing : {"lorentz_berthelot", "geometric"}, default "lorentz_berthelot"
///     The Lennard-Jones mixing rule of unlike sites.
/// electrostatic_cutoff : float, optional
///     Charges' and dipoles' cutoff (required when a site has one, unless
///     `electrostatics` is given).
/// electrostatics : dict, optional
///     Instead of `electrostatic_cutoff`, a scene's ``[body_interactions]
///     electrostatics`` table: ``{"kind": "cutoff", "cutoff": r,
///     "truncation": "plain"}`` (or ``"shifted_force"``, LAMMPS
///     ``lj/sf/dipole/sf``) or
///     ``{"kind": "ewald", "accuracy": 1e-6, "method": "pme", "surface":
///     "conducting"}`` (a periodic box; with ``"pme"`` also the forced
///     ``"order"``, ``"grid"``, ``"real_cutoff"`` and ``"alpha"``), with a
///     scene's defaults and checks.
/// units : {"reduced", "real"}, default "reduced"
///     The units of every value given and returned (real: velocities in
///     Angstrom/fs, energies in kcal/mol, forces in kcal/(mol Angstrom),
///     torques and the virial in kcal/mol, pressures in atm; a body type
///     may then name a water model, ``{"model": "spce"}``).
///
/// Returns
/// -------
/// dict
///     ``energies`` (dict: ``lennard_jones``, ``lennard_jones_tail``,
///     ``electrostatic``, ``total``), ``forces`` and ``torques`` (n, 3,
///     space frame, torques about the centres), ``site_forces`` (sites of
///     body 0, then of body 1, ..., 3), ``virial`` (3, 3, the molecular
///     virial ``sum_pairs R_IJ f_ij^T``), ``pressure`` (float in a box,
///     else None; its tail correction included), ``pressure_tail`` and
///     ``site_positions`` (the sites' positions in space, in the order of
///     ``site_forces``).
///
/// Raises
/// ------
/// ValueError
///     For bad shapes or values (named), a box shorter than twice the
///     largest cutoff plus 0.3, forced PME parameters that do not reach the
///     accuracy (``electrostatics.grid: ...``, saying what they reach).
/// quatrot.SceneError
///     For a bad body type (the field named: ``body_types[0].mass``).
///
/// Examples
/// --------
/// ```python
///
/// Two Lennard-Jones spheres at the potential's minimum, 2^(1/6) apart:
///
/// >>> sphere = {"sites": [{"position": [0, 0, 0], "lennard_jones":
/// ...     {"epsilon": 1.0, "sigma": 1.0}}], "mass": 1.0, "inertia": [[0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]]}
/// >>> state = quatrot.bodies_evaluate([sphere], [[0, 0, 0], [2 ** (1 / 6), 0, 0]],
/// ...     [[1, 0, 0, 0]] * 2, lj_cutoff=2.5)
/// >>> round(state["energies"]["total"], 12)
/// -1.0
/// >>> bool(abs(state["forces"]).max() < 1e-12)
/// True
///
/// In real units, two unit charges 1 Angstrom apart have the Coulomb
/// constant's energy in kcal/mol (CODATA 2018):
///
/// >>> ion = {"sites": [{"position": [0, 0, 0], "charge": 1.0}], "mass": 1.0,
/// ...     "inertia": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}
/// >>> state = quatrot.bodies_evaluate([ion], [[0, 0, 0], [1, 0, 0]], [[1, 0, 0, 0]] * 2,
/// ...     electrostatic_cutoff=5.0, units="real")
/// >>> round(state["energies"]["electrostatic"], 7)
/// 332.0637133
///
/// ```
#[pyfunction]
#[pyo3(signature = (body_types, positions, orientations, *, kinds=None, velocities=None, box_lengths=None, lj_cutoff=None, truncation=None, mixing=None, electrostatic_cutoff=None, electrostatics=None, units=None))]
#[allow(clippy::too_many_arguments)]
fn bodies_evaluate<'py>(
    py: Python<'py>,
    body_types: &Bound<'py, PyAny>,
    positions: &Bound<'py, PyAny>,
    orientations: &Bound<'py, PyAny>,
    kinds: Option<Vec<usize>>,
    velocities: Option<&Bound<'py, PyAny>>,
    box_lengths: Option<&Bound<'py, PyAny>>,
    lj_cutoff: Option<f64>,
    truncation: Option<&str>,
    mixing: Option<&str>,
    electrostatic_cutoff: Option<f64>,
    electrostatics: Option<&Bound<'py, PyAny>>,
    units: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    let units = named::<Units>(units, "units")?;
    let table = electrostatics.is_some();
    let electrostatics = electrostatics_choice(electrostatic_cutoff, electrostatics)?;
    let types = body_types_of(body_types, units)?;
    let positions = Items::new(positions, "positions", &[3], Values::Finite)?;
    let orientations = Items::new(orientations, "orientations", &[4], Values::Quaternions)?;
    let velocities = Items::optional(velocities, "velocities", &[3])?;
    let mut per_body = vec![&positions, &orientations];
    per_body.extend(velocities.iter());
    let (n, _) = common_len(&per_body)?;
    let kinds = kinds.unwrap_or_else(|| vec![0; n]);
    if kinds.len() != n {
        let message = format!("expected {n} kinds (one per body), got {}", kinds.len());
        return Err(invalid("kinds", message));
    }
    let bodies = (0..n)
        .map(|i| Body {
            kind: kinds[i],
            position: positions.vector(i),
            image: [0; 3],
            velocity: velocities.as_ref().map_or(Vector3::zeros(), |v| {
                v.vector(i).map(|c| units.to_internal(c, Dimension::Rate))
            }),
            orientation: orientations.quat(i),
            angular_momentum_body: Vector3::zeros(),
        })
        .collect();
    let space = match single(box_lengths, "box_lengths", &[3])? {
        Some(l) => Space::Periodic(l.vector(0)),
        None => Space::Open,
    };
    let options = InteractionOptions {
        lennard_jones: lj_cutoff
            .map(|cutoff| -> PyResult<_> {
                Ok(LennardJonesOptions {
                    cutoff,
                    truncation: named::<Truncation>(truncation, "truncation")?,
                    mixing: named::<Mixing>(mixing, "mixing")?,
                })
            })
            .transpose()?,
        electrostatics,
        skin: DEFAULT_SKIN,
    };
    let mut system =
        BodySystem::new(types, bodies, space, &options).map_err(|e| argument_path(e, table))?;
    let (evaluation, pressure) = py.detach(|| {
        let mut e = Evaluation::default();
        system.evaluate(&mut e);
        let pressure = system.pressure(&e);
        (e, pressure)
    });
    let in_units = |p: f64| units.from_internal(p, Dimension::Pressure);
    let pressures = (pressure.map(in_units), in_units(evaluation.pressure_tail));
    let out = result(py, &evaluation, pressures)?;
    out.set_item("site_positions", rows(py, &site_positions(&system))?)?;
    Ok(out)
}

/// The sites' positions in space, bodies in order, each body's sites in order.
fn site_positions(system: &BodySystem) -> Vec<Vector3<f64>> {
    system
        .bodies
        .iter()
        .flat_map(|b| {
            let sites = &system.types[b.kind].sites;
            sites
                .iter()
                .map(|s| b.position + b.orientation.body_to_space(&s.position))
        })
        .collect()
}

/// The electrostatics of `electrostatic_cutoff` or of the `electrostatics`
/// table (not both).
fn electrostatics_choice(
    cutoff: Option<f64>,
    table: Option<&Bound<'_, PyAny>>,
) -> PyResult<Option<ElectrostaticsOptions>> {
    match (cutoff, table) {
        (Some(_), Some(_)) => {
            let message = "give electrostatic_cutoff or electrostatics, not both".to_string();
            Err(invalid("electrostatics", message))
        }
        (Some(cutoff), None) => Ok(Some(ElectrostaticsOptions::Cutoff(
            cutoff,
            ElectrostaticTruncation::Plain,
        ))),
        (None, Some(value)) => body_electrostatics(to_toml(value, "electrostatics")?)
            .map(Some)
            .map_err(|e| scene_error(&e)),
        (None, None) => Ok(None),
    }
}

/// The neighbour lists' skin of an evaluation (any value gives the same
/// result; LAMMPS's default in LJ units).
const DEFAULT_SKIN: f64 = 0.3;

fn body_types_of(value: &Bound<'_, PyAny>, units: Units) -> PyResult<Vec<crate::bodies::BodyType>> {
    body_types(to_toml(value, "body_types")?, units).map_err(|e| scene_error(&e))
}

/// The choice named `name` (argument `argument`), the default when absent.
fn named<T: serde::de::DeserializeOwned + Default>(
    name: Option<&str>,
    argument: &str,
) -> PyResult<T> {
    name.map_or(Ok(T::default()), |n| Ok(from_name(argument, n)?))
}

/// The rows of `v` as an (n, 3) array.
fn rows<'py>(py: Python<'py>, v: &[Vector3<f64>]) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    collect(py, (v.len(), false), &[3], |i| Ok(v[i].into()))
}

/// The result dict of `e`, with the pressure and its tail correction.
fn result<'py>(
    py: Python<'py>,
    e: &Evaluation,
    (pressure, pressure_tail): (Option<f64>, f64),
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let energies = PyDict::new(py);
    energies.set_item("lennard_jones", e.lennard_jones)?;
    energies.set_item("lennard_jones_tail", e.lennard_jones_tail)?;
    energies.set_item("electrostatic", e.electrostatic)?;
    energies.set_item("total", e.potential_energy())?;
    out.set_item("energies", energies)?;
    out.set_item("forces", rows(py, &e.force)?)?;
    out.set_item("torques", rows(py, &e.torque)?)?;
    out.set_item("site_forces", rows(py, &e.site_force)?)?;
    out.set_item("virial", array(py, &[3, 3], row_major(&e.virial).to_vec())?)?;
    out.set_item("pressure", pressure)?;
    out.set_item("pressure_tail", pressure_tail)?;
    Ok(out)
}

/// Adds the bodies' functions to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(bodies_evaluate, m)?)
}
