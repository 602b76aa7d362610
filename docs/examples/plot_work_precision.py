"""
Work and precision of the five integrators
==========================================

Every integrator runs the built-in ``dipole_in_field`` scene (one dipolar
spherical top librating in a uniform field) at a few time steps to the same
time; the largest energy error of each run is plotted against its time
step, with lines of slope 2 and 5 for the second-order baselines and
Allen's fifth-order Gear schemes. ``make bench`` measures the same at
equal cost per unit time (the benchmarks page).
"""

import argparse

import matplotlib.pyplot as plt
import numpy as np

import quatrot

parser = argparse.ArgumentParser()
parser.add_argument("--quick", action="store_true", help="fewer time steps")
parser.add_argument("--out", default=None, help="unused (the figure is shown)")
args = parser.parse_args()

INTEGRATORS = ["gear_a", "gear_b", "no_squish", "dlm", "richardson"]
DTS = [0.04, 0.02, 0.01] if args.quick else [0.04, 0.02, 0.01, 0.005, 0.0025]
T_END = 4.0

# %%
# Each run overrides the scene's integrator, time step and length; the
# recorded ``energy_error`` column is the total energy's relative error.
errors = {name: [] for name in INTEGRATORS}
for name in INTEGRATORS:
    for dt in DTS:
        result = quatrot.run("dipole_in_field", integrator=name, dt=dt, steps=int(round(T_END / dt)))
        errors[name].append(np.max(np.abs(result["series"]["energies"]["energy_error"])))
    print(f"{name:>10}: " + ", ".join(f"{e:.1e}" for e in errors[name]))

# %%
fig, ax = plt.subplots(figsize=(6, 4))
for name in INTEGRATORS:
    ax.loglog(DTS, errors[name], "o-", label=name)
dts = np.array(DTS)
ax.loglog(dts, 1e-1 * (dts / dts[0]) ** 2, "k:", lw=0.8, label="slope 2")
ax.loglog(dts, 1e-5 * (dts / dts[0]) ** 5, "k--", lw=0.8, label="slope 5")
ax.set_xlabel("time step")
ax.set_ylabel("largest relative energy error")
ax.set_title(f"dipole_in_field to t = {T_END}")
ax.legend(fontsize=8)
fig.tight_layout()
