"""What scenes record, against independent references: the multipole
quantities (M, M2, P1, P2 and the directors) against scipy and numpy on the
run's quaternions; the GSD trajectory read back with the gsd package; the
dielectric constant of a run against the ideal dipolar gas and against the
formula applied by hand; and its refusals."""

import json
from pathlib import Path

import numpy as np
import pytest
import quatrot

from validation.shared.output_readers import column_differences, expected_columns, gsd_differences
from validation.shared.scene_runs import body_multipoles, variant

# Rotations and 3x3 eigen decompositions in double precision, of sums of
# up to ~20 unit-scale terms, relative to the column's scale.
DOUBLE_TOLERANCE = 1e-12
# GSD stores float32: relative rounding 6e-8 on unit-scale numbers.
FLOAT32_TOLERANCE = 3e-7
# |eps - exact| / error: two-sided normal probability 6e-5.
Z_MAX = 4.0
MULTIPOLE_QUANTITIES = ("M", "M2", "P1_dipole", "P2_dipole", "P2_quadrupole")


def tops(cells: int = 2, every: int = 5) -> dict:
    """The built-in asymmetric tops with dipoles and quadrupoles (open), recording every multipole quantity."""
    return variant("multipole_tops_bcc", cells=cells, every=every, quantities=MULTIPOLE_QUANTITIES + ("temperature",))


def test_multipole_quantities_match_numpy_on_the_runs_quaternions(tmp_path: Path):
    """Every column of M, M2, P1_dipole, P2_dipole and P2_quadrupole (with
    the directors) equals scipy's rotations and numpy's eigh on the
    quaternions of the same run's trajectory, at every sample; the CSV
    written holds the same numbers."""
    scene = tops()
    result = quatrot.run(scene, steps=60, out_dir=tmp_path)
    q = result["trajectory"]["orientations"]
    mu, theta = body_multipoles(scene, q.shape[1])
    series = result["series"]["samples"]
    expected = expected_columns(q, mu, theta)
    assert set(expected) <= set(series)
    scale = {name: max(1.0, float(np.max(np.abs(v)))) for name, v in expected.items()}
    for name, difference in column_differences(series, expected).items():
        assert difference <= DOUBLE_TOLERANCE * scale[name], name
    written = np.genfromtxt(tmp_path / "samples.csv", delimiter=",", names=True)
    for name in expected:
        np.testing.assert_array_equal(written[name], series[name])


def test_a_quantity_of_a_multipole_no_rotor_carries_is_refused():
    """The scene names the quantity and says what is missing."""
    scene = variant("dipole_lattice_sc", cells=2, every=5, quantities=("P2_quadrupole",))
    with pytest.raises(quatrot.SceneError, match=r"record.series\[0\].quantities\[0\]: `P2_quadrupole` needs rotors that carry a quadrupole, and none does"):
        quatrot.run(scene, steps=5)


@pytest.mark.parametrize("periodic", [True, False], ids=["periodic", "open"])
def test_gsd_trajectory_of_a_scene_reads_back_with_gsd(tmp_path: Path, periodic: bool):
    """`format = "gsd"` writes trajectory.gsd: gsd.hoomd reads as many frames
    as the run kept, their steps, the box (the Ewald lattice's periodic box,
    or the open cluster's sites grown by 1), the positions and the
    normalised orientations, to float32 precision."""
    if periodic:
        scene, box = variant("dipole_lattice_sc", cells=3, every=10), np.full(3, 3.0)
    else:
        scene, box = tops(every=10), None
    scene["record"]["trajectory"] = {"every": 10, "format": "gsd"}
    result = quatrot.run(scene, steps=50, out_dir=tmp_path)
    assert not (tmp_path / "trajectory.dcd").exists()
    differences = gsd_differences(tmp_path / "trajectory.gsd", result, box)
    assert differences["frames"] == 0 and differences["step"] == 0
    for what in ("box", "position", "orientation"):
        assert differences[what] <= FLOAT32_TOLERANCE, (what, differences)


def ideal_gas_run(rng, frames: int, n: int, mu: float, temperature: float, box: float, surface: str) -> dict:
    """A dict shaped as quatrot.run's result: an Ewald summary and a series
    of M from n independent uniformly oriented dipoles per frame."""
    u = rng.normal(size=(frames, n, 3))
    m = mu * np.sum(u / np.linalg.norm(u, axis=-1, keepdims=True), axis=1)
    interactions = {"boundary": "periodic", "box": [box] * 3, "sum": "ewald", "accuracy": 1e-12, "surface": surface, "path": "ewald_direct"}
    series = {"step": np.arange(frames, dtype=float), "M_x": m[:, 0], "M_y": m[:, 1], "M_z": m[:, 2], "temperature": np.full(frames, temperature)}
    return {"summary": {"interactions": interactions}, "series": {"observables": series}}


@pytest.mark.parametrize("surface", ["conducting", "vacuum"])
def test_run_dielectric_constant_of_the_ideal_dipolar_gas(surface: str):
    """Synthetic runs of 64 independent dipoles (seed 3, 8000 frames): eps
    from the run dict's boundary and box agrees with the closed form within
    4 of its errors, and equals dielectric_constant applied by hand."""
    n, mu, temperature, box = 64, 1.2, 1.5, 8.0
    run = ideal_gas_run(np.random.default_rng(3), 8000, n, mu, temperature, box, surface)
    eps = quatrot.run_dielectric_constant(run)
    y = 4 * np.pi * n * mu**2 / (9 * box**3 * temperature)
    exact = 1 + 3 * y if surface == "conducting" else (1 + 2 * y) / (1 - y)
    assert abs(eps["epsilon"] - exact) < Z_MAX * eps["error"]
    s = run["series"]["observables"]
    m = np.column_stack([s["M_x"], s["M_y"], s["M_z"]])
    by_hand = quatrot.dielectric_constant(m, box**3, temperature, boundary=surface)
    assert by_hand["epsilon"] == eps["epsilon"] and by_hand["error"] == eps["error"]


def test_run_dielectric_constant_from_files_and_refusals(tmp_path: Path):
    """The built-in Ewald lattice (short run, M and the temperature every 2
    steps): the result from the output directory equals the one from the
    dict; the truncated variant is refused with the reason."""
    scene = variant("dipole_lattice_sc", every=2, quantities=("M", "temperature"))
    result = quatrot.run(scene, steps=40, out_dir=tmp_path)
    assert json.loads((tmp_path / "summary.json").read_text())["interactions"]["path"] == "ewald_lattice_fft"
    from_dict = quatrot.run_dielectric_constant(result)
    from_dir = quatrot.run_dielectric_constant(tmp_path, series="samples")
    assert from_dict["epsilon"] == from_dir["epsilon"] and from_dict["error"] == from_dir["error"]
    cutoff = variant("dipole_lattice_sc_cutoff", every=2, quantities=("M", "temperature"))
    with pytest.raises(ValueError, match="boundary: cutoff: no fluctuation formula applies to a plain spherical cutoff"):
        quatrot.run_dielectric_constant(quatrot.run(cutoff, steps=4))
    with pytest.raises(ValueError, match="series: no series `energies`"):
        quatrot.run_dielectric_constant(result, series="energies")
