"""Trajectory files through mdtraj: the DCD + PDB that ``quatrot.run`` writes for the lattice of asymmetric tops are loaded by mdtraj; each rotor's orientation is recovered by least-squares superposition (Kabsch) of the body template of its four atoms (centre and markers along body axes 1, 2, 3) onto the coordinates mdtraj returns, and compared with the quaternions the same run returned (double cover handled: Q and -Q are one rotation).

Passing proves a user can read orientations back from the files with a
standard tool: atom order, residue layout, Angstrom lengths, the direction of
each marker (columns of R(Q) = A^T, not rows) and the frame count. Precision
is that of DCD's float32 coordinates; the files cannot carry more.
(mdtraj's own ``superpose`` is not used: its float32 QCP solver reports
unconverged rotations on 4-atom sets a few hundredths of a nanometre wide.)
The DCD of a periodic run carries the box (CHARMM unit-cell record): mdtraj
reads its lengths and 90-degree angles; the open run's DCD has none."""

from __future__ import annotations

import mdtraj as md
import numpy as np

import quatrot
from validation.shared import scene_runs
from validation.shared.check import Check, Context
from validation.shared.scene_runs import variant

MARKER_LENGTH = 0.3
# mdtraj reads DCD and PDB lengths as Angstrom and returns nanometres.
ANGSTROM_PER_NM = 10.0
# float32 coordinates (relative 6e-8) of magnitude up to ~5 give ~3e-7 absolute,
# ~1e-6 rad on a 0.3 marker; factor 10.
ANGLE_TOLERANCE = 1e-5
POSITION_TOLERANCE = 1e-5  # the centres, same float32 rounding
# The cell is written in double precision and read back as float32 by
# mdtraj: relative 6e-8 on lengths of a few units, and exact 90 degrees.
CELL_TOLERANCE = 1e-5
PERIODIC_CUTOFF = 2.0


def unit_cell_error(files, box_lengths) -> float:
    """Largest deviation of mdtraj's unit cell from the box (lengths, in the
    scene's units) and from 90 degrees, over all frames of a periodic run."""
    traj = md.load_dcd(str(files / "trajectory.dcd"), top=str(files / "topology.pdb"))
    if traj.unitcell_lengths is None:
        return float("inf")
    lengths = np.abs(traj.unitcell_lengths * ANGSTROM_PER_NM - box_lengths).max()
    angles = np.abs(traj.unitcell_angles - 90.0).max()
    return float(max(lengths, angles))


def rotation_angle(q, p) -> np.ndarray:
    """Rotation angle between unit quaternions (..., 4), blind to the sign."""
    dot = np.abs(np.sum(q * p, axis=-1))
    return 2.0 * np.arccos(np.minimum(1.0, dot))


def superpose(body: np.ndarray, space: np.ndarray) -> np.ndarray:
    """Least-squares rotations R (..., 3, 3) with R b_i ~ s_i after centring both
    point sets (Kabsch, by SVD; proper rotations only). ``body`` (k, 3), ``space`` (..., k, 3)."""
    b = body - body.mean(axis=0)
    s = space - space.mean(axis=-2, keepdims=True)
    u, _, vt = np.linalg.svd(np.einsum("ki,...kj->...ij", b, s))
    v, ut = np.swapaxes(vt, -1, -2), np.swapaxes(u, -1, -2)
    d = np.sign(np.linalg.det(v @ ut))
    fix = np.broadcast_to(np.eye(3), d.shape + (3, 3)).copy()
    fix[..., 2, 2] = d
    return v @ fix @ ut


def _matrix_to_quaternion(r: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(r.reshape(-1, 3, 3)).as_quat(scalar_first=True).reshape(r.shape[:-2] + (4,))


def _plot(t, angles, out_dir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 3.2))
    ax.semilogy(t, np.maximum(angles.max(axis=1), 1e-12), "o-", ms=3, label="largest over rotors")
    ax.semilogy(t, np.maximum(np.median(angles, axis=1), 1e-12), "s-", ms=3, label="median")
    ax.axhline(ANGLE_TOLERANCE, color="k", lw=1, label="tolerance")
    ax.set_xlabel("time")
    ax.set_ylabel("angle between rotations (rad)")
    ax.set_title("orientation recovered from mdtraj's coordinates by superposition vs quatrot's quaternion", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    path = out_dir / "trajectory_mdtraj.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def run(ctx: Context) -> list[Check]:
    cells, steps, every = (2, 60, 20) if ctx.quick else (3, 2000, 100)
    ctx.out_dir.mkdir(parents=True, exist_ok=True)
    files = ctx.out_dir / "mdtraj_run"
    scene = variant("multipole_tops_bcc", cells=cells, every=every, marker_length=MARKER_LENGTH, integrator="gear_b")
    out = scene_runs.run(scene, steps=steps, out_dir=files)
    frames, sites = out["trajectory"], out["sites"]
    n = len(sites)
    traj = md.load_dcd(str(files / "trajectory.dcd"), top=str(files / "topology.pdb"))
    layout_ok = (
        traj.n_frames == len(frames["step"])
        and traj.n_atoms == 4 * n
        and traj.topology.n_residues == n
        and [a.name for a in traj.topology.residue(0).atoms] == ["C", "O", "N", "S"]
    )
    centres = traj.xyz[:, ::4].astype(np.float64) * ANGSTROM_PER_NM
    position_err = float(np.abs(centres - sites[None]).max()) if layout_ok else float("inf")
    q = frames["orientations"] / np.linalg.norm(frames["orientations"], axis=-1, keepdims=True)
    if layout_ok:
        xyz = traj.xyz.astype(np.float64).reshape(traj.n_frames, n, 4, 3) * ANGSTROM_PER_NM
        rotations = superpose(np.vstack([np.zeros(3), MARKER_LENGTH * np.eye(3)]), xyz)
        angles = rotation_angle(_matrix_to_quaternion(rotations), q)
    else:
        angles = np.full((1, 1), np.inf)
    periodic = variant("multipole_tops_bcc", cells=cells, every=every, marker_length=MARKER_LENGTH, integrator="gear_b")
    periodic["interactions"]["boundary"] = {"kind": "periodic", "cutoff": PERIODIC_CUTOFF}
    periodic_files = ctx.out_dir / "mdtraj_periodic_run"
    scene_runs.run(periodic, steps=every, out_dir=periodic_files)
    box_lengths = cells * periodic["rotors"]["spacing"]
    cell_err = unit_cell_error(periodic_files, box_lengths)
    open_has_no_cell = traj.unitcell_lengths is None
    refs = {"mdtraj": md.__version__, "quatrot": quatrot.__version__}
    where = f"{traj.n_frames} frames (every {every} of {steps} steps, scheme B) of {n} asymmetric tops, marker length {MARKER_LENGTH}"
    checks = [
        Check(
            "DCD+PDB load: layout and centres",
            "mdtraj reads the files with one residue of 4 atoms (C, O, N, S) per rotor, one frame per saved step, and the centres on the sites.",
            POSITION_TOLERANCE,
            position_err,
            refs,
            f"{where}; layout {'as expected' if layout_ok else 'WRONG (frames, atoms, residues or names)'}; largest centre error (length units).",
        ),
        Check(
            "orientations by superposition vs quaternions",
            "The rotation recovered from the markers mdtraj read is the run's R(Q) (sign of Q ignored); float32 precision only.",
            ANGLE_TOLERANCE,
            float(angles.max()),
            refs,
            f"{where}; largest angle between rotations (rad), median {np.median(angles):.3g}.",
        ),
    ]
    checks.append(
        Check(
            "DCD unit cell of a periodic run",
            "mdtraj reads the CHARMM unit-cell record of a periodic run as the scene's box (lengths and 90-degree angles) in every frame, and finds none in the open run's DCD.",
            CELL_TOLERANCE,
            cell_err if open_has_no_cell else float("inf"),
            refs,
            f"{n} tops, box {box_lengths} (cubic), cutoff {PERIODIC_CUTOFF}; largest |length - L| or |angle - 90| (length units, degrees); open run without a cell: {open_has_no_cell}.",
        )
    )
    if not ctx.quick:
        checks[1].plots.append(_plot(frames["time"], angles, ctx.out_dir))
    return checks
