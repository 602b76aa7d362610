"""The note's orientation conventions expressed in ASE's and scipy's terms.

quatrot (and Allen's note): ``Q = (q0, q1, q2, q3)`` scalar first, Hamilton
product, ``A(Q)`` of eq 7 maps space to body (``r_b = A r_s``), ``R(Q) = A^T``
maps body to space and is the active rotation of ``Q``; Euler angles
``(phi, theta, psi)`` in Goldstein's y-convention (eq 8), radians, with
``R = Rz(phi) Ry(theta) Rz(psi)``.

* scipy ``Rotation``: active; ``from_quat``/``as_quat`` are scalar LAST unless
  ``scalar_first=True``; ``as_matrix()`` is ``R``; ``from_euler('ZYZ', ...)``
  (upper case) is intrinsic, so ``('ZYZ', [phi, theta, psi])`` is the note's.
* ASE ``Quaternion``: scalar first, Hamilton product; ``rotation_matrix()`` is
  the active ``R``; ``from_euler_angles(a, b, c, 'zyz')`` is
  ``Rz(c) Ry(b) Rz(a)``, so its first angle is the note's ``psi``.
* ASE ``Atoms.rotate(angle, axis, center)``: active rotation of the positions
  about ``center``, angle in DEGREES: body template -> space.
* ASE ``Atoms.euler_rotate(phi, theta, psi, center)``: DEGREES, Goldstein's
  x-convention (z, x', z''), passive: positions ``p -> c + A_x (p - c)``,
  space -> body. The note's y-convention angles map to
  ``(phi + 90, theta, psi - 90)`` degrees.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation


def scipy_rotation(q) -> Rotation:
    """The scipy rotation of scalar-first quaternions ``q`` (n, 4) or (4,): ``R(Q)``."""
    return Rotation.from_quat(np.asarray(q, float), scalar_first=True)


def scipy_rotation_from_euler_y(angles) -> Rotation:
    """The scipy rotation ``R`` of the note's y-convention angles (radians)."""
    return Rotation.from_euler("ZYZ", np.asarray(angles, float))


def euler_y_to_ase_zyz(angles) -> np.ndarray:
    """Arguments ``(a, b, c)`` of ASE ``Quaternion.from_euler_angles(a, b, c, 'zyz')``
    giving the note's ``Q(phi, theta, psi)``: ``(psi, theta, phi)``."""
    phi, theta, psi = np.asarray(angles, float).T
    return np.stack([psi, theta, phi], axis=-1)


def euler_y_to_ase_euler_rotate(angles) -> np.ndarray:
    """Degrees ``(phi_x, theta_x, psi_x)`` for ASE ``Atoms.euler_rotate`` (x-convention)
    whose passive rotation is the note's ``A(phi, theta, psi)``."""
    phi, theta, psi = np.degrees(np.asarray(angles, float)).T
    return np.stack([phi + 90.0, theta, psi - 90.0], axis=-1)


def axis_angle_degrees(q) -> tuple[np.ndarray, float]:
    """Axis and angle (degrees) of one unit quaternion, for ASE ``Atoms.rotate``."""
    q = np.asarray(q, float)
    s = np.linalg.norm(q[1:])
    return q[1:] / s, np.degrees(2.0 * np.arctan2(s, q[0]))


def same_rotation(a, b) -> float:
    """Largest componentwise distance between quaternions ``a`` and ``b`` (..., 4),
    blind to the sign (``Q`` and ``-Q`` are one rotation)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1)).max())


def scipy_q_dot(q, omega, frame: str, h: float = 1e-5) -> np.ndarray:
    """``dQ/dt`` at ``t = 0`` by central differences of motion built by scipy alone:
    ``R(t) = R(Q) Rot(w t)`` for ``frame='body'``, ``Rot(w t) R(Q)`` for ``'space'``,
    with the sign of each ``Q(t)`` matched to ``q``."""
    q = np.asarray(q, float)
    start = scipy_rotation(q)

    def at(t):
        step = Rotation.from_rotvec(np.asarray(omega, float) * t)
        quat = (start * step if frame == "body" else step * start).as_quat(scalar_first=True)
        return quat * np.sign(np.sum(quat * q, axis=-1))[..., None]

    return (at(h) - at(-h)) / (2 * h)
