"""The conversions of the rigid-water verdict runs (validation/shared/water_box_runs.py):
the temperatures split from site velocities, and a state read back from a
GSD frame of quatrot's."""

import numpy as np
import pytest

import quatrot
from validation.shared import water_box_runs as runs
from validation.shared.water_runs import BOLTZMANN, MASSES, body_sites, principal_moments

pytest.importorskip("gsd")


def random_state(seed, n=8, box=12.0):
    rng = np.random.default_rng(seed)
    q = rng.normal(size=(n, 4))
    return runs.BoxState(box, rng.uniform(0, box, (n, 3)), q / np.linalg.norm(q, axis=1, keepdims=True),
                         rng.normal(scale=0.004, size=(n, 3)), rng.normal(scale=0.02, size=(n, 3)))


def test_temperatures_split_translation_and_rotation():
    """From site velocities V + omega x (R s): T_trans = sum M V^2 / ((3N - 3) k)
    and T_rot = sum I_k w_k^2 / (3N k), the body-frame closed forms."""
    state = random_state(3)
    _, velocities = runs.sites_of(state)
    t_trans, t_rot = runs.temperatures(velocities)
    n, mass = len(state.centres), sum(MASSES)
    moments = principal_moments(body_sites())
    kinetic_trans = 0.5 * mass * (state.velocities**2).sum() / 4.184e-4
    kinetic_rot = 0.5 * (moments * state.omega_body**2).sum() / 4.184e-4
    assert t_trans == pytest.approx(2 * kinetic_trans / ((3 * n - 3) * BOLTZMANN), rel=1e-12)
    assert t_rot == pytest.approx(2 * kinetic_rot / (3 * n * BOLTZMANN), rel=1e-12)


def test_a_gsd_frame_reads_back_as_the_given_state(tmp_path):
    """quatrot writes a given state to its first GSD frame; reading it back
    recovers centres, orientations, velocities and body angular velocities
    to float32 resolution (the angular momentum's convention included)."""
    import gsd.hoomd

    state = random_state(5)
    scene = runs.builtin()
    scene["bodies"] = {"kind": "given", "box": [state.box] * 3, "list": [
        {"position": c.tolist(), "orientation": q.tolist(), "velocity": v.tolist(), "angular_velocity": w.tolist()}
        for c, q, v, w in zip(state.centres, state.orientations, state.velocities, state.omega_body)]}
    for table in ("initial", "thermostat"):
        scene.pop(table)
    scene["body_interactions"] = {"lennard_jones": {"cutoff": 5.0}, "electrostatics": {"kind": "cutoff", "cutoff": 5.0},
                                  "skin": 0.5}
    scene["run"] = {"dt": 1.0, "steps": 1}
    scene["record"] = {"trajectory": {"every": 1, "format": "gsd"}}
    quatrot.run(scene, out_dir=tmp_path)
    with gsd.hoomd.open(tmp_path / "trajectory.gsd") as frames:
        found = runs.state_from_frame(frames[0])
    assert found.box == pytest.approx(state.box, rel=1e-7)
    np.testing.assert_allclose(found.centres, state.centres, atol=1e-5)
    sign = np.sign((found.orientations * state.orientations).sum(axis=1))[:, None]
    np.testing.assert_allclose(found.orientations * sign, state.orientations, atol=1e-6)
    np.testing.assert_allclose(found.velocities, state.velocities, atol=1e-8)
    np.testing.assert_allclose(found.omega_body, state.omega_body, rtol=1e-5, atol=1e-8)
