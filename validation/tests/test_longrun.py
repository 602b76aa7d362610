"""The long-run machinery (`validation.longrun`): the experiment's systems
written as scenes are the experiment's systems; its configurations are the
Rust table's; stability per run length, windows of a run and the crossover
time follow their definitions. The long runs themselves are in `make
validate` (`long_runs`, `accuracy_at_length`); their quick versions run in
`test_checks_quick.py`."""

import math
from pathlib import Path

import numpy as np
import pytest
import quatrot
import quatrot.sweep

from validation.shared import gear_systems
from validation.longrun import accuracy, grid, survival, systems

#: Energies of the same state computed two ways (scene run vs numpy + multipole_evaluate).
ENERGY_TOLERANCE = 1e-12


def test_configurations_are_the_rust_experiment_rows_in_order():
    arrays, options = gear_systems.rotor_in_field(quick=True)
    short = dict(dt=0.05, t_energy=0.5, t_error=0.2, t_stability=0.2)
    rows = quatrot.gear_corrections_table(**arrays, **(options | short))
    assert [r["label"] for r in rows] == list(systems.CONFIGURATIONS)


@pytest.mark.parametrize("system", ["rotor", "lattice"])
def test_scene_of_the_experiment_has_the_experiment_energy(system):
    """Initial total energy of the scene run = potential (multipole_evaluate
    on the experiment's arrays) + 1/2 sum I w^2 (numpy)."""
    if system == "rotor":
        arrays, options = gear_systems.rotor_in_field(quick=True)
        scene = systems.rotor_in_field()
    else:
        arrays, options = gear_systems.lattice(20261121)
        scene = systems.multipole_lattice(20261121)
    evaluate = {k: options[k] for k in ("field", "box_lengths", "cutoff") if k in options}
    if "dipoles" in options:
        evaluate["dipoles_body"] = options["dipoles"]
    if "quadrupoles" in options:
        evaluate["quadrupoles_body"] = options["quadrupoles"]
    potential, _, _ = quatrot.multipole_evaluate(arrays["sites"], arrays["orientations"], **evaluate)
    kinetic = 0.5 * np.sum(arrays["inertia"] * arrays["omega_body"] ** 2)
    scene["record"] = {"series": [{"name": "e", "every": 1, "quantities": ["total_energy"]}]}
    result = quatrot.run(scene, steps=1)
    measured = result["series"]["e"]["total_energy"][0]
    assert abs(measured - (potential + kinetic)) <= ENERGY_TOLERANCE * max(1.0, abs(potential + kinetic))


def point(label, dt, status, last_step, steps=100):
    return grid.Point(label, dt, steps, status, "", last_step, 0.0, Path("."))


def test_largest_stable_step_at_each_length():
    points = [point("x", 0.1, "completed", 100), point("x", 0.2, "blew_up", 50), point("x", 0.4, "completed", 100)]
    assert survival.stability(points, "x", 10) == survival.Stability(10, 0.4, True, None, None)
    # at 60 steps the 0.2 run has failed: 0.4 does not count above it
    assert survival.stability(points, "x", 60) == survival.Stability(60, 0.1, False, 0.2, 50)
    points = [point("y", 0.1, "blew_up", 3)]
    assert survival.stability(points, "y", 10).largest is None


def test_window_statistics_over_a_prefix_of_a_run():
    p = point("x", 0.5, "completed", 4, steps=4)
    p.series = {
        "step": np.arange(5.0),
        "time": 0.5 * np.arange(5.0),
        "energy_error": np.array([0.0, 1.0, 2.0, 3.0, -10.0]),
        "q_dot_q": np.array([0.0, 1e-3, 0.0, 0.0, 5.0]),
    }
    w = survival.window(p, 3)
    assert w.drift == pytest.approx(2.0)  # slope 1 per step, 2 per unit time
    assert w.max_energy_error == 3.0 and w.max_q_dot_q == 1e-3
    assert survival.window(p, 5) is None  # longer than the run


def test_crossover_is_the_first_time_from_which_the_symplectic_error_stays_below():
    t = np.arange(1.0, 6.0)
    sym = accuracy.Curve("S", 0.1, 10, t, np.array([1.0, 1.0, 1.0, 1.0, 1.0]))
    assert accuracy.crossover(sym, accuracy.Curve("G", 0.1, 10, t, np.array([0.1, 2.0, 0.5, 3.0, 4.0]))) == 4.0
    assert accuracy.crossover(sym, accuracy.Curve("G", 0.1, 10, t, np.full(5, 2.0))) == 1.0
    assert accuracy.crossover(sym, accuracy.Curve("G", 0.1, 10, t, np.full(5, 0.5))) is None


def test_equal_cost_steps_spend_the_same_per_unit_time():
    dts = accuracy.equal_cost_dts({"a": 1.0, "b": 3.0}, 0.01)
    assert dts == {"a": 0.01, "b": pytest.approx(0.03)}
    assert math.isclose(1.0 / dts["a"], 3.0 / dts["b"])


def test_orientation_angle_is_the_rotation_angle_sign_blind_and_precise_when_small():
    """`orientation.angles` gives the angle of the rotation between two
    orientations (scipy's magnitude of R_ref^-1 R), for Q and -Q alike, and
    keeps full relative precision at 1e-12 rad (acos near 1 would give 0 or ~1e-8)."""
    from scipy.spatial.transform import Rotation

    from validation.longrun import orientation

    rng = np.random.default_rng(5)
    for angle in (1e-12, 1e-6, 0.3, 3.0):
        ref = Rotation.random(random_state=rng)
        axis = rng.normal(size=3)
        turn = Rotation.from_rotvec(angle * axis / np.linalg.norm(axis))
        q = (turn * ref).as_quat(scalar_first=True)
        q_ref = ref.as_quat(scalar_first=True)
        expected = (ref.inv() * turn * ref).magnitude()
        for sign in (1.0, -1.0):
            assert math.isclose(float(orientation.angles(sign * q, q_ref)), expected, rel_tol=1e-4)


def test_lyapunov_time_of_an_exponential_separation():
    """A separation 1e-12 exp(t / 7) (with an O(1) plateau after it) gives the Lyapunov time 7."""
    from validation.longrun import orientation

    t = np.linspace(0.0, 300.0, 301)
    separation = np.minimum(1e-12 * np.exp(t / 7.0), 2.0)
    assert math.isclose(orientation.lyapunov_time(t, separation), 7.0, rel_tol=1e-9)
    assert orientation.lyapunov_time(t, np.full_like(t, 1e-13)) is None
    # A regular system's phase error grows as a power of t: no Lyapunov time.
    assert orientation.lyapunov_time(t, 1e-12 * t**2) is None


def test_orientation_crossover_only_within_the_compared_window():
    """A symplectic error (growing as t) ends below a Gear error (growing as
    t^2) from their crossing on; cut before the crossing, there is none."""
    from validation.longrun import orientation

    t = np.geomspace(1.0, 1e4, 41)
    symplectic = orientation.Curve("s", 0.1, t, 1e-4 * t, t * 0, 0.0)
    gear = orientation.Curve("g", 0.1, t, 1e-7 * t**2, t * 0, 0.0)
    crossing = float(t[np.nonzero(1e-4 * t < 1e-7 * t**2)[0][0]])
    assert orientation.crossover(symplectic, gear) == crossing
    assert orientation.crossover(symplectic, gear, until=500.0) is None


def test_orientation_chain_is_the_uninterrupted_run():
    """The chain of restarts gives, at each sample step, the orientations of
    one uninterrupted run recording every step (bit for bit), so sampling costs
    nothing and changes nothing."""
    from validation.longrun import orientation

    scene = systems.rotor_in_field()
    steps = [1, 7, 30, 100]
    found = orientation.chain(scene, {"kind": "gear_b"}, 0.02, steps)
    whole = quatrot.sweep.apply(scene, {"integrator": {"kind": "gear_b"}, "run.dt": 0.02, "run.steps": 100, "record": {"trajectory": {"every": 1}}})
    frames = quatrot.run(whole, threads=1)["trajectory"]
    expected = np.array([frames["orientations"][list(frames["step"]).index(s)] for s in steps])
    assert found["error"] == ""
    assert np.array_equal(found["orientations"], expected)
