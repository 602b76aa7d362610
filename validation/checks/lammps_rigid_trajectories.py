"""Rigid three-site molecules run by quatrot's NO_SQUISH and by LAMMPS
``fix rigid/nve/small`` (NO_SQUISH, Miller et al. 2002, with velocity
Verlet for the centres) from the same initial state (issue 39): the
Lewis-Wahnstrom o-terphenyl liquid of the built-in ``lewis_wahnstrom_otp``
(256 molecules, fcc at the built-in's density, all in its orientation;
its thermostat removed), Maxwell velocities and body angular velocities at T* = 0.5,
LJ force-shifted at 2.612 (LAMMPS ``pair_style lj/smooth/linear``, the same
potential), intramolecular pairs excluded (``neigh_modify exclude
molecule/intra``), dt = 0.002.

Mapping: LAMMPS builds each body from its atoms (sites of mass 1 at
``X + R(Q) s``, velocities ``V + omega x R(Q) s``), finds the centre of
mass, the principal axes and the angular momentum itself. Measured: the
potential and the kinetic energy at every step (float64 in both codes,
relative to |PE|) and the sites' positions every 10 steps (quatrot's from
its float32 GSD centres and orientations) over 100 steps (quick: 20).
Found: the same trajectory to round-off (LAMMPS's sweep 3, 2, 1, 2, 3 of
its principal axes is quatrot's), energies within ~1e-14 relative for
100 steps, sites within the float32 resolution."""

from __future__ import annotations

import tomllib
from pathlib import Path

import gsd.hoomd
import numpy as np

import quatrot
from validation.shared.check import Check, Context
from validation.shared.lammps_bodies import periodic_cube, side_by_side, unwrapped_positions
from validation.shared.lammps_driver import lammps_version, space_to_body

TEMPERATURE = 0.5
CUTOFF = 2.612
DT = 0.002
EVERY = 10
# Relative to |PE|: sums of ~10^4 pair terms in another order (5e-14 at
# t = 0, 6e-15 after 100 steps): a 20-fold margin for chaotic growth.
ENERGY_ROUNDOFF = 1e-12
# Site coordinates up to ~10 in float32 (GSD centres and orientations):
# 2e-7 measured; a tenfold margin.
FLOAT32_TOLERANCE = 2e-6


def builtin():
    return tomllib.loads(quatrot.builtin_scenes()["lewis_wahnstrom_otp"])


def initial_state(seed: int):
    """The built-in's centres and orientation; velocities and body angular
    velocities at T (the principal moments from the sites)."""
    scene = builtin()
    sites = np.array([s["position"] for s in scene["body_types"][0]["sites"]])
    n = scene["bodies"]["counts"][0]
    box = (n / scene["bodies"]["density"]) ** (1 / 3)
    cells = round((n / 4) ** (1 / 3))
    a = box / cells
    grid = np.array([[i, j, k] for i in range(cells) for j in range(cells) for k in range(cells)], dtype=float)
    basis = np.array([[0.25, 0.25, 0.25], [0.75, 0.75, 0.25], [0.75, 0.25, 0.75], [0.25, 0.75, 0.75]])
    centres = ((grid[:, None, :] + basis[None]) * a).reshape(-1, 3)
    q = np.array(scene["bodies"]["orientation"], dtype=float)
    q /= np.linalg.norm(q)
    rng = np.random.default_rng(seed)
    mass = float(len(sites))
    moments = np.array([np.sum(np.delete(sites, k, axis=1) ** 2) for k in range(3)])
    velocities = rng.normal(scale=np.sqrt(TEMPERATURE / mass), size=(n, 3))
    velocities -= velocities.mean(axis=0)
    omega_body = rng.normal(size=(n, 3)) * np.sqrt(TEMPERATURE / moments)
    return box, sites, centres, q, velocities, omega_body


def site_positions(centres, orientations, sites):
    """X + R(Q) s for each body (rows) and site."""
    rotations = np.array([space_to_body(q).T for q in orientations])
    return centres[:, None, :] + np.einsum("nij,sj->nsi", rotations, sites)


def lammps_run(box, sites, centres, q, velocities, omega_body, dt, steps):
    """Per-step pe and ke; every EVERY steps the unwrapped site positions."""
    n, per = len(centres), len(sites)
    rotation = space_to_body(q).T
    x = site_positions(centres, np.tile(q, (n, 1)), sites).reshape(-1, 3)
    omega_space = omega_body @ rotation.T
    v = (velocities[:, None, :] + np.cross(omega_space[:, None, :], (rotation @ sites.T).T[None])).reshape(-1, 3)
    # Sites wrapped into the box with their image counts, so that LAMMPS
    # unwraps each molecule whole.
    images = np.floor(x / box)
    lmp = periodic_cube(box, "molecular", x - images * box)
    try:
        lmp.command("mass 1 1.0")
        for i, m in enumerate(images.astype(int)):
            lmp.command(f"set atom {i + 1} mol {i // per + 1} image {m[0]} {m[1]} {m[2]}")
        for c in [
            f"pair_style lj/smooth/linear {CUTOFF:.17g}",
            "pair_coeff * * 1.0 1.0",
            "neighbor 0.3 bin",
            "neigh_modify every 1 delay 0 check yes exclude molecule/intra all",
            "fix integrate all rigid/nve/small molecule",
            "thermo_style custom step pe ke",
            "thermo_modify norm no",
            f"timestep {dt:.17g}",
        ]:
            lmp.command(c)
        lmp.numpy.extract_atom("v")[: n * per] = v
        energies, frames = [], []
        for step in range(steps + 1):
            lmp.command("run 0" if step == 0 else "run 1 pre no post no")
            energies.append([lmp.get_thermo("pe"), lmp.get_thermo("ke")])
            if step % EVERY == 0:
                frames.append((unwrapped_positions(lmp, n * per, box).reshape(n, per, 3),))
        return np.array(energies), frames
    finally:
        lmp.close()


def quatrot_run(box, sites, centres, q, velocities, omega_body, dt, steps, out_dir: Path):
    """quatrot's per-step energies and the sites of its GSD frames."""
    scene = builtin()
    scene["bodies"] = {
        "kind": "given",
        "box": [box] * 3,
        "list": [
            {"position": c.tolist(), "orientation": q.tolist(), "velocity": v.tolist(), "angular_velocity": w.tolist()}
            for c, v, w in zip(centres, velocities, omega_body)
        ],
    }
    scene.pop("initial", None)
    scene.pop("thermostat", None)
    scene["run"] = {"dt": dt, "steps": steps}
    scene["record"] = {
        "series": [{"name": "e", "every": 1, "quantities": ["potential_energy", "kinetic_energy"]}],
        "trajectory": {"every": EVERY, "format": "gsd"},
    }
    series = quatrot.run(scene, out_dir=str(out_dir))["series"]["e"]
    frames = []
    with gsd.hoomd.open(str(out_dir / "trajectory.gsd")) as f:
        for frame in f:
            p = frame.particles
            x = p.position.astype(float) + box / 2 + p.image * box
            frames.append((site_positions(x, p.orientation.astype(float), sites),))
    return np.stack([series["potential_energy"], series["kinetic_energy"]], axis=1), frames


def run(ctx: Context) -> list[Check]:
    steps = 20 if ctx.quick else 100
    ctx.progress(f"o-terphenyl, LAMMPS rigid/nve/small and quatrot NO_SQUISH: {steps} steps")
    energy, sites, _ = side_by_side(lammps_run, quatrot_run, initial_state(ctx.seed), DT, steps)
    d = {"energy": energy, "sites": sites}
    refs = {"LAMMPS": lammps_version(), "quatrot": quatrot.__version__}
    marks = [k for k in (0, 1, 10, 20, 50, 100) if k <= steps]
    details = (
        "energy difference relative to |PE| at steps "
        + ", ".join(f"{k}: {d['energy'][k]:.1e}" for k in marks)
        + "; sites (float32) at steps "
        + ", ".join(f"{EVERY * k}: {x:.1e}" for k, x in enumerate(d["sites"]))
    )
    return [
        Check(
            name="o-terphenyl, NO_SQUISH vs LAMMPS rigid/nve/small: energies per step",
            proves=(
                f"quatrot's NO_SQUISH for rigid molecules is LAMMPS's fix rigid/nve/small: the potential and kinetic "
                f"energies agree at every step to {steps} to round-off and its chaotic growth (largest over steps, "
                "relative to |PE|); a different splitting would differ by ~1e-8 after one step"
            ),
            tolerance=ENERGY_ROUNDOFF,
            measured=float(d["energy"].max()),
            references=refs,
            details=details,
        ),
        Check(
            name="o-terphenyl, NO_SQUISH vs LAMMPS rigid/nve/small: site trajectories",
            proves=(
                "the sites of both codes (minimum image) agree every 10 steps to the resolution of quatrot's float32 "
                "GSD frames (largest component difference)"
            ),
            tolerance=FLOAT32_TOLERANCE,
            measured=float(d["sites"].max()),
            references=refs,
            details=details,
        ),
    ]
