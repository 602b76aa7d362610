"""The rigid-water speed benchmark's pipeline (validation/bench/water_speed.py,
``--quick``: spce_water_512, a few steps): every code is timed, the
accuracies are measured, ns/day follows the formula, and the section lands
between its markers."""

import json
import math

import pytest

from validation.bench import water_speed

pytest.importorskip("gsd")
pytest.importorskip("openmm")


def test_ns_per_day_is_the_steps_per_day_times_dt():
    """1 ms per step of 2 fs: 86,400,000 steps a day, 172.8 ns."""
    assert water_speed.ns_per_day(1e-3) == pytest.approx(172.8, rel=1e-12)


def test_quick_run_writes_its_section(tmp_path):
    (tmp_path / "RESULTS.md").write_text("# Benchmark results\n\nother text\n")
    assert water_speed.main(["--quick", "--out", str(tmp_path), "--cache", str(tmp_path / "cache")]) == 0
    result = json.loads((tmp_path / "results.json").read_text())["water_speed"]
    assert result["scene"] == "spce_water_512" and result["molecules"] == 512
    # Two and four steps time the pipeline, not the codes: the differences
    # are finite but may be noise of either sign.
    assert len(result["timings"]) == len(water_speed.INTEGRATORS) + 2 and result["blew_up"] == {}
    for name, timing in result["timings"].items():
        assert math.isfinite(timing["seconds_per_step"]), name
    # The verdict is one named integrator's, with each round's ratio.
    assert result["verdict_integrator"] in water_speed.INTEGRATORS
    for peer in water_speed.TARGETS:
        assert len(result["ratio_rounds"][peer]) == result["rounds"] == 1
    for code in ("quatrot", "OpenMM", "LAMMPS"):
        error = result["accuracy"]["codes"][code]["chosen"]["error"]
        assert 0 < error < 1e-2, (code, error)
    assert result["accuracy"]["reference_check"] < 1e-5
    text = (tmp_path / "RESULTS.md").read_text()
    assert "other text" in text and water_speed.BEGIN in text and water_speed.END in text
