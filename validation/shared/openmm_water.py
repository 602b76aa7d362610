"""Rigid water models as published, and OpenMM's energies and forces of
rigid water (``NonbondedForce``, Reference platform, double precision):
shared by the single-point tests (validation/tests/test_water_*.py) and the
report's water check.

The parameters are restated from the papers, not read from quatrot:
SPC/E, Berendsen, Grigera & Straatsma, J. Phys. Chem. 91, 6269 (1987);
TIP3P, Jorgensen et al., J. Chem. Phys. 79, 926 (1983) (A = 582.0e3 kcal
A^12/mol, C = 595.0 kcal A^6/mol); TIP4P/2005, Abascal & Vega, J. Chem.
Phys. 123, 234505 (2005) (epsilon/k_B = 93.2 K, with the exact k_B N_A of
SI 2019). Units: Angstrom, degrees, e, kcal/mol.
"""

from __future__ import annotations

import numpy as np

KJ_PER_KCAL = 4.184
PUBLISHED = {
    "spce": dict(r=1.0, angle=109.47, q_h=0.4238, d_om=0.0, sigma=3.166, epsilon=0.650 / KJ_PER_KCAL),
    "tip3p": dict(
        r=0.9572, angle=104.52, q_h=0.417, d_om=0.0,
        sigma=(582.0e3 / 595.0) ** (1 / 6), epsilon=595.0**2 / (4 * 582.0e3),
    ),
    "tip4p_2005": dict(
        r=0.9572, angle=104.52, q_h=0.5564, d_om=0.1546,
        sigma=3.1589, epsilon=93.2 * 1.380649e-23 * 6.02214076e23 / 4184,
    ),
}


def site_parameters(model):
    """(charge, sigma, epsilon) per site, O H H (M), from the published values."""
    p = PUBLISHED[model]
    q_negative = -2 * p["q_h"]
    oxygen = (0.0 if p["d_om"] else q_negative, p["sigma"], p["epsilon"])
    sites = [oxygen, (p["q_h"], 1.0, 0.0), (p["q_h"], 1.0, 0.0)]
    if p["d_om"]:
        sites.append((q_negative, 1.0, 0.0))
    return sites


def water_system(model, molecules, *, box=None, cutoff=None, tolerance=None, dispersion_correction=True,
                 masses=None):
    """An OpenMM ``System`` of ``molecules`` rigid-water molecules, each
    one's own pairs excluded, charges in force group 0 and Lennard-Jones in
    group 1: all pairs without a box; with a cubic ``box`` (A), PME at
    ``tolerance`` (``ewaldErrorTolerance``) and Lennard-Jones cut at
    ``cutoff`` (A), with OpenMM's dispersion correction when asked. With
    ``masses`` (g/mol of O, H, H), the particles have them and each molecule
    is kept rigid by three distance constraints (SETTLE); a four-site
    model's M is then a massless virtual site, ``O + a (H1 - O) + a (H2 - O)``
    with ``a = d_OM / (2 r_OH cos(angle / 2))`` (on the bisector, ``d_OM``
    from O). Without, unit masses and no constraints (single points)."""
    import openmm

    parameters = site_parameters(model)
    system = openmm.System()
    coulomb, lj = openmm.NonbondedForce(), openmm.NonbondedForce()
    if box is not None:
        side = box / 10
        system.setDefaultPeriodicBoxVectors(
            openmm.Vec3(side, 0, 0), openmm.Vec3(0, side, 0), openmm.Vec3(0, 0, side)
        )
    for force, group in ((coulomb, 0), (lj, 1)):
        force.setForceGroup(group)
        if box is None:
            force.setNonbondedMethod(openmm.NonbondedForce.NoCutoff)
        else:
            force.setNonbondedMethod(openmm.NonbondedForce.PME)
            force.setCutoffDistance(cutoff / 10)
            force.setEwaldErrorTolerance(tolerance)
        system.addForce(force)
    coulomb.setUseDispersionCorrection(False)
    lj.setUseDispersionCorrection(dispersion_correction and box is not None)
    site_masses = None if masses is None else list(masses) + [0.0] * (len(parameters) - len(masses))
    for _ in range(molecules):
        for k, (charge, sigma, epsilon) in enumerate(parameters):
            system.addParticle(1.0 if masses is None else site_masses[k])
            coulomb.addParticle(charge, 0.1, 0.0)
            lj.addParticle(0.0, sigma / 10, epsilon * KJ_PER_KCAL)
    per = len(parameters)
    for m in range(molecules):
        for i in range(m * per, (m + 1) * per):
            for j in range(i + 1, (m + 1) * per):
                coulomb.addException(i, j, 0.0, 0.1, 0.0)
                lj.addException(i, j, 0.0, 0.1, 0.0)
    if masses is not None:
        p = PUBLISHED[model]
        o_h, h_h = p["r"] / 10, 2 * p["r"] * np.sin(np.radians(p["angle"] / 2)) / 10
        along = p["d_om"] / (2 * p["r"] * np.cos(np.radians(p["angle"] / 2)))
        for m in range(molecules):
            o = per * m
            for (a, b), length in (((0, 1), o_h), ((0, 2), o_h), ((1, 2), h_h)):
                system.addConstraint(o + a, o + b, length)
            if p["d_om"]:
                system.setVirtualSite(o + 3, openmm.ThreeParticleAverageSite(o, o + 1, o + 2, 1 - 2 * along,
                                                                              along, along))
    return system


def openmm_water(site_positions, model, molecules, *, box=None, cutoff=None, tolerance=None,
                 dispersion_correction=True):
    """OpenMM's energies (kcal/mol: ``electrostatic``, ``lennard_jones``)
    and total site forces (kcal/mol/A) of :func:`water_system`'s molecules
    at ``site_positions`` (A), Reference platform (double precision)."""
    import openmm
    from openmm import unit

    system = water_system(model, molecules, box=box, cutoff=cutoff, tolerance=tolerance,
                          dispersion_correction=dispersion_correction)
    context = openmm.Context(
        system, openmm.VerletIntegrator(0.001), openmm.Platform.getPlatformByName("Reference")
    )
    context.setPositions(np.asarray(site_positions) / 10.0)
    energies = {}
    for name, group in (("electrostatic", {0}), ("lennard_jones", {1})):
        state = context.getState(getEnergy=True, groups=group)
        energies[name] = state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole) / KJ_PER_KCAL
    forces = context.getState(getForces=True).getForces(asNumpy=True)
    return energies, forces.value_in_unit(unit.kilojoule_per_mole / unit.nanometer) / (KJ_PER_KCAL * 10)


def relative_rms(a, b):
    """RMS over sites of |a - b| over the RMS of |b|."""
    return float(np.sqrt(((a - b) ** 2).sum(axis=1).mean() / (b**2).sum(axis=1).mean()))


def textbook_tail(model, molecules, volume, cutoff):
    """The Lennard-Jones tail energy (kcal/mol) of ``molecules`` O sites,
    (8/3) pi n^2 / V epsilon sigma^3 [(sigma/r_c)^9 / 3 - (sigma/r_c)^3]
    (Allen & Tildesley eq 2.144)."""
    _, sigma, epsilon = site_parameters(model)[0]
    s = sigma / cutoff
    return 8 / 3 * np.pi * molecules**2 / volume * epsilon * sigma**3 * (s**9 / 3 - s**3)


def openmm_tail_factor(molecules, sites_per_molecule):
    """OpenMM's dispersion correction over the textbook tail when only the
    n O sites of N particles carry Lennard-Jones: (n + 1) N / (n (N + 1))
    (its class-pair average over N(N+1)/2 pairs, times N^2; ERRATA.md)."""
    n, particles = molecules, sites_per_molecule * molecules
    return (n + 1) * particles / (n * (particles + 1))
