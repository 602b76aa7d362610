"""The free (or uniform-field dipole) asymmetric top integrated by scipy's
DOP853 at rtol 1e-12, independently of quatrot: eq 10 of the note,
``Q' = 1/2 Q*(0, w_b)`` (Hamilton product), and Euler's equations
``I w_b' = n_b - w_b x (I w_b)``, with the optional body torque
``n_b = mu_b x E_b``, ``E_b = A(Q) E`` and ``A`` the matrix of eq 7 (space to
body). Shared by the fixture generators (``fixtures/gen_free_top.py``,
``gen_dipole_field.py``) and the ``dynamics`` check."""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

RTOL = 1e-12
ATOL = 1e-14


def hamilton(p, q):
    """The Hamilton product ``(p0 q0 - p.q, p0 q + q0 p + p x q)``."""
    p0, pv = p[0], p[1:]
    q0, qv = q[0], q[1:]
    return np.concatenate([[p0 * q0 - pv @ qv], p0 * qv + q0 * pv + np.cross(pv, qv)])


def space_to_body(q):
    """The matrix A(Q) of eq 7 of the note, as printed (space to body)."""
    q0, q1, q2, q3 = q
    return np.array(
        [
            [q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 + q0 * q3), 2 * (q1 * q3 - q0 * q2)],
            [2 * (q1 * q2 - q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3, 2 * (q2 * q3 + q0 * q1)],
            [2 * (q1 * q3 + q0 * q2), 2 * (q2 * q3 - q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3],
        ]
    )


def integrate(inertia, q0, omega_body0, times, dipole_body=None, field=None):
    """Orientations and body angular velocities at ``times`` (DOP853)."""
    inertia = np.asarray(inertia, float)

    def rhs(_t, y):
        q, w = y[:4], y[4:]
        torque_body = np.zeros(3)
        if dipole_body is not None:
            torque_body = np.cross(dipole_body, space_to_body(q) @ np.asarray(field, float))
        q_dot = 0.5 * hamilton(q, np.concatenate([[0.0], w]))
        w_dot = (torque_body - np.cross(w, inertia * w)) / inertia
        return np.concatenate([q_dot, w_dot])

    y0 = np.concatenate([np.asarray(q0, float) / np.linalg.norm(q0), omega_body0])
    sol = solve_ivp(rhs, (times[0], times[-1]), y0, method="DOP853", t_eval=times, rtol=RTOL, atol=ATOL)
    if not sol.success:
        raise RuntimeError(sol.message)
    return sol.y[:4].T, sol.y[4:].T
