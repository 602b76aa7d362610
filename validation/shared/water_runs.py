"""Rigid SPC/E clusters run side by side by quatrot, LAMMPS ``fix
rigid/nve/small`` and OpenMM with SETTLE (issue 41, item 3), shared by the
report's check (validation/checks/water_trajectories.py) and its tests.

A cluster is a jittered cubic grid of molecules 3.1 A apart in open space,
every pair within the cutoff (30 A, above the cluster's size), Lennard-Jones
between oxygens, each molecule's own pairs excluded, at rest as a whole but
with Maxwell-Boltzmann centre and body angular velocities at 298 K. All
three codes start from the same sites and site velocities
``V + omega x (R s)``: quatrot takes the centres, orientations and body
angular velocities, LAMMPS builds its bodies from the atoms, OpenMM keeps
the atoms rigid by SETTLE. Units: A, fs, kcal/mol, g/mol, e."""

from __future__ import annotations

import math

import numpy as np

import quatrot
from validation.shared.lammps_driver import _load_lammps, space_to_body
from validation.shared.openmm_water import site_parameters, water_system

CUTOFF = 30.0  # A: above the cluster's size, so every pair counts
SPACING = 3.1  # A between neighbouring centres
TEMPERATURE = 298.0
BOLTZMANN = 1.380649e-23 * 6.02214076e23 / 4184  # kcal/(mol K), exact since SI 2019
# kcal/mol per (g/mol) in A^2/fs^2: 4184 J/kg = 4184 m^2/s^2 = 4.184e-4 A^2/fs^2.
VELOCITY_SQUARED = 4.184e-4
# O 15.9994, H 1.008 g/mol: restated from src/scene/water.rs's sources
# (IUPAC standard atomic weights, the masses of the LAMMPS and CHARMM water
# examples); the comparison itself checks that the codes agree on them
# through the kinetic energy at t = 0.
MASSES = (15.9994, 1.008, 1.008)


def quatrot_coulomb_constant() -> float:
    """quatrot's energy of two unit charges 1 A apart, kcal/mol."""
    ion = {"sites": [{"position": [0, 0, 0], "charge": 1.0}], "mass": 1.0, "inertia": np.eye(3).tolist()}
    state = quatrot.bodies_evaluate(
        [ion], [[0, 0, 0], [1, 0, 0]], [[1, 0, 0, 0]] * 2, electrostatic_cutoff=5.0, units="real"
    )
    return state["energies"]["electrostatic"]


def cluster(per_side: int, seed: int):
    """Centres, unit orientations, centre velocities (A/fs, zero total
    momentum) and body angular velocities (1/fs, body principal frame)."""
    rng = np.random.default_rng(seed)
    n = per_side**3
    grid = np.array([[i, j, k] for i in range(per_side) for j in range(per_side) for k in range(per_side)], float)
    centres = grid * SPACING + rng.uniform(-0.2, 0.2, (n, 3))
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    kt = BOLTZMANN * TEMPERATURE
    velocities = rng.normal(scale=math.sqrt(kt / sum(MASSES) * VELOCITY_SQUARED), size=(n, 3))
    velocities -= velocities.mean(axis=0)
    moments = principal_moments(body_sites())
    omega_body = rng.normal(size=(n, 3)) * np.sqrt(kt / moments * VELOCITY_SQUARED)
    return centres, q, velocities, omega_body


def body_sites() -> np.ndarray:
    """quatrot's SPC/E sites in its body frame (one molecule at the origin,
    identity orientation): centre of mass at the origin, principal axes."""
    state = quatrot.bodies_evaluate([{"model": "spce"}], [[0, 0, 0]], [[1, 0, 0, 0]], units="real",
        lj_cutoff=CUTOFF, electrostatic_cutoff=CUTOFF,
    )
    return np.asarray(state["site_positions"])


def principal_moments(sites: np.ndarray) -> np.ndarray:
    """Diagonal of the inertia tensor of `sites` with MASSES (g/mol A^2);
    the off-diagonal part must vanish in a principal frame."""
    m = np.asarray(MASSES)
    tensor = np.eye(3) * np.sum(m * (sites**2).sum(axis=1)) - np.einsum("s,si,sj->ij", m, sites, sites)
    off_diagonal = tensor - np.diag(np.diag(tensor))
    if np.abs(off_diagonal).max() > 1e-12 * np.abs(tensor).max():
        raise ValueError(f"quatrot's SPC/E body frame is not principal: {tensor}")
    return np.diag(tensor).copy()


def sites_and_velocities(centres, orientations, velocities, omega_body):
    """Sites X + R s and their velocities V + omega x (R s), (n, 3, 3) each,
    with R = A(Q)^T (eq 7) taking the body frame to space."""
    s = body_sites()
    rotations = np.array([space_to_body(q).T for q in orientations])
    arms = np.einsum("nij,sj->nsi", rotations, s)
    omega_space = np.einsum("nij,nj->ni", rotations, omega_body)
    return centres[:, None, :] + arms, velocities[:, None, :] + np.cross(omega_space[:, None, :], arms)


def quatrot_series(state, integrator: str, dt: float, steps: int) -> np.ndarray:
    """quatrot's potential and kinetic energy at every step, (steps + 1, 2)."""
    centres, q, velocities, omega_body = state
    scene = {
        "version": 1,
        "name": "spce_cluster",
        "units": "real",
        "body_types": [{"model": "spce"}],
        "bodies": {"kind": "given", "list": [
            {"position": c.tolist(), "orientation": o.tolist(), "velocity": v.tolist(), "angular_velocity": w.tolist()}
            for c, o, v, w in zip(centres, q, velocities, omega_body)
        ]},
        "body_interactions": {
            "lennard_jones": {"cutoff": CUTOFF},
            "electrostatics": {"kind": "cutoff", "cutoff": CUTOFF},
        },
        "integrator": {"kind": integrator},
        "run": {"dt": dt, "steps": steps},
        "record": {"series": [{"name": "e", "every": 1, "quantities": ["potential_energy", "kinetic_energy"]}]},
    }
    series = quatrot.run(scene)["series"]["e"]
    return np.stack([series["potential_energy"], series["kinetic_energy"]], axis=1)


def lammps_series(state, dt: float, steps: int) -> np.ndarray:
    """LAMMPS ``units real``, ``pair_style lj/cut/coul/cut``, ``fix
    rigid/nve/small molecule``: pe and ke at every step. LAMMPS's constants
    are divided out (ERRATA.md's traps table): its Coulomb constant
    (332.06371) is 9.9e-9 below quatrot's (CODATA 2018), so its charges are
    scaled by the square root of the constants' ratio and both codes
    compute the same forces; its time unit ``48.88821291`` fs (``ftm2v``,
    ``mvv2e``) is the exact ``sqrt(1e7 / 4184)`` rounded, 3.3e-11 above it,
    so its masses are scaled by ``ftm2v / ftm2v_exact``: the same
    accelerations, and ``ke = m' v^2 mvv2e / 2`` the exact kinetic energy
    (``ftm2v mvv2e = 1`` in LAMMPS)."""
    sites, site_velocities = sites_and_velocities(*state)
    n = len(sites)
    (q_o, sigma, epsilon), (q_h, _, _), _ = site_parameters("spce")
    lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    try:
        for c in ["units real", "atom_style full", "atom_modify map array sort 0 0", "boundary f f f",
                  "region box block -60 60 -60 60 -60 60", "create_box 2 box"]:
            lmp.command(c)
        mass_scale = lmp.extract_global("ftm2v") * 1e7 / 4184
        lmp.command(f"mass 1 {MASSES[0] * mass_scale:.17g}")
        lmp.command(f"mass 2 {MASSES[1] * mass_scale:.17g}")
        scale = math.sqrt(quatrot_coulomb_constant() / lmp.extract_global("qqr2e"))
        for i, molecule in enumerate(sites):
            for k, x in enumerate(molecule):
                lmp.command(f"create_atoms {1 if k == 0 else 2} single {x[0]:.17g} {x[1]:.17g} {x[2]:.17g}")
                charge = (q_o if k == 0 else q_h) * scale
                lmp.command(f"set atom {3 * i + k + 1} mol {i + 1} charge {charge:.17g}")
        for c in [f"pair_style lj/cut/coul/cut {CUTOFF:.17g}", f"pair_coeff 1 1 {epsilon:.17g} {sigma:.17g}",
                  "pair_coeff 2 2 0.0 1.0", "pair_coeff 1 2 0.0 1.0",
                  "neighbor 2.0 bin", "neigh_modify every 1 delay 0 check yes exclude molecule/intra all",
                  "fix integrate all rigid/nve/small molecule", "thermo_style custom step pe ke",
                  "thermo_modify norm no", f"timestep {dt:.17g}"]:
            lmp.command(c)
        lmp.numpy.extract_atom("v")[: 3 * n] = site_velocities.reshape(-1, 3)
        energies = []
        for step in range(steps + 1):
            lmp.command("run 0" if step == 0 else "run 1 pre no post no")
            energies.append([lmp.get_thermo("pe"), lmp.get_thermo("ke")])
        return np.array(energies)
    finally:
        lmp.close()


def openmm_series(state, dt: float, steps: int) -> np.ndarray:
    """OpenMM (Reference platform, double precision): the molecules kept
    rigid by SETTLE (three distance constraints per molecule), velocity
    Verlet with position and velocity constraints (a ``CustomIntegrator``:
    ``VerletIntegrator`` is leapfrog, whose velocities lag the positions by
    half a step, so from the same velocities its trajectory differs at
    first order in dt); potential and kinetic energy at every step, kcal/mol."""
    import openmm
    from openmm import unit

    sites, site_velocities = sites_and_velocities(*state)
    system = water_system("spce", len(sites), masses=MASSES)
    integrator = openmm.CustomIntegrator(dt / 1000)
    integrator.addPerDofVariable("x1", 0)
    integrator.addUpdateContextState()
    integrator.addComputePerDof("v", "v+0.5*dt*f/m")
    integrator.addComputePerDof("x", "x+dt*v")
    integrator.addComputePerDof("x1", "x")
    integrator.addConstrainPositions()
    integrator.addComputePerDof("v", "v+0.5*dt*f/m+(x-x1)/dt")
    integrator.addConstrainVelocities()
    integrator.setConstraintTolerance(1e-12)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName("Reference"))
    context.setPositions(sites.reshape(-1, 3) / 10)
    context.setVelocities(site_velocities.reshape(-1, 3) * 100)  # A/fs to nm/ps
    energies = []
    for step in range(steps + 1):
        if step:
            integrator.step(1)
        s = context.getState(getEnergy=True)
        energies.append([s.getPotentialEnergy().value_in_unit(unit.kilocalorie_per_mole),
                         s.getKineticEnergy().value_in_unit(unit.kilocalorie_per_mole)])
    return np.array(energies)


def lammps_water_box(site_positions, box: float, cutoff: float, accuracy: float):
    """LAMMPS ``units real`` single point of rigid SPC/E in a periodic cube:
    ``pair_style lj/cut/coul/long`` with ``pair_modify tail yes`` and
    ``kspace_style pppm`` at `accuracy` (tin-foil); each molecule's own
    pairs excluded the way LAMMPS users do it (O-H bonds of ``bond_style
    zero``, ``special_bonds lj/coul 0 0 0``, so that the pair style also
    removes their reciprocal-space part). Charges scaled to quatrot's
    Coulomb constant (``lammps_series``). Returns the energies (LJ inside
    the cutoff, its tail, electrostatic; kcal/mol) and the site forces in
    the order of `site_positions` (O H H per molecule)."""
    sites = np.asarray(site_positions, float)
    (q_o, sigma, epsilon), (q_h, _, _), _ = site_parameters("spce")
    lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    try:
        for c in ["units real", "atom_style full", "atom_modify map array sort 0 0", "boundary p p p",
                  f"region box block 0 {box:.17g} 0 {box:.17g} 0 {box:.17g}",
                  "create_box 2 box bond/types 1 extra/bond/per/atom 2 extra/special/per/atom 2",
                  f"mass 1 {MASSES[0]:.17g}", f"mass 2 {MASSES[1]:.17g}", "bond_style zero", "bond_coeff 1",
                  "special_bonds lj/coul 0.0 0.0 0.0"]:
            lmp.command(c)
        scale = math.sqrt(quatrot_coulomb_constant() / lmp.extract_global("qqr2e"))
        for i, x in enumerate(np.mod(sites, box)):
            lmp.command(f"create_atoms {1 if i % 3 == 0 else 2} single {x[0]:.17g} {x[1]:.17g} {x[2]:.17g}")
            lmp.command(f"set atom {i + 1} mol {i // 3 + 1} charge {(q_o if i % 3 == 0 else q_h) * scale:.17g}")
        for i in range(0, len(sites), 3):
            lmp.command(f"create_bonds single/bond 1 {i + 1} {i + 2} special yes")
            lmp.command(f"create_bonds single/bond 1 {i + 1} {i + 3} special yes")
        for c in ["special_bonds lj/coul 0.0 0.0 0.0", f"pair_style lj/cut/coul/long {cutoff:.17g}",
                  f"pair_coeff 1 1 {epsilon:.17g} {sigma:.17g}", "pair_coeff 2 2 0.0 1.0", "pair_coeff 1 2 0.0 1.0",
                  "pair_modify tail yes", f"kspace_style pppm {accuracy:.17g}", "neighbor 2.0 bin",
                  "thermo_style custom step evdwl etail ecoul elong", "thermo_modify norm no"]:
            lmp.command(c)
        lmp.command("run 0 post no")
        n = len(sites)
        order = np.argsort(lmp.numpy.extract_atom("id")[:n])
        tail = lmp.get_thermo("etail")
        energies = {"lennard_jones": lmp.get_thermo("evdwl") - tail, "lennard_jones_tail": tail,
                    "electrostatic": lmp.get_thermo("ecoul") + lmp.get_thermo("elong")}
        return energies, np.array(lmp.numpy.extract_atom("f")[:n][order]), lmp.extract_global("qqr2e")
    finally:
        lmp.close()
