"""The Lennard-Jones fluid of moving bodies against the published equation
of state of Johnson, Zollweg and Gubbins, Mol. Phys. 78, 591 (1993)
(``validation.shared.lj_eos``): bodies with one LJ site (epsilon = sigma =
1, no dipole; their free rotation carries no energy into translation) at
T* = 2.0, rho* = 0.5 and 0.8 and at T* = 1.35, rho* = 0.8; LJ cut at 3.0
with the plain truncation and its analytic tail corrections to the energy
and the pressure (Allen and Tildesley eqs 2.144-2.145, which assume g = 1
beyond the cutoff); NO_SQUISH at constant energy.

Each run starts on an fcc lattice at the temperature the energy balance
asks for (the lattice's potential energy per body from a one-step run, the
liquid's from the equation of state: T_init = T + 2/3 (U_eos(T) -
U_lattice)), melts, and is averaged after a fifth of its steps; the
equation is evaluated at the run's mean T_trans. Measured: the largest
|run - equation| / allowed over the energy per body and the pressure,
where allowed = 4 sigma_run (Flyvbjerg-Petersen blocking of the series,
``quatrot.block_average``; the T error carried through the equation's
slope) plus the equation's own accuracy, which this check takes as 0.03
in U/N and 0.05 in P: our budget for the fit's deviations from its
simulation data in the dense liquid and for the cutoff's structural
effect (g(r) not exactly 1 at r = 3), not a number quoted from the paper.

Passing proves that bodies' LJ energies, tail corrections, virial pressure
and NVE dynamics sample the LJ fluid's thermodynamics as published; it does
not test dipoles or molecules. Production: 500 bodies, 20,000 steps of dt
= 0.004 per state (time 80); quick: 256 bodies, 3,000 steps at T* = 2.0,
rho* = 0.8 only, with the statistical allowance of the short run."""

from __future__ import annotations

import numpy as np

import quatrot
from validation.shared import lj_eos
from validation.shared.check import Check, Context

STATES = ((2.0, 0.5), (2.0, 0.8), (1.35, 0.8))
CUTOFF = 3.0
DT = 0.004
SAMPLE_EVERY = 10
EQUILIBRATION = 0.2  # the fraction of the run left out
Z = 4.0  # sigma_run multiples allowed (two-sided normal 6e-5)
EOS_ACCURACY = {"energy": 0.03, "pressure": 0.05}


def scene(density: float, temperature: float, cells: int, steps: int) -> dict:
    """cells^3 fcc cells of LJ bodies at density, started at temperature."""
    return {
        "version": 1,
        "name": f"lj_{density}",
        "body_types": [{
            "mass": 1.0,
            "inertia": [[0.025, 0.0, 0.0], [0.0, 0.025, 0.0], [0.0, 0.0, 0.025]],
            "sites": [{"position": [0.0, 0.0, 0.0], "lennard_jones": {"epsilon": 1.0, "sigma": 1.0}}],
        }],
        "bodies": {"kind": "lattice", "lattice": "fcc", "counts": [4 * cells**3], "density": density},
        "body_interactions": {"lennard_jones": {"cutoff": CUTOFF, "truncation": "plain"}, "skin": 0.3},
        "initial": {"kind": "random", "seed": 39, "temperature": temperature},
        "integrator": {"kind": "no_squish"},
        "run": {"dt": DT, "steps": steps},
        "record": {"series": [{"name": "s", "every": SAMPLE_EVERY, "quantities": ["potential_energy", "pressure", "T_trans"]}]},
    }


def starting_temperature(temperature: float, density: float, cells: int) -> float:
    """The lattice temperature whose melt lands near `temperature`."""
    lattice = quatrot.run(scene(density, temperature, cells, 1))["series"]["s"]
    u_lattice = lattice["potential_energy"][0] / (4 * cells**3)
    return temperature + 2.0 / 3.0 * (lj_eos.internal_energy(temperature, density) - u_lattice)


def state_point(temperature: float, density: float, cells: int, steps: int) -> dict:
    """The run's means and errors, and the equation at its mean T."""
    n = 4 * cells**3
    start = starting_temperature(temperature, density, cells)
    series = quatrot.run(scene(density, start, cells, steps))["series"]["s"]
    keep = slice(int(EQUILIBRATION * len(series["T_trans"])), None)
    t = quatrot.block_average(series["T_trans"][keep])
    measured = {
        "energy": quatrot.block_average(series["potential_energy"][keep] / n),
        "pressure": quatrot.block_average(series["pressure"][keep]),
    }
    h = 1e-4
    out = {"T": t["mean"], "T_error": t["error"], "start": start}
    for name, f in (("energy", lj_eos.internal_energy), ("pressure", lj_eos.pressure)):
        slope = (f(t["mean"] + h, density) - f(t["mean"] - h, density)) / (2 * h)
        sigma = float(np.hypot(measured[name]["error"], slope * t["error"]))
        allowed = Z * sigma + EOS_ACCURACY[name]
        out[name] = {
            "run": measured[name]["mean"],
            "eos": f(t["mean"], density),
            "sigma": sigma,
            "allowed": allowed,
        }
    return out


def run(ctx: Context) -> list[Check]:
    states = ((2.0, 0.8),) if ctx.quick else STATES
    cells, steps = (4, 3000) if ctx.quick else (5, 20000)
    checks = []
    for temperature, density in states:
        ctx.progress(f"LJ fluid T* = {temperature}, rho* = {density}: {steps} steps")
        point = state_point(temperature, density, cells, steps)
        ratios = {name: abs(point[name]["run"] - point[name]["eos"]) / point[name]["allowed"] for name in EOS_ACCURACY}
        details = "; ".join(
            f"{name}: run {point[name]['run']:.4f} +- {point[name]['sigma']:.4f}, JZG {point[name]['eos']:.4f}"
            f" (allowed {point[name]['allowed']:.4f})"
            for name in EOS_ACCURACY
        )
        checks.append(
            Check(
                name=f"LJ fluid T*={temperature} rho*={density}: U/N and P vs Johnson-Zollweg-Gubbins",
                proves=(
                    "bodies with one LJ site (cutoff 3, plain truncation with tail corrections, NVE NO_SQUISH) reproduce "
                    "the potential energy per particle and the pressure of the published LJ equation of state "
                    "(Mol. Phys. 78, 591 (1993)) within the run's statistical error plus the equation's accuracy; "
                    "measured: the larger |run - JZG| / allowed"
                ),
                tolerance=1.0,
                measured=float(max(ratios.values())),
                references={"Johnson, Zollweg, Gubbins 1993": "Mol. Phys. 78, 591", "quatrot": quatrot.__version__},
                details=(
                    f"{4 * cells**3} bodies, {steps} steps of dt = {DT} (averaged after {EQUILIBRATION:.0%}), "
                    f"started at T = {point['start']:.3f}, mean T_trans {point['T']:.4f} +- {point['T_error']:.4f}; {details}"
                ),
            )
        )
    return checks
