"""The systems of the note's correction experiment as the arrays and options
of ``quatrot.gear_corrections_table``: the single asymmetric rotor in a
uniform field and the periodic 4 x 4 x 4 lattice of dipolar and quadrupolar
rotors. Shared by the ``gear_corrections`` and ``accuracy_at_length`` checks
and by the long runs (`validation.longrun.systems`)."""

from __future__ import annotations

import numpy as np


def rotor_in_field(quick: bool):
    """One asymmetric top with a dipole in a uniform field (as the DOP853 fixture)."""
    q0 = np.array([[0.9, -0.2, 0.3, 0.1]])
    arrays = dict(
        sites=np.zeros((1, 3)),
        inertia=np.array([[1.0, 1.7, 2.6]]),
        orientations=q0 / np.linalg.norm(q0),
        omega_body=np.array([[0.5, 0.8, -0.4]]),
    )
    options = dict(dipoles=np.array([[0.3, -0.2, 1.0]]), field=np.array([0.4, 0.0, 1.5]))
    times = dict(dt=0.05, t_energy=50.0, t_error=5.0, t_stability=10.0) if quick else dict(dt=0.05, t_energy=200.0, t_error=10.0, t_stability=50.0)
    return arrays, options | times


def lattice(seed: int):
    """4 x 4 x 4 simple-cubic periodic lattice (spacing 1, cutoff 2), alternating
    spherical and asymmetric tops, each with a dipole and a quadrupole; random
    orientations and body angular velocities at temperature 0.5."""
    rng = np.random.default_rng(seed)
    grid = np.arange(4.0)
    sites = np.array([[x, y, z] for x in grid for y in grid for z in grid])
    n = len(sites)
    inertia = np.where(np.arange(n)[:, None] % 2 == 0, [1.0, 1.0, 1.0], [0.8, 1.0, 1.3])
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    w = rng.normal(size=(n, 3)) * np.sqrt(0.5 / inertia)
    arrays = dict(sites=sites, inertia=inertia, orientations=q, omega_body=w)
    quadrupole = np.diag([0.25, 0.25, -0.5])
    options = dict(
        dipoles=np.tile([0.0, 0.0, 1.0], (n, 1)),
        quadrupoles=np.tile(quadrupole, (n, 1, 1)),
        box_lengths=np.array([4.0, 4.0, 4.0]),
        cutoff=2.0,
        dt=0.01,
        t_energy=20.0,
        t_error=1.0,
        t_stability=5.0,
        sample_every=5,
    )
    return arrays, options
