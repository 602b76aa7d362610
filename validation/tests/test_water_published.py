"""The references the check ``water_published`` reads
(validation/shared/water_nvt_runs.py): NIST's coexistence rows as printed
on the pages, the pressure error worked by hand, and the OpenMM fixture's
provenance."""

import pytest

from validation.shared import water_nvt_runs as wp


def test_nist_rows_are_the_300_k_rows_of_the_pages():
    """The 300 K rows of the SAT-TMMC pages (rho_liq +/- in kg/m^3, p_sat in bar)."""
    rows = {"spce": (998.1, 2.928, 1.017e-2), "tip3p": (983.9, 0.2332, 5.123e-2),
            "tip4p_2005": (996.5, 1.456, 8.018e-3)}
    for model, (rho, sigma, p_sat) in rows.items():
        c = wp.NIST_COEXISTENCE[model]
        assert (c.temperature, c.rho * 1000, c.sigma_rho * 1000, c.p_sat) == pytest.approx((300, rho, sigma, p_sat))
        assert model.replace("_", "") + "-water-lrc" in c.url


def test_tip3p_pressure_error_by_hand():
    """0.2332 kg/m^3 of 983.9 over 45.2e-6 /bar: 5.244 bar = 5.175 atm; p_sat 0.05123 bar."""
    expected, error = wp.expected_coexistence_pressure(wp.NIST_COEXISTENCE["tip3p"])
    assert expected == pytest.approx(0.05123 / 1.01325, rel=1e-12)
    assert error == pytest.approx(0.0002332 / (0.9839 * 45.2e-6) / 1.01325, rel=1e-12)
    assert error == pytest.approx(5.175, abs=0.01)


def test_openmm_fixture_has_every_model_at_its_coexistence_state():
    for model, c in wp.NIST_COEXISTENCE.items():
        ref = wp.openmm_reference(model)
        assert (ref["temperature"], ref["density"]) == (c.temperature, c.rho)
        assert ref["production_ps"] >= 30 and ref["energy"][1] < 0.03
        assert ref["openmm"]
