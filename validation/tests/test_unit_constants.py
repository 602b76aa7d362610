"""The Coulomb and Boltzmann constants of LAMMPS ``units real`` and OpenMM,
measured in each code and compared with CODATA (issue 41, item 1: they
differ in the 7th to 9th digit, which a 1e-9 comparison sees).

Each constant is measured by what the code computes, not read from its
documentation: the energy of two unit charges 1 Angstrom (LAMMPS) or 1 nm
(OpenMM) apart with no cutoff in reach, and the temperature LAMMPS reports
for velocities of known kinetic energy. The reference values come from the
SI definitions: since 2019 ``k_B`` and ``N_A`` are exact, so ``R = k_B N_A``
is exact; ``e^2 / (4 pi eps0)`` carries CODATA's measured ``eps0``, which
changed between CODATA 2018 (8.8541878128e-12 F/m) and CODATA 2022
(8.8541878188e-12 F/m) by 6.8e-10 relative. 1 kcal = 4184 J (thermochemical).
"""

import math

import numpy as np
import pytest

from validation.shared.lammps_driver import _load_lammps

openmm = pytest.importorskip("openmm")

E = 1.602176634e-19  # C, exact (SI 2019)
N_A = 6.02214076e23  # 1/mol, exact
K_B = 1.380649e-23  # J/K, exact
KCAL = 4184.0  # J
EPS0 = {"CODATA 2018": 8.8541878128e-12, "CODATA 2022": 8.8541878188e-12}  # F/m


def coulomb_kcal_per_mol_angstrom(eps0: float) -> float:
    """``e^2 N_A / (4 pi eps0)`` in kcal/mol Angstrom."""
    return E**2 / (4 * math.pi * eps0) * N_A / KCAL * 1e10


def boltzmann_kcal_per_mol_kelvin() -> float:
    return K_B * N_A / KCAL


def lammps_real():
    lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    for c in [
        "units real",
        "atom_style charge",
        "region b block 0 40 0 40 0 40",
        "create_box 1 b",
        "create_atoms 1 single 10 10 10",
        "create_atoms 1 single 11 10 10",
        "mass 1 1.0",
        "set atom 1 charge 1.0",
        "set atom 2 charge 1.0",
        "pair_style coul/cut 15.0",
        "pair_coeff * *",
        "velocity all set 0.01 0.0 0.0",
        "thermo_style custom pe ke temp",
        "run 0",
    ]:
        lmp.command(c)
    return lmp


def test_lammps_real_coulomb_constant_is_332_06371():
    """LAMMPS's two unit charges 1 Angstrom apart have the energy
    ``qqr2e = 332.06371`` kcal/mol: 9.3e-9 below CODATA 2018's (OpenMM's)
    value and 8.6e-9 below CODATA 2022's."""
    lmp = lammps_real()
    try:
        energy = lmp.get_thermo("pe")
        qqr2e = lmp.extract_global("qqr2e")
    finally:
        lmp.close()
    assert energy == pytest.approx(qqr2e, rel=1e-15)
    assert qqr2e == 332.06371
    for name, eps0 in EPS0.items():
        relative = (energy - coulomb_kcal_per_mol_angstrom(eps0)) / coulomb_kcal_per_mol_angstrom(eps0)
        assert -1.0e-8 < relative < -8.0e-9, (name, relative)


def test_lammps_real_boltzmann_constant_is_not_the_si_one():
    """LAMMPS's ``temp`` divides by ``boltz = 0.0019872067`` kcal/mol/K,
    1.23e-6 above the exact ``k_B N_A / 4184`` (and 1e-7 above CODATA
    2006's ``8.314472 / 4184``; LAMMPS's source cites none): a temperature or ``k_B T`` compared at
    1e-9 between LAMMPS and another code differs by this much."""
    lmp = lammps_real()
    try:
        ke, temp = lmp.get_thermo("ke"), lmp.get_thermo("temp")
        boltz = lmp.extract_global("boltz")
    finally:
        lmp.close()
    # Two atoms, velocity momentum not removed: 3N - 3 = 3 degrees of freedom.
    assert temp == pytest.approx(2 * ke / (3 * boltz), rel=1e-14)
    assert boltz == 0.0019872067
    relative = (boltz - boltzmann_kcal_per_mol_kelvin()) / boltzmann_kcal_per_mol_kelvin()
    assert relative == pytest.approx(1.2285e-6, rel=1e-3)


def test_lammps_real_kinetic_energy_constant_is_rounded():
    """LAMMPS's ``ke`` multiplies m v^2 / 2 (g/mol, A/fs) by ``mvv2e =
    48.88821291^2``, the time unit sqrt(1e7 / 4184) fs rounded to 10
    digits: 6.56e-11 above the exact 2390.05736... (1 kcal = 4184 J), so a
    LAMMPS kinetic energy compared with another code's at 1e-10 differs by
    the constant alone (found by validation/checks/water_trajectories.py,
    whose rigid water agrees with LAMMPS to round-off once it is divided out)."""
    lmp = lammps_real()
    try:
        ke, mvv2e = lmp.get_thermo("ke"), lmp.extract_global("mvv2e")
    finally:
        lmp.close()
    exact = 1e7 / KCAL  # (g/mol) (A/fs)^2 in kcal/mol: 1e-3 kg * 1e10 m^2/s^2 / 4184 J
    # Two atoms of mass 1 at 0.01 A/fs.
    assert ke == pytest.approx(2 * 0.5 * 1.0 * 0.01**2 * mvv2e, rel=1e-15)
    assert mvv2e == 48.88821291**2
    assert (mvv2e - exact) / exact == pytest.approx(6.5613e-11, rel=1e-3)


def openmm_coulomb_kcal_per_mol_angstrom() -> float:
    """OpenMM's ``NonbondedForce`` energy (Reference platform, no cutoff) of
    two unit charges 1 nm apart, in kcal/mol Angstrom."""
    from openmm import unit

    system = openmm.System()
    force = openmm.NonbondedForce()
    force.setNonbondedMethod(openmm.NonbondedForce.NoCutoff)
    for _ in range(2):
        system.addParticle(1.0)
        force.addParticle(1.0, 1.0, 0.0)
    system.addForce(force)
    context = openmm.Context(
        system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName("Reference")
    )
    context.setPositions([openmm.Vec3(0, 0, 0), openmm.Vec3(1, 0, 0)])
    kj_nm = context.getState(getEnergy=True).getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)
    return kj_nm * 10.0 / 4.184


def test_openmm_constants_are_codata_2018():
    """OpenMM's ``NonbondedForce`` (Reference platform, no cutoff): two unit
    charges 1 nm apart have 138.935457644 kJ/mol, CODATA 2018 to 1e-15,
    6.8e-10 above CODATA 2022; its Python gas constant is the exact SI one."""
    from openmm import unit

    kcal_angstrom = openmm_coulomb_kcal_per_mol_angstrom()
    codata_2018 = coulomb_kcal_per_mol_angstrom(EPS0["CODATA 2018"])
    codata_2022 = coulomb_kcal_per_mol_angstrom(EPS0["CODATA 2022"])
    assert kcal_angstrom == pytest.approx(codata_2018, rel=1e-14)
    assert (kcal_angstrom - codata_2022) / codata_2022 == pytest.approx(6.78e-10, rel=1e-2)
    r = unit.MOLAR_GAS_CONSTANT_R.value_in_unit(unit.kilocalorie_per_mole / unit.kelvin)
    assert r == pytest.approx(boltzmann_kcal_per_mol_kelvin(), rel=1e-15)
    # The two codes' Coulomb constants, side by side.
    assert np.isclose((332.06371 - kcal_angstrom) / kcal_angstrom, -9.93e-9, rtol=1e-2)
