"""Moving bodies run by quatrot and by LAMMPS from the same initial state
(issue 39): the Stockmayer fluid (256 dipolar LJ spheres, mu = 1, fcc at
rho* = 0.8 displaced at random, random dipoles, Maxwell velocities and
angular velocities at T* = 1.35 perpendicular to the dipoles) by quatrot's
DLM and by LAMMPS ``fix nve/sphere update dipole/dlm`` (``pair_style
lj/cut/dipole/cut 2.5``, plain truncation of both terms), dt = 0.002.

Conventions mapped: LAMMPS's sphere has the moment of inertia
``0.4 m (d/2)^2`` from its ``diameter`` d, so d = 0.5 gives quatrot's
0.025; its dipole is a vector, quatrot's the body vector (0, 0, mu) turned
by the orientation of ``lammps_driver.quatrot_rotor``; its omega is space
frame, quatrot's body frame. quatrot's potential energy includes the LJ tail
correction, a constant at fixed N and V, which LAMMPS's style leaves out
(ERRATA.md): it is subtracted (``quatrot.bodies_evaluate``).

Found: the codes agree at t = 0 to round-off (energies 7e-16 relative),
and differ from the first step on, at O(dt^3) per step: the DLM steps are
not the same algorithm (ERRATA.md's DLM rows: LAMMPS's Cayley rotations,
its omega sense, its frame rebuilt from the dipole, its body-axis sweep
for spheres where quatrot takes the exact flow), while the translation is
velocity Verlet in both. Measured: the potential, translational and
rotational kinetic energies at every step (float64 in both codes,
relative to |PE|), the space dipoles and the centres (minimum image, every
10 steps from quatrot's float32 GSD file: resolved to ~2e-7) at t = 0.2
(quick: 0.04) for dt = 0.002 and 0.001; the dipoles' difference must fall
as dt^2 (the centres' follows it through the forces, above the float32
floor at t = 0.2: 1.3e-5 and 3.5e-6 measured, order 1.9)."""

from __future__ import annotations

from pathlib import Path

import gsd.hoomd
import numpy as np

import quatrot
from validation.shared.check import Check, Context
from validation.shared.lammps_bodies import periodic_cube, side_by_side, unwrapped_positions
from validation.shared.lammps_driver import lammps_version, quatrot_rotor, space_to_body

N_SIDE = 4  # fcc: 256 spheres
DENSITY, TEMPERATURE = 0.8, 1.35
MU, MASS, INERTIA = 1.0, 1.0, 0.025
DIAMETER = 2.0 * np.sqrt(INERTIA / (0.4 * MASS))
CUTOFF, DT = 2.5, 0.002
EVERY = 10
# Energies at t = 0: sums of ~10^4 pair terms in another order.
ENERGY_ROUNDOFF = 1e-12  # relative to |PE|
# Orders fitted from two step sizes, not yet exactly asymptotic.
ORDER_TOLERANCE = 0.3


def initial_state(seed: int):
    """fcc centres displaced by up to 0.05, dipoles, velocities and space
    angular velocities (perpendicular to the dipoles), zero momentum."""
    rng = np.random.default_rng(seed)
    box = (4 * N_SIDE**3 / DENSITY) ** (1 / 3)
    a = box / N_SIDE
    cells = np.array([[i, j, k] for i in range(N_SIDE) for j in range(N_SIDE) for k in range(N_SIDE)], dtype=float)
    basis = np.array([[0.25, 0.25, 0.25], [0.75, 0.75, 0.25], [0.75, 0.25, 0.75], [0.25, 0.75, 0.75]])
    centres = ((cells[:, None, :] + basis[None]) * a).reshape(-1, 3) + rng.uniform(-0.05, 0.05, (4 * N_SIDE**3, 3))
    n = len(centres)
    dipoles = rng.normal(size=(n, 3))
    dipoles /= np.linalg.norm(dipoles, axis=1)[:, None]
    dipoles[dipoles[:, 2] < -0.99] *= -1  # quatrot_rotor is undefined at -z
    velocities = rng.normal(scale=np.sqrt(TEMPERATURE / MASS), size=(n, 3))
    velocities -= velocities.mean(axis=0)
    omega = rng.normal(scale=np.sqrt(TEMPERATURE / INERTIA), size=(n, 3))
    omega -= np.sum(omega * dipoles, axis=1)[:, None] * dipoles
    return box, centres, dipoles * MU, velocities, omega


def lammps_run(box, centres, dipoles, velocities, omega, dt, steps):
    """Per-step pe, ke, erotate; every EVERY steps unwrapped x and mu."""
    lmp = periodic_cube(box, "hybrid sphere dipole", centres)
    n = len(centres)
    try:
        for c in [
            f"set type 1 diameter {DIAMETER:.17g}",
            f"set type 1 mass {MASS:.17g}",
            f"pair_style lj/cut/dipole/cut {CUTOFF:.17g}",
            "pair_coeff * * 1.0 1.0",
            "neighbor 0.3 bin",
            "neigh_modify every 1 delay 0 check yes",
            "fix integrate all nve/sphere update dipole/dlm",
            "compute rke all erotate/sphere",
            "thermo_style custom step pe ke c_rke",  # get_thermo reads pe and ke; c_rke by extract_compute
            "thermo_modify norm no",
            f"timestep {dt:.17g}",
        ]:
            lmp.command(c)
        for i in range(n):
            lmp.command(f"set atom {i + 1} dipole {dipoles[i, 0]:.17g} {dipoles[i, 1]:.17g} {dipoles[i, 2]:.17g}")
        lmp.numpy.extract_atom("v")[:n] = velocities
        lmp.numpy.extract_atom("omega")[:n] = omega
        energies, frames = [], []
        for step in range(steps + 1):
            lmp.command("run 0" if step == 0 else "run 1 pre no post no")
            energies.append([lmp.get_thermo("pe"), lmp.get_thermo("ke"), lmp.extract_compute("rke", 0, 0)])
            if step % EVERY == 0:
                order = np.argsort(lmp.numpy.extract_atom("id")[:n])
                frames.append((unwrapped_positions(lmp, n, box), np.array(lmp.numpy.extract_atom("mu")[:n, :3][order])))
        return np.array(energies), frames
    finally:
        lmp.close()


def quatrot_run(box, centres, dipoles, velocities, omega, dt, steps, out_dir: Path):
    """quatrot's per-step energies (LJ tail left out) and GSD frames."""
    sphere = {
        "mass": MASS,
        "inertia": (np.eye(3) * INERTIA).tolist(),
        "sites": [{"position": [0, 0, 0], "lennard_jones": {"epsilon": 1.0, "sigma": 1.0}, "dipole": [0, 0, MU]}],
    }
    rotors = [quatrot_rotor(d, w) for d, w in zip(dipoles, omega)]
    bodies = [
        {"position": x.tolist(), "orientation": q.tolist(), "velocity": v.tolist(), "angular_velocity": w.tolist()}
        for x, (q, w), v in zip(centres, rotors, velocities)
    ]
    scene = {
        "version": 1,
        "name": "stockmayer_vs_lammps",
        "body_types": [sphere],
        "bodies": {"kind": "given", "list": bodies, "box": [box] * 3},
        "body_interactions": {
            "lennard_jones": {"cutoff": CUTOFF, "truncation": "plain"},
            "electrostatics": {"kind": "cutoff", "cutoff": CUTOFF},
            "skin": 0.3,
        },
        "integrator": {"kind": "dlm"},
        "run": {"dt": dt, "steps": steps},
        "record": {
            "series": [{"name": "e", "every": 1, "quantities": ["potential_energy", "translational_kinetic_energy", "rotational_kinetic_energy"]}],
            "trajectory": {"every": EVERY, "format": "gsd"},
        },
    }
    series = quatrot.run(scene, out_dir=str(out_dir))["series"]["e"]
    tail = quatrot.bodies_evaluate(
        [sphere], centres, [q for q, _ in rotors], box_lengths=[box] * 3, lj_cutoff=CUTOFF, electrostatic_cutoff=CUTOFF
    )["energies"]["lennard_jones_tail"]
    energies = np.stack(
        [series["potential_energy"] - tail, series["translational_kinetic_energy"], series["rotational_kinetic_energy"]], axis=1
    )
    frames = []
    with gsd.hoomd.open(str(out_dir / "trajectory.gsd")) as f:
        for frame in f:
            p = frame.particles
            x = p.position.astype(float) + box / 2 + p.image * box
            mu = np.array([space_to_body(q).T @ [0.0, 0.0, MU] for q in p.orientation.astype(float)])
            frames.append((x, mu))
    return energies, frames


def differences(state, dt: float, steps: int) -> dict:
    """Both codes over `steps` steps of `dt`: the energies' largest relative
    difference at step 0 and at the end, the centres' largest difference
    over the frames, the dipoles' at the end."""
    energy, centres, frames = side_by_side(lammps_run, quatrot_run, state, dt, steps)
    (_, ours), (_, reference) = frames[-1]
    return {
        "energy_start": float(energy[0]),
        "energy_end": float(energy[-1]),
        "centres": float(centres.max()),
        "dipoles_end": float(np.abs(ours - reference).max()),
    }


def run(ctx: Context) -> list[Check]:
    duration = 0.04 if ctx.quick else 0.2
    state = initial_state(ctx.seed)
    ctx.progress(f"Stockmayer fluid, LAMMPS and quatrot DLM: t = {duration} at dt = {DT} and {DT / 2}")
    coarse = differences(state, DT, round(duration / DT))
    fine = differences(state, DT / 2, round(duration / (DT / 2)))
    order = float(np.log2(coarse["dipoles_end"] / fine["dipoles_end"]))
    refs = {"LAMMPS": lammps_version(), "quatrot": quatrot.__version__}
    summary = "; ".join(
        f"dt {dt}: energies at step 0 {d['energy_start']:.1e}, at t = {duration} {d['energy_end']:.1e} (relative to |PE|), "
        f"dipoles {d['dipoles_end']:.1e}, centres (float32) {d['centres']:.1e}"
        for dt, d in ((DT, coarse), (DT / 2, fine))
    )
    return [
        Check(
            name="Stockmayer fluid, DLM vs LAMMPS nve/sphere dipole/dlm: energies at t = 0",
            proves="both codes start from the same state: potential, translational and rotational kinetic energies agree to round-off (relative to |PE|)",
            tolerance=ENERGY_ROUNDOFF,
            measured=max(coarse["energy_start"], fine["energy_start"]),
            references=refs,
            details=summary,
        ),
        Check(
            name="Stockmayer fluid, DLM vs LAMMPS nve/sphere dipole/dlm: the trajectories differ at O(dt^2)",
            proves=(
                f"the two DLM steps differ only as ERRATA.md's DLM rows say (LAMMPS's Cayley rotations, omega sense, "
                f"rebuilt frame and body-axis sweep for spheres): at t = {duration} the space dipoles differ by an "
                f"amount of order 2 in dt (measured: |fitted order - 2|, order {order:.2f}), not round-off and not an "
                "O(dt) mistake; the energies and centres follow (details)"
            ),
            tolerance=ORDER_TOLERANCE,
            measured=abs(order - 2.0),
            references=refs,
            details=summary,
        ),
    ]
