"""The rigid o-terphenyl liquid against published energies and pressures of
the same model (issue 39's "published equation of state of a rigid
molecular liquid"): the built-in ``lewis_wahnstrom_otp`` (the
Lewis-Wahnstrom three-site model, force-shifted LJ at 2.612 sigma, rho* =
0.32655) held at T* by a Bussi thermostat, against the canonical Monte
Carlo of M. P. Allen and D. J. Tildesley's example ``mc_nvt_poly_lj`` on the
same model and density (GUIDE.md of github.com/Allen-Tildesley/examples,
section "Polyatomic Lennard-Jones program": E = PE/N + 3T per molecule and
P at T* = 1.0 and 2.0, with their error bars).

Each run starts from the built-in's fcc lattice at T*, NO_SQUISH with dt
= 0.002, the thermostat at T* (tau 0.1); the first fifth is left out.
Measured: the larger of |E_run - E_AT| and |P_run - P_AT| over their
combined standard error sqrt(sigma_run^2 + sigma_AT^2) (the run's from
Flyvbjerg-Petersen blocking, ``quatrot.block_average``), against 4
(two-sided normal 6e-5). E_run = <PE>/N + 3 T* (the canonical kinetic
energy of six degrees of freedom, as Allen and Tildesley define E); the
pressure is quatrot's molecular virial pressure (their Monte Carlo's
molecular pressure has the same mean). Passing says quatrot's
multi-site Lennard-Jones bodies, their force-shifted truncation, the
molecular virial and the thermostatted dynamics reproduce the model's
published thermodynamics; the supercooled state of the built-in (T* =
0.5) relaxes too slowly to be checked at this length. Production: 20,000
steps at each temperature; quick: 2,000 steps at T* = 2.0. Found while
writing it: T* = 1.0, E -9.813(11) against -9.817(9), P 5.861(28) against
5.86(2); T* = 2.0, E -4.048(16) against -4.07(1), P 12.437(43) against
12.37(4): 1.2 combined sigmas at most."""

from __future__ import annotations

import tomllib

import numpy as np

import quatrot
from validation.shared.check import Check, Context

SOURCE = "Allen & Tildesley examples, GUIDE.md, mc_nvt_poly_lj"
# T*: (E, its error, P, its error), Allen and Tildesley's Monte Carlo at rho* = 0.32655.
REFERENCE = {1.0: (-9.817, 0.009, 5.86, 0.02), 2.0: (-4.07, 0.01, 12.37, 0.04)}
LEFT_OUT = 0.2
EVERY = 10
TAU = 0.1
Z = 4.0  # combined standard errors allowed (two-sided normal 6e-5)


def measure(temperature: float, steps: int) -> dict:
    """<PE>/N + 3 T and <P> of the thermostatted built-in, with their blocked errors."""
    scene = tomllib.loads(quatrot.builtin_scenes()["lewis_wahnstrom_otp"])
    scene["initial"]["temperature"] = temperature
    scene["thermostat"] = {"kind": "bussi", "temperature": temperature, "tau": TAU, "seed": 39}
    scene["run"]["steps"] = steps
    scene["record"] = {"series": [{"name": "s", "every": EVERY, "quantities": ["potential_energy", "pressure"]}]}
    series = quatrot.run(scene)["series"]["s"]
    keep = slice(int(LEFT_OUT * len(series["pressure"])), None)
    n = sum(scene["bodies"]["counts"])
    energy = quatrot.block_average(np.asarray(series["potential_energy"][keep]) / n + 3 * temperature)
    pressure = quatrot.block_average(np.asarray(series["pressure"][keep]))
    return {"energy": energy, "pressure": pressure}


def run(ctx: Context) -> list[Check]:
    states, steps = ((2.0,), 2000) if ctx.quick else (tuple(REFERENCE), 20_000)
    checks = []
    for temperature in states:
        ctx.progress(f"o-terphenyl at T* = {temperature}: {steps} steps")
        found = measure(temperature, steps)
        e_ref, e_err, p_ref, p_err = REFERENCE[temperature]
        z = {
            "energy": abs(found["energy"]["mean"] - e_ref) / np.hypot(found["energy"]["error"], e_err),
            "pressure": abs(found["pressure"]["mean"] - p_ref) / np.hypot(found["pressure"]["error"], p_err),
        }
        checks.append(
            Check(
                name=f"o-terphenyl T*={temperature} rho*=0.32655: E and P vs Allen-Tildesley Monte Carlo",
                proves=(
                    "the thermostatted Lewis-Wahnstrom liquid (three force-shifted LJ sites per rigid body, NO_SQUISH) "
                    "has the energy per molecule and the pressure that Allen and Tildesley's canonical Monte Carlo of "
                    "the same model publishes, within the combined statistical errors; measured: the larger "
                    "|run - reference| / combined sigma"
                ),
                tolerance=Z,
                measured=float(max(z.values())),
                references={SOURCE: f"T*={temperature}: E {e_ref}({e_err}), P {p_ref}({p_err})", "quatrot": quatrot.__version__},
                details=(
                    f"256 molecules, {steps} steps of dt = 0.002, Bussi tau {TAU}, averaged after {LEFT_OUT:.0%}: "
                    f"E {found['energy']['mean']:.4f} +- {found['energy']['error']:.4f} (reference {e_ref} +- {e_err}), "
                    f"P {found['pressure']['mean']:.3f} +- {found['pressure']['error']:.3f} (reference {p_ref} +- {p_err})"
                ),
            )
        )
    return checks
