"""LAMMPS's long-range dipole sums (pair lj/cut/dipole/long with epsilon 0,
kspace_style ewald/dipole and pppm/dipole, tin-foil boundary, units lj so
qqrd2e = 1 = 1 / (4 pi eps0) as in quatrot) against quatrot's converged Ewald
sum (accuracy 1e-14; itself checked against the numpy sum and the closed
forms in the ewald_numpy module) on the 1000-dipole simple-cubic lattice of
scenes/dipole_lattice_sc.toml (10^3, spacing 1, |mu| = 1, real-space cutoff
3.1 for LAMMPS): energies, torques and a short NVE trajectory, with each
code's error at each requested accuracy.

LAMMPS's `accuracy` is a relative RMS force error, relative to the force
between two unit charges at unit distance (1 in lj units), so an absolute
RMS error in lj units; its torque error on these pinned dipoles is measured
the same way (RMS over the atoms of |tau_LAMMPS - tau_converged|). The
trajectory: LAMMPS's fix nve/sphere update dipole/dlm driven by its own
long-range sum, against a numpy restatement of the same step (its agreement
with LAMMPS is checked in the lammps_dipoles module) driven by quatrot's
converged torques, so that the difference shows the effect of LAMMPS's
long-range error on the motion."""

from __future__ import annotations

import numpy as np
import quatrot

from validation.checks.base import Check, Context
from validation import dlm_restatement as restated
from validation.lammps_dipoles import DipoleSystem, lammps_version, quatrot_rotor, run_lammps

CONVERGED = 1e-14
BOX = 10.0
CUTOFF = 3.1
INERTIA = 0.1  # unit mass and diameter: 0.4 m (d/2)^2, the scene's inertia
DT, STEPS = 0.002, 20  # the scene's time step
# Requested accuracies LAMMPS misses on this lattice (ERRATA.md): its RMS
# torque error stops at ~4e-7 with ewald/dipole and real-space cutoff 3.1.
MISSES = {("ewald/dipole", 1e-7)}
# The same sum to round-off (pair kernel, truncated at 3.1) in both codes.
TRUNCATED_ROUNDOFF = 1e-12


def lattice(seed: int) -> DipoleSystem:
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


def restated_trajectory(system: DipoleSystem, torque_of):
    """LAMMPS's dipole/dlm step in numpy (half kick, free DLM rotation, half
    kick), with the torques of ``torque_of(dipoles)``: the dipoles per step."""
    mu, omega = system.dipoles.copy(), system.omega.copy()
    out = [mu.copy()]
    torque = torque_of(mu)
    for _ in range(STEPS):
        omega = omega + 0.5 * DT / INERTIA * torque
        stepped = [_lammps_free_step(m, w) for m, w in zip(mu, omega)]
        mu = np.array([s[0] for s in stepped])
        omega = np.array([s[1] for s in stepped])
        torque = torque_of(mu)
        omega = omega + 0.5 * DT / INERTIA * torque
        out.append(mu.copy())
    return np.array(out)


def _lammps_free_step(mu: np.ndarray, omega: np.ndarray):
    """LAMMPS's DLM free rotation of one sphere (its frame rebuilt from the
    dipole, validation/dlm_restatement.py): the new dipole and space omega."""
    length = np.linalg.norm(mu)
    frame = restated.lammps_frame(mu / length)
    frame, w = restated.sweep(frame, frame @ omega, DT, restated.LAMMPS_DLM)
    return frame[2] * length, frame.T @ w


def run(ctx: Context) -> list[Check]:
    version = lammps_version()
    refs = {"LAMMPS": version, "quatrot": quatrot.__version__}
    system = lattice(ctx.seed)
    n = len(system.sites)
    checks: list[Check] = []

    # The truncated sums first: the same model in both codes.
    e_cut, t_cut = quatrot_sum(system.sites, system.dipoles, cutoff=CUTOFF)
    lmp = run_lammps(system, DT, 0)
    checks.append(
        Check(
            name="LAMMPS lj/cut/dipole/cut vs quatrot cutoff 3.1, 1000-dipole lattice: energy",
            proves="both codes sum the same truncated model (the mapping and units of the long-range comparisons)",
            tolerance=TRUNCATED_ROUNDOFF,
            measured=abs(lmp.potential[0] - e_cut) / abs(e_cut),
            references=refs,
            details=f"LAMMPS {lmp.potential[0]:.15g}, quatrot {e_cut:.15g}",
        )
    )

    e_ref, t_ref = quatrot_sum(system.sites, system.dipoles, sum="ewald", accuracy=CONVERGED)
    runs = [("ewald/dipole", 1e-4), ("ewald/dipole", 1e-5)]
    if ctx.quick:
        runs.append(("pppm/dipole", 1e-3))
    else:
        runs += [("ewald/dipole", 1e-6), ("ewald/dipole", 1e-7), ("pppm/dipole", 1e-4), ("pppm/dipole", 1e-5), ("pppm/dipole", 1e-6)]
    table = []
    for style, accuracy in runs:
        ctx.progress(f"LAMMPS {style} at accuracy {accuracy:g}")
        lmp = run_lammps(DipoleSystem(**{**system.__dict__, "kspace": (style, accuracy)}), DT, 0)
        e, t = lmp.potential[0], lmp.torque[0]
        rms = float(np.sqrt(np.mean(np.sum((t - t_ref) ** 2, axis=1))))
        energy_error = abs(e - e_ref) / n
        table.append(f"{style} {accuracy:g}: energy per dipole {energy_error:.2e}, RMS torque {rms:.2e}")
        if (style, accuracy) in MISSES:
            checks.append(
                Check(
                    name=f"LAMMPS {style} accuracy {accuracy:g}: misses the requested accuracy (trap reproduced)",
                    proves="LAMMPS's RMS torque error stays above the accuracy it was asked for (ERRATA.md), at least twice it: measured = 2 x accuracy / error",
                    tolerance=1.0,
                    measured=2 * accuracy / rms,
                    references=refs,
                    details=f"RMS |tau - tau_converged| {rms:.3e} for requested {accuracy:g}; energy {e:.12g} vs converged {e_ref:.12g} ({energy_error:.2e} per dipole)",
                )
            )
            continue
        checks.append(
            Check(
                name=f"LAMMPS {style} accuracy {accuracy:g}: RMS torque error within the requested accuracy",
                proves="LAMMPS's long-range dipole sum meets the accuracy it was asked for, measured against quatrot's converged Ewald sum (absolute lj units, as LAMMPS defines it)",
                tolerance=accuracy,
                measured=rms,
                references=refs,
                details=f"RMS |tau - tau_converged| {rms:.3e}; energy {e:.12g} vs converged {e_ref:.12g} ({energy_error:.2e} per dipole)",
            )
        )
        checks.append(
            Check(
                name=f"LAMMPS {style} accuracy {accuracy:g}: energy per dipole within the requested accuracy",
                proves="LAMMPS's long-range energy per dipole agrees with quatrot's converged sum to the requested accuracy (lj units)",
                tolerance=accuracy,
                measured=energy_error,
                references=refs,
                details=f"energy {e:.12g} vs converged {e_ref:.12g}",
            )
        )
    checks[1].details += "\n\nAll: " + "; ".join(table)
    checks += _trajectory_checks(ctx, system, refs)
    return checks


def _trajectory_checks(ctx, system, refs) -> list[Check]:
    """A short NVE run with LAMMPS's ewald/dipole (and pppm/dipole in full
    mode) against the restated step driven by quatrot's converged torques."""
    converged = restated_trajectory(system, lambda mu: quatrot_sum(system.sites, mu, sum="ewald", accuracy=CONVERGED)[1])
    out = []
    for style, accuracy in [("ewald/dipole", 1e-6)] + ([] if ctx.quick else [("pppm/dipole", 1e-5)]):
        ctx.progress(f"LAMMPS {style} at accuracy {accuracy:g}: {STEPS} NVE steps")
        lmp = run_lammps(DipoleSystem(**{**system.__dict__, "kspace": (style, accuracy)}), DT, STEPS)
        deviation = float(np.max(np.linalg.norm(lmp.dipoles - converged, axis=2)))
        energy = lmp.potential + lmp.kinetic
        drift = float(np.max(np.abs(energy - energy[0])) / lmp.kinetic[0])
        # The kick of a torque error delta over the run moves a dipole by ~ delta t^2 / (2 I).
        bound = accuracy * (STEPS * DT) ** 2 / (2 * INERTIA) * 10 + 1e-12
        out.append(
            Check(
                name=f"LAMMPS {style} accuracy {accuracy:g}: {STEPS}-step NVE trajectory vs the converged sum",
                proves="LAMMPS's dipoles follow the trajectory that quatrot's converged torques drive through the same (restated) DLM step, to the effect of LAMMPS's torque error",
                tolerance=bound,
                measured=deviation,
                references=refs,
                details=f"max |mu_LAMMPS - mu_restated| over {STEPS} steps of dt {DT}: {deviation:.2e}; LAMMPS max |dE|/KE0 {drift:.2e}; "
                f"tolerance 10 x accuracy t^2 / (2 I)",
            )
        )
    return out
