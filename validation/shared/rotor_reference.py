"""Independent references and error measures for the benchmarks and the
long-run studies (`validation.longrun.at_length`).

Single rotors: scipy DOP853 at rtol 1e-12 on the rigid-body equations in
quaternion form (eq 10 and Euler's equations), with the torque of a body
dipole in a uniform field; nothing from quatrot is used.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from validation.shared.lammps_driver import space_to_body

RTOL = 1e-12
ATOL = 1e-14


def hamilton(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The Hamilton product ``p * q`` (scalar first)."""
    p0, pv, q0, qv = p[0], p[1:], q[0], q[1:]
    return np.concatenate([[p0 * q0 - pv @ qv], p0 * qv + q0 * pv + np.cross(pv, qv)])


def single_rotor_final(inertia, dipole_body, field, q0, omega_body0, time: float) -> np.ndarray:
    """The orientation at ``time`` of one rotor (principal moments ``inertia``,
    body dipole ``dipole_body`` or None, uniform field ``field`` or None)."""
    return single_rotor_path(inertia, dipole_body, field, q0, omega_body0, [time])[-1]


def single_rotor_path(inertia, dipole_body, field, q0, omega_body0, times, rtol: float = RTOL, atol: float = ATOL) -> np.ndarray:
    """The orientations (unit, one row per time) of the rotor of
    `single_rotor_final` at the increasing ``times`` (> 0)."""
    inertia = np.asarray(inertia, float)
    mu_b = None if dipole_body is None else np.asarray(dipole_body, float)
    e = None if field is None else np.asarray(field, float)

    def rhs(_t, y):
        q, w = y[:4], y[4:]
        torque_body = np.zeros(3)
        if mu_b is not None and e is not None:
            a = space_to_body(q / np.linalg.norm(q))
            torque_body = a @ np.cross(a.T @ mu_b, e)
        q_dot = 0.5 * hamilton(q, np.concatenate([[0.0], w]))
        w_dot = (torque_body - np.cross(w, inertia * w)) / inertia
        return np.concatenate([q_dot, w_dot])

    y0 = np.concatenate([np.asarray(q0, float), np.asarray(omega_body0, float)])
    times = np.asarray(times, float)
    sol = solve_ivp(rhs, (0.0, float(times[-1])), y0, method="DOP853", rtol=rtol, atol=atol, t_eval=times)
    q = sol.y[:4].T
    return q / np.linalg.norm(q, axis=1)[:, None]


def rotation_angle(q: np.ndarray, q_ref: np.ndarray) -> float:
    """The largest (over rotors) angle of the rotation taking ``q_ref`` to
    ``q`` (rows of unit quaternions; sign-blind)."""
    q = np.atleast_2d(q) / np.linalg.norm(np.atleast_2d(q), axis=1)[:, None]
    r = np.atleast_2d(q_ref)
    dot = np.abs(np.sum(q * r, axis=1))
    chord = np.linalg.norm(q - np.sign(np.sum(q * r, axis=1))[:, None] * r, axis=1)
    # 2 atan2(|sin|, |cos|) of the half angle, accurate for small angles
    return float(np.max(2.0 * np.arctan2(chord * np.sqrt(np.maximum(0.0, 1 - chord**2 / 4)), dot)))


def body_z_in_space(q: np.ndarray) -> np.ndarray:
    """``R(Q) e_z`` per row (the dipole or quadrupole axis of an axial rotor)."""
    q = np.atleast_2d(q)
    q = q / np.linalg.norm(q, axis=1)[:, None]
    q0, q1, q2, q3 = q.T
    return np.stack([2 * (q1 * q3 + q0 * q2), 2 * (q2 * q3 - q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3], axis=1)


def axis_angle(u: np.ndarray, u_ref: np.ndarray) -> float:
    """The largest (over rotors) angle between two sets of axes (rows)."""
    cross = np.linalg.norm(np.cross(u, u_ref), axis=1)
    dot = np.sum(u * u_ref, axis=1)
    norms = np.linalg.norm(u, axis=1) * np.linalg.norm(u_ref, axis=1)
    return float(np.max(np.arctan2(cross / norms, dot / norms)))
