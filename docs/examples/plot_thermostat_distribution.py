"""
A thermostatted run and its distribution
========================================

A dipole of moment 1 (inertia 0.1) in a uniform field E = 1 along z, held at
temperature T by the Langevin thermostat (DLM steps), samples the
canonical distribution of its orientation: ``cos theta`` of the dipole
with the field is distributed as ``exp(mu E cos theta / T)`` on [-1, 1].
The histogram of the run's trajectory is compared with it.
"""

import argparse

import matplotlib.pyplot as plt
import numpy as np

import quatrot
from quatrot import quaternion

parser = argparse.ArgumentParser()
parser.add_argument("--quick", action="store_true", help="a shorter run")
parser.add_argument("--out", default=None, help="unused (the figure is shown)")
args = parser.parse_args()

TEMPERATURE = 0.5
STEPS = 100_000 if args.quick else 1_000_000

# %%
# The scene as a dict: the same structure as a TOML scene file.
scene = {
    "version": 1,
    "name": "dipole_in_field_langevin",
    "rotors": {"kind": "sites", "sites": [{"position": [0.0, 0.0, 0.0]}], "default": {"inertia": 0.1, "dipole": [0.0, 0.0, 1.0]}},
    "fields": {"uniform": [0.0, 0.0, 1.0]},
    "initial": {"kind": "uniform", "orientation": [1.0, 0.0, 0.0, 0.0], "omega_body": [0.0, 0.0, 0.0]},
    "integrator": {"kind": "dlm"},
    "thermostat": {"kind": "langevin", "temperature": TEMPERATURE, "friction": 1.0, "seed": 3},
    "run": {"dt": 0.01, "steps": STEPS},
    "record": {"trajectory": {"every": 20}},
}
result = quatrot.run(scene)

# %%
# The dipole's space-frame direction in every frame, after the first tenth.
q = result["trajectory"]["orientations"][:, 0]
kept = q[len(q) // 10 :]
cos_theta = quaternion.body_to_space(kept, np.tile([0.0, 0.0, 1.0], (len(kept), 1)))[:, 2]

x = np.linspace(-1, 1, 201)
exact = np.exp(x / TEMPERATURE)
exact /= np.trapezoid(exact, x)
mean_exact = np.trapezoid(x * exact, x)
print(f"<cos theta>: run {cos_theta.mean():.3f}, exact {mean_exact:.3f} ({len(kept)} frames)")

fig, ax = plt.subplots(figsize=(6, 4))
ax.hist(cos_theta, bins=40, range=(-1, 1), density=True, alpha=0.6, label="Langevin run (DLM)")
ax.plot(x, exact, "k-", label="exp(mu E cos / T), normalised")
ax.set_xlabel("cos theta (dipole . field)")
ax.set_ylabel("probability density")
ax.set_title(f"T = {TEMPERATURE}, {STEPS} steps")
ax.legend()
fig.tight_layout()
