"""quatrot's point-multipole energies and torques against OpenMM's
AmoebaMultipoleForce, live, on fresh seeded clusters (dipole-only,
quadrupole-only, mixed). Construction and units: validation/shared/openmm_multipoles.py."""

from __future__ import annotations

import numpy as np
import quatrot

from validation.shared.check import Check, Context
from validation.shared.openmm_multipoles import OpenMMCluster, random_cluster, random_orientations, versions

ENERGY_TOLERANCE = 1e-9  # same closed forms in double precision on both sides
TORQUE_TOLERANCE = 1e-7  # OpenMM maps torques to frame-atom forces and back; relative to the largest torque


def _stack(items, shape):
    return np.array([np.zeros(shape) if x is None else x for x in items], float)


def run(ctx: Context) -> list[Check]:
    rng = np.random.default_rng(ctx.seed + 3)
    sizes, configurations = ((8,), 2) if ctx.quick else ((8, 27, 64), 10)
    refs = {"openmm": versions()["openmm"], "quatrot": quatrot.__version__}
    checks = []
    for kind in ("dipole", "quadrupole", "mixed"):
        energy_err = torque_err = 0.0
        for n in sizes:
            sites, dipoles, quadrupoles = random_cluster(rng, n, kind)
            omm = OpenMMCluster(sites, dipoles, quadrupoles)
            mu, theta = _stack(dipoles, 3), _stack(quadrupoles, (3, 3))
            for _ in range(configurations):
                q = random_orientations(rng, n)
                e_ref, t_ref = omm.evaluate(q)
                e, _, t = quatrot.multipole_evaluate(sites, q, dipoles_body=mu, quadrupoles_body=theta)
                energy_err = max(energy_err, abs(e - e_ref) / abs(e_ref))
                torque_err = max(torque_err, np.abs(t - t_ref).max() / np.abs(t_ref).max())
        detail = f"{kind} clusters of {sizes} rotors, {configurations} random orientation sets each"
        checks.append(
            Check(
                name=f"multipoles {kind} energy vs OpenMM",
                proves="the interaction tensors and the quadrupole factor 3 agree with AmoebaMultipoleForce (not the eq 14 gradient)",
                tolerance=ENERGY_TOLERANCE,
                measured=energy_err,
                references=refs,
                details=detail,
            )
        )
        checks.append(
            Check(
                name=f"multipoles {kind} torques vs OpenMM",
                proves="space-frame torques agree with OpenMM's forces on frame atoms, summed as (r_a - r_site) x F_a",
                tolerance=TORQUE_TOLERANCE,
                measured=torque_err,
                references=refs,
                details=detail,
            )
        )
    return checks
