"""Exact canonical references for the thermostat checks, independent of
quatrot: the Maxwell distribution of body angular velocities, the Gamma
distribution of a rotor's kinetic energy, ``cos(theta)`` of a dipole in a
uniform field, and the orientation of an axial quadrupole in a field
gradient by scipy quadrature; and the statistics that judge samples against
them.

Reduced units, ``k_B = 1``. The quadrupole convention is quatrot's
(Buckingham, ``V = -1/3 Theta : G`` with ``G[a][b] = dE_b / dr_a``): an axial
quadrupole ``Theta_b = theta0 diag(-1/2, -1/2, 1)`` whose axis points along
the unit vector ``u`` has ``Theta = theta0 (3/2 u u - 1/2 I)``, so in a
traceless gradient ``V(u) = -theta0/2 u.G.u`` (checked against quatrot's
energies by the check module), and the rotation about ``u`` is uniform:
``p(u) ~ exp(theta0 u.G.u / (2 T))`` on the sphere.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy import integrate, special, stats

QUAD_TOLERANCE = 1e-11


def dipole_cos_cdf(c, x: float):
    """CDF of ``cos(theta)`` for ``p(c) ~ exp(x c)`` on [-1, 1]."""
    c = np.clip(np.asarray(c, float), -1.0, 1.0)
    return (np.exp(x * (c - 1.0)) - np.exp(-2.0 * x)) / -np.expm1(-2.0 * x)


def langevin_function(x: float) -> float:
    """``<cos theta> = coth x - 1/x``."""
    return 1.0 / np.tanh(x) - 1.0 / x


def dipole_cos_variance(x: float) -> float:
    """``Var cos(theta) = 1 - 2 L(x)/x - L(x)^2``."""
    l = langevin_function(x)
    return 1.0 - 2.0 * l / x - l * l


class AxialQuadrupole:
    """The orientation of an axial quadrupole's axis ``u`` in the diagonal
    traceless gradient ``diag(g)`` at temperature ``T``:
    ``p(u) ~ exp(k u.G.u)``, ``k = theta0 / (2 T)``. Two independent
    quadratures: the marginal of ``u_z`` with the azimuth integrated in
    closed form (``int exp(a cos^2 + b sin^2) dphi = 2 pi exp((a+b)/2)
    I0((a-b)/2)``, scipy's ``i0``), and moments by ``dblquad`` over the
    sphere."""

    def __init__(self, theta0: float, gradient_diagonal, temperature: float):
        self.g = np.asarray(gradient_diagonal, float)
        if abs(self.g.sum()) > 1e-12:
            raise ValueError("the gradient must be traceless")
        self.k = theta0 / (2.0 * temperature)
        # Normalise the exponent by its largest value (no overflow).
        self.shift = self.k * self.g.max()
        self.norm = integrate.quad(self._marginal_unnormalised, -1.0, 1.0, epsabs=0, epsrel=QUAD_TOLERANCE)[0]
        grid = np.linspace(-1.0, 1.0, 2001)
        pieces = [integrate.quad(self.marginal, a, b, epsabs=0, epsrel=QUAD_TOLERANCE)[0] for a, b in zip(grid[:-1], grid[1:])]
        self._grid, self._cdf = grid, np.concatenate([[0.0], np.cumsum(pieces)])

    def _marginal_unnormalised(self, c: float) -> float:
        s2 = 1.0 - c * c
        a, b = self.k * self.g[0] * s2, self.k * self.g[1] * s2
        return 2.0 * np.pi * np.exp(0.5 * (a + b) + self.k * self.g[2] * c * c - self.shift) * special.i0(0.5 * (a - b))

    def marginal(self, c: float) -> float:
        """The density of ``u_z``."""
        return self._marginal_unnormalised(c) / self.norm

    def cdf(self, c):
        """The CDF of ``u_z`` (the marginal integrated piecewise on 2000 intervals)."""
        return np.interp(c, self._grid, self._cdf)

    def _weight(self, phi: float, c: float) -> float:
        s = np.sqrt(max(0.0, 1.0 - c * c))
        u = np.array([s * np.cos(phi), s * np.sin(phi), c])
        return float(np.exp(self.k * (u * u) @ self.g - self.shift))

    def moment(self, f) -> float:
        """``<f(u)>`` by ``dblquad`` over ``c = u_z`` and the azimuth."""

        def weighted(phi, c):
            s = np.sqrt(max(0.0, 1.0 - c * c))
            return f(np.array([s * np.cos(phi), s * np.sin(phi), c])) * self._weight(phi, c)

        z = integrate.dblquad(self._weight, -1.0, 1.0, 0.0, 2.0 * np.pi, epsabs=0, epsrel=QUAD_TOLERANCE)[0]
        return integrate.dblquad(weighted, -1.0, 1.0, 0.0, 2.0 * np.pi, epsabs=0, epsrel=QUAD_TOLERANCE)[0] / z

    @functools.cached_property
    def axis_moments(self) -> dict[str, float]:
        """``<u_a^2>`` and ``<u_a^4>`` for a = x, z (``dblquad``)."""
        return {f"{name}{power}": self.moment(lambda v, a=a, power=power: v[a] ** power) for a, name in ((0, "x"), (2, "z")) for power in (2, 4)}

    def normalisation_agreement(self) -> float:
        """The relative difference of the two quadratures' normalisations."""
        z2 = integrate.dblquad(self._weight, -1.0, 1.0, 0.0, 2.0 * np.pi, epsabs=0, epsrel=QUAD_TOLERANCE)[0]
        return abs(z2 / self.norm - 1.0)


def ks_p(samples, cdf) -> float:
    """scipy's one-sample Kolmogorov-Smirnov p-value (exact for the sample size)."""
    return float(stats.kstest(np.asarray(samples, float), cdf).pvalue)


def mean_p(samples, mean: float, variance: float) -> float:
    """Two-sided p-value of the sample mean against ``mean`` (normal, exact variance)."""
    samples = np.asarray(samples, float)
    z = (samples.mean() - mean) / np.sqrt(variance / samples.size)
    return float(2.0 * stats.norm.sf(abs(z)))


def maxwell_p_values(omega_body, moments, temperature: float) -> dict[str, float]:
    """Body angular velocities ``(n, 3)`` of rotors with principal moments
    ``(3,)``: components over ``sqrt(T/I_a)`` against the standard normal,
    each rotor's kinetic energy over ``T`` against Gamma(3/2), its mean
    against 3/2 (variance 3/2)."""
    omega_body = np.asarray(omega_body, float)
    scaled = (omega_body / np.sqrt(temperature / np.asarray(moments))).ravel()
    kinetic = 0.5 * (omega_body**2 * np.asarray(moments)).sum(axis=1) / temperature
    return {
        "omega ~ normal(0, T/I)": ks_p(scaled, stats.norm.cdf),
        "K ~ Gamma(3/2, T)": ks_p(kinetic, stats.gamma(1.5).cdf),
        "<K> = 3T/2": mean_p(kinetic, 1.5, 1.5),
    }
