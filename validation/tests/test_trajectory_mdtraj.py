"""The trajectory files (DCD + PDB) load in mdtraj, and the orientations
recovered from the marker sites by superposition (Kabsch) are the
quaternions the run returned: the centre sits on the site and the markers
along the body axes, `r = site + L R(Q) e_a` with `R(Q)` body to space."""

from pathlib import Path

import mdtraj as md
import numpy as np
import quatrot
from scipy.spatial.transform import Rotation

# DCD stores float32 coordinates: absolute error ~ 6e-8 x 4.5 (box) ~ 3e-7,
# i.e. ~1e-6 rad on a marker 0.3 from the centre; allow a factor 10.
ANGLE_TOLERANCE = 1e-5
# Same float32 rounding for the positions of the centres.
POSITION_TOLERANCE = 1e-5
# mdtraj reads DCD and PDB lengths as Angstrom and returns nanometres.
ANGSTROM_PER_NM = 10.0
MARKER_LENGTH = 0.3
# PDB coordinates are written with three decimals.
PDB_PRECISION = 5e-4

SCENE = {
    "version": 1,
    "name": "tops_for_mdtraj",
    "rotors": {
        "kind": "lattice",
        "lattice": "bcc",
        "cells": 2,
        "spacing": 1.5,
        "default": {"inertia": [0.1, 0.15, 0.2], "dipole": [0.0, 0.0, 1.0]},
    },
    "interactions": {"boundary": {"kind": "open"}},
    "initial": {"kind": "random", "seed": 11, "temperature": 1.0},
    "integrator": {"kind": "no_squish"},
    "run": {"dt": 0.002, "steps": 60},
    "record": {"trajectory": {"every": 10, "marker_length": MARKER_LENGTH}},
}


def kabsch(body: np.ndarray, space: np.ndarray) -> np.ndarray:
    """The rotation R minimising sum |R b_i - s_i|^2 over centred point sets."""
    b = body - body.mean(axis=0)
    s = space - space.mean(axis=0)
    u, _, vt = np.linalg.svd(b.T @ s)
    d = np.sign(np.linalg.det(vt.T @ u.T))
    return vt.T @ np.diag([1.0, 1.0, d]) @ u.T


def rotation_angle(q: np.ndarray, p: np.ndarray) -> float:
    """Angle between two unit quaternions' rotations (double cover aware)."""
    return 2.0 * np.arccos(min(1.0, abs(float(np.dot(q, p)))))


def test_dcd_and_pdb_load_and_give_back_the_orientations(tmp_path: Path):
    result = quatrot.run(SCENE, out_dir=tmp_path)
    frames = result["trajectory"]
    n = result["sites"].shape[0]
    traj = md.load_dcd(str(tmp_path / "trajectory.dcd"), top=str(tmp_path / "topology.pdb"))
    assert traj.n_frames == len(frames["step"]) == 7
    assert traj.n_atoms == 4 * n
    assert traj.topology.n_residues == n
    assert [a.name for a in traj.topology.residue(0).atoms] == ["C", "O", "N", "S"]

    body = np.vstack([np.zeros(3), MARKER_LENGTH * np.eye(3)])
    worst_angle = 0.0
    for f in range(traj.n_frames):
        xyz = traj.xyz[f].astype(np.float64) * ANGSTROM_PER_NM
        for i in range(n):
            atoms = xyz[4 * i : 4 * i + 4]
            np.testing.assert_allclose(atoms[0], result["sites"][i], atol=POSITION_TOLERANCE)
            r = kabsch(body, atoms)
            x, y, z, w = Rotation.from_matrix(r).as_quat()
            recovered = np.array([w, x, y, z])
            q = frames["orientations"][f, i]
            worst_angle = max(worst_angle, rotation_angle(recovered, q / np.linalg.norm(q)))
    assert worst_angle < ANGLE_TOLERANCE, worst_angle


def test_first_frame_is_the_initial_state(tmp_path: Path):
    """Frame 0 is step 0: the markers give the scene's initial orientations."""
    result = quatrot.run(SCENE, out_dir=tmp_path)
    # The integrator's setup may renormalise the initial quaternions (round-off).
    np.testing.assert_allclose(result["trajectory"]["orientations"][0], result["initial_orientations"], atol=1e-15)
    top = md.load_pdb(str(tmp_path / "topology.pdb"))
    first = md.load_dcd(str(tmp_path / "trajectory.dcd"), top=top).xyz[0]
    # The PDB has three decimals (Angstrom); the DCD frame 0 is the same geometry.
    np.testing.assert_allclose(top.xyz[0] * ANGSTROM_PER_NM, first * ANGSTROM_PER_NM, atol=PDB_PRECISION)
