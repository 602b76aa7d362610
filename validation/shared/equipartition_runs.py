"""Equipartition between rotation and translation in NVE runs of the body
built-ins (issue 39), shared by `make validate`'s check
(`validation/checks/equipartition_bodies.py`, 2e4 steps per run) and `make
bench`'s production verdict (`validation/bench/equipartition.py`, 1e5).

Each run is a built-in with the integrator swapped and its thermostat
removed (constant energy), recording T_trans, T_rot and the total energy.
The difference d = T_rot - T_trans is block averaged (Flyvbjerg-Petersen,
``quatrot.block_average``) after the fraction `left_out`; the verdict is
|<d>| / sigma_<d> against `Z_MAX`. The ratio <T_rot> / <T_trans> = 1 +
<d> / <T_trans> carries the same error, sigma_<d> / <T_trans>."""

from __future__ import annotations

import tomllib

import numpy as np

import quatrot

SCENES = ("stockmayer_fluid", "lewis_wahnstrom_otp")
INTEGRATORS = ("no_squish", "dlm", "richardson", "gear_a", "gear_b")
QUANTITIES = ("T_trans", "T_rot", "total_energy")
Z_MAX = 4.0  # sigma multiples allowed (two-sided normal 6e-5 per run)


def nve_scene(scene_name: str, integrator: str, steps: int, every: int) -> dict:
    """The built-in with `integrator`, no thermostat, `steps` steps, recording `QUANTITIES` every `every`."""
    scene = tomllib.loads(quatrot.builtin_scenes()[scene_name])
    scene.pop("thermostat", None)
    scene["integrator"] = {"kind": integrator}
    scene["run"]["steps"] = steps
    scene["record"] = {"series": [{"name": "t", "every": every, "quantities": list(QUANTITIES)}]}
    return scene


def run_series(scene: dict) -> dict[str, np.ndarray]:
    """The `time` and `QUANTITIES` columns of `scene`'s run."""
    series = quatrot.run(scene)["series"]["t"]
    return {k: np.asarray(series[k], dtype=float) for k in ("time", *QUANTITIES)}


def measure(series: dict, left_out: float) -> dict:
    """<T_rot>, <T_trans>, the blocked mean and error of their difference and
    its z, the ratio and its error, and the temperature and energy over the
    kept part (means over its first and last tenth: does the run heat?)."""
    keep = int(left_out * len(series["T_rot"]))
    t_rot, t_trans = np.asarray(series["T_rot"])[keep:], np.asarray(series["T_trans"])[keep:]
    energy = np.asarray(series["total_energy"])[keep:]
    difference = quatrot.block_average(t_rot - t_trans)
    tenth = max(1, len(t_rot) // 10)
    mean_trans = float(np.mean(t_trans))
    return {
        "T_rot": float(np.mean(t_rot)),
        "T_trans": mean_trans,
        "difference": difference["mean"],
        "error": difference["error"],
        "converged": bool(difference["converged"]),
        "z": abs(difference["mean"]) / difference["error"],
        "ratio": float(np.mean(t_rot)) / mean_trans,
        "ratio_error": difference["error"] / mean_trans,
        "T_trans_first_tenth": float(np.mean(t_trans[:tenth])),
        "T_trans_last_tenth": float(np.mean(t_trans[-tenth:])),
        "energy_first_tenth": float(np.mean(energy[:tenth])),
        "energy_last_tenth": float(np.mean(energy[-tenth:])),
    }
