"""The configurations of issue 40's PME references and each code's evaluation
of them, shared by the check (``checks/pme_references.py``) and the charge
benchmark (``bench/charges.py``).

Units. A configuration is written in nm and e (OpenMM's units); quatrot reads
the same numbers in its reduced units (4 pi eps0 = 1), so its energies and
forces are OpenMM's divided by ``ONE_4PI_EPS0`` (kJ mol^-1 nm e^-2, CODATA
2018, OpenMM 8's value). LAMMPS runs in ``units lj`` (``qqrd2e = 1``) with
every length given in Angstrom (the nm numbers times 10), so that its
``accuracy`` keeps its documented meaning (relative to the force between two
unit charges 1 Angstrom apart, 1 in these units): its energies and torques
are the reduced ones divided by 10, its forces divided by 100.

The water-like set: rigid three-site molecules of SPC/E geometry (O-H 0.1
nm, H-O-H 109.47 degrees) and charges (-0.8476 e on O, +0.4238 e on each H),
centres on a simple-cubic lattice at liquid water's 33.4 molecules per nm^3,
each displaced uniformly by up to a tenth of the spacing per axis, random
orientations. Every pair of sites interacts, within a molecule too (no
exclusions in any code), so that the sum is the plain Ewald sum of 3 N point
charges.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import erfc

from validation.shared.ewald_reference import S_CONVERGED, image_shifts, wave_vectors
from validation.shared.openmm_multipoles import ONE_4PI_EPS0, random_orientations, rotation

WATER_DENSITY = 33.4  # molecules per nm^3 (liquid water at 300 K)
OH, HOH = 0.1, math.radians(109.47)  # SPC/E geometry (nm, rad)
CHARGES = (-0.8476, 0.4238, 0.4238)  # SPC/E (e): O, H, H
ANGSTROM_PER_NM = 10.0


def water_sites(rng, molecules: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sites (3 N, 3) nm, charges (3 N,) e and the box (3,) nm of ``molecules``
    water-like molecules (module doc), in a cube holding the next cube number
    of lattice cells, the cells kept chosen at random."""
    edge = math.ceil(round(molecules ** (1 / 3), 9))
    spacing = (1.0 / WATER_DENSITY) ** (1 / 3) * (molecules / edge**3) ** (-1 / 3)
    box = edge * spacing
    cells = np.stack(np.meshgrid(*[np.arange(edge)] * 3, indexing="ij"), -1).reshape(-1, 3)
    cells = cells[np.sort(rng.choice(len(cells), molecules, replace=False))]
    centres = (cells + 0.5 + rng.uniform(-0.1, 0.1, cells.shape)) * spacing
    # O at the origin, the Hs in the body xz plane, symmetric about z.
    body = np.array([[0, 0, 0], [OH * math.sin(HOH / 2), 0, OH * math.cos(HOH / 2)], [-OH * math.sin(HOH / 2), 0, OH * math.cos(HOH / 2)]])
    sites = np.concatenate([c + body @ rotation(q).T for c, q in zip(centres, random_orientations(rng, molecules))])
    return sites, np.tile(CHARGES, molecules), np.full(3, box)


def charge_ewald(sites, charges, box, alpha=None) -> tuple[float, np.ndarray]:
    """The converged Ewald energy and forces (conducting surface, neutral or
    with the uniform background's -pi Q^2 / (2 V alpha^2)) of point charges in
    an orthorhombic box, from the textbook formulas (Allen & Tildesley,
    Computer Simulation of Liquids, 2nd ed., eqs 6.4-6.6), in numpy, both
    sums converged to exp(-S^2) ~ 1e-21 as ``ewald_reference.ewald``:

    V = 1/2 sum_{i != j, images} q_i q_j erfc(a r) / r
        + (2 pi / V) sum_{k != 0} exp(-k^2 / 4 a^2) / k^2 |S(k)|^2
        - a / sqrt(pi) sum q^2 - pi Q^2 / (2 V a^2),   S(k) = sum_j q_j exp(-i k.r_j).
    """
    sites, charges, box = (np.asarray(x, float) for x in (sites, charges, box))
    n = len(sites)
    volume = float(np.prod(box))
    alpha = 5.0 / box.min() if alpha is None else alpha
    rc, kc = S_CONVERGED / alpha, 2 * alpha * S_CONVERGED
    shifts = image_shifts(box, rc)
    energy = 0.0
    forces = np.zeros((n, 3))
    for t in range(n):
        r = (sites[t] - sites[None, :, :] + shifts[:, None, :]).reshape(-1, 3)
        q = np.tile(charges, len(shifts))
        d = np.linalg.norm(r, axis=1)
        keep = (d <= rc) & (d > 1e-12)
        r, q, d = r[keep], q[keep], d[keep]
        b0 = erfc(alpha * d) / d
        energy += 0.5 * charges[t] * np.sum(q * b0)
        b1 = (b0 + 2 * alpha / math.sqrt(math.pi) * np.exp(-((alpha * d) ** 2))) / d**2
        forces[t] = charges[t] * np.sum((q * b1)[:, None] * r, axis=0)
    k, k2 = wave_vectors(box, kc)
    g = 4 * math.pi / volume * np.exp(-k2 / (4 * alpha**2)) / k2
    phase = np.exp(-1j * sites @ k.T)  # (n, k)
    s = phase.T @ charges
    energy += 0.5 * float(np.sum(g * np.abs(s) ** 2))
    # F_i = -dV/dr_i, dS/dr_i = -i k q_i exp(-i k.r_i)
    forces -= charges[:, None] * np.imag(np.conj(s)[None, :] * phase * g[None, :]) @ k
    total = float(charges.sum())
    energy -= alpha / math.sqrt(math.pi) * float(charges @ charges) + math.pi * total**2 / (2 * volume * alpha**2)
    return energy, forces


def openmm_charges(sites, charges, box, cutoff, tolerance, platform="Reference"):
    """An OpenMM ``NonbondedForce`` with PME (tin-foil surface, no
    exceptions: every pair summed, no switching, no dispersion correction,
    epsilon 0) on ``platform`` (CPU: one thread): a function of the
    positions (nm) giving the reduced energy and forces, with
    ``.parameters()`` (alpha, grid) and ``.state()`` (an evaluation at the
    positions set, for timing)."""
    import openmm as mm
    from openmm import unit

    system = mm.System()
    force = mm.NonbondedForce()
    force.setNonbondedMethod(mm.NonbondedForce.PME)
    force.setCutoffDistance(cutoff)
    force.setEwaldErrorTolerance(tolerance)
    force.setUseDispersionCorrection(False)
    force.setUseSwitchingFunction(False)
    for q in charges:
        system.addParticle(1.0)
        force.addParticle(float(q), 0.1, 0.0)
    system.setDefaultPeriodicBoxVectors(*(mm.Vec3(*(np.eye(3)[a] * box[a])) for a in range(3)))
    system.addForce(force)
    properties = {"Threads": "1"} if platform == "CPU" else {}
    context = mm.Context(system, mm.VerletIntegrator(1e-3), mm.Platform.getPlatformByName(platform), properties)

    def evaluate(positions):
        context.setPositions(np.asarray(positions, float) * unit.nanometer)
        state = context.getState(getEnergy=True, getForces=True)
        energy = state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)
        forces = state.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer)
        return energy / ONE_4PI_EPS0, np.asarray(forces) / ONE_4PI_EPS0

    evaluate.parameters = lambda: force.getPMEParametersInContext(context)
    evaluate.state = lambda: context.getState(getEnergy=True, getForces=True)
    return evaluate


def lammps_charges(sites, charges, box, cutoff, accuracy):
    """LAMMPS ``pair_style coul/long`` + ``kspace_style pppm`` (tin-foil) at
    ``accuracy`` on the configuration (units and scaling: module doc): the
    reduced energy and forces."""
    from validation.shared.lammps_driver import _load_lammps

    lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    try:
        a = ANGSTROM_PER_NM
        lx, ly, lz = np.asarray(box) * a
        cmds = [
            "units lj",
            "atom_style charge",
            "boundary p p p",
            "atom_modify map array sort 0 0",
            f"region box block 0 {lx:.17g} 0 {ly:.17g} 0 {lz:.17g}",
            "create_box 1 box",
            "mass 1 1.0",
        ]
        for s in np.mod(np.asarray(sites) * a, [lx, ly, lz]):
            cmds.append(f"create_atoms 1 single {s[0]:.17g} {s[1]:.17g} {s[2]:.17g}")
        cmds += [
            f"pair_style coul/long {cutoff * a:.17g}",
            "pair_coeff * *",
            f"kspace_style pppm {accuracy:.17g}",
            "neighbor 1.0 bin",
            "thermo_modify norm no",
        ]
        for c in cmds:
            lmp.command(c)
        for i, q in enumerate(charges):
            lmp.command(f"set atom {i + 1} charge {q:.17g}")
        lmp.command("variable pe equal pe")
        lmp.command("run 0 post no")
        n = len(sites)
        order = np.argsort(lmp.numpy.extract_atom("id")[:n])
        energy = float(lmp.extract_variable("pe")) * a
        forces = np.array(lmp.numpy.extract_atom("f")[:n][order]) * a * a
        return energy, forces
    finally:
        lmp.close()


def rms(a) -> float:
    """RMS over rows of the row norms."""
    a = np.asarray(a, float)
    return float(np.sqrt(np.mean(np.sum(a.reshape(len(a), -1) ** 2, axis=1))))
