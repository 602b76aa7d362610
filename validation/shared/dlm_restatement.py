"""The DLM step of pinned dipolar spheres written again in numpy, with a
switch for each way LAMMPS's ``fix nve/sphere update dipole/dlm`` and
quatrot's ``dlm`` (split sweep) differ, so that each code is reproduced to
round-off by the same sweep.

LAMMPS's step (``FixNVESphere::initial_integrate`` and ``final_integrate``,
2025 version), as its source describes it: half kick of the space angular
velocity with the torque; the space-to-body frame that takes the unit dipole
to body z, rebuilt from the dipole every step (the reflection ``-I`` when the
dipole is exactly along -z); rotations about body axes x, y, z, y, x for
dt/2, dt/2, dt, dt/2, dt/2, each a Cayley matrix ``R`` of the angle
``t w_k``, turning the frame by ``R^T`` and the body omega by ``R``; the
dipole read back as the frame's third row; half kick with the new torques.

quatrot's DLM with ``SphericalTops::Split`` takes the same sweep with exact
rotations, turns the body omega by ``R^T`` (the exact flow of each kinetic
term: the space angular momentum is kept) and carries the full orientation
from step to step. The sweep order (the DLM paper's 1, 2, 3, 2, 1) is one
argument shared by both variants.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from validation.shared import dipole_reference as ref
from validation.shared.lammps_driver import DipoleSystem


@dataclass(frozen=True)
class Variant:
    """Which DLM step to take (module doc)."""

    cayley: bool  # Cayley rotation matrices (LAMMPS) instead of exact rotations
    lammps_sense: bool  # body omega turned by R (LAMMPS) instead of R^T
    rebuild_frame: bool  # frame rebuilt from the dipole each step (LAMMPS) instead of carried
    axes: tuple[int, int, int] = (0, 1, 2)  # the sweep's outer, middle, inner body axes

    def reversed(self) -> Variant:
        """The same step with the sweep reversed (inner axis outermost)."""
        outer, middle, inner = self.axes
        return Variant(self.cayley, self.lammps_sense, self.rebuild_frame, (inner, middle, outer))


LAMMPS_DLM = Variant(cayley=True, lammps_sense=True, rebuild_frame=True)
QUATROT_SPLIT = Variant(cayley=False, lammps_sense=False, rebuild_frame=False)


def rotation(axis: int, angle: float, cayley: bool) -> np.ndarray:
    """Rotation by ``angle`` about coordinate axis ``axis`` as LAMMPS's
    ``BuildR*Matrix`` lays it out; Cayley's rational approximation of cos and
    sin when ``cayley``."""
    if cayley:
        c = (1 - angle * angle / 4) / (1 + angle * angle / 4)
        s = angle / (1 + angle * angle / 4)
    else:
        c, s = np.cos(angle), np.sin(angle)
    r = np.eye(3)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    r[i, i] = r[j, j] = c
    r[i, j], r[j, i] = -s, s
    return r


def lammps_frame(a: np.ndarray) -> np.ndarray:
    """LAMMPS's space-to-body frame of the unit dipole ``a`` (body z along ``a``)."""
    s2 = a[0] ** 2 + a[1] ** 2
    if s2 == 0.0:
        return np.eye(3) / a[2]
    k = (1.0 - a[2]) / s2
    return np.array(
        [
            [1 - k * a[0] ** 2, -k * a[0] * a[1], -a[0]],
            [-k * a[0] * a[1], 1 - k * a[1] ** 2, -a[1]],
            [a[0], a[1], 1 - k * s2],
        ]
    )


def sweep(frame: np.ndarray, omega_body: np.ndarray, dt: float, variant: Variant) -> tuple[np.ndarray, np.ndarray]:
    """The free rotation of one sphere: the frame and the body omega after
    the sweep of ``variant`` over ``dt``."""
    outer, middle, inner = variant.axes
    w = omega_body
    for axis, fraction in [(outer, 0.5), (middle, 0.5), (inner, 1.0), (middle, 0.5), (outer, 0.5)]:
        r = rotation(axis, fraction * dt * w[axis], variant.cayley)
        w = (r if variant.lammps_sense else r.T) @ w
        frame = r.T @ frame
    return frame, w


@dataclass
class Trajectory:
    """Every step of a restated run (index 0 is t = 0)."""

    dipoles: np.ndarray  # (steps+1, n, 3) space frame
    omega: np.ndarray  # (steps+1, n, 3) space frame
    frames: np.ndarray  # (steps+1, n, 3, 3) space to body


def run(system: DipoleSystem, dt: float, steps: int, variant: Variant) -> Trajectory:
    """``steps`` restated DLM steps of ``variant`` from the system's dipoles
    and space omegas, starting from LAMMPS's frame of each dipole."""
    n = len(system.sites)
    lengths = np.linalg.norm(system.dipoles, axis=1)
    mu, w = system.dipoles.copy(), system.omega.copy()
    frames = np.array([lammps_frame(m / length) for m, length in zip(mu, lengths)])
    out = Trajectory(np.zeros((steps + 1, n, 3)), np.zeros((steps + 1, n, 3)), np.zeros((steps + 1, n, 3, 3)))
    out.dipoles[0], out.omega[0], out.frames[0] = mu, w, frames
    torque = ref.torques(system, mu)
    for k in range(1, steps + 1):
        w = w + 0.5 * dt * torque / system.inertia
        for i in range(n):
            frame = lammps_frame(mu[i] / lengths[i]) if variant.rebuild_frame else frames[i]
            frames[i], w_body = sweep(frame, frame @ w[i], dt, variant)
            w[i] = frames[i].T @ w_body
            mu[i] = frames[i][2] * lengths[i]
        torque = ref.torques(system, mu)
        w = w + 0.5 * dt * torque / system.inertia
        out.dipoles[k], out.omega[k], out.frames[k] = mu, w, frames
    return out
