"""An independent Ewald sum for point dipoles and Buckingham quadrupoles in an
orthorhombic box, written in numpy from the textbook formulas (Smith, CCP5
Newsletter 46 (1998); Aguado & Madden, J. Chem. Phys. 119, 7471 (2003); the
surface term of de Leeuw, Perram & Smith, Proc. R. Soc. A 373, 27 (1980)).
It shares no code with quatrot: the real-space part contracts full Cartesian
derivative tensors of erfc(alpha r)/r (built here by einsum), the reciprocal
part is a direct sum over every wave vector of the box, and torques come
from the derivatives of this energy under rotations of each multipole.

Reduced units, 4 pi eps0 = 1. Multipoles are in the space frame: mu (n, 3),
Theta (n, 3, 3) traceless (Buckingham: phi(r) = r.Theta.r / r^5).

    V = sum_{pairs, images} [-mu_t mu_s : T2 + 1/3 mu_t Theta_s : T3
                             - 1/3 Theta_t mu_s : T3 + 1/9 Theta_t Theta_s :: T4]
        + (2 pi / V) sum_{k != 0} exp(-k^2 / 4 a^2) / k^2 |S(k)|^2
        - 2 a^3 / (3 sqrt(pi)) sum mu^2 - 8 a^5 / (45 sqrt(pi)) sum Theta:Theta
        [+ 2 pi |M|^2 / (3 V) in vacuum]

with T_l = grad^l erfc(a r)/r at r = r_t - r_s and
S(k) = sum_j (-i mu_j.k - 1/3 k.Theta_j.k) exp(-i k.r_j).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import erfc

# Far below double round-off: exp(-S^2) ~ 1e-21 in both spaces.
S_CONVERGED = 6.9


def _derivative_tensors(r: np.ndarray, alpha: float):
    """grad^l of erfc(alpha |r|)/|r| for l = 2, 3, 4, for an array of offsets
    r (m, 3): arrays (m, 3, 3), (m, 3, 3, 3), (m, 3, 3, 3, 3)."""
    d = np.linalg.norm(r, axis=1)
    b = [erfc(alpha * d) / d]
    gauss = np.exp(-((alpha * d) ** 2)) / (alpha * math.sqrt(math.pi))
    for l in range(1, 5):
        gauss = gauss * 2 * alpha**2
        b.append(((2 * l - 1) * b[-1] + gauss) / d**2)
    eye = np.eye(3)
    rr = np.einsum("ma,mb->mab", r, r)
    t2 = rr * b[2][:, None, None] - eye * b[1][:, None, None]
    # grad^3: -r r r B3 + (delta r) B2, symmetrised over the three indices
    rrr = np.einsum("ma,mb,mc->mabc", r, r, r)
    dr = np.einsum("ab,mc->mabc", eye, r)
    t3 = -rrr * b[3][:, None, None, None] + (dr + dr.transpose(0, 1, 3, 2) + dr.transpose(0, 3, 2, 1)) * b[2][:, None, None, None]
    rrrr = np.einsum("ma,mb,mc,md->mabcd", r, r, r, r)
    pairs = sum(np.einsum(f"{d},m{x},m{y}->mabcd", eye, r, r) for d, x, y in _DELTA_R_R)
    dd = sum(np.einsum(f"{d1},{d2}->abcd", eye, eye) for d1, d2 in (("ab", "cd"), ("ac", "bd"), ("ad", "bc")))
    t4 = rrrr * b[4][:, None, None, None, None] - pairs * b[3][:, None, None, None, None] + dd[None] * b[2][:, None, None, None, None]
    return t2, t3, t4


# delta over one index pair, r r over the other two: the six terms of grad^4.
_DELTA_R_R = (("ab", "c", "d"), ("ac", "b", "d"), ("ad", "b", "c"), ("bc", "a", "d"), ("bd", "a", "c"), ("cd", "a", "b"))


@dataclass
class EwaldResult:
    energy: float
    field: np.ndarray  # (n, 3): -dV/dmu
    conjugate: np.ndarray  # (n, 3, 3): dV/dTheta (symmetrised)
    torques: np.ndarray  # (n, 3) space frame


def image_shifts(box, rc) -> np.ndarray:
    """The lattice vectors of the box's images reaching within ``rc`` of the box, (m, 3)."""
    m = np.ceil(rc / box).astype(int) + 1
    return np.array(np.meshgrid(*[np.arange(-k, k + 1) for k in m], indexing="ij")).reshape(3, -1).T * box


def wave_vectors(box, kc) -> tuple[np.ndarray, np.ndarray]:
    """Every wave vector ``2 pi (h / L_x, k / L_y, l / L_z)`` with ``0 < |k| <= kc``, and ``|k|^2``."""
    kmax = np.floor(kc * box / (2 * math.pi)).astype(int)
    grid = np.array(np.meshgrid(*[np.arange(-k, k + 1) for k in kmax], indexing="ij")).reshape(3, -1).T
    k = grid * (2 * math.pi / box)
    k2 = np.einsum("ka,ka->k", k, k)
    keep = (k2 > 0) & (k2 <= kc * kc)
    return k[keep], k2[keep]


def ewald(sites, box, mu=None, theta=None, surface="conducting", alpha=None) -> EwaldResult:
    """The converged Ewald energy, fields and torques (see the module doc)."""
    sites = np.asarray(sites, float)
    box = np.asarray(box, float)
    n = len(sites)
    mu = np.zeros((n, 3)) if mu is None else np.asarray(mu, float)
    theta = np.zeros((n, 3, 3)) if theta is None else np.asarray(theta, float)
    volume = float(np.prod(box))
    if alpha is None:
        alpha = 5.0 / box.min()
    rc = S_CONVERGED / alpha
    kc = 2 * alpha * S_CONVERGED

    # Real space: every image within rc, every ordered pair, half the sum.
    # V is bilinear, so dV/dmu_t and dV/dTheta_t collect the target's terms.
    dv_dmu = np.zeros((n, 3))
    dv_dtheta = np.zeros((n, 3, 3))
    shifts = image_shifts(box, rc)
    for t in range(n):
        r = sites[t] - sites[None, :, :] + shifts[:, None, :]  # (images, sources, 3): r_t - (r_s - shift)
        r = r.reshape(-1, 3)
        src = np.tile(np.arange(n), len(shifts))
        d = np.linalg.norm(r, axis=1)
        keep = (d <= rc) & (d > 1e-12)
        r, src = r[keep], src[keep]
        t2, t3, t4 = _derivative_tensors(r, alpha)
        mu_s, th_s = mu[src], theta[src]
        # dV/dmu_t of [-mu_t mu_s : T2 + 1/3 mu_t Theta_s : T3]
        dv_dmu[t] = -np.einsum("mab,mb->a", t2, mu_s) + np.einsum("mabc,mbc->a", t3, th_s) / 3
        # dV/dTheta_t of [-1/3 Theta_t mu_s : T3 + 1/9 Theta_t Theta_s :: T4]
        dv_dtheta[t] = -np.einsum("mabc,mc->ab", t3, mu_s) / 3 + np.einsum("mabcd,mcd->ab", t4, th_s) / 9
    # Each pair appears from both ends: V_real = 1/2 sum_t (mu_t.dV/dmu_t + Theta_t:dV/dTheta_t).

    # Reciprocal space: every wave vector with 0 < |k| <= kc.
    k, k2 = wave_vectors(box, kc)
    g = 4 * math.pi / volume * np.exp(-k2 / (4 * alpha**2)) / k2
    phase = np.exp(-1j * sites @ k.T)  # (n, k): exp(-i k.r_j)
    coef = -1j * (mu @ k.T) - np.einsum("ka,jab,kb->jk", k, theta, k) / 3
    s = np.sum(coef * phase, axis=0)
    recip = 0.5 * np.sum(g * np.abs(s) ** 2)
    # dV/dmu_j = 1/2 sum_k g 2 Re[conj(S) dS/dmu_j], dS/dmu_j = -i k exp(-i k.r_j)
    w = g * np.conj(s)
    recip_dmu = np.real(np.einsum("k,jk,ka->ja", w, -1j * phase, k))
    recip_dtheta = np.real(np.einsum("k,jk,ka,kb->jab", w, phase, k, k)) * (-1 / 3)
    dv_dmu += recip_dmu
    dv_dtheta += recip_dtheta

    # Self and surface terms.
    a3 = 2 * alpha**3 / (3 * math.sqrt(math.pi))
    a5 = 8 * alpha**5 / (45 * math.sqrt(math.pi))
    dv_dmu -= 2 * a3 * mu
    dv_dtheta -= 2 * a5 * theta
    total = mu.sum(axis=0)
    if surface == "vacuum":
        dv_dmu += 4 * math.pi * total / (3 * volume)
    elif surface != "conducting":
        raise ValueError(f"surface: {surface!r}")

    # V is a quadratic form in the multipoles: V = 1/2 sum (mu.dV/dmu + Theta:dV/dTheta).
    energy = 0.5 * (np.einsum("ja,ja->", mu, dv_dmu) + np.einsum("jab,jab->", theta, dv_dtheta))
    # The reciprocal part summed directly, as a check of the derivative above.
    recip_from_derivative = 0.5 * (np.einsum("ja,ja->", mu, recip_dmu) + np.einsum("jab,jab->", theta, recip_dtheta))
    if abs(recip_from_derivative - recip) > 1e-12 * max(1.0, abs(recip)):
        raise AssertionError(f"reciprocal energy {recip} vs its derivative form {recip_from_derivative}")
    dv_dtheta = 0.5 * (dv_dtheta + dv_dtheta.transpose(0, 2, 1))

    # Torques: -dV/dphi for a rotation of multipole j about axis u:
    # d mu = u x mu, d Theta = [u]x Theta - Theta [u]x.
    torques = np.zeros((n, 3))
    for a in range(3):
        u = np.eye(3)[a]
        ux = np.array([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
        dmu = np.cross(u, mu)
        dth = ux @ theta - theta @ ux
        torques[:, a] = -(np.einsum("ja,ja->j", dv_dmu, dmu) + np.einsum("jab,jab->j", dv_dtheta, dth))
    return EwaldResult(energy=float(energy), field=-dv_dmu, conjugate=dv_dtheta, torques=torques)
