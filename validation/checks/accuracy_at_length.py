"""Which scheme buys the most accuracy per second depends on how long the run
is (issue 15, item 2). Each scheme runs at the time step of equal cost per
unit time (costs measured side by side in one sweep, `validation.longrun.accuracy`)
over the same time span, on the experiment's single rotor in a field and on
its 64-rotor multipole lattice, each a `quatrot.sweep` on a local Dask
cluster of two workers. The energy error up to each time is plotted against
run length; the crossover time after which each symplectic scheme is more
accurate in energy than each Gear scheme at equal cost is reported. The
orientation error against run length (`validation.longrun.orientation`:
A, B, B +higher, NO_SQUISH and DLM at the same steps, rounded to a multiple
of dt0/8, against scheme B +higher at dt0/8 (A for B +higher itself) whose
own error is estimated at dt0/16, and against scipy's DOP853 on the rotor) is measured over a span of
its own (`Study.orientation_steps`), plotted beside the energy error, with its
crossovers and, on the chaotic lattice, the Lyapunov time of the reference
pair and the time from which orientation errors are meaningless.
`make bench` runs the same study longer (`python -m validation.bench.longrun`)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import quatrot

from validation.longrun import grid, orientation, systems
from validation.longrun.at_length import Outcome, Study, measure, orientation_table, plot, studies, table
from validation.shared.check import Check, Context

#: A symplectic scheme's error bound: its error up to the end of the run over
#: its error up to a tenth of it stays below this (bounded, no secular drift;
#: 2 allows the bounded oscillation to reach a new extreme late in the run).
BOUNDED_RATIO = 2.0
#: The reference is good enough where its distance from DOP853 is below this
#: fraction of the smallest scheme error it is used to measure (the errors
#: shown are then right to 10 %).
REFERENCE_FRACTION = 0.1


def orientation_checks(o: Outcome) -> list[Check]:
    """The reference's independent check (rotor: DOP853) and its step-pair estimate."""
    r = o.orientation
    if r is None:
        return []
    refs = {"quatrot": quatrot.__version__}
    checks = []
    if r.dop853:
        import scipy

        d = r.dop853
        checks.append(
            Check(
                name=f"orientation at length {o.study.name}: reference vs scipy DOP853",
                proves=f"the orientation reference ({orientation.REFERENCE} at dt0/{orientation.REFINE}) agrees with scipy's DOP853 "
                f"(rtol {d['rtol']:g}, nothing from quatrot) over t <= {d['span']:g} to within {REFERENCE_FRACTION} of the smallest "
                "scheme error it measures there: measured = the largest such fraction",
                tolerance=REFERENCE_FRACTION,
                measured=d["max_fraction"],
                references={**refs, "scipy": scipy.__version__},
                details=f"largest angle {d['max_distance']:.3e} rad over {d['samples']} samples; step pair u vs u/2: {d['pair_max']:.3e}",
            )
        )
    first = r.meaningless_after if r.meaningless_after is not None else r.span
    keep = r.pair_times < first
    est = float(np.max(np.maximum(r.pair_separation, r.alternate_separation)[keep])) if keep.any() else math.nan
    checks.append(
        Check(
            name=f"orientation at length {o.study.name}: every chain ran and the reference resolves the errors at the start",
            proves="every scheme's orientation chain ran to the end of the span (or stopped at a recorded blow-up), and the "
            "reference's own error estimate is below a tenth of every scheme's error at least until the first sample after "
            "10 steps: measured = the estimate's fraction of the smallest error at the first sample",
            tolerance=REFERENCE_FRACTION,
            measured=_first_fraction(r),
            references=refs,
            details=f"largest reference error estimate before t = {first:.4g}: {est:.3e} rad; Lyapunov time "
            f"{'none' if r.lyapunov_time is None else format(r.lyapunov_time, '.3g')}",
        )
    )
    return checks


def _first_fraction(r: orientation.Outcome) -> float:
    estimate = np.maximum(r.pair_separation, r.alternate_separation)
    fractions = []
    for c in r.curves.values():
        k = int(np.searchsorted(r.pair_times, c.times[0]))
        if math.isfinite(c.error[0]):
            fractions.append(estimate[k] / c.error[0] if c.error[0] > 0 else math.inf)
    return float(max(fractions)) if fractions else math.inf


def checks_for(o: Outcome) -> list[Check]:
    refs = {"quatrot (scene runs through quatrot.sweep on Dask)": quatrot.__version__}
    bad = [p for p in o.points if p.status not in ("completed", "blew_up")]
    checks = [
        Check(
            name=f"accuracy at length {o.study.name}: every run finished",
            proves="each scheme's equal-cost run ran to the end of the span or stopped at a recorded blow-up",
            tolerance=0,
            measured=len(bad),
            references=refs,
            details="; ".join(f"{p.label}: {p.status} {p.error}" for p in bad),
        )
    ]
    for s in systems.SYMPLECTIC:
        c = o.curves[s]
        n = len(c.times)
        ratio = float(c.error[-1] / c.error[n // 10 - 1]) if c.error[n // 10 - 1] > 0 else math.inf
        checks.append(
            Check(
                name=f"accuracy at length {o.study.name}: {s} energy error bounded",
                proves=f"the symplectic {s}'s energy error up to the end of the run is within {BOUNDED_RATIO}x its error "
                "up to a tenth of it (no secular drift over the run)",
                tolerance=BOUNDED_RATIO,
                measured=ratio,
                references=refs,
                details=f"max |dE|/K0: {c.error[n // 10 - 1]:.3g} up to t = {c.times[n // 10 - 1]:.4g}, {c.error[-1]:.3g} up to t = {c.times[-1]:.4g}",
            )
        )
    return checks


def measure_all(found: list[Study], out_dir: Path, ctx: Context) -> list[Outcome]:
    outcomes = []
    with grid.connect() as client:
        for study in found:
            ctx.progress(f"{study.name}: costs, then {len(systems.SCHEMES)} runs over {study.steps} steps of dt {study.dt0:g}")
            outcomes.append(measure(study, out_dir / "sweeps" / study.name.replace(" ", "_"), client))
    return outcomes


def run(ctx: Context) -> list[Check]:
    ctx.out_dir.mkdir(parents=True, exist_ok=True)
    outcomes = measure_all(studies(ctx), ctx.out_dir, ctx)
    (ctx.out_dir / "accuracy_at_length.md").write_text(
        "# Accuracy per second against run length\n\n" + "\n".join(table(o) + "\n" + orientation_table(o) for o in outcomes)
    )
    checks = []
    for o in outcomes:
        found = checks_for(o)
        found[0].details = (found[0].details + "\n\n" if found[0].details else "") + table(o) + "\n" + orientation_table(o)
        checks += found + orientation_checks(o)
    if not ctx.quick:
        checks[0].plots.append(plot(outcomes, ctx.out_dir))
    return checks
