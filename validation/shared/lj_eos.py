"""Two equations of state of the Lennard-Jones fluid, both fitted to
simulations of the full (untruncated) LJ potential, in reduced units
(epsilon = sigma = k_B = 1): Kolafa and Nezbeda's (1994, KN: the `kn_`
functions at the end, the reference of the equation-of-state check) and,
first, J. K. Johnson, J. A. Zollweg and K. E. Gubbins, "The Lennard-Jones
equation of state revisited", Mol. Phys. 78, 591 (1993) (JZG): a modified
Benedict-Webb-Rubin form.

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

import cmath
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


# Kolafa and Nezbeda, "The Lennard-Jones fluid: an accurate analytic and
# theoretically-based equation of state", Fluid Phase Equilib. 100, 1 (1994)
# (KN), their eq 30 for the residual Helmholtz energy per particle:
#
#     A_res = T A_HS(eta) + exp(-gamma rho^2) rho T dB2(T) + sum_ij C_ij T^(i/2) rho^j,
#
# A_HS = (5/3) ln(1 - eta) + eta (34 - 33 eta + 4 eta^2) / (6 (1 - eta)^2) the
# hard-sphere term at the packing eta = pi rho d^3 / 6 of the hybrid
# Barker-Henderson diameter d(T), dB2 the second virial coefficient's
# correction, gamma = 1.92907278; the coefficients are the paper's, as
# restated by SklogWiki's "Lennard-Jones equation of state" page. P and U
# (eqs 31-32) are taken here as exact derivatives of A_res (complex step:
# f'(x) = Im f(x + i h) / h to round-off), not from their printed forms.
KN_GAMMA = 1.92907278
# d(T) = sum_k D_k T^(k/2) + D_ln ln T, k = -2, -1, 0, 1.
KN_DIAMETER = {-2: 0.011117524, -1: -0.076383859, 0: 1.080142248, 1: 0.000693129}
KN_DIAMETER_LN = -0.063920968
# dB2(T) = sum_k B_k T^(k/2), k = -7 .. 0.
KN_VIRIAL = {-7: -0.58544978, -6: 0.43102052, -5: 0.87361369, -4: -4.13749995, -3: 2.90616279, -2: -7.02181962, 0: 0.02459877}
# C_ij: {i: (C_i2, C_i3, ...)} for T^(i/2) rho^j, j = 2, 3, ...
KN_C = {
    0: (2.01546797, -28.17881636, 28.28313847, -10.42402873),
    -1: (-19.58371655, 75.62340289, -120.70586598, 93.92740328, -27.37737354),
    -2: (29.34470520, -112.35356937, 170.64908980, -123.06669187, 34.42288969),
    -4: (-13.37031968, 65.38059570, -115.09233113, 88.91973082, -25.62099890),
}
_STEP = 1e-20


def kn_helmholtz_residual(temperature, density):
    """A_res / N of KN eq 30 (accepts complex arguments for the derivatives)."""
    d = sum(c * temperature ** (k / 2) for k, c in KN_DIAMETER.items()) + KN_DIAMETER_LN * cmath.log(temperature)
    eta = math.pi / 6 * density * d**3
    hard = 5 / 3 * cmath.log(1 - eta) + eta * (34 - 33 * eta + 4 * eta**2) / (6 * (1 - eta) ** 2)
    virial = sum(c * temperature ** (k / 2) for k, c in KN_VIRIAL.items())
    polynomial = sum(c * temperature ** (i / 2) * density ** (j + 2) for i, cs in KN_C.items() for j, c in enumerate(cs))
    return temperature * hard + cmath.exp(-KN_GAMMA * density**2) * density * temperature * virial + polynomial


def kn_pressure(temperature: float, density: float) -> float:
    """P = rho T + rho^2 dA_res/drho."""
    slope = kn_helmholtz_residual(temperature, complex(density, _STEP)).imag / _STEP
    return density * temperature + density**2 * slope


def kn_internal_energy(temperature: float, density: float) -> float:
    """U_res / N = d(A_res / T)/d(1/T) = A_res - T dA_res/dT."""
    slope = kn_helmholtz_residual(complex(temperature, _STEP), density).imag / _STEP
    return kn_helmholtz_residual(temperature, density).real - temperature * slope
