"""Energies along trajectories against OpenMM: saved frames of the multipolar lattice scenes, run by scheme A and scheme B, re-evaluated with OpenMM's AmoebaMultipoleForce (Reference platform, double precision) and compared with the potential energy quatrot recorded at the same step; the kinetic energy 2I|Q'|^2 (eq 10, with ASE's quaternion product) against 1/2 w.Iw; and the total-energy drift of both schemes as OpenMM's potential sees it.

The lattices are run as open-boundary clusters (all pairs on both sides,
no sum over images), where both codes evaluate the same closed-form pair
energies in double precision and can agree to 1e-9. Periodic lattices are
compared elsewhere: quatrot's periodic boundary is an Ewald sum by default
(a truncated sum when the scene asks for `sum = "cutoff"`), and
AmoebaMultipoleForce's only periodic method, PME, misses its own error
tolerance for point multipoles by up to ~200x (ERRATA.md), so the
``ewald_openmm`` module compares them with OpenMM's error recorded per
tolerance, and ``ewald_numpy`` checks the Ewald sum itself. Passing proves
the energy the integrators conserve is the physical multipole energy at the
configurations they visit (tensors, the quadrupole factor, body-to-space
mapping of the multipoles); it does not test the torques
(``multipoles_openmm`` does) nor the periodic sums."""

from __future__ import annotations

import ase
import numpy as np
from ase.quaternions import Quaternion

import quatrot
from validation.shared.check import Check, Context
from validation.shared.openmm_multipoles import OpenMMCluster, versions
from validation.shared import scene_runs
from validation.shared.scene_runs import ENERGIES, body_multipoles, principal_moments, variant

# Both sides sum the same closed-form pair energies in double precision;
# relative to the largest |V| along the run (cancellations make V near zero
# possible, so not relative to each V).
ENERGY_TOLERANCE = 1e-9
# Kinetic energies from the same w_b by two formulas: round-off of sums of
# unit-scale squares.
KINETIC_TOLERANCE = 1e-12
# Total energy as OpenMM sees it, largest |E(t) - E(0)| relative to the mean
# kinetic energy: the usual MD criterion of 0.1 % (Gear schemes measure ~1e-6).
DRIFT_TOLERANCE = 1e-3
SCHEMES = ("gear_a", "gear_b")


def _scenes(quick: bool) -> dict[str, tuple[dict, int, int]]:
    """name -> (open-boundary scene, steps, sampling interval)."""
    if quick:
        return {
            "multipole_tops_bcc, 16 tops": (variant("multipole_tops_bcc", cells=2, every=50, quantities=ENERGIES), 100, 50),
            "dipole_lattice_sc, 8 open": (variant("dipole_lattice_sc", cells=2, open_boundary=True, every=50, quantities=ENERGIES), 100, 50),
        }
    return {
        "multipole_tops_bcc, 54 tops": (variant("multipole_tops_bcc", every=40, quantities=ENERGIES), 2000, 40),
        "dipole_lattice_sc, 64 open": (variant("dipole_lattice_sc", cells=4, open_boundary=True, every=40, quantities=ENERGIES), 2000, 40),
        "quadrupole_lattice_fcc, 32 open": (variant("quadrupole_lattice_fcc", cells=2, open_boundary=True, every=40, quantities=ENERGIES), 2000, 40),
    }


def _kinetic(q, omega_body, inertia):
    """(2 sum_k I_k vec(Q~*Q')_k^2 with Q' = 1/2 Q*(0, w_b) by ASE's product, 1/2 w.Iw):
    for a spherical top the first is 2I|Q'|^2."""
    two_i_q_dot, half_w_i_w = 0.0, 0.0
    for qk, wk in zip(q, omega_body):
        quat = Quaternion(qk / np.linalg.norm(qk))
        q_dot = Quaternion(0.5 * (quat * Quaternion(np.concatenate([[0.0], wk]))).q)
        if np.allclose(inertia, inertia[0]):
            two_i_q_dot += 2.0 * inertia[0] * float(q_dot.q @ q_dot.q)
        else:
            body = (quat.conjugate() * q_dot).q[1:]
            two_i_q_dot += 2.0 * float(inertia @ body**2)
        half_w_i_w += 0.5 * float(wk @ (inertia * wk))
    return two_i_q_dot, half_w_i_w


def _plot(drifts, out_dir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(len(drifts), 1, figsize=(8, 2.4 * len(drifts) + 0.5))
    for ax, (label, per_scheme) in zip(np.atleast_1d(axes), drifts.items()):
        for scheme, (t, rel) in per_scheme.items():
            ax.plot(t, rel, "o-", ms=2, lw=0.8, label=scheme)
        ax.set_title(label, fontsize=9)
        ax.set_ylabel("(E - E0) / <K>")
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 2))
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    np.atleast_1d(axes)[-1].set_xlabel("time")
    fig.suptitle("total energy = OpenMM potential + 1/2 w.Iw, along quatrot's trajectories", fontsize=10)
    fig.tight_layout()
    path = out_dir / "energies_openmm_drift.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def run_scene(scene, steps):
    """Per scheme: worst relative potential error, worst kinetic errors, OpenMM-seen drift series."""
    results = {}
    omm = None
    for scheme in SCHEMES:
        out = scene_runs.run(dict(scene, integrator={"kind": scheme}), steps=steps)
        sites, frames, samples = out["sites"], out["trajectory"], out["series"]["samples"]
        n = len(sites)
        mu, theta = body_multipoles(scene, n)
        inertia = principal_moments(scene)
        if omm is None:
            omm = OpenMMCluster(sites, list(mu), list(theta))
        step_of_sample = {int(s): k for k, s in enumerate(samples["step"])}
        v_omm, v_q, kin_q, kin_formula, kin_ref, times = [], [], [], [], [], []
        for f, step in enumerate(frames["step"]):
            k = step_of_sample[int(step)]
            energy, _ = omm.evaluate(frames["orientations"][f])
            two_i, half = _kinetic(frames["orientations"][f], frames["omega_body"][f], inertia)
            v_omm.append(energy)
            v_q.append(samples["potential_energy"][k])
            kin_q.append(samples["kinetic_energy"][k])
            kin_formula.append(two_i)
            kin_ref.append(half)
            times.append(frames["time"][f])
        v_omm, v_q, kin_ref = np.array(v_omm), np.array(v_q), np.array(kin_ref)
        total = v_omm + kin_ref
        results[scheme] = {
            "potential": float(np.abs(v_q - v_omm).max() / np.abs(v_omm).max()),
            "kinetic": float(max(np.abs(np.array(kin_formula) - kin_ref).max(), np.abs(np.array(kin_q) - kin_ref).max()) / kin_ref.max()),
            "drift": (np.array(times), (total - total[0]) / kin_ref.mean()),
            "frames": len(times),
            "n": n,
            "v_range": (float(v_omm.min()), float(v_omm.max())),
        }
    return results


def run(ctx: Context) -> list[Check]:
    refs = {"openmm": versions()["openmm"], "quatrot": quatrot.__version__}
    checks, drifts = [], {}
    for label, (scene, steps, every) in _scenes(ctx.quick).items():
        ctx.progress(f"{label}: schemes A and B, {steps} steps, OpenMM on every {every}th")
        results = run_scene(scene, steps)
        drifts[label] = {}
        inertia = principal_moments(scene)
        kinetic_formula = "2I|Q'|^2" if np.allclose(inertia, inertia[0]) else "2 sum_k I_k vec(Q~*Q')_k^2"
        for scheme, r in results.items():
            where = f"{r['frames']} frames (every {every} of {steps} steps, dt = {scene['run']['dt']:g}) of {r['n']} rotors"
            checks.append(
                Check(
                    f"{label}, {scheme}: potential energy vs OpenMM",
                    "The potential quatrot records along the run is AmoebaMultipoleForce's energy of the same configuration.",
                    ENERGY_TOLERANCE,
                    r["potential"],
                    refs,
                    f"{where}; max |V_quatrot - V_OpenMM| / max |V_OpenMM|; V_OpenMM in [{r['v_range'][0]:.4g}, {r['v_range'][1]:.4g}].",
                )
            )
            checks.append(
                Check(
                    f"{label}, {scheme}: kinetic energy {kinetic_formula} = 1/2 w.Iw",
                    "Eq 10 (Q' = 1/2 Q*(0, w_b), ASE's product) gives 2I|Q'|^2 (general: 2 sum I_k vec(Q~Q')_k^2) equal to 1/2 w.Iw, and quatrot's recorded kinetic energy is that value.",
                    KINETIC_TOLERANCE,
                    r["kinetic"],
                    {"ASE": ase.__version__, "quatrot": quatrot.__version__},
                    f"{where}; largest of both differences relative to max K.",
                )
            )
            t, rel = r["drift"]
            drifts[label][scheme] = (t, rel)
            slope = float(np.polyfit(t, rel, 1)[0])
            checks.append(
                Check(
                    f"{label}, {scheme}: total-energy drift with OpenMM's potential",
                    "The integrator conserves the physical energy (OpenMM's potential plus 1/2 w.Iw) to 0.1 % of the kinetic energy; the slope is informative only.",
                    DRIFT_TOLERANCE,
                    float(np.abs(rel).max()),
                    refs,
                    f"{where}; max |E - E0|/<K> = {np.abs(rel).max():.3g}, fitted drift {slope:.3g} per unit time.",
                )
            )
    if not ctx.quick:
        path = _plot(drifts, ctx.out_dir)
        next(c for c in checks if "drift" in c.name).plots.append(path)
    return checks
