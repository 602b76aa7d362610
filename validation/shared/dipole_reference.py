"""Independent references for pinned dipolar spherical tops, in the space
frame only (no quaternions, no body frame, nothing shared with quatrot or
LAMMPS): energies, torques, and a tight DOP853 integration of

    d mu_i / dt = w_i x mu_i,    I d w_i / dt = mu_i x F_i,
    F_i = E + sum_{j != i} (3 (mu_j . u) u - mu_j) / r^3,   r u = r_i - r_j,

with V = sum_{i<j} (mu_i . mu_j - 3 (mu_i . u)(mu_j . u)) / r^3 - sum_i mu_i . E
(reduced units, 4 pi eps0 = 1). Also the exact free rotation of a sphere.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from validation.shared.lammps_driver import DipoleSystem

RTOL = 1e-12  # DOP853 tolerances: far below the integrator errors compared
ATOL = 1e-13


def _field(system: DipoleSystem) -> np.ndarray:
    return np.zeros(3) if system.field is None else np.asarray(system.field, dtype=float)


def _pair_geometry(system: DipoleSystem):
    """Unit vectors u_ij and distances r_ij for r_i - r_j (diagonal: u = 0, r = inf)."""
    r = system.sites[:, None, :] - system.sites[None, :, :]
    d = np.linalg.norm(r, axis=-1)
    np.fill_diagonal(d, np.inf)
    return r / d[..., None], d


def local_fields(system: DipoleSystem, dipoles: np.ndarray) -> np.ndarray:
    """F_i: the external field plus the dipole fields of all other sites."""
    u, d = _pair_geometry(system)
    mu_dot_u = np.einsum("jc,ijc->ij", dipoles, u)
    pair = (3.0 * mu_dot_u[..., None] * u - dipoles[None, :, :]) / d[..., None] ** 3
    return _field(system) + pair.sum(axis=1)


def energy(system: DipoleSystem, dipoles: np.ndarray) -> float:
    """V: the pair sum over i < j (half the double sum) plus the field term."""
    u, d = _pair_geometry(system)
    mu_u = np.einsum("ic,ijc->ij", dipoles, u)
    mu_mu = dipoles @ dipoles.T
    # mu_u[j, i] = mu_j . u_ji = -mu_j . u_ij
    pair = (mu_mu + 3.0 * mu_u * mu_u.T) / d**3
    return 0.5 * float(pair.sum()) - float(np.sum(dipoles @ _field(system)))


def torques(system: DipoleSystem, dipoles: np.ndarray) -> np.ndarray:
    """Space-frame torques mu_i x F_i."""
    return np.cross(dipoles, local_fields(system, dipoles))


def trajectory(system: DipoleSystem, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Dipoles and space omegas at ``times`` (starting at 0), DOP853."""
    n = len(system.sites)
    inertia = system.inertia

    def rhs(_, y):
        mu = y[: 3 * n].reshape(n, 3)
        w = y[3 * n :].reshape(n, 3)
        return np.concatenate([np.cross(w, mu).ravel(), (torques(system, mu) / inertia).ravel()])

    y0 = np.concatenate([system.dipoles.ravel(), system.omega.ravel()])
    sol = solve_ivp(rhs, (0.0, float(times[-1])), y0, method="DOP853", t_eval=times, rtol=RTOL, atol=ATOL)
    y = sol.y.T
    return y[:, : 3 * n].reshape(-1, n, 3), y[:, 3 * n :].reshape(-1, n, 3)


def free_rotation(dipole: np.ndarray, omega: np.ndarray, t: float) -> np.ndarray:
    """Exact free sphere: the dipole turns about the constant omega by |omega| t."""
    return Rotation.from_rotvec(omega * t).apply(dipole)
