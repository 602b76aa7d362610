"""Rigid water at 298 K and 0.997 g/cm^3 against published values (issue 41,
item 4): the published values, the expected potential energy and pressure
at the built-ins' density, and the NVT runs that measure them (shared by
the check ``water_published`` and ``python -m validation.bench.water_nvt``).

Published values
----------------
C. Vega and J. L. F. Abascal, "Simulating water with rigid
non-polarizable models: a general perspective", Phys. Chem. Chem. Phys.
13, 19663 (2011), the table of properties the review scores its models on
(its own simulations, one protocol for every model: NpT molecular dynamics
at 1 bar, Ewald sums for the charges, Lennard-Jones cut at 8.5 to 9.5 A
with the analytic tail corrections to energy and pressure): at 298 K the
density ``rho0`` (g/cm^3), the isothermal compressibility ``kappa``
(1e-6/bar), the thermal expansion coefficient ``alpha`` (1e-4/K) and the
enthalpy of vaporisation ``dh_vap`` (kcal/mol) *without* the polarisation
correction of Berendsen et al. 1987 (the review discusses it apart). The
models' papers give the same picture under their own protocols: SPC/E
(Berendsen, Grigera & Straatsma, J. Phys. Chem. 91, 6269 (1987): twin-range
cutoff, no Ewald; it was fitted so that the potential energy *plus* the
polarisation correction 5.22 kJ/mol equals water's -41.5 kJ/mol);
TIP3P (Jorgensen et al., J. Chem. Phys. 79, 926 (1983), Table III: Monte
Carlo with a spherical cutoff, -9.86 kcal/mol at 0.982 g/cm^3);
TIP4P/2005 (Abascal & Vega, J. Chem. Phys. 123, 234505 (2005): Ewald,
0.9979 g/cm^3 at 298 K and 1 bar). Only the review's numbers are compared,
being one protocol that matches quatrot's (PME, LJ tail) for all three.

The tables give the values to their last digit without error bars: their
errors are taken as one unit of the last digit (density 0.001 g/cm^3,
enthalpy 0.01 kcal/mol) and 5 % of the compressibility (the typical
error of a fluctuation estimate of 2 to 10 ns), stated with each verdict.

Expected values at 0.997 g/cm^3
-------------------------------
*Potential energy per molecule.* For a rigid model the gas has no
intermolecular energy and the kinetic energies of liquid and gas cancel
at one temperature, so with an ideal vapour and ``p V_liquid`` negligible
(1.8 J/mol at 1 bar) ``U(rho0) = R T - dh_vap``. From ``rho0`` to ``rho``
at constant T, ``(dU/dV)_T = T (dp/dT)_V - p = T alpha / kappa - p``,
so ``U(rho) = U(rho0) + (T alpha / kappa) (v(rho) - v(rho0))`` per
molecule (``v = M / (N_A rho)``; p = 1 bar is negligible beside
``T alpha / kappa``, thousands of bar); half of this correction is added
to the error (alpha and kappa vary along the path).

*Pressure.* ``kappa = (d ln rho / dp)_T`` integrated from 1 bar at
``rho0`` to ``rho`` at constant kappa: ``p = 1 bar + ln(rho / rho0) /
kappa``. Its error: ``sigma_rho0 / (rho0 kappa)`` and ``ln(rho / rho0)
sigma_kappa / kappa^2`` in quadrature. The change of kappa over the path
is second order: ``(1/2) (d kappa/dp) dp^2``, with ``d ln kappa / dp`` about
-3e-4 /bar for water, under 5 % of ``p`` for ``|p| < 300 bar``, covered by
the error of kappa. quatrot reports atm (1 atm = 1.01325 bar exactly).

Measurement
-----------
Each model runs the built-in ``spce_water_512`` with its body type
replaced (512 molecules, 0.997 g/cm^3, LJ 10 A + tail, PME 1e-5, NO_SQUISH
at 2 fs) from its simple-cubic start, one thread; the first
``equilibration`` steps are discarded and the rest block averaged
(``quatrot.block_average``: the plateau of the block error). The
potential energy is the configurational one; the pressure is the
molecular one (the centres' kinetic term and the molecular virial,
checked against ``-dU/dV`` by finite differences in the quick mode of
validation/checks/water_published.py)."""

from __future__ import annotations

import math
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import quatrot

TEMPERATURE = 298.0
DENSITY = 0.997  # g/cm^3: the built-ins' 0.0333275 molecules per A^3
MOLAR_MASS = 15.9994 + 2 * 1.008  # g/mol (src/scene/water.rs)
AVOGADRO = 6.02214076e23
GAS_CONSTANT = 8.314462618 / 4184  # kcal/(mol K), exact since SI 2019
ATM_IN_BAR = 1.01325
# J/m^3 (Pa) times (cm^3/mol) in kcal/mol: 1 bar cm^3 = 0.1 J.
BAR_CM3_IN_KCAL = 0.1 / 4184
MOLECULES = 512
SCENE = "spce_water_512"
THERMOSTATS = ("langevin", "bussi", "nose_hoover")


@dataclass(frozen=True)
class Published:
    """A model's values at 298 K and 1 bar (module doc) and their errors."""

    rho0: float  # g/cm^3
    kappa: float  # 1e-6 / bar
    alpha: float  # 1e-4 / K
    dh_vap: float  # kcal/mol, no polarisation correction
    sigma_rho0: float = 0.001
    sigma_dh_vap: float = 0.01
    sigma_kappa_fraction: float = 0.05


# Vega & Abascal 2011's table of properties (module doc).
PUBLISHED = {
    "spce": Published(rho0=0.994, kappa=46.1, alpha=5.14, dh_vap=11.79),
    "tip3p": Published(rho0=0.980, kappa=57.4, alpha=9.2, dh_vap=10.05),
    "tip4p_2005": Published(rho0=0.997, kappa=46.0, alpha=2.8, dh_vap=11.99),
}
SOURCE = "Vega & Abascal, PCCP 13, 19663 (2011), table of properties at 298 K, 1 bar (Ewald, LJ tail)"


def molar_volume(rho: float) -> float:
    """cm^3/mol."""
    return MOLAR_MASS / rho


def expected_energy(p: Published, rho: float = DENSITY) -> tuple[float, float]:
    """Potential energy per molecule at `rho` (kcal/mol) and its error."""
    at_rho0 = GAS_CONSTANT * TEMPERATURE - p.dh_vap
    stiffness = TEMPERATURE * p.alpha * 1e-4 / (p.kappa * 1e-6)  # bar
    correction = stiffness * (molar_volume(rho) - molar_volume(p.rho0)) * BAR_CM3_IN_KCAL
    return at_rho0 + correction, math.hypot(p.sigma_dh_vap, correction / 2)


def expected_pressure(p: Published, rho: float = DENSITY) -> tuple[float, float]:
    """Pressure at `rho` and 298 K (atm) and its error."""
    kappa = p.kappa * 1e-6
    strain = math.log(rho / p.rho0)
    bar = 1.0 + strain / kappa
    error = math.hypot(p.sigma_rho0 / (p.rho0 * kappa), strain * p.sigma_kappa_fraction / kappa)
    return bar / ATM_IN_BAR, error / ATM_IN_BAR


def thermostat_table(kind: str) -> dict:
    """Each with a 100 fs time constant: Langevin friction 0.01/fs (the
    built-in's 0.05/fs damps the liquid's relaxation from the lattice:
    its pressure still climbs after 10 ps, where these settle within 2 ps),
    Bussi and Nose-Hoover (chain 3) each on translation and rotation apart."""
    if kind == "langevin":
        return {"kind": "langevin", "temperature": TEMPERATURE, "friction": 0.01, "seed": 2}
    if kind == "bussi":
        return {"kind": "bussi", "temperature": TEMPERATURE, "tau": 100.0, "seed": 2}
    return {"kind": "nose_hoover", "temperature": TEMPERATURE, "tau": 100.0, "chain": 3}


def nvt_run(model: str, thermostat: str, steps: int, out_dir: Path, every: int = 5) -> dict:
    """The built-in with `model` and `thermostat` for `steps` steps of 2
    fs from its lattice, one thread: its series (potential energy per
    molecule, pressure in atm, temperatures) and its process CPU time."""
    scene = tomllib.loads(quatrot.builtin_scenes()[SCENE])
    scene["body_types"] = [{"model": model}]
    scene["thermostat"] = thermostat_table(thermostat)
    scene["run"].update(steps=steps, threads=1)
    scene["record"] = {"series": [{"name": "series", "every": every,
                                   "quantities": ["potential_energy", "pressure", "T_trans", "T_rot"]}]}
    started = time.process_time()
    series = quatrot.run(scene, out_dir=out_dir)["series"]["series"]
    return {"time_ps": np.asarray(series["time"]) / 1000,
            "energy": np.asarray(series["potential_energy"]) / MOLECULES,
            "pressure": np.asarray(series["pressure"]), "T_trans": np.asarray(series["T_trans"]),
            "T_rot": np.asarray(series["T_rot"]), "cpu_seconds": time.process_time() - started}


def averages(found: dict, equilibration_ps: float) -> dict:
    """Block averages of the energy and pressure after `equilibration_ps`."""
    keep = found["time_ps"] > equilibration_ps
    out = {"averaged_ps": float(found["time_ps"][keep][-1] - found["time_ps"][keep][0])}
    for column in ("energy", "pressure", "T_trans", "T_rot"):
        block = quatrot.block_average(found[column][keep])
        out[column] = (float(block["mean"]), float(block["error"]))
    return out


def z_scores(model: str, measured: dict) -> dict:
    """|measured - expected| / combined error, for energy and pressure."""
    p = PUBLISHED[model]
    out = {}
    for column, (expected, error) in (("energy", expected_energy(p)), ("pressure", expected_pressure(p))):
        mean, statistical = measured[column]
        out[column] = {"expected": expected, "published_error": error, "measured": mean,
                       "statistical_error": statistical,
                       "z": abs(mean - expected) / math.hypot(error, statistical)}
    return out
