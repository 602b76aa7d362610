"""Built-in scenes as dicts, adjusted for a check (size, boundary, integrator,
what to record) and run through ``quatrot.run``; shared by the trajectory
checks (ASE, OpenMM, mdtraj, dynamics)."""

from __future__ import annotations

import copy
import tomllib

import numpy as np

import quatrot

ENERGIES = ("kinetic_energy", "potential_energy", "total_energy")


def builtin(name: str) -> dict:
    """The built-in scene ``name`` as a dict (parsed from the TOML quatrot embeds)."""
    return tomllib.loads(quatrot.builtin_scenes()[name])


def variant(
    name: str,
    *,
    integrator: str | dict | None = None,
    cells: int | None = None,
    open_boundary: bool = False,
    every: int | None = None,
    quantities: tuple[str, ...] = (),
    marker_length: float | None = None,
) -> dict:
    """A copy of built-in ``name`` with the given lattice size, open boundaries,
    integrator (a kind or a dict with options) and a record of ``quantities``
    and trajectory frames every ``every`` steps (nothing else recorded)."""
    scene = copy.deepcopy(builtin(name))
    if cells is not None:
        scene["rotors"]["cells"] = cells
    if open_boundary and "interactions" in scene:
        scene["interactions"]["boundary"] = {"kind": "open"}
    if integrator is not None:
        scene["integrator"] = {"kind": integrator} if isinstance(integrator, str) else dict(integrator)
    if every is not None:
        record = {k: v for k, v in scene.get("record", {}).items() if k == "energy_error_threshold"}
        if quantities:
            record["series"] = [{"name": "samples", "every": every, "quantities": list(quantities)}]
        record["trajectory"] = {"every": every} | ({"marker_length": marker_length} if marker_length else {})
        scene["record"] = record
    return scene


def body_multipoles(scene: dict, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Per-rotor body dipoles (n, 3) and quadrupoles (n, 3, 3) of a scene whose
    rotors all take the lattice default (zeros where absent)."""
    default = scene["rotors"].get("default", {})
    if scene["rotors"].get("override"):
        raise ValueError("per-rotor overrides are not mapped by body_multipoles")
    mu = np.asarray(default.get("dipole", np.zeros(3)), float)
    theta = np.asarray(default.get("quadrupole", np.zeros((3, 3))), float)
    return np.tile(mu, (n, 1)), np.tile(theta, (n, 1, 1))


def principal_moments(scene: dict) -> np.ndarray:
    """The default principal moments (3,) of a scene's rotors (a scalar means a spherical top)."""
    inertia = np.asarray(scene["rotors"]["default"]["inertia"], float)
    return np.broadcast_to(inertia, (3,)).astype(float)


def run(scene: dict, **options) -> dict:
    """``quatrot.run`` on a scene dict; ``options`` are its keywords (dt, steps, out_dir, ...)."""
    return quatrot.run(scene, **options)
