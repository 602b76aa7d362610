"""Rigid rotations against ASE along real trajectories: the lattice of asymmetric tops (``multipole_tops_bcc``) run by scheme A and by scheme B; at every saved frame each rotor's body-frame site template is placed in space by ASE (``Atoms.rotate`` with the quaternion's axis and angle; ``Atoms.euler_rotate`` with the note's Euler angles from quatrot, converted to ASE's x-convention by ``validation/shared/frames.py``) and by quatrot's body-to-space mapping ``r = site + R(Q) b``.

Passing proves that the orientations the integrators produce mean, in ASE's
terms, the rotations quatrot applies to body-frame sites (eqs 7-8 along
trajectories that visit generic orientations, not only random samples), and
that quatrot's Euler angles of those orientations are ASE's. It says nothing
about whether the trajectories are right (the dynamics and OpenMM modules
check that)."""

from __future__ import annotations

import ase
import numpy as np
from ase import Atoms

import quatrot
from quatrot import quaternion as qr
from validation.shared import scene_runs
from validation.shared.check import Check, Context
from validation.shared.frames import axis_angle_degrees, euler_y_to_ase_euler_rotate
from validation.shared.scene_runs import variant

# ASE and quatrot both build a 3x3 rotation from the same unit quaternion in
# double precision (through axis-angle or Euler angles and back): round-off on
# positions of order 1 (sites) plus the template (length < 1).
ROUND_OFF = 1e-12
SCHEMES = ("gear_a", "gear_b")
# An asymmetric body-frame template: markers along the three body axes and
# one generic site, so that every rotation is detected.
TEMPLATE = np.array([[0.3, 0.0, 0.0], [0.0, 0.3, 0.0], [0.0, 0.0, 0.3], [0.21, -0.13, 0.37]])


def _ase_rotate(site, q):
    atoms = Atoms("H4", positions=site + TEMPLATE)
    axis, angle = axis_angle_degrees(q)
    atoms.rotate(angle, axis, center=site)
    return atoms.positions


def _ase_euler_rotate(site, angles_inverse):
    """ASE's euler_rotate is passive (A, space to body); the angles of Q~,
    (-psi, -theta, -phi), make it apply A(Q~) = R(Q), body to space."""
    atoms = Atoms("H4", positions=site + TEMPLATE)
    phi, theta, psi = euler_y_to_ase_euler_rotate(angles_inverse)
    atoms.euler_rotate(phi=phi, theta=theta, psi=psi, center=site)
    return atoms.positions


def _plot(per_frame, out_dir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 3.2))
    for label, (t, err) in per_frame.items():
        ax.semilogy(t, np.maximum(err, 1e-17), "o-", ms=3, lw=0.8, label=label)
    ax.axhline(ROUND_OFF, color="k", lw=1, label="tolerance")
    ax.set_xlabel("time")
    ax.set_ylabel("max |ASE - quatrot| position (0 drawn at 1e-17)")
    ax.set_title("body sites placed by ASE vs quatrot, every saved frame", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    path = out_dir / "rigid_rotations_ase.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def run(ctx: Context) -> list[Check]:
    cells, steps, every = (2, 100, 50) if ctx.quick else (3, 2000, 100)
    scene = variant("multipole_tops_bcc", cells=cells, every=every)
    refs = {"ASE": ase.__version__, "quatrot": quatrot.__version__}
    checks, per_frame = [], {}
    for scheme in SCHEMES:
        ctx.progress(f"{scheme}: {steps} steps, ASE on every {every}th frame")
        out = scene_runs.run(dict(scene, integrator={"kind": scheme}), steps=steps)
        sites, frames = out["sites"], out["trajectory"]
        frame_rotate, frame_euler = [], []
        for q_frame in frames["orientations"]:
            q_frame = q_frame / np.linalg.norm(q_frame, axis=1, keepdims=True)
            angles = qr.to_euler_y(q_frame)
            err_rotate = err_euler = 0.0
            for site, q, (phi, theta, psi) in zip(sites, q_frame, angles):
                ours = site + qr.body_to_space(np.tile(q, (len(TEMPLATE), 1)), TEMPLATE)
                err_rotate = max(err_rotate, float(np.abs(_ase_rotate(site, q) - ours).max()))
                inverse = np.array([-psi, -theta, -phi])
                err_euler = max(err_euler, float(np.abs(_ase_euler_rotate(site, inverse) - ours).max()))
            frame_rotate.append(err_rotate)
            frame_euler.append(err_euler)
        per_frame[f"{scheme}, Atoms.rotate"] = (frames["time"], np.array(frame_rotate))
        per_frame[f"{scheme}, Atoms.euler_rotate"] = (frames["time"], np.array(frame_euler))
        err_rotate, err_euler = max(frame_rotate), max(frame_euler)
        where = f"{len(frames['step'])} frames (every {every} of {steps} steps) of {len(sites)} asymmetric tops, 4-site template"
        checks.append(
            Check(
                f"{scheme} trajectory: Atoms.rotate(axis, angle) = site + R(Q) b",
                "The orientations along the run, read as ASE axis-angle rotations, place every body site where quatrot's R(Q) does.",
                ROUND_OFF,
                err_rotate,
                refs,
                f"{where}; largest position difference.",
            )
        )
        checks.append(
            Check(
                f"{scheme} trajectory: Atoms.euler_rotate(note's angles) = site + R(Q) b",
                "quatrot's y-convention Euler angles of each orientation, converted to ASE's x-convention, rotate the template as R(Q) does.",
                ROUND_OFF,
                err_euler,
                refs,
                f"{where}; euler_rotate is passive, so the angles of Q~ are passed; largest position difference.",
            )
        )
    if not ctx.quick:
        checks[0].plots.append(_plot(per_frame, ctx.out_dir))
    return checks
