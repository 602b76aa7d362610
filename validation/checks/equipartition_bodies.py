"""The equipartition check for moving bodies (issue 39): in NVE runs of
the two built-ins, the Stockmayer fluid (256 dipolar spheres, 2 rotational
degrees of freedom each: no torque reaches the spin about the dipole) and
the Lewis-Wahnstrom o-terphenyl liquid (256 three-site molecules, 3 each),
does each integrator keep T_rot = T_trans?

This check runs 20,000 steps per run (time 40), the first 30 % left out:
its verdict says its length. The verdict at production length, 1e5 steps
per run for all ten runs, is `make bench`'s (`validation/bench/
equipartition.py`, the equipartition section of benchmarks/RESULTS.md):
ten 1e5-step runs take about two hours of a 2-core machine, four times
`make validate`'s budget.

Each run is the built-in with the integrator swapped and its thermostat
removed (`validation.shared.equipartition_runs`): dt = 0.002, the fcc start at
the built-in's initial temperature, which melts (the melt and the sharing
of its heat take ~5,000 steps for the Stockmayer fluid, ~600 for
o-terphenyl); recorded every 100 steps. The Stockmayer fluid keeps heating
in NVE (its dipoles are cut without a shift: the energy jumps as pairs
cross the cutoff). Quick: o-terphenyl with NO_SQUISH, 2,000 steps recorded
every 10, the first 40 % left out. The difference d = T_rot - T_trans is
block averaged; measured: |<d>| / sigma_<d>, against 4 (two-sided normal
6e-5 per run). Passing says the integrator shares kinetic energy equally
between rotation and translation at this dt to the resolution of the run,
with the degrees of freedom counted as quatrot counts them; a failure says
by how much it does not (the ratio <T_rot>/<T_trans> is in the details)."""

from __future__ import annotations

import quatrot
from validation.shared import equipartition_runs as ep
from validation.shared.check import Check, Context

EQUILIBRATION = {"production": 0.3, "quick": 0.4}
PRODUCTION_STEPS = 20_000


def run(ctx: Context) -> list[Check]:
    if ctx.quick:
        runs, steps, every, left_out = [("lewis_wahnstrom_otp", "no_squish")], 2000, 10, EQUILIBRATION["quick"]
    else:
        runs = [(s, i) for s in ep.SCENES for i in ep.INTEGRATORS]
        steps, every, left_out = PRODUCTION_STEPS, 100, EQUILIBRATION["production"]
    checks = []
    for scene_name, integrator in runs:
        ctx.progress(f"{scene_name} with {integrator}: {steps} steps")
        e = ep.measure(ep.run_series(ep.nve_scene(scene_name, integrator, steps, every)), left_out)
        checks.append(
            Check(
                name=f"equipartition {scene_name} {integrator}: T_rot = T_trans",
                proves=(
                    f"NVE with {integrator} over {steps} steps of dt = 0.002 keeps the rotational and translational "
                    "temperatures of the built-in equal within the statistical error (|<T_rot - T_trans>| / sigma); "
                    "the 1e5-step verdict is make bench's (benchmarks/RESULTS.md, equipartition section)"
                ),
                tolerance=ep.Z_MAX,
                measured=e["z"],
                references={"equipartition": "exact", "quatrot": quatrot.__version__},
                details=(
                    f"{steps} steps, averaged after {left_out:.0%}: <T_rot> {e['T_rot']:.4f}, <T_trans> {e['T_trans']:.4f}, "
                    f"ratio {e['ratio']:.4f} +- {e['ratio_error']:.4f}, <T_rot - T_trans> {e['difference']:.2e} +- {e['error']:.1e}"
                    + ("" if e["converged"] else " (blocking not converged: the error is a lower bound)")
                ),
            )
        )
    return checks
