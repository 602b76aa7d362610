"""
Tutorial: orientational order and dynamics of a dipolar rotor lattice
=====================================================================

What a new user of quatrot does first, step by step:

1. build a lattice scene as a Python dict (the same structure as a TOML
   scene file, docs/scenes.md);
2. run it canonically (at a stated temperature, with a thermostat) with
   ``quatrot.run``;
3. compute the polar and nematic order parameters P1 and P2 from the run's
   trajectory with ``quatrot.order_parameters`` and plot them, next to the
   values the run recorded itself;
4. compute the dielectric constant from the run's total dipole with
   ``quatrot.run_dielectric_constant``;
5. compute the orientational correlation function C1(t) = <u(0).u(t)> with
   ``quatrot.orientational_correlations`` and compare it with the closed form
   of the free spherical top in thermal equilibrium,

       C1(t) = 1/3 + (2/3) (1 - s^2 t^2) exp(-s^2 t^2 / 2),   s^2 = T / I.

   The closed form holds for free rotors, so that comparison uses a
   weak-coupling run: the same lattice with dipoles 20 times smaller
   (pair energies mu^2 / a^3 = 0.0025 against T = 1), held at T by a Bussi
   thermostat, which rescales all angular velocities by one common factor
   close to 1 and so leaves each rotor's free motion alone.

Run it with::

    python docs/examples/tutorial_rotor_lattice.py            # full: about a minute
    python docs/examples/tutorial_rotor_lattice.py --quick    # a few seconds (make test)
    QUATROT_TUTORIAL_QUICK=1 python docs/examples/tutorial_rotor_lattice.py

It writes ``tutorial_rotor_lattice.png`` into ``--out`` (default: the
current directory) and stops with an AssertionError if a result disagrees
with its reference. ``make test`` runs it in quick mode; ``make validate``
runs it in full and puts its plot in the report (``validation/checks/
tutorial.py``).

Units are reduced: lengths in lattice spacings, k_B = 1, 4 pi eps0 = 1.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np

import quatrot

# The statistical test of C1: rotors are split into GROUPS groups, each
# group's C1(t) is an independent estimate, and at every lag the mean over
# groups is compared with the closed form in units of its standard error
# (a t statistic with GROUPS - 1 degrees of freedom). |t| above T_MAX at any
# lag fails: for t with 15 degrees of freedom P(|t| > 6) = 2.4e-5 per lag,
# about 1e-3 over the 40 lags compared.
GROUPS = 16
T_MAX = 6.0
# P1 and P2 from the trajectory and from the run's own series are the same
# double-precision computation on the same quaternions: round-off only.
SAME_NUMBERS = 1e-12


def lattice_scene(cells: int, dipole: float, temperature: float, thermostat: dict, steps: int, every: int, seed: int) -> dict:
    """A simple-cubic lattice of cells^3 dipolar spherical tops (spacing 1,
    moment of inertia 0.1, dipole along body z), periodic with the Ewald sum
    (conducting surroundings), started from random orientations and thermal
    angular velocities at ``temperature``, integrated by DLM with the given
    thermostat. The run records the total dipole M, the order parameters
    and the temperature every ``every`` steps, and keeps trajectory frames
    at the same steps."""
    return {
        "version": 1,
        "name": "tutorial_lattice",
        "rotors": {
            "kind": "lattice",
            "lattice": "simple_cubic",
            "cells": cells,
            "spacing": 1.0,
            "default": {"inertia": 0.1, "dipole": [0.0, 0.0, dipole]},
        },
        # A periodic boundary takes the Ewald sum with conducting ("tin
        # foil") surroundings by default: the dielectric constant then
        # follows from eps = 1 + 4 pi <|M|^2 - <M>^2> / (3 V T).
        "interactions": {"terms": ["dipole_dipole"], "boundary": {"kind": "periodic"}},
        "initial": {"kind": "random", "seed": seed, "temperature": temperature},
        "integrator": {"kind": "dlm"},
        "thermostat": {"temperature": temperature, "seed": seed + 1} | thermostat,
        "run": {"dt": 0.002, "steps": steps},
        "record": {
            "series": [{"name": "samples", "every": every, "quantities": ["M", "M2", "P1_dipole", "P2_dipole", "temperature"]}],
            "trajectory": {"every": every},
        },
    }


def order_from_trajectory(result: dict) -> dict:
    """P1 and P2 of the dipole axis (body z) in every trajectory frame."""
    q = result["trajectory"]["orientations"]  # (frames, rotors, 4), scalar first
    # direction: also P1 along the space z axis, and each rotor's cos(theta).
    return quatrot.order_parameters(q, axis=[0.0, 0.0, 1.0], direction=[0.0, 0.0, 1.0])


def c1_by_groups(result: dict, frame_dt: float, max_lag: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """C1(t) of the dipole axis: the mean over GROUPS groups of rotors and its
    standard error (the groups' estimates are independent)."""
    q = result["trajectory"]["orientations"]
    groups = np.array_split(np.arange(q.shape[1]), GROUPS)
    per_group = [quatrot.orientational_correlations(q[:, g], frame_dt, axes=[0.0, 0.0, 1.0], max_lag=max_lag) for g in groups]
    c1 = np.array([c["c1"] for c in per_group])
    return per_group[0]["time"], c1.mean(axis=0), c1.std(axis=0, ddof=1) / np.sqrt(GROUPS)


def free_top_c1(t: np.ndarray, temperature: float, inertia: float) -> np.ndarray:
    """The closed form for free spherical tops in thermal equilibrium."""
    s2 = temperature / inertia
    return 1 / 3 + 2 / 3 * (1 - s2 * t * t) * np.exp(-0.5 * s2 * t * t)


def main(quick: bool = False, out_dir: Path = Path(".")) -> dict:
    """Runs the tutorial; returns what it measured (the validation report
    reads it) after asserting every comparison."""
    temperature, inertia = 1.0, 0.1
    cells, steps, every = (6, 1000, 5) if quick else (10, 10000, 5)
    frame_dt = every * 0.002
    measured = {"cells": cells, "steps": steps, "temperature": temperature}

    # -- 1-2. The dipolar lattice (|mu| = 1) at T = 1, Langevin thermostat
    # (friction 1 per unit time: each angular velocity forgets itself over
    # t ~ 1, some 500 steps).
    scene = lattice_scene(cells, 1.0, temperature, {"kind": "langevin", "friction": 1.0}, steps, every, seed=7)
    lattice = quatrot.run(scene)
    series = lattice["series"]["samples"]  # columns as numpy arrays

    # -- 3. Order parameters from the trajectory, frame by frame.
    order = order_from_trajectory(lattice)
    # They are the quantities the run recorded (P1_dipole, P2_dipole), at
    # the same steps, computed by the same library functions.
    same = max(np.max(np.abs(order["p2"] - series["P2_dipole"])), np.max(np.abs(order["p1"] - series["P1_dipole"])))
    assert same < SAME_NUMBERS, f"order parameters differ from the recorded series by {same}"
    # For identical dipoles, P1 along z is M_z / (N |mu|).
    n = cells**3
    along_z = np.max(np.abs(order["p1_direction"] - series["M_z"] / n))
    assert along_z < SAME_NUMBERS, f"P1 along z differs from M_z / N by {along_z}"
    # At T = 1 this lattice is disordered: P2 is the O(N^-1/2) noise of a
    # finite sample, and P1 along z averages to zero.
    equilibrated = slice(len(order["p2"]) // 5, None)  # skip the first fifth
    p2 = quatrot.block_average(order["p2"][equilibrated])
    p1z = quatrot.block_average(order["p1_direction"][equilibrated])
    measured |= {"same_numbers": float(max(same, along_z)), "p2": p2, "p1_z": p1z}
    print(f"lattice of {n} dipoles, {steps} steps: <P2> = {p2['mean']:.4f} +- {p2['error']:.4f}, <P1_z> = {p1z['mean']:.4f} +- {p1z['error']:.4f}")

    # -- 4. The dielectric constant from the fluctuation of M (the summary
    # says the sum was Ewald with conducting surroundings, so the formula
    # eps = 1 + 4 pi F / (3 V T) applies; T is the run's mean temperature).
    eps = quatrot.run_dielectric_constant(lattice)
    measured["epsilon"] = eps
    print(f"dielectric constant: {eps['epsilon']:.2f} +- {eps['error']:.2f}")

    # -- 5. C1(t) against the free top: the weak-coupling lattice (|mu| =
    # 0.05) at the same temperature with a Bussi thermostat (tau = 1).
    weak = quatrot.run(lattice_scene(cells, 0.05, temperature, {"kind": "bussi", "tau": 1.0}, steps, every, seed=11))
    max_lag = int(round(1.2 / frame_dt))  # up to t = 1.2, where C1 has settled at 1/3
    t, c1, c1_error = c1_by_groups(weak, frame_dt, max_lag)
    exact = free_top_c1(t, temperature, inertia)
    worst = float(np.max(np.abs(c1[1:] - exact[1:]) / c1_error[1:]))
    # The test can fail: the same estimates against the closed form at
    # twice the temperature are far outside their errors.
    wrong = float(np.max(np.abs(c1[1:] - free_top_c1(t, 2 * temperature, inertia)[1:]) / c1_error[1:]))
    measured |= {"c1_worst_t": worst, "c1_wrong_t": wrong, "c1_lags": len(t) - 1}
    print(f"C1 of the weakly coupled lattice vs the free top: largest |t| {worst:.2f} over {len(t) - 1} lags (against 2T: {wrong:.1f})")
    assert worst < T_MAX, f"C1 is {worst:.1f} standard errors from the free-top closed form"
    assert wrong > T_MAX, f"C1 cannot tell T from 2T (|t| {wrong:.1f})"
    # The dipolar lattice itself is not free: its C1 for comparison.
    t_lattice, c1_lattice, c1_lattice_error = c1_by_groups(lattice, frame_dt, max_lag)

    # -- The figure: P1 and P2 against time, C1(t) of both runs.
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.8))
    time = series["time"]
    left.plot(time, order["p2"], lw=0.8, label="P2 (dipole axis)")
    left.plot(time, order["p1"], lw=0.8, label="P1 along the director")
    left.plot(time, order["p1_direction"], lw=0.8, label="P1 along z")
    left.axhline(0, color="k", lw=0.5)
    left.set_xlabel("time")
    left.set_title(f"{n} dipoles, Ewald, Langevin T = {temperature}", fontsize=9)
    left.legend(fontsize=7)
    right.errorbar(t, c1, yerr=c1_error, fmt="o", ms=2.5, label="weak coupling (|mu| = 0.05), Bussi")
    right.plot(t, exact, "k-", lw=1, label="free spherical top, closed form")
    right.errorbar(t_lattice, c1_lattice, yerr=c1_lattice_error, fmt="s", ms=2, label="dipolar lattice (|mu| = 1), Langevin")
    right.set_xlabel("time")
    right.set_ylabel("C1(t)")
    right.set_title(f"C1(t), T = {temperature}, I = {inertia}", fontsize=9)
    right.legend(fontsize=7)
    fig.tight_layout()
    out_dir.mkdir(parents=True, exist_ok=True)
    measured["plot"] = out_dir / "tutorial_rotor_lattice.png"
    fig.savefig(measured["plot"], dpi=110)
    print(f"plot: {measured['plot']}")
    return measured


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.strip().split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="a few-second version (also QUATROT_TUTORIAL_QUICK=1)")
    parser.add_argument("--out", type=Path, default=Path("."), help="folder for the plot (default: here)")
    args = parser.parse_args()
    main(quick=args.quick or os.environ.get("QUATROT_TUTORIAL_QUICK") == "1", out_dir=args.out)
