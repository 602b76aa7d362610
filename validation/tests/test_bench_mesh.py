"""The mesh benchmark's analysis (validation/bench/mesh.py) on synthetic
timings whose answers are known in closed form: power laws that cross at a
chosen N, and measured times a known factor off the model's."""

import math

import pytest

from validation.bench import mesh

ACCURACIES = (1e-4, 1e-5, 1e-6)
SIZES = (125, 512, 1000, 2197)


def raw_timings(direct_factor: dict, pme_factor: dict) -> dict:
    """Direct sums costing N^1.5 and PME 8 N (equal at N = 64) in the
    models; the timed cases are the models times `direct_factor[carries]`
    and `pme_factor[carries]`. Dipole rows at 1e-5 sit in `mesh_scaling`
    (as the bench writes them), the others in `crossover`; old rows carry
    no `carries` key and are dipoles."""
    choices, crossover, scaling = [], [], []
    for carries in ("dipoles", "quadrupoles"):
        for accuracy in ACCURACIES:
            for n in SIZES:
                direct, pme = n**1.5 * 1e-6, 8 * n * 1e-6
                choices.append({"rotors": n, "accuracy": accuracy, "carries": carries,
                                "direct_seconds": direct, "pme_seconds": pme})
                for method, model, factor in (("direct", direct, direct_factor), ("pme", pme, pme_factor)):
                    case = {"rotors": n, "accuracy": accuracy, "method": method,
                            "median_cpu_seconds": model * factor[carries]}
                    if carries == "dipoles" and accuracy == 1e-5:
                        scaling.append(case)
                    else:
                        crossover.append(case | {"carries": carries})
    return {"auto_choices": choices, "crossover": crossover, "mesh_scaling": scaling}


def test_the_calibration_is_the_geometric_mean_of_measured_over_modelled():
    raw = raw_timings({"dipoles": 1.0, "quadrupoles": 1.75}, {"dipoles": 0.5, "quadrupoles": 0.6})
    found = {(c["carries"], c["method"]): c for c in mesh.calibration(raw)}
    expected = {("dipoles", "direct"): 1.0, ("dipoles", "pme"): 0.5,
                ("quadrupoles", "direct"): 1.75, ("quadrupoles", "pme"): 0.6}
    assert set(found) == set(expected)
    for key, factor in expected.items():
        c = found[key]
        assert c["cases"] == len(ACCURACIES) * len(SIZES), key
        assert c["geometric_mean"] == pytest.approx(factor, rel=1e-12), key
        assert c["least"] == pytest.approx(factor, rel=1e-12) and c["most"] == pytest.approx(factor, rel=1e-12)


def test_crossovers_are_found_for_each_kind_where_the_power_laws_meet():
    """Measured direct N^1.5 k_d against PME 8 N k_p meet at N = (8 k_p / k_d)^2:
    dipoles (k_d 1, k_p 2) at 256, quadrupoles (k_d 2, k_p 4.5) at 324;
    the models (k = 1) at 64, below the sizes timed, so none is found."""
    raw = raw_timings({"dipoles": 1.0, "quadrupoles": 2.0}, {"dipoles": 2.0, "quadrupoles": 4.5})
    rows = mesh.crossovers(raw)
    assert [(r["carries"], r["accuracy"]) for r in rows] == [(k, a) for k in ("dipoles", "quadrupoles") for a in ACCURACIES]
    for r in rows:
        expected = 256 if r["carries"] == "dipoles" else 324
        # Log-log interpolation of two power laws is exact.
        assert r["measured"] == pytest.approx(expected, rel=1e-9), r
        assert r["model"] is None, r


def test_a_path_that_cannot_be_built_is_left_out_of_the_model_crossover():
    choices = [{"rotors": n, "accuracy": 1e-5, "direct_seconds": d, "pme_seconds": p}
               for n, d, p in ((100, 1.0, 2.0), (200, None, 2.0), (400, 4.0, 2.0))]
    found = mesh.model_crossover(choices, 1e-5)
    # Between 100 and 400, log(d/p) runs from -log 2 to +log 2: the middle, N = 200.
    assert found == pytest.approx(200.0, rel=1e-12)
    assert not math.isnan(found)
