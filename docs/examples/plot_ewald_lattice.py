"""
An Ewald sum on a dipole lattice
================================

The energy of a periodic simple-cubic lattice of randomly oriented point
dipoles, by ``quatrot.multipole_evaluate``: the Ewald sum (conducting
surroundings, relative accuracy 1e-12) against the truncated sum at
growing cutoffs (every image inside the cutoff is summed, so the cutoff
may exceed half the box). The truncated sums wander about the Ewald value
without settling: the dipolar sum converges only conditionally.
"""

import argparse

import matplotlib.pyplot as plt
import numpy as np

import quatrot
from quatrot import quaternion

parser = argparse.ArgumentParser()
parser.add_argument("--quick", action="store_true", help="fewer cutoffs")
parser.add_argument("--out", default=None, help="unused (the figure is shown)")
args = parser.parse_args()

# %%
# A 4 x 4 x 4 lattice of unit spacing and random orientations (seeded);
# every rotor carries the same body dipole along z.
cells = 4
grid = np.arange(cells, dtype=float)
sites = np.array(np.meshgrid(grid, grid, grid, indexing="ij")).reshape(3, -1).T
rng = np.random.default_rng(7)
orientations = quaternion.exp(rng.normal(size=(len(sites), 3)))
dipoles = np.tile([0.0, 0.0, 1.0], (len(sites), 1))
box = [float(cells)] * 3

energy, gradient, torques, details = quatrot.multipole_evaluate(
    sites, orientations, dipoles_body=dipoles, box_lengths=box, sum="ewald", details=True
)
print(f"Ewald energy {energy:.10f} by path {details['path']}, alpha {details['alpha']:.3f}")

# %%
# The truncated sums.
cutoffs = np.linspace(1.5, 6.0, 6 if args.quick else 19)
truncated = [quatrot.multipole_evaluate(sites, orientations, dipoles_body=dipoles, box_lengths=box, cutoff=c)[0] for c in cutoffs]

fig, ax = plt.subplots(figsize=(6, 4))
ax.plot(cutoffs, truncated, "o-", label="truncated sum")
ax.axhline(energy, color="k", lw=1, label="Ewald sum (conducting)")
ax.set_xlabel("cutoff (lattice spacings)")
ax.set_ylabel("energy")
ax.set_title(f"{len(sites)} dipoles, simple cubic, periodic")
ax.legend()
fig.tight_layout()
