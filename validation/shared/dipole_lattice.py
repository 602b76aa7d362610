"""The 1000-dipole simple-cubic lattice of the long-range comparisons with
LAMMPS (10^3, spacing 1, box 10, |mu| = 1, I = 0.1: the lattice of the
built-in scene dipole_lattice_sc, with random orientations and T = 1 angular
velocities from a seed) and quatrot's sum on it for LAMMPS's space dipoles.
Shared by the ``ewald_lammps`` check and the Ewald benchmark
(``python -m validation.bench.ewald``)."""

from __future__ import annotations

import numpy as np
import quatrot

from validation.shared.lammps_driver import DipoleSystem, quatrot_rotor

#: quatrot's requested accuracy for the converged reference sum.
CONVERGED = 1e-14
BOX = 10.0
#: LAMMPS's real-space cutoff (and the truncated sums' cutoff).
CUTOFF = 3.1
INERTIA = 0.1  # unit mass and diameter: 0.4 m (d/2)^2, the scene's inertia
DT = 0.002  # the scene's time step


def lattice(seed: int) -> DipoleSystem:
    """The lattice with the orientations and angular velocities drawn from `seed`."""
    rng = np.random.default_rng(seed)
    sites = np.array([[x, y, z] for x in range(10) for y in range(10) for z in range(10)], float)
    mu = rng.normal(size=(1000, 3))
    mu /= np.linalg.norm(mu, axis=1)[:, None]
    # Temperature 1: each omega component ~ N(0, sqrt(T / I)), the part along the dipole removed.
    omega = rng.normal(size=(1000, 3)) * np.sqrt(1.0 / INERTIA)
    omega -= np.sum(omega * mu, axis=1)[:, None] * mu
    return DipoleSystem(sites=sites, dipoles=mu, omega=omega, box=BOX, cutoff=CUTOFF)


def quatrot_sum(sites, dipoles, **boundary):
    """quatrot's energy and space torques for LAMMPS's space dipoles."""
    q = np.array([quatrot_rotor(m, np.zeros(3))[0] for m in dipoles])
    lengths = np.linalg.norm(dipoles, axis=1)
    body = np.column_stack([np.zeros_like(lengths), np.zeros_like(lengths), lengths])
    e, _, t = quatrot.multipole_evaluate(sites, q, dipoles_body=body, box_lengths=np.full(3, BOX), **boundary)
    return e, t
