"""Rigid water in real units against OpenMM (issue 41, items 1-3).

A small open cluster of 8 water molecules, all pairs (cutoffs above the
cluster's size), Lennard-Jones on O only, each molecule's own pairs
excluded: quatrot's ``bodies_evaluate(units="real")`` against OpenMM's
``NonbondedForce`` (NoCutoff, Reference platform, double precision) built
here from the models' published parameters (restated below from the papers,
not read from quatrot). Energies by term and site forces agree to round-off
once the two codes' Coulomb constants are divided out: both are measured
(two unit charges 1 Angstrom apart) and their ratio is the ratio of the
electrostatic energies. quatrot uses CODATA 2018 (332.0637133 kcal A/(mol
e^2)), as OpenMM does, so the ratio is 1 to round-off; LAMMPS's 332.06371
would make it 1 - 9.9e-9 (test_unit_constants.py).

Then a short constant-energy run of a water cluster in real units, from the
CLI and from Python, against the same run written in the engine's reduced
units by hand (charges times sqrt(C), time in units of 48.888 fs): the same
trajectory, so the same energy conservation and integrator order.
"""

import csv
import json
import math
import subprocess
import sys

import numpy as np
import pytest

import quatrot

pytest.importorskip("openmm")

from validation.shared.openmm_water import KJ_PER_KCAL, PUBLISHED, openmm_water, site_parameters  # noqa: E402
from validation.shared.water_runs import quatrot_coulomb_constant  # noqa: E402
from validation.tests.test_unit_constants import openmm_coulomb_kcal_per_mol_angstrom  # noqa: E402

MOLECULES = 8
CUTOFF = 30.0  # Angstrom: above the cluster's size, so every pair counts
# Round-off of sums of ~100 pair terms of either sign, relative to the
# largest term.
ROUND_OFF = 1e-11


def cluster(seed=11):
    """8 centres on a 2 x 2 x 2 grid 3.1 A apart, jittered, random orientations."""
    rng = np.random.default_rng(seed)
    grid = np.array([[i, j, k] for i in range(2) for j in range(2) for k in range(2)], float)
    positions = grid * 3.1 + rng.uniform(-0.2, 0.2, (MOLECULES, 3))
    q = rng.normal(size=(MOLECULES, 4))
    return positions, q / np.linalg.norm(q, axis=1, keepdims=True)


@pytest.mark.parametrize("model", sorted(PUBLISHED))
def test_a_water_cluster_matches_openmm_by_term(model):
    """Energies by term (kcal/mol and kJ/mol), site forces, body forces and
    torques of 8 rigid molecules against OpenMM; the electrostatic energies'
    ratio is the ratio of the two codes' Coulomb constants."""
    positions, orientations = cluster()
    state = quatrot.bodies_evaluate(
        [{"model": model}], positions, orientations,
        lj_cutoff=CUTOFF, electrostatic_cutoff=CUTOFF, units="real",
    )
    sites = state["site_positions"]
    parameters = site_parameters(model)
    assert sites.shape == (MOLECULES * len(parameters), 3)
    reference, site_forces = openmm_water(sites, model, MOLECULES)
    reference_kj = {k: v * KJ_PER_KCAL for k, v in reference.items()}
    energies = state["energies"]
    c_quatrot, c_openmm = quatrot_coulomb_constant(), openmm_coulomb_kcal_per_mol_angstrom()
    print(f"{model}: Coulomb constants quatrot {c_quatrot!r}, OpenMM {c_openmm!r} kcal A/(mol e^2)")
    assert c_quatrot / c_openmm == pytest.approx(1.0, abs=1e-14)  # both CODATA 2018
    ratio = energies["electrostatic"] / reference["electrostatic"]
    assert ratio == pytest.approx(c_quatrot / c_openmm, abs=ROUND_OFF)
    assert energies["lennard_jones"] == pytest.approx(reference["lennard_jones"], rel=ROUND_OFF)
    assert energies["lennard_jones_tail"] == 0.0
    total_kj = energies["total"] * KJ_PER_KCAL
    assert total_kj == pytest.approx(sum(reference_kj.values()), rel=ROUND_OFF)
    scale = np.abs(site_forces).max()
    np.testing.assert_allclose(state["site_forces"], site_forces, rtol=0, atol=ROUND_OFF * scale)
    per = len(parameters)
    body_forces = site_forces.reshape(MOLECULES, per, 3).sum(axis=1)
    arms = sites.reshape(MOLECULES, per, 3) - positions[:, None, :]
    torques = np.cross(arms, site_forces.reshape(MOLECULES, per, 3)).sum(axis=1)
    np.testing.assert_allclose(state["forces"], body_forces, rtol=0, atol=ROUND_OFF * scale)
    np.testing.assert_allclose(state["torques"], torques, rtol=0, atol=ROUND_OFF * scale)


# The engine's units of a real-units scene, from the SI definitions (the
# test's own arithmetic): time unit sqrt(1e7 / 4184) fs, charge times sqrt(C).
TIME_UNIT_FS = math.sqrt(1e7 / 4184)
COULOMB = 1.602176634e-19**2 * 6.02214076e23 / (4 * math.pi * 8.8541878128e-12) / 4184 * 1e10


def nve_scene(units, dt_fs, steps):
    """8 SPC/E molecules at rest in open space, all pairs: in real units
    naming the model, or in reduced units with the sites written out and
    converted by hand."""
    positions, orientations = cluster()
    velocities = np.random.default_rng(5).normal(scale=0.004, size=(MOLECULES, 3))  # A/fs
    if units == "real":
        body_type, scale, dt = {"model": "spce"}, 1.0, dt_fs
    else:
        p = PUBLISHED["spce"]
        half = math.radians(p["angle"] / 2)
        x, z = p["r"] * math.sin(half), p["r"] * math.cos(half)
        charge = math.sqrt(COULOMB)
        lj = {"epsilon": p["epsilon"], "sigma": p["sigma"]}
        body_type = {"sites": [
            {"position": [0, 0, 0], "mass": 15.9994, "charge": -2 * p["q_h"] * charge, "lennard_jones": lj},
            {"position": [x, 0, z], "mass": 1.008, "charge": p["q_h"] * charge},
            {"position": [-x, 0, z], "mass": 1.008, "charge": p["q_h"] * charge},
        ]}
        scale, dt = TIME_UNIT_FS, dt_fs / TIME_UNIT_FS
    bodies = [
        {"position": r.tolist(), "orientation": q.tolist(), "velocity": (v * scale).tolist()}
        for r, q, v in zip(positions, orientations, velocities)
    ]
    scene = {
        "version": 1,
        "name": f"water_nve_{units}",
        "body_types": [body_type],
        "bodies": {"kind": "given", "list": bodies},
        "body_interactions": {
            "lennard_jones": {"cutoff": CUTOFF},
            "electrostatics": {"kind": "cutoff", "cutoff": CUTOFF},
        },
        "integrator": {"kind": "no_squish"},
        "run": {"dt": dt, "steps": steps},
        "record": {"series": [{"name": "energies", "every": 10, "quantities": ["total_energy", "T_trans"]}]},
    }
    if units == "real":
        scene["units"] = "real"
    return scene


def energy_error(series):
    total = series["total_energy"]
    return np.abs(total - total[0]).max()


def test_a_real_units_run_is_the_reduced_run_converted():
    """The same 8-molecule SPC/E run written in real units and, converted by
    hand, in reduced units: the same energies (kcal/mol in both) and
    temperatures (K against k_B T), times in fs against time units; the
    summary names its units and the constants used."""
    steps = 200
    real = quatrot.run(nve_scene("real", 0.5, steps))
    reduced = quatrot.run(nve_scene("reduced", 0.5, steps))
    a, b = real["series"]["energies"], reduced["series"]["energies"]
    np.testing.assert_allclose(a["time"], b["time"] * TIME_UNIT_FS, rtol=1e-14)
    np.testing.assert_allclose(a["total_energy"], b["total_energy"], rtol=1e-10)
    boltzmann = 1.380649e-23 * 6.02214076e23 / 4184
    np.testing.assert_allclose(a["T_trans"] * boltzmann, b["T_trans"], rtol=1e-9)
    units = real["summary"]["units"]
    assert (units["time"], units["energy"], units["temperature"]) == ("fs", "kcal/mol", "K")
    assert units["coulomb_constant"] == pytest.approx(COULOMB, rel=1e-15)
    assert "units" not in reduced["summary"]
    assert real["summary"]["dt"] == 0.5


def test_a_real_units_run_keeps_its_integrator_order():
    """NO_SQUISH is second order in real units as in reduced ones: halving
    dt divides the largest energy error of 100 fs by about 4."""
    errors = [energy_error(quatrot.run(nve_scene("real", dt, int(100 / dt)))["series"]["energies"])
              for dt in (1.0, 0.5)]
    assert 3.0 < errors[0] / errors[1] < 5.0, errors


def toml_value(value):
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + " }"
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, str):
        return json.dumps(value)
    return repr(value)


def test_the_cli_writes_real_units_and_names_them(tmp_path):
    """From the command line: `check` shows dt in fs, the CSV's time column is in fs, summary.json
    records the units, the series equal the Python run's, and the GSD's
    first frame has the given velocities in A/fs (float32)."""
    import gsd.hoomd

    scene = nve_scene("real", 0.5, 50)
    scene["record"]["trajectory"] = {"every": 10, "format": "gsd"}
    text = "\n".join(f"{k} = {toml_value(v)}" for k, v in scene.items())
    path = tmp_path / "water.toml"
    path.write_text(text)
    out = tmp_path / "out"
    check = subprocess.run([sys.executable, "-m", "quatrot", "check", str(path)],
                           check=True, capture_output=True, text=True)
    assert "8 bodies, no_squish, dt 0.5 fs, 50 steps" in check.stdout
    subprocess.run([sys.executable, "-m", "quatrot", "run", str(path), "--out", str(out)], check=True)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["units"]["system"] == "real" and summary["units"]["pressure"] == "atm"
    with open(out / "energies.csv") as f:
        rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
    python = quatrot.run(scene)["series"]["energies"]
    np.testing.assert_array_equal([float(r["time"]) for r in rows], python["time"])
    assert float(rows[-1]["time"]) == 25.0
    np.testing.assert_array_equal([float(r["total_energy"]) for r in rows], python["total_energy"])
    given = [b["velocity"] for b in scene["bodies"]["list"]]
    with gsd.hoomd.open(out / "trajectory.gsd") as frames:
        np.testing.assert_allclose(frames[0].particles.velocity, given, rtol=1e-6)


def test_a_generated_start_is_at_its_temperature_in_kelvin():
    """64 SPC/E molecules drawn at 298 K: T_trans and T_rot at t = 0 come
    out in K near 298 (a wrong factor, k_B or 4.184, is off by 500 or 4;
    the bounds are 3 standard deviations of 189 and 192 degrees of freedom)."""
    scene = nve_scene("real", 1.0, 1)
    del scene["bodies"]["list"]
    scene["bodies"] = {"kind": "random", "counts": [64], "density": 0.0005, "closest": 3.0}
    scene["body_interactions"] = {
        "lennard_jones": {"cutoff": 9.0}, "electrostatics": {"kind": "cutoff", "cutoff": 9.0},
    }
    scene["initial"] = {"kind": "random", "seed": 4, "temperature": 298.0}
    scene["record"]["series"][0]["quantities"] = ["T_trans", "T_rot"]
    series = quatrot.run(scene)["series"]["energies"]
    for column in ("T_trans", "T_rot"):
        assert 298 * (1 - 3 * math.sqrt(2 / 189)) < series[column][0] < 298 * (1 + 3 * math.sqrt(2 / 189))


def test_bodies_evaluate_gives_the_ideal_gas_pressure_in_atm():
    """Two bodies that do not interact, moving at given velocities (A/fs) in
    a 20 A box: P = 2 K_trans / (3 V), converted by hand to atm (1
    kcal/(mol A^3) = 4184 / N_A * 1e30 / 101325 atm)."""
    point = {"sites": [{"position": [0, 0, 0], "mass": 10.0}], "inertia": np.eye(3).tolist()}
    velocities = np.array([[0.01, 0.0, 0.0], [0.0, -0.02, 0.005]])
    state = quatrot.bodies_evaluate(
        [point], [[1, 1, 1], [5, 5, 5]], [[1, 0, 0, 0]] * 2,
        velocities=velocities, box_lengths=[20.0] * 3, units="real",
    )
    kinetic = 0.5 * 10.0 * (velocities**2).sum() * 1e-3 * 1e-20 / 1e-30 / 4184  # kcal/mol
    atm_per_kcal_mol_a3 = 4184 / 6.02214076e23 * 1e30 / 101325
    expected = 2 * kinetic / (3 * 20.0**3) * atm_per_kcal_mol_a3
    assert state["pressure"] == pytest.approx(expected, rel=1e-13)
    assert state["pressure_tail"] == 0.0


def test_point_dipoles_are_in_debye():
    """Two point dipoles of 2 D head to tail 3 A apart in real units: the
    closed form -2 mu^2 / r^3 with mu = 2 D = 2 * 0.20819434 e A (1 D =
    1e-21 / c C m) and the Coulomb constant, in kcal/mol."""
    polar = {"sites": [{"position": [0, 0, 0], "dipole": [0, 0, 2.0]}], "mass": 1.0,
             "inertia": np.eye(3).tolist()}
    state = quatrot.bodies_evaluate(
        [polar], [[0, 0, 0], [0, 0, 3.0]], [[1, 0, 0, 0]] * 2, electrostatic_cutoff=5.0, units="real"
    )
    debye = 1e-21 / 299792458 / (1.602176634e-19 * 1e-10)
    mu = 2.0 * debye
    assert state["energies"]["electrostatic"] == pytest.approx(-2 * COULOMB * mu**2 / 3.0**3, rel=1e-14)


def test_openmm_tip4p_2005_virtual_site_is_quatrot_s_m_site():
    """The rigid OpenMM TIP4P/2005 of the NVT fixture (masses, SETTLE, M a
    massless ``ThreeParticleAverageSite``): M placed by OpenMM from quatrot's
    O, H, H is quatrot's M site, and the three constraints hold quatrot's
    geometry, for the 8 molecules of :func:`cluster`."""
    import openmm

    from validation.shared.openmm_water import water_system
    from validation.shared.water_runs import MASSES

    positions, orientations = cluster()
    sites = np.asarray(quatrot.bodies_evaluate(
        [{"model": "tip4p_2005"}], positions, orientations, lj_cutoff=CUTOFF, electrostatic_cutoff=CUTOFF,
        units="real")["site_positions"]).reshape(MOLECULES, 4, 3)
    system = water_system("tip4p_2005", MOLECULES, masses=MASSES)
    assert [system.getParticleMass(k)._value for k in range(4)] == [*MASSES, 0.0]
    context = openmm.Context(system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName("Reference"))
    moved = sites.copy()
    moved[:, 3] += 0.5  # M is not read from here: OpenMM places it
    context.setPositions(moved.reshape(-1, 3) / 10)
    context.computeVirtualSites()
    placed = context.getState(getPositions=True).getPositions(asNumpy=True)._value.reshape(MOLECULES, 4, 3) * 10
    assert np.abs(placed[:, 3] - sites[:, 3]).max() < 1e-12 * 10
    for c in range(system.getNumConstraints()):
        i, j, length = system.getConstraintParameters(c)
        a, b = sites.reshape(-1, 3)[i], sites.reshape(-1, 3)[j]
        assert np.linalg.norm(a - b) / 10 == pytest.approx(length._value, rel=1e-12)
