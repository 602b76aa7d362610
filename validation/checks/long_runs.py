"""The note's correction experiment at production lengths (issue 15): every
configuration of `experiments::gear_corrections` (scheme A, scheme B with
each of its corrections) on the experiment's single rotor in a field, its
4 x 4 x 4 multipole lattice and the built-in 1000-dipole lattice, run to
`STEPS` steps or until it fails, at every time step of a geometric grid, as
one `quatrot.sweep` per system on a local Dask cluster of two workers. A run
fails when its state is non-finite or its energy error leaves
`STABILITY_ENERGY_FRACTION` of the initial kinetic energy (the experiment's
own criterion), checked every 10 steps (100 on the 1000-dipole lattice,
where each check costs an energy evaluation); its failure step is recorded. Since a run that lasts `STEPS` steps contains every shorter run,
the same runs give the largest stable step at 1e3, 1e4 and 1e5 steps, and
the note's claims and open question are judged at each of those lengths.
The short-run table (`gear_corrections`) is the reference these verdicts
extend."""

from __future__ import annotations

from validation.longrun import grid, systems
from validation.longrun.experiment import STEPS, plot, run_system, systems_for, table, verdicts
from validation.shared.check import Check, Context


def run(ctx: Context) -> list[Check]:
    steps = 2_000 if ctx.quick else STEPS
    ctx.out_dir.mkdir(parents=True, exist_ok=True)
    report = [f"# The correction experiment at {steps} steps\n"]
    checks, results = [], []
    with grid.connect() as client:
        for s in systems_for(ctx):
            ctx.progress(f"{s.name}: {len(systems.CONFIGURATIONS) * len(s.dts())} runs of {steps} steps")
            points = run_system(s, steps, ctx.out_dir / "sweeps", client)
            found, lines = verdicts(s, points, steps)
            checks += found
            report += [table(s, points, steps), "Verdicts:\n", "\n".join(lines) + "\n"]
            results.append((s, points, steps))
    (ctx.out_dir / "long_runs.md").write_text("\n".join(report))
    if not ctx.quick:
        checks[1].plots.append(plot(results, ctx.out_dir))
    return checks
