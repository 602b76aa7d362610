"""LAMMPS on the 1000-rotor dipole lattice, from the same initial state as
quatrot's runs (mapping of :mod:`validation.shared.lammps_driver`), with the same
error and energy measures."""

from __future__ import annotations

import json
import os
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from validation.shared.benchmark_scenes import LATTICE_SCENE
from validation.shared.rotor_reference import axis_angle, body_z_in_space
from validation.shared.lammps_driver import DipoleSystem, lammps_version, run_lammps, time_lammps

UPDATES = ("dipole/dlm", "dipole")
REPEATS = 3


def lattice_system(system: dict, cutoff: float) -> DipoleSystem:
    """The quatrot lattice as pinned LAMMPS spheres (unit mass and diameter:
    I = 0.1 as in the scene)."""
    q = np.array(system["orientations"])
    w_b = np.array(system["omega_body"])
    mu = np.linalg.norm(system["dipole_body"])
    u = body_z_in_space(q)
    # omega_space = R(Q) omega_body = A(Q)^T omega_body
    from validation.shared.lammps_driver import space_to_body

    w_s = np.array([space_to_body(qi).T @ wi for qi, wi in zip(q, w_b)])
    box = system["box_lengths"][0]
    return DipoleSystem(sites=np.array(system["sites"]), dipoles=u * mu, omega=w_s, cutoff=cutoff, box=box)


def _slope(t, y) -> float:
    return float(np.polyfit(t, y, 1)[0]) if len(t) > 1 else float("nan")


def runs(study: dict, reference_axes: np.ndarray, cutoff: float) -> tuple[list[dict], str]:
    """One record per (update, dt), shaped like quatrot's runs."""
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    system = lattice_system(study["system"], cutoff)
    n = len(system.sites)
    steps_of = {r["dt"]: r["steps"] for r in study["runs"]}
    out = []
    for update in UPDATES:
        for dt, steps in sorted(steps_of.items(), reverse=True):
            traj = run_lammps(system, dt, steps, update)
            energy = traj.potential + traj.kinetic
            error = (energy - energy[0]) / traj.kinetic[0]
            walls = [time_lammps(system, dt, steps, update)[0] for _ in range(REPEATS)]
            wall = float(np.median(walls))
            out.append(
                {
                    "scheme": f"LAMMPS {update}",
                    "dt": dt,
                    "steps": steps,
                    "wall_median": wall,
                    "wall_seconds": walls,
                    "torque_evaluations": steps + 1,
                    "energy_error_max": float(np.max(np.abs(error))),
                    "energy_drift_per_time": _slope(traj.time, error),
                    "error": axis_angle(traj.dipoles[-1], reference_axes),
                    "rotor_steps_per_second": n * steps / wall,
                    "failure": None,
                }
            )
    return out, lammps_version()


SCENE = Path(f"scenes/{LATTICE_SCENE}.toml")
CLI = Path("target/release/quatrot")
THROUGHPUT_STEPS = 2000
CLI_SCHEMES = ("no_squish", "gear_b")


def _cli_seconds(scene: Path, integrator: str, out: str) -> tuple[float, float]:
    """Seconds of the `quatrot` CLI on one thread: its step loop (from its
    summary; set-up excluded, as LAMMPS's `run` below) and the whole process
    (start, scene, pair list, Gear start-up, loop, summary)."""
    env = {**os.environ, "RAYON_NUM_THREADS": "1"}
    command = [str(CLI), "run", str(scene), "--integrator", integrator, "--steps", str(THROUGHPUT_STEPS), "--out", out]
    started = time.perf_counter()
    subprocess.run(command, env=env, check=True, capture_output=True)
    whole = time.perf_counter() - started
    return json.loads((Path(out) / "summary.json").read_text())["wall_seconds"], whole


def side_by_side(study: dict, cutoff: float) -> dict:
    """Rotor-steps per second, one thread, of the `quatrot` CLI (the built-in
    lattice scene with its recording removed) and of LAMMPS, in alternation
    (REPEATS rounds; medians), at the scene's dt."""
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    if not CLI.exists() or not SCENE.exists():
        return {}
    system = lattice_system(study["system"], cutoff)
    n = len(system.sites)
    text = SCENE.read_text().split("[record]")[0]
    dt = float(next(line.split("=")[1] for line in text.splitlines() if line.startswith("dt")))
    seconds: dict[str, list[float]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        scene = Path(tmp) / "lattice.toml"
        scene.write_text(text)
        for _ in range(REPEATS):
            for integrator in CLI_SCHEMES:
                loop, whole = _cli_seconds(scene, integrator, tmp)
                seconds.setdefault(f"quatrot CLI {integrator}, step loop", []).append(loop)
                seconds.setdefault(f"quatrot CLI {integrator}, whole process", []).append(whole)
            for update in UPDATES:
                seconds.setdefault(f"LAMMPS {update}", []).append(time_lammps(system, dt, THROUGHPUT_STEPS, update)[0])
    return {
        "steps": THROUGHPUT_STEPS,
        "dt": dt,
        "rotors": n,
        "seconds": seconds,
        "rotor_steps_per_second": {k: n * THROUGHPUT_STEPS / float(np.median(v)) for k, v in seconds.items()},
    }
