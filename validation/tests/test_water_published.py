"""The values the check ``water_published`` expects
(validation/shared/water_nvt_runs.py), against closed forms worked by hand
from the published table: at the model's own density the pressure is 1 bar
and the energy ``R T - dh_vap``; away from it the pressure follows ``ln(rho /
rho0) / kappa`` and the energy ``T alpha / kappa`` times the change of
molar volume."""

import math

import pytest

from validation.shared import water_nvt_runs as wp


def test_at_the_model_s_own_density_the_pressure_is_one_bar_and_the_energy_rt_less_dh_vap():
    p = wp.PUBLISHED["spce"]
    pressure, _ = wp.expected_pressure(p, rho=p.rho0)
    assert pressure == pytest.approx(1 / 1.01325, rel=1e-12)  # atm
    energy, error = wp.expected_energy(p, rho=p.rho0)
    # R T at 298 K: 8.314462618 * 298 / 4184 = 0.5921869 kcal/mol.
    assert energy == pytest.approx(0.5921869 - 11.79, abs=1e-6)
    assert error == pytest.approx(0.01, rel=1e-12)


def test_tip3p_at_0_997_by_hand():
    """TIP3P (rho0 0.980, kappa 57.4e-6/bar, alpha 9.2e-4/K): p = 1 + ln(0.997
    / 0.980) / 57.4e-6 = 300.6 bar = 296.7 atm; the energy 0.0354 kcal/mol
    below R T - dh_vap (298 * 9.2e-4 / 57.4e-6 = 4776 bar times 18.0154 (1 /
    0.997 - 1 / 0.980) = -0.3135 cm^3/mol, 0.1 J per bar cm^3)."""
    p = wp.PUBLISHED["tip3p"]
    pressure, error = wp.expected_pressure(p)
    assert pressure == pytest.approx((1 + math.log(0.997 / 0.980) / 57.4e-6) / 1.01325, rel=1e-12)
    assert pressure == pytest.approx(296.7, abs=0.1)
    # 0.001 / (0.980 * 57.4e-6) = 17.8 bar and 5 % of 299.6 bar = 15.0 bar in quadrature.
    assert error == pytest.approx(math.hypot(17.78, 14.98) / 1.01325, rel=1e-3)
    energy, _ = wp.expected_energy(p)
    assert energy - (0.5921869 - 10.05) == pytest.approx(-0.03579, rel=2e-3)
