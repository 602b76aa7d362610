"""LAMMPS's long-range dipole sums (pair lj/cut/dipole/long with epsilon 0,
kspace_style ewald/dipole and pppm/dipole, tin-foil boundary, units lj so
qqrd2e = 1 = 1 / (4 pi eps0) as in quatrot) against quatrot's converged Ewald
sum (accuracy 1e-14; itself checked against the numpy sum and the closed
forms in the ewald_numpy module) on a 1000-dipole simple-cubic lattice
(10^3, spacing 1, box 10, |mu| = 1, I = 0.1: the lattice of the built-in
scene dipole_lattice_sc, whose own sum is the Ewald sum, with random
orientations and T = 1 angular velocities from the check's seed; LAMMPS's
real-space cutoff is 3.1): energies, torques and a short NVE trajectory,
with each code's error at each requested accuracy. The two codes' truncated
sums (LAMMPS lj/cut/dipole/cut, quatrot's cutoff sum of
dipole_lattice_sc_cutoff, both cut at 3.1) are compared first, to round-off,
to check the mapping and units the long-range comparisons rely on.

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

from validation.shared.check import Check, Context
from validation.shared import dlm_restatement as restated
from validation.shared.dipole_lattice import CONVERGED, CUTOFF, DT, INERTIA, lattice, quatrot_sum
from validation.shared.lammps_driver import DipoleSystem, lammps_version, run_lammps

STEPS = 20  # NVE steps of each trajectory
# Requested accuracies LAMMPS misses on this lattice (ERRATA.md): its RMS
# torque error stops at ~4e-7 with ewald/dipole and real-space cutoff 3.1.
MISSES = {("ewald/dipole", 1e-7)}
# The same sum to round-off (pair kernel, truncated at 3.1) in both codes.
TRUNCATED_ROUNDOFF = 1e-12
# The LAMMPS runs (kspace style, requested accuracy) of each mode. Those in
# TRAJECTORIES run STEPS NVE steps, and their first frame gives their
# single-point checks, so each long-range set-up is paid once. pppm/dipole's
# set-up grows steeply with the accuracy on this lattice (measured 2026-11-23
# under load ~16: 133 s at 1e-4, more than 8 min at 1e-5, against 0.6-2.3 s
# for ewald/dipole at 1e-4 to 1e-7), so the full mode checks pppm/dipole at
# 1e-4 only, for the energy, the torques and the trajectory alike
# (`make validate`'s 30-minute budget); ewald/dipole keeps every level.
RUNS_QUICK = [("ewald/dipole", 1e-4), ("ewald/dipole", 1e-5), ("ewald/dipole", 1e-6), ("pppm/dipole", 1e-3)]
RUNS_FULL = [("ewald/dipole", 1e-4), ("ewald/dipole", 1e-5), ("ewald/dipole", 1e-6), ("ewald/dipole", 1e-7), ("pppm/dipole", 1e-4)]
TRAJECTORIES_QUICK = {("ewald/dipole", 1e-6)}
TRAJECTORIES_FULL = {("ewald/dipole", 1e-6), ("pppm/dipole", 1e-4)}


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
    dipole, validation/shared/dlm_restatement.py): the new dipole and space omega."""
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
    runs, trajectories = (RUNS_QUICK, TRAJECTORIES_QUICK) if ctx.quick else (RUNS_FULL, TRAJECTORIES_FULL)
    converged = None
    table = []
    trajectory_checks = []
    for style, accuracy in runs:
        steps = STEPS if (style, accuracy) in trajectories else 0
        ctx.progress(f"LAMMPS {style} at accuracy {accuracy:g}" + (f": {steps} NVE steps" if steps else ""))
        lmp = run_lammps(DipoleSystem(**{**system.__dict__, "kspace": (style, accuracy)}), DT, steps)
        if steps:
            if converged is None:
                converged = restated_trajectory(system, lambda mu: quatrot_sum(system.sites, mu, sum="ewald", accuracy=CONVERGED)[1])
            trajectory_checks.append(_trajectory_check(style, accuracy, lmp, converged, refs))
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
    return checks + trajectory_checks


def _trajectory_check(style: str, accuracy: float, lmp, converged: np.ndarray, refs) -> Check:
    """A LAMMPS NVE run with its long-range sum at `accuracy` against the
    restated step driven by quatrot's converged torques (`converged`)."""
    deviation = float(np.max(np.linalg.norm(lmp.dipoles - converged, axis=2)))
    energy = lmp.potential + lmp.kinetic
    drift = float(np.max(np.abs(energy - energy[0])) / lmp.kinetic[0])
    # The kick of a torque error delta over the run moves a dipole by ~ delta t^2 / (2 I).
    bound = accuracy * (STEPS * DT) ** 2 / (2 * INERTIA) * 10 + 1e-12
    return Check(
        name=f"LAMMPS {style} accuracy {accuracy:g}: {STEPS}-step NVE trajectory vs the converged sum",
        proves="LAMMPS's dipoles follow the trajectory that quatrot's converged torques drive through the same (restated) DLM step, to the effect of LAMMPS's torque error",
        tolerance=bound,
        measured=deviation,
        references=refs,
        details=f"max |mu_LAMMPS - mu_restated| over {STEPS} steps of dt {DT}: {deviation:.2e}; LAMMPS max |dE|/KE0 {drift:.2e}; "
        f"tolerance 10 x accuracy t^2 / (2 I)",
    )
