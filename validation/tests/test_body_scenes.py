"""Scenes of moving bodies (issue 39) run from Python: a given-bodies scene
starts with the energy and pressure `quatrot.bodies_evaluate` gives for the
same state, and the GSD trajectory of a built-in reads back with the gsd
package, its velocities and HOOMD angular momenta giving the kinetic
energies the series recorded."""

import tomllib
from pathlib import Path

import gsd.hoomd
import numpy as np
import pytest

import quatrot

MOLECULE = {
    "sites": [
        {"position": [0.0, 0.53, 0.0], "mass": 1.0, "lennard_jones": {"epsilon": 1.0, "sigma": 1.0}},
        {"position": [0.61, -0.26, 0.0], "mass": 1.0, "lennard_jones": {"epsilon": 1.0, "sigma": 1.0}, "charge": 0.4},
        {"position": [-0.61, -0.26, 0.0], "mass": 1.0, "lennard_jones": {"epsilon": 0.8, "sigma": 1.1}, "charge": -0.4},
    ]
}
SPHERE = {
    "mass": 2.0,
    "inertia": [[0.2, 0, 0], [0, 0.3, 0], [0, 0, 0.4]],
    "sites": [{"position": [0, 0, 0], "lennard_jones": {"epsilon": 1.0, "sigma": 1.0}, "dipole": [0.0, 0.3, 1.2]}],
}
POSITIONS = [[1.0, 1.0, 1.0], [2.6, 1.2, 1.1], [1.3, 2.7, 0.8], [5.5, 5.2, 5.9], [4.0, 1.5, 4.4]]
ORIENTATIONS = [[1, 0, 0, 0], [0.9, 0.1, 0.3, 0.2], [0.5, 0.5, 0.5, 0.5], [0.2, -0.4, 0.8, 0.1], [0.7, 0.0, 0.7, 0.0]]
VELOCITIES = [[0.1, 0.2, 0.0], [-0.2, 0.0, 0.1], [0.0, -0.3, 0.2], [0.3, 0.1, -0.1], [-0.2, 0.0, -0.2]]
KINDS = [0, 0, 0, 1, 1]
BOX = [6.5, 6.5, 6.5]


def given_scene() -> dict:
    bodies = [
        {"type": k, "position": p, "orientation": q, "velocity": v}
        for k, p, q, v in zip(KINDS, POSITIONS, ORIENTATIONS, VELOCITIES)
    ]
    return {
        "version": 1,
        "body_types": [MOLECULE, SPHERE],
        "bodies": {"kind": "given", "list": bodies, "box": BOX},
        "body_interactions": {
            "lennard_jones": {"cutoff": 2.5, "truncation": "plain"},
            "electrostatics": {"kind": "cutoff", "cutoff": 2.5},
        },
        "integrator": {"kind": "no_squish"},
        "run": {"dt": 0.001, "steps": 2},
        "record": {"series": [{"name": "series", "every": 1, "quantities": ["potential_energy", "pressure"]}]},
    }


def test_a_given_scene_starts_where_bodies_evaluate_says():
    """Step 0 of the run is the state bodies_evaluate evaluates: the same
    potential energy (tail included) and pressure, to the last bit."""
    result = quatrot.run(given_scene())
    series = result["series"]["series"]
    state = quatrot.bodies_evaluate(
        [MOLECULE, SPHERE], POSITIONS, ORIENTATIONS, kinds=KINDS, velocities=VELOCITIES,
        box_lengths=BOX, lj_cutoff=2.5, electrostatic_cutoff=2.5,
    )
    assert state["energies"]["electrostatic"] != 0.0 and state["energies"]["lennard_jones"] != 0.0
    assert series["potential_energy"][0] == state["energies"]["total"]
    assert series["pressure"][0] == state["pressure"]
    assert result["summary"]["bodies"] == {
        "count": 5, "per_type": [3, 2], "sites": 11, "box": BOX, "neighbour_builds": 1,
    }


def quaternion_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton products of rows of scalar-first quaternions."""
    a0, av = a[:, :1], a[:, 1:]
    b0, bv = b[:, :1], b[:, 1:]
    scalar = a0 * b0 - np.sum(av * bv, axis=1, keepdims=True)
    vector = a0 * bv + b0 * av + np.cross(av, bv)
    return np.hstack([scalar, vector])


# float32 trajectories keep about 7 digits; sums of 256 terms keep about 6.
FLOAT32_SUMS = 2e-6


def test_a_builtin_writes_a_gsd_trajectory_of_its_bodies(tmp_path: Path):
    """lewis_wahnstrom_otp's GSD frames: the box, the types, masses and
    moments; K_trans from velocities and K_rot from HOOMD's angular momentum
    quaternions (L_body = vec(Q~ P) / 2) equal the recorded series; centres
    unwrapped with their images move continuously."""
    scene = tomllib.loads(quatrot.builtin_scenes()["lewis_wahnstrom_otp"])
    scene["run"]["steps"] = 60
    scene["record"]["series"][0]["every"] = 20
    scene["record"]["trajectory"]["every"] = 20
    result = quatrot.run(scene, out_dir=str(tmp_path))
    series = result["series"]["series"]
    side = (256 / 0.32655) ** (1 / 3)
    with gsd.hoomd.open(str(tmp_path / "trajectory.gsd")) as frames:
        assert len(frames) == 4
        first = frames[0]
        np.testing.assert_allclose(first.configuration.box, [side, side, side, 0, 0, 0], rtol=1e-7)
        assert first.particles.N == 256 and list(first.particles.types) == ["type0"]
        np.testing.assert_array_equal(first.particles.mass, 3.0)
        previous = None
        for k, frame in enumerate(frames):
            assert frame.configuration.step == 20 * k
            p = frame.particles
            k_trans = 0.5 * np.sum(p.mass[:, None] * p.velocity.astype(float) ** 2)
            conjugate = p.orientation.astype(float) * [1, -1, -1, -1]
            l_body = 0.5 * quaternion_product(conjugate, p.angmom.astype(float))[:, 1:]
            moments = p.moment_inertia.astype(float)
            k_rot = 0.5 * np.sum(np.where(moments > 0, l_body**2 / np.where(moments > 0, moments, 1), 0))
            assert k_trans == pytest.approx(series["translational_kinetic_energy"][k], rel=FLOAT32_SUMS)
            assert k_rot == pytest.approx(series["rotational_kinetic_energy"][k], rel=FLOAT32_SUMS)
            assert np.all(np.abs(p.position) <= side / 2)
            unwrapped = p.position.astype(float) + p.image * side
            if previous is not None:
                assert np.abs(unwrapped - previous).max() < 0.5
            previous = unwrapped
