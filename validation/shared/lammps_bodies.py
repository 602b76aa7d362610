"""LAMMPS set-up shared by the comparisons of moving bodies
(validation/checks/lammps_body_trajectories.py, lammps_rigid_trajectories.py,
validation/tests/test_bodies_lammps.py): a periodic cube in LJ units, the
unwrapped atom positions, and both codes run side by side."""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

from validation.shared.lammps_driver import _load_lammps


def periodic_cube(box: float, atom_style: str, positions: np.ndarray):
    """A LAMMPS instance with the cube ``[0, box)^3``, periodic, LJ units,
    one atom type, and atoms at `positions` (inside the box) kept in
    creation order (``sort 0 0``)."""
    lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    for c in [
        "units lj",
        f"atom_style {atom_style}",
        "atom_modify map array sort 0 0",
        "boundary p p p",
        f"region box block 0 {box:.17g} 0 {box:.17g} 0 {box:.17g}",
        "create_box 1 box",
    ]:
        lmp.command(c)
    for x in positions:
        lmp.command(f"create_atoms 1 single {x[0]:.17g} {x[1]:.17g} {x[2]:.17g}")
    return lmp


def unwrapped_positions(lmp, n: int, box: float) -> np.ndarray:
    """The first n atoms' positions by id, unwrapped by their image flags
    (LAMMPS packs the three counts in one integer, 10 bits each)."""
    order = np.argsort(lmp.numpy.extract_atom("id")[:n])
    image = np.array(lmp.numpy.extract_atom("image")[:n][order]).astype(np.int64)
    counts = np.stack([(image & 1023) - 512, ((image >> 10) & 1023) - 512, (image >> 20) - 512], axis=1)
    return np.array(lmp.numpy.extract_atom("x")[:n][order]) + counts * box


def side_by_side(lammps_run: Callable, quatrot_run: Callable, state: tuple, dt: float, steps: int):
    """Both codes from `state` (its first item the box side): the energies'
    largest difference per step relative to |PE| at t = 0, the largest
    minimum-image difference of the first array of each frame pair, and the
    frame pairs. `lammps_run(*state, dt, steps)` and `quatrot_run(*state,
    dt, steps, out_dir)` return (energies per step, frames)."""
    box = state[0]
    reference, lammps_frames = lammps_run(*state, dt, steps)
    with tempfile.TemporaryDirectory() as tmp:
        ours, quatrot_frames = quatrot_run(*state, dt, steps, Path(tmp))
    energy = np.abs(ours - reference).max(axis=1) / abs(reference[0, 0])
    positions = []
    for ours_frame, lammps_frame in zip(quatrot_frames, lammps_frames):
        d = ours_frame[0] - lammps_frame[0]
        positions.append(np.abs(d - box * np.round(d / box)).max())
    return energy, np.array(positions), list(zip(quatrot_frames, lammps_frames))
