"""Rigid SPC/E boxes run at constant energy from one equilibrated state by
quatrot's integrators, OpenMM (SETTLE) and LAMMPS (``fix rigid/nve/small``
or ``fix rattle``), for issue 41's verdicts (validation/bench/water.py).

The state is the last frame of the built-in ``spce_water_512`` (512
molecules, 298 K, Langevin NVT from a lattice; its GSD frame: centres,
orientations, velocities and angular momenta in float32, converted to
float64 once and cached). Every code then runs the same model: LJ between
oxygens cut at 10 A with the analytic tail, charges by PME (quatrot at
relative accuracy 1e-5; OpenMM ``ewaldErrorTolerance`` 1e-5 on its CPU
platform, single precision, one thread; LAMMPS ``pppm`` 1e-5 in its own
definition), conducting surface, molecules' own pairs excluded.

Each run returns, every ``sample_fs``, the total energy per molecule and
the translational and rotational temperatures (for the atomistic codes
from the site velocities: the molecules' centre-of-mass velocities give
``T_trans`` over 3N - 3 degrees of freedom, the rest of the kinetic energy
``T_rot`` over 3N; OpenMM's leapfrog velocities are half a step behind its
positions), every ``frame_fs`` the unwrapped oxygen positions, and the
process CPU time of the run."""

from __future__ import annotations

import math
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import quatrot
from validation.shared.lammps_bodies import unwrapped_positions
from validation.shared.lammps_driver import _load_lammps, space_to_body
from validation.shared.openmm_water import site_parameters, water_system
from validation.shared.water_runs import BOLTZMANN, MASSES, body_sites, quatrot_coulomb_constant

SCENE = "spce_water_512"
CUTOFF = 10.0
ACCURACY = 1e-5


@dataclass
class BoxState:
    """Centres (A), unit orientations, centre velocities (A/fs), body
    angular velocities (1/fs) of the molecules in a cube of side ``box``."""

    box: float
    centres: np.ndarray
    orientations: np.ndarray
    velocities: np.ndarray
    omega_body: np.ndarray


def builtin(name: str = SCENE) -> dict:
    return tomllib.loads(quatrot.builtin_scenes()[name])


def equilibrated_state(cache: Path, steps: int | None = None, name: str = SCENE) -> BoxState:
    """The last frame of the built-in `name` (a water box with its
    thermostat) after its run (or `steps` steps), cached."""
    scene = builtin(name)
    steps = steps or scene["run"]["steps"]
    path = cache / f"{name}_{steps}.npz"
    if not path.exists():
        import gsd.hoomd

        scene["run"]["steps"] = steps
        scene["record"]["trajectory"] = {"every": steps, "format": "gsd"}
        out = cache / f"{name}_{steps}"
        quatrot.run(scene, out_dir=out)
        with gsd.hoomd.open(out / "trajectory.gsd") as frames:
            state = state_from_frame(frames[-1])
        cache.mkdir(parents=True, exist_ok=True)
        np.savez(path, **vars(state))
    data = np.load(path)
    return BoxState(float(data["box"]), data["centres"], data["orientations"], data["velocities"], data["omega_body"])


def state_from_frame(frame) -> BoxState:
    """A periodic GSD frame of quatrot's (float32, centred box) in float64:
    centres wrapped into [0, L), orientations renormalised, body angular
    velocities from GSD's angular momentum ``2 Q (0, L_body)`` (HOOMD's
    convention) over the moments."""
    p, box = frame.particles, float(frame.configuration.box[0])
    q = p.orientation.astype(float)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    body_l = np.array([quaternion_product(conjugate(a), b)[1:] / 2 for a, b in zip(q, p.angmom.astype(float))])
    return BoxState(box, np.mod(p.position.astype(float) + box / 2, box), q, p.velocity.astype(float),
                    body_l / p.moment_inertia.astype(float))


def conjugate(q):
    return np.array([q[0], -q[1], -q[2], -q[3]])


def quaternion_product(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def sites_of(state: BoxState):
    """Sites (n, 3, 3) and their velocities V + omega x (R s)."""
    s = body_sites()
    rotations = np.array([space_to_body(q).T for q in state.orientations])
    arms = np.einsum("nij,sj->nsi", rotations, s)
    omega = np.einsum("nij,nj->ni", rotations, state.omega_body)
    return state.centres[:, None, :] + arms, state.velocities[:, None, :] + np.cross(omega[:, None, :], arms)


def temperatures(site_velocities: np.ndarray) -> tuple[float, float]:
    """T_trans over 3N - 3 and T_rot over 3N degrees of freedom (K) of
    molecules' site velocities (n, 3, 3) in A/fs."""
    m = np.asarray(MASSES)
    kinetic = 0.5 * np.einsum("s,nsi,nsi->", m, site_velocities, site_velocities) / 4.184e-4
    centre = np.einsum("s,nsi->ni", m, site_velocities) / m.sum()
    translational = 0.5 * m.sum() * (centre**2).sum() / 4.184e-4
    n = len(site_velocities)
    k = BOLTZMANN
    return 2 * translational / ((3 * n - 3) * k), 2 * (kinetic - translational) / (3 * n * k)


def result(times, totals, t_trans, t_rot, frames, started, failed_at=None) -> dict:
    return {"time_ps": np.asarray(times) / 1000, "total_per_molecule": np.asarray(totals),
            "T_trans": np.asarray(t_trans), "T_rot": np.asarray(t_rot), "oxygens": np.asarray(frames),
            "cpu_seconds": time.process_time() - started, "failed_at_fs": failed_at}


def sample_steps(dt: float, length_fs: float, sample_fs: float) -> range:
    """The steps at which every run here samples: 0, `every`, 2 `every`, ...
    up to the run's ``round(length_fs / dt)`` steps, `every` being
    ``round(sample_fs / dt)`` (at least 1). The last sample can fall short of
    `length_fs` (at 3 fs: 3,333 steps sampled every 7, the last at 9,996
    fs of 10 ps)."""
    return range(0, round(length_fs / dt) + 1, max(1, round(sample_fs / dt)))


def quatrot_run(state: BoxState, integrator: str, dt: float, length_fs: float, sample_fs: float,
                frame_fs: float, out_dir: Path) -> dict:
    """The built-in's model from `state` at constant energy, one thread."""
    import gsd.hoomd

    n = len(state.centres)
    steps = round(length_fs / dt)
    scene = given_scene(state, integrator, dt, steps)
    scene["record"] = {
        "series": [{"name": "series", "every": sample_steps(dt, length_fs, sample_fs).step,
                    "quantities": ["total_energy", "T_trans", "T_rot"]}],
        "trajectory": {"every": max(1, round(frame_fs / dt)), "format": "gsd"},
    }
    started = time.process_time()
    failed_at = None
    try:
        series = quatrot.run(scene, out_dir=out_dir)["series"]["series"]
    except quatrot.BlowUpError as e:
        series = e.result["series"]["series"]
        failed_at = float(series["time"][-1]) if len(series["time"]) else 0.0
    oxygen = body_sites()[0]
    frames = []
    with gsd.hoomd.open(out_dir / "trajectory.gsd") as f:
        for frame in f:
            p = frame.particles
            centres = p.position.astype(float) + state.box / 2 + p.image * state.box
            rotations = np.array([space_to_body(q).T for q in p.orientation.astype(float)])
            frames.append(centres + rotations @ oxygen)
    return result(series["time"], series["total_energy"] / n, series["T_trans"], series["T_rot"], frames, started,
                  failed_at)


def given_scene(state: BoxState, integrator: str, dt: float, steps: int, accuracy: float = ACCURACY) -> dict:
    """The built-in's model from `state` at constant energy, one thread,
    PME at `accuracy`, nothing recorded."""
    scene = builtin()
    scene["bodies"] = {"kind": "given", "box": [state.box] * 3, "list": [
        {"position": c.tolist(), "orientation": q.tolist(), "velocity": v.tolist(), "angular_velocity": w.tolist()}
        for c, q, v, w in zip(state.centres, state.orientations, state.velocities, state.omega_body)]}
    for table in ("initial", "thermostat", "record"):
        scene.pop(table, None)
    scene["body_interactions"]["electrostatics"]["accuracy"] = accuracy
    scene["integrator"] = {"kind": integrator}
    scene["run"] = {"dt": dt, "steps": steps, "threads": 1}
    return scene


def openmm_context(state: BoxState, dt: float, tolerance: float = ACCURACY):
    """OpenMM 8 CPU platform, one thread, ``VerletIntegrator`` with SETTLE,
    ``ewaldErrorTolerance`` `tolerance`, at `state`: (context, integrator)."""
    import openmm

    sites, velocities = sites_of(state)
    system = water_system("spce", len(sites), box=state.box, cutoff=CUTOFF, tolerance=tolerance, masses=MASSES)
    integrator = openmm.VerletIntegrator(dt / 1000)
    platform = openmm.Platform.getPlatformByName("CPU")
    context = openmm.Context(system, integrator, platform, {"Threads": "1"})
    context.setPositions(sites.reshape(-1, 3) / 10)
    context.setVelocities(velocities.reshape(-1, 3) * 100)
    return context, integrator


def openmm_run(state: BoxState, dt: float, length_fs: float, sample_fs: float, frame_fs: float) -> dict:
    """OpenMM 8 CPU platform, one thread, ``VerletIntegrator`` with SETTLE."""

    import openmm  # noqa: F401
    from openmm import unit

    n = len(state.centres)
    context, integrator = openmm_context(state, dt)
    samples, frame_every = sample_steps(dt, length_fs, sample_fs), max(1, round(frame_fs / dt))
    every = samples.step
    times, totals, t_trans, t_rot, frames = [], [], [], [], []
    started = time.process_time()
    failed_at = None
    for step in samples:
        if step:
            integrator.step(every)
        s = context.getState(getEnergy=True, getVelocities=True, getPositions=step % frame_every == 0)
        total = (s.getPotentialEnergy() + s.getKineticEnergy()).value_in_unit(unit.kilocalorie_per_mole)
        if not math.isfinite(total):
            failed_at = step * dt
            break
        v = s.getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond) / 100
        tt, tr = temperatures(v.reshape(n, 3, 3))
        times.append(step * dt), totals.append(total / n), t_trans.append(tt), t_rot.append(tr)
        if step % frame_every == 0:
            x = s.getPositions(asNumpy=True).value_in_unit(unit.angstrom)
            frames.append(np.asarray(x).reshape(n, 3, 3)[:, 0])
    return result(times, totals, t_trans, t_rot, frames, started, failed_at)


def lammps_run(state: BoxState, dt: float, length_fs: float, sample_fs: float, frame_fs: float,
               constraint: str) -> dict:
    """LAMMPS ``units real``, ``lj/cut/coul/long`` + ``pppm`` (tail on),
    serial: ``fix rigid/nve/small molecule`` (``constraint = "rigid"``) or
    ``fix nve`` + ``fix rattle`` on the O-H bonds and the H-O-H angle
    (``"rattle"``). Charges scaled to quatrot's Coulomb constant; the
    molecules' own pairs excluded by ``special_bonds``."""
    n, box = len(state.centres), state.box
    started = time.process_time()
    lmp = lammps_box(state, dt, constraint)
    try:
        samples, frame_every = sample_steps(dt, length_fs, sample_fs), max(1, round(frame_fs / dt))
        every = samples.step
        times, totals, t_trans, t_rot, frames = [], [], [], [], []
        failed_at = None
        for step in samples:
            lmp.command("run 0 post no" if step == 0 else f"run {every} pre no post no")
            total = lmp.get_thermo("etotal")
            if not math.isfinite(total):
                failed_at = step * dt
                break
            order = np.argsort(lmp.numpy.extract_atom("id")[: 3 * n])
            v = np.array(lmp.numpy.extract_atom("v")[: 3 * n][order])
            tt, tr = temperatures(v.reshape(n, 3, 3))
            times.append(step * dt), totals.append(total / n), t_trans.append(tt), t_rot.append(tr)
            if step % frame_every == 0:
                frames.append(unwrapped_positions(lmp, 3 * n, box).reshape(n, 3, 3)[:, 0])
        return result(times, totals, t_trans, t_rot, frames, started, failed_at)
    finally:
        lmp.close()


def lammps_box(state: BoxState, dt: float, constraint: str, accuracy: float = ACCURACY):
    """The LAMMPS instance of :func:`lammps_run` at `state`, ``pppm`` at
    `accuracy`, ready to run (the caller closes it)."""
    sites, velocities = sites_of(state)
    n = len(sites)
    (q_o, sigma, epsilon), (q_h, _, _), _ = site_parameters("spce")
    box = state.box
    lmp = _load_lammps().lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])
    try:
        for c in ["units real", "atom_style full", "atom_modify map array sort 0 0", "boundary p p p",
                  f"region box block 0 {box:.17g} 0 {box:.17g} 0 {box:.17g}",
                  "create_box 2 box bond/types 1 angle/types 1 extra/bond/per/atom 2 extra/angle/per/atom 1 "
                  "extra/special/per/atom 2",
                  f"mass 1 {MASSES[0]:.17g}", f"mass 2 {MASSES[1]:.17g}", "bond_style zero", "bond_coeff 1 1.0",
                  "angle_style zero", "angle_coeff 1 109.47", "special_bonds lj/coul 0.0 0.0 0.0"]:
            lmp.command(c)
        scale = math.sqrt(quatrot_coulomb_constant() / lmp.extract_global("qqr2e"))
        flat = sites.reshape(-1, 3)
        images = np.floor(flat / box)
        for i, x in enumerate(flat - images * box):
            lmp.command(f"create_atoms {1 if i % 3 == 0 else 2} single {x[0]:.17g} {x[1]:.17g} {x[2]:.17g}")
            m = images[i].astype(int)
            lmp.command(f"set atom {i + 1} mol {i // 3 + 1} charge {(q_o if i % 3 == 0 else q_h) * scale:.17g} "
                        f"image {m[0]} {m[1]} {m[2]}")
        for i in range(0, 3 * n, 3):
            lmp.command(f"create_bonds single/bond 1 {i + 1} {i + 2} special no")
            lmp.command(f"create_bonds single/bond 1 {i + 1} {i + 3} special no")
            lmp.command(f"create_bonds single/angle 1 {i + 2} {i + 1} {i + 3} special {'yes' if i == 3 * n - 3 else 'no'}")
        integrate = (["fix integrate all rigid/nve/small molecule"] if constraint == "rigid" else
                     ["fix integrate all nve", "fix constrain all rattle 1e-10 100 0 b 1 a 1"])
        for c in [f"pair_style lj/cut/coul/long {CUTOFF:.17g}", f"pair_coeff 1 1 {epsilon:.17g} {sigma:.17g}",
                  "pair_coeff 2 2 0.0 1.0", "pair_coeff 1 2 0.0 1.0", "pair_modify tail yes",
                  f"kspace_style pppm {accuracy:.17g}", "neighbor 2.0 bin", "neigh_modify every 1 delay 0 check yes",
                  *integrate, "thermo_style custom step etotal", "thermo_modify norm no", f"timestep {dt:.17g}"]:
            lmp.command(c)
        lmp.numpy.extract_atom("v")[: 3 * n] = velocities.reshape(-1, 3)
        return lmp
    except Exception:
        lmp.close()
        raise
