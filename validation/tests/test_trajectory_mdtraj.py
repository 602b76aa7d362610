"""The trajectory files (DCD + PDB) load in mdtraj, and the orientations
recovered from the marker sites by superposition (Kabsch, the check
module's `superpose`) are the
quaternions the run returned: the centre sits on the site and the markers
along the body axes, `r = site + L R(Q) e_a` with `R(Q)` body to space."""

from pathlib import Path

import mdtraj as md
import numpy as np
import quatrot
from scipy.spatial.transform import Rotation

from small_scenes import tops_bcc
from validation.checks.trajectory_mdtraj import rotation_angle, superpose

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

SCENE = tops_bcc("no_squish", {"kind": "open"}, {"every": 10, "marker_length": MARKER_LENGTH})


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
            r = superpose(body, atoms)
            recovered = Rotation.from_matrix(r).as_quat(scalar_first=True)
            q = frames["orientations"][f, i]
            worst_angle = max(worst_angle, float(rotation_angle(recovered, q / np.linalg.norm(q))))
    assert worst_angle < ANGLE_TOLERANCE, worst_angle


def test_periodic_dcd_carries_the_unit_cell(tmp_path: Path):
    """A periodic run's DCD has CHARMM's unit-cell record: mdtraj reads the
    box (lattice of 2 cells of 1.5, Angstrom to nm) and 90-degree angles in
    every frame; the open run of the other tests has no unit cell."""
    scene = dict(SCENE, interactions={"boundary": {"kind": "periodic", "cutoff": 1.4}})
    quatrot.run(scene, out_dir=tmp_path)
    traj = md.load_dcd(str(tmp_path / "trajectory.dcd"), top=str(tmp_path / "topology.pdb"))
    assert traj.unitcell_lengths is not None
    np.testing.assert_allclose(traj.unitcell_lengths * ANGSTROM_PER_NM, 3.0, atol=POSITION_TOLERANCE)
    np.testing.assert_allclose(traj.unitcell_angles, 90.0, atol=POSITION_TOLERANCE)
    assert traj.n_frames == 7
    open_run = tmp_path / "open"
    quatrot.run(SCENE, out_dir=open_run)
    assert md.load_dcd(str(open_run / "trajectory.dcd"), top=str(open_run / "topology.pdb")).unitcell_lengths is None


def test_first_frame_is_the_initial_state(tmp_path: Path):
    """Frame 0 is step 0: the markers give the scene's initial orientations."""
    result = quatrot.run(SCENE, out_dir=tmp_path)
    # The integrator's setup may renormalise the initial quaternions (round-off).
    np.testing.assert_allclose(result["trajectory"]["orientations"][0], result["initial_orientations"], atol=1e-15)
    top = md.load_pdb(str(tmp_path / "topology.pdb"))
    first = md.load_dcd(str(tmp_path / "trajectory.dcd"), top=top).xyz[0]
    # The PDB has three decimals (Angstrom); the DCD frame 0 is the same geometry.
    np.testing.assert_allclose(top.xyz[0] * ANGSTROM_PER_NM, first * ANGSTROM_PER_NM, atol=PDB_PRECISION)


def test_mdtraj_superpose_fails_on_small_marker_sets():
    """Trap (ERRATA.md): mdtraj 1.11's `Trajectory.superpose` (float32 QCP)
    prints "UNCONVERGED ROTATION MATRIX" and returns the identity for point
    sets spanning about 0.1 nm or less, such as quatrot's markers (0.3 reduced
    units are written as 0.3 Angstrom, which mdtraj reads as 0.03 nm); the same
    sets scaled to 1 nm superpose fine. The SVD fit of quatrot's checks
    recovers the rotations at any scale. If the first assertion starts
    failing, mdtraj has been fixed and the trap row can go."""
    rotations = Rotation.random(20, random_state=2)
    top = md.Topology()
    residue = top.add_residue("ROT", top.add_chain())
    for name in "CONS":
        top.add_atom(name, md.element.carbon, residue)

    def misfit(length_nm: float) -> float:
        body = np.vstack([np.zeros(3), length_nm * np.eye(3)])
        xyz = np.stack([r.apply(body) for r in rotations]).astype(np.float32)
        fitted = md.Trajectory(xyz, top).superpose(md.Trajectory(body[None].astype(np.float32), top))
        recovered = superpose(body, xyz.astype(np.float64))
        assert np.abs(recovered - rotations.as_matrix()).max() < 1e-5  # float32 input
        return float(np.abs(fitted.xyz - body[None]).max()) / length_nm

    assert misfit(MARKER_LENGTH / ANGSTROM_PER_NM) > 0.5  # identity returned: off by a marker length
    assert misfit(1.0) < 1e-4  # float32 rounding
