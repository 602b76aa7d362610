"""quatrot's moving bodies against LAMMPS at one configuration (issue 39):
a Stockmayer fluid (dipolar Lennard-Jones spheres, random and
non-overlapping, periodic) evaluated by LAMMPS ``pair_style
lj/cut/dipole/cut`` and by ``quatrot.bodies_evaluate``: the Lennard-Jones
and electrostatic energies, the forces, the torques and the pressure agree
to round-off; the same with charges on the spheres too. The shifted-force
truncation of charges and dipoles against ``lj/sf/dipole/sf`` (Allen &
Germano 2006) likewise, its Lennard-Jones switched off (``epsilon = 0``:
LAMMPS's own shifted-force Lennard-Jones is quadratic in ``r^2``, not
quatrot's ``force_shifted``).

LAMMPS runs in LJ units (``qqrd2e = 1``: 4 pi eps0 = 1 as in quatrot), its
``lj/cut/dipole/cut`` truncating both terms without shifting them (its
source: the energy is the bare pair energy for ``r < cutoff``), as
quatrot's plain Lennard-Jones truncation and cutoff electrostatics. It has
no tail correction for this style, so quatrot's tail terms are left out of
the comparison and checked against the textbook closed form instead.
"""

import math

import numpy as np
import pytest

import quatrot
from validation.shared.lammps_bodies import periodic_cube
from validation.shared.lammps_driver import _load_lammps, quatrot_rotor, space_to_body

N = 256
DENSITY = 0.5
CLOSEST = 0.9  # the smallest centre distance of the random configuration
CUTOFF = 2.5
MU = 1.2
MASS, INERTIA = 1.0, 0.1
# Round-off: sums of ~40 pair terms of size ~1 in either order; the energy
# is a sum of ~5000 pair terms.
FORCE_TOLERANCE = 1e-11
ENERGY_TOLERANCE = 1e-12  # relative


def configuration(seed: int):
    """Random non-overlapping centres (sequential insertion), random dipole
    directions, velocities and alternating charges."""
    rng = np.random.default_rng(seed)
    box = (N / DENSITY) ** (1 / 3)
    centres = []
    while len(centres) < N:
        x = rng.uniform(0.0, box, 3)
        if all(np.linalg.norm((x - c) - box * np.round((x - c) / box)) >= CLOSEST for c in centres):
            centres.append(x)
    directions = rng.normal(size=(N, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    directions[directions[:, 2] < -0.99] *= -1  # quatrot_rotor is undefined at -z
    velocities = rng.normal(size=(N, 3))
    velocities -= velocities.mean(axis=0)
    charges = np.where(np.arange(N) % 2 == 0, 0.7, -0.7)
    return box, np.array(centres), directions, velocities, charges


def lammps_single_point(box, centres, dipoles, velocities, charges, style="lj/cut/dipole/cut", epsilon=1.0):
    """LAMMPS's evdwl, ecoul, forces, torques and pressure with pair `style`
    and Lennard-Jones `epsilon`."""
    lmp = periodic_cube(box, "hybrid sphere dipole", centres)
    try:
        for c in [
            f"set type 1 mass {MASS:.17g}",
            f"pair_style {style} {CUTOFF:.17g}",
            f"pair_coeff * * {epsilon:.17g} 1.0",
            "neighbor 0.3 bin",
            "thermo_style custom step pe evdwl ecoul press",
            "thermo_modify norm no",
        ]:
            lmp.command(c)
        for i in range(N):
            mx, my, mz = dipoles[i]
            lmp.command(f"set atom {i + 1} dipole {mx:.17g} {my:.17g} {mz:.17g}")
            lmp.command(f"set atom {i + 1} charge {charges[i]:.17g}")
        v = lmp.numpy.extract_atom("v")
        v[:N] = velocities
        lmp.command("run 0")
        order = np.argsort(lmp.numpy.extract_atom("id")[:N])
        return {
            "evdwl": lmp.get_thermo("evdwl"),
            "ecoul": lmp.get_thermo("ecoul"),
            "press": lmp.get_thermo("press"),
            "forces": np.array(lmp.numpy.extract_atom("f")[:N][order]),
            "torques": np.array(lmp.numpy.extract_atom("torque")[:N][order]),
        }
    finally:
        lmp.close()


def both_codes(charged: bool, style: str, lennard_jones: bool, **options):
    """LAMMPS's single point with `style` and quatrot's state with
    `options`, on the configuration of seed 39 (Lennard-Jones on the sites
    or not, charges or not)."""
    box, centres, directions, velocities, charges = configuration(seed=39)
    if not charged:
        charges = np.zeros(N)
    orientations = np.array([quatrot_rotor(d, np.zeros(3))[0] for d in directions])
    # The space dipoles quatrot builds, R(Q) (0, 0, mu), given to LAMMPS.
    dipoles = np.array([space_to_body(q).T @ [0.0, 0.0, MU] for q in orientations])
    epsilon = 1.0 if lennard_jones else 0.0
    reference = lammps_single_point(box, centres, dipoles, velocities, charges, style, epsilon)
    site = {"position": [0, 0, 0], "dipole": [0, 0, MU]}
    if lennard_jones:
        site["lennard_jones"] = {"epsilon": 1.0, "sigma": 1.0}
        options["lj_cutoff"] = CUTOFF
    options.setdefault("electrostatics", {"kind": "cutoff", "cutoff": CUTOFF})
    sphere = {"sites": [site], "mass": MASS, "inertia": np.eye(3) * INERTIA}
    # Charges per body: two body types that differ only in the charge.
    types = [sphere]
    kinds = [0] * N
    if charged:
        types = [
            {**sphere, "sites": [{**sphere["sites"][0], "charge": q}]} for q in (0.7, -0.7)
        ]
        kinds = [0 if q > 0 else 1 for q in charges]
    state = quatrot.bodies_evaluate(
        types, centres, orientations, kinds=kinds, velocities=velocities,
        box_lengths=[box] * 3, **options,
    )
    return reference, state


@pytest.mark.parametrize("charged", [False, True], ids=["stockmayer", "charged_stockmayer"])
def test_single_point_matches_lammps_lj_cut_dipole_cut(charged):
    reference, state = both_codes(charged, "lj/cut/dipole/cut", lennard_jones=True)
    energies = state["energies"]
    assert energies["lennard_jones"] == pytest.approx(reference["evdwl"], rel=ENERGY_TOLERANCE)
    assert energies["electrostatic"] == pytest.approx(reference["ecoul"], rel=ENERGY_TOLERANCE)
    np.testing.assert_allclose(state["forces"], reference["forces"], rtol=0, atol=FORCE_TOLERANCE)
    np.testing.assert_allclose(state["torques"], reference["torques"], rtol=0, atol=FORCE_TOLERANCE)
    pressure = state["pressure"] - state["pressure_tail"]
    assert pressure == pytest.approx(reference["press"], rel=ENERGY_TOLERANCE)
    # The tail corrections (not in LAMMPS's style): Allen and Tildesley eqs
    # 2.144-2.145 for one kind of site.
    rho, x3 = DENSITY, (1.0 / CUTOFF) ** 3
    e_tail = 8 / 3 * math.pi * N * rho * (x3**3 / 3 - x3)
    p_tail = 16 / 3 * math.pi * rho**2 * (2 * x3**3 / 3 - x3)
    assert energies["lennard_jones_tail"] == pytest.approx(e_tail, rel=1e-12)
    assert state["pressure_tail"] == pytest.approx(p_tail, rel=1e-12)


@pytest.mark.parametrize("charged", [False, True], ids=["dipoles", "charges_and_dipoles"])
def test_shifted_force_matches_lammps_lj_sf_dipole_sf(charged):
    """The shifted-force charges and dipoles (energy, forces, torques,
    pressure) against ``lj/sf/dipole/sf`` to round-off."""
    shifted = {"kind": "cutoff", "cutoff": CUTOFF, "truncation": "shifted_force"}
    reference, state = both_codes(charged, "lj/sf/dipole/sf", lennard_jones=False, electrostatics=shifted)
    assert reference["evdwl"] == 0.0
    assert state["energies"]["electrostatic"] == pytest.approx(reference["ecoul"], rel=ENERGY_TOLERANCE)
    np.testing.assert_allclose(state["forces"], reference["forces"], rtol=0, atol=FORCE_TOLERANCE)
    np.testing.assert_allclose(state["torques"], reference["torques"], rtol=0, atol=FORCE_TOLERANCE)
    assert state["pressure"] == pytest.approx(reference["press"], rel=ENERGY_TOLERANCE)
    # Not the plain truncation: the shift changes the energy far above round-off.
    plain = both_codes(charged, "lj/cut/dipole/cut", lennard_jones=False)[1]
    assert abs(plain["energies"]["electrostatic"] - reference["ecoul"]) > 1e-3 * abs(reference["ecoul"])


def test_trap_lj_cut_dipole_cut_ignores_tail_corrections():
    """Trap (ERRATA.md): LAMMPS accepts ``pair_modify tail yes`` for
    ``lj/cut/dipole/cut`` and adds nothing, while ``lj/cut`` adds the tail
    energy and pressure (two spheres 1.1 apart in a box of 8)."""

    def energy_and_pressure(style, tail):
        lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
        try:
            for c in [
                "units lj",
                "atom_style hybrid sphere dipole",
                "boundary p p p",
                "region box block 0 8 0 8 0 8",
                "create_box 1 box",
                "create_atoms 1 single 1 1 1",
                "create_atoms 1 single 2.1 1 1",
                "set type 1 mass 1",
                f"pair_style {style} {CUTOFF}",
                "pair_coeff * * 1.0 1.0",
                f"pair_modify tail {tail}",
                "thermo_style custom step pe press",
                "thermo_modify norm no",
                "run 0",
            ]:
                lmp.command(c)
            return lmp.get_thermo("pe"), lmp.get_thermo("press")
        finally:
            lmp.close()

    assert energy_and_pressure("lj/cut/dipole/cut", "yes") == energy_and_pressure("lj/cut/dipole/cut", "no")
    with_tail, without = energy_and_pressure("lj/cut", "yes"), energy_and_pressure("lj/cut", "no")
    x3, volume = (1.0 / CUTOFF) ** 3, 8.0**3
    e_tail = 8 / 3 * math.pi * 2 * (2 / volume) * (x3**3 / 3 - x3)
    assert with_tail[0] - without[0] == pytest.approx(e_tail, rel=1e-12)
