"""quatrot's Ewald sums (FFT lattice sum and direct sum) against an
independent numpy Ewald sum (validation/shared/ewald_reference.py: full Cartesian
derivative tensors, a direct sum over every wave vector, torques from
rotations of the energy; no code shared with quatrot) and against the closed
form of aligned cubic dipole lattices, -(2 pi / 3) n mu^2 per dipole with a
conducting surface (the Lorentz field). Energies and torques, dipoles and
quadrupoles, lattices with vacancies and irregular sites, both surfaces."""

from __future__ import annotations

import math

import numpy as np
import quatrot

from validation.shared.check import Check, Context
from validation.shared.ewald_reference import ewald
from validation.shared.openmm_multipoles import random_orientations, random_quadrupole, rotation

# Both sums converged far below round-off (quatrot at accuracy 1e-14, numpy
# at exp(-6.9^2)); sums of ~1e4 terms of mixed signs: relative round-off.
ENERGY_TOLERANCE = 1e-11
TORQUE_TOLERANCE = 1e-10  # relative to the largest torque
CLOSED_FORM_TOLERANCE = 1e-13  # the lattice sums' round-off (see tests/ewald.rs)
ACCURACY = 1e-14


def cubic(kind: str, cells, spacing: float):
    """Sites (lattice constant ``spacing``) and box of sc, bcc or fcc cells."""
    basis = {"sc": [[0, 0, 0]], "bcc": [[0, 0, 0], [0.5, 0.5, 0.5]], "fcc": [[0, 0, 0], [0, 0.5, 0.5], [0.5, 0, 0.5], [0.5, 0.5, 0]]}[kind]
    cells = np.broadcast_to(np.asarray(cells), (3,))
    corners = np.array([[x, y, z] for x in range(cells[0]) for y in range(cells[1]) for z in range(cells[2])], float)
    sites = (corners[:, None, :] + np.array(basis, float)[None]).reshape(-1, 3) * spacing
    return sites, cells * spacing


def _space(q, mu_body, theta_body):
    r = np.array([rotation(x) for x in q])
    mu = None if mu_body is None else np.einsum("nab,nb->na", r, mu_body)
    theta = None if theta_body is None else np.einsum("nab,nbc,ndc->nad", r, theta_body, r)
    return mu, theta


def systems(rng, quick: bool):
    """(name, sites, box, dipoles_body or None, quadrupoles_body or None)."""
    out = []
    sites, box = cubic("sc", (3, 4, 3), 1.0)
    keep = np.arange(len(sites)) != 5
    out.append(("sc 3x4x3 dipoles, one vacancy", sites[keep], box, rng.normal(size=(keep.sum(), 3)), None))
    sites, box = cubic("fcc", 2, 1.5)
    n = len(sites)
    out.append(("fcc 2^3 dipoles + quadrupoles", sites, box, rng.normal(size=(n, 3)), np.array([random_quadrupole(rng, 1.0) for _ in range(n)])))
    box = np.array([2.8, 3.1, 2.5])
    n = 10
    sites = rng.uniform(0, 1, (n, 3)) * box
    mu = rng.normal(size=(n, 3)) * (np.arange(n) % 3 != 1)[:, None]
    theta = np.array([random_quadrupole(rng, 1.0) * (k % 3 != 0) for k in range(n)])
    out.append(("10 irregular sites, mixed", sites, box, mu, theta))
    if not quick:
        sites, box = cubic("bcc", 2, 1.3)
        n = len(sites)
        out.append(("bcc 2^3 quadrupoles", sites, box, None, np.array([random_quadrupole(rng, 1.0) for _ in range(n)])))
        sites, box = cubic("sc", 5, 1.1)
        n = len(sites)
        out.append(("sc 5^3 dipoles", sites, box, rng.normal(size=(n, 3)), None))
    return out


def run(ctx: Context) -> list[Check]:
    rng = np.random.default_rng(ctx.seed + 14)
    refs = {"numpy Ewald (validation/shared/ewald_reference.py)": np.__version__, "quatrot": quatrot.__version__}
    checks = []
    # Closed forms: quatrot (both paths) and the numpy sum itself.
    worst = {"quatrot FFT": 0.0, "quatrot direct": 0.0, "numpy": 0.0}
    details = []
    mu_vector = np.array([0.3, -0.5, 0.8])
    lattices = [("sc", (3, 3, 3), 1.0), ("bcc", 2, 1.2), ("fcc", 2, 1.6)] + ([] if ctx.quick else [("sc", (6, 4, 3), 1.1), ("fcc", 3, 1.4)])
    for kind, cells, spacing in lattices:
        sites, box = cubic(kind, cells, spacing)
        n = len(sites)
        lorentz = -(2 * math.pi / 3) * n / np.prod(box) * mu_vector @ mu_vector
        q = np.tile([1.0, 0, 0, 0], (n, 1))
        mu = np.tile(mu_vector, (n, 1))
        for label, method in (("quatrot FFT", "auto"), ("quatrot direct", "direct")):
            e, _, _ = quatrot.multipole_evaluate(sites, q, dipoles_body=mu, box_lengths=box, sum="ewald", accuracy=ACCURACY, method=method)
            worst[label] = max(worst[label], abs(e / n - lorentz) / abs(lorentz))
        if n <= 32:
            worst["numpy"] = max(worst["numpy"], abs(ewald(sites, box, mu=mu).energy / n - lorentz) / abs(lorentz))
        details.append(f"{kind} {cells} cells, spacing {spacing}: -(2 pi/3) n mu^2 = {lorentz:.15g}")
    for label, value in worst.items():
        checks.append(
            Check(
                name=f"ewald closed form, aligned cubic dipole lattices, {label}",
                proves="the conducting-surface Ewald energy of fully aligned sc, bcc and fcc dipole lattices is the Lorentz value -(2 pi / 3) n mu^2 per dipole",
                tolerance=CLOSED_FORM_TOLERANCE,
                measured=value,
                references={"closed form (Lorentz field)": "-", **refs},
                details="; ".join(details),
            )
        )
    # Random systems against the numpy sum.
    for name, sites, box, mu_b, theta_b in systems(rng, ctx.quick):
        n = len(sites)
        q = random_orientations(rng, n)
        mu_s, theta_s = _space(q, mu_b, theta_b)
        for surface in ("conducting", "vacuum"):
            ref = ewald(sites, box, mu=mu_s, theta=theta_s, surface=surface)
            for method in ("auto", "direct"):
                e, _, t, info = quatrot.multipole_evaluate(
                    sites, q, dipoles_body=mu_b, quadrupoles_body=theta_b, box_lengths=box, sum="ewald", accuracy=ACCURACY, surface=surface, method=method, details=True
                )
                if method == "direct" and info["path"] == "ewald_direct" and name.startswith("10 irregular"):
                    continue  # auto is already the direct sum on irregular sites
                de = abs(e - ref.energy) / abs(ref.energy)
                dt = float(np.abs(t - ref.torques).max() / np.abs(ref.torques).max())
                detail = f"quatrot {e:.15g}, numpy {ref.energy:.15g}; path {info['path']}, alpha {info['alpha']:.4g}"
                checks.append(
                    Check(
                        name=f"ewald {name}, {surface}, {info['path']}: energy vs numpy",
                        proves="quatrot's Ewald energy (real, reciprocal, self and surface terms) equals an independent numpy Ewald sum",
                        tolerance=ENERGY_TOLERANCE,
                        measured=de,
                        references=refs,
                        details=detail,
                    )
                )
                checks.append(
                    Check(
                        name=f"ewald {name}, {surface}, {info['path']}: torques vs numpy",
                        proves="quatrot's Ewald torques (from its fields E and W) equal the numpy sum's rotation derivatives of the energy",
                        tolerance=TORQUE_TOLERANCE,
                        measured=dt,
                        references=refs,
                        details=detail,
                    )
                )
    return checks
