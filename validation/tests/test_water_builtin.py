"""The built-in ``spce_water_512`` (issue 41): 512 rigid SPC/E molecules at
298 K and 0.997 g/cm^3 in real units, PME, a Langevin equilibration from a
simple-cubic lattice.

Checked here from its first frames, against numbers computed from the
published model (not from quatrot): the mass density from the molecules'
published masses and the box; no two sites of different molecules closer
than 1.6 A at the start (O-H hydrogen bonds are 1.8 A; a closer pair would
be a bad start); the start's temperatures near 298 K; and a short stretch of
the equilibration keeps the total momentum's change within the Langevin
noise (the thermostat acts on each body) and lowers the potential energy.
The equilibration itself (20 ps) is the report's business (`make validate`).
"""

import tomllib

import numpy as np
import pytest

import quatrot

gsd_hoomd = pytest.importorskip("gsd.hoomd")

AVOGADRO = 6.02214076e23
MASS = 15.9994 + 2 * 1.008  # g/mol, the SPC/E molecule's published masses


def short_run(tmp_path, steps):
    scene = tomllib.loads(quatrot.builtin_scenes()["spce_water_512"])
    scene["run"]["steps"] = steps
    scene["record"]["trajectory"]["every"] = steps
    scene["record"]["series"][0]["every"] = 1
    out = tmp_path / "water"
    result = quatrot.run(scene, out_dir=out)
    with gsd_hoomd.open(out / "trajectory.gsd") as frames:
        first = frames[0]
    return scene, result, first


def minimum_image_distances(sites, per, box):
    """Every distance between sites of different molecules (minimum image)."""
    d = sites[:, None, :] - sites[None, :, :]
    d -= box * np.round(d / box)
    r = np.sqrt((d**2).sum(axis=-1))
    molecule = np.arange(len(sites)) // per
    return r[molecule[:, None] != molecule[None, :]]


def test_the_start_is_512_molecules_at_the_stated_density_with_no_close_sites(tmp_path):
    scene, result, first = short_run(tmp_path, 1)
    assert first.particles.N == 512
    box = float(first.configuration.box[0])
    density = 512 * MASS / AVOGADRO / (box * 1e-8) ** 3  # g/cm^3
    assert density == pytest.approx(0.997, rel=2e-5)  # 0.0333275 per A^3, 6 digits
    state = quatrot.bodies_evaluate(
        [{"model": "spce"}], first.particles.position.astype(float),
        first.particles.orientation.astype(float), box_lengths=[box] * 3,
        lj_cutoff=10.0, electrostatic_cutoff=10.0, units="real",
    )
    sites = state["site_positions"]
    closest = minimum_image_distances(sites, 3, box).min()
    oxygens = minimum_image_distances(sites[::3], 1, box).min()
    print(f"closest sites of different molecules at the start: {closest:.3f} A, oxygens {oxygens:.3f} A")
    assert closest > 1.0
    assert oxygens > 2.9
    series = result["series"]["series"]
    # 512 molecules: 1533 and 1536 degrees of freedom; 298 K within 4
    # standard deviations sqrt(2 / n_f) of a Maxwell-Boltzmann draw.
    for column in ("T_trans", "T_rot"):
        assert series[column][0] == pytest.approx(298.0, rel=4 * (2 / 1533) ** 0.5)


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
