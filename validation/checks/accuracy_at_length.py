"""Which scheme buys the most accuracy per second depends on how long the run
is (issue 15, item 2). Each scheme runs at the time step of equal cost per
unit time (costs measured side by side in one sweep, `validation.longrun.accuracy`)
over the same time span, on the experiment's single rotor in a field and on
its 64-rotor multipole lattice, each a `quatrot.sweep` on a local Dask
cluster of two workers. The energy error up to each time is plotted against
run length; the crossover time after which each symplectic scheme is more
accurate in energy than each Gear scheme at equal cost is reported. The
orientation error against run length is not measured here (see the README).
`make bench` runs the same study longer (`python -m validation.bench.longrun`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import quatrot

from validation.checks.base import Check, Context
from validation.checks.long_runs import fmt
from validation.longrun import accuracy, grid, systems

#: Samples of each run's energy error (and points of the curves).
SAMPLES = 2_000
#: A symplectic scheme's error bound: its error up to the end of the run over
#: its error up to a tenth of it stays below this (bounded, no secular drift;
#: 2 allows the bounded oscillation to reach a new extreme late in the run).
BOUNDED_RATIO = 2.0


@dataclass
class Study:
    name: str
    scene: dict
    #: The cheapest scheme's step; the others get equal-cost steps from it.
    dt0: float
    #: Steps of the cheapest scheme (the time span is `dt0 * steps`).
    steps: int
    #: Steps of the cost runs (`n` and `2n`).
    cost_steps: int


def studies(ctx: Context, long: bool = False) -> list[Study]:
    """The validation report's lengths (quick: the machinery only); `long`:
    `make bench`'s long-run mode (1e7 steps of the rotor, 1e6 of the lattice)."""
    rotor = systems.rotor_in_field()
    if ctx.quick:
        return [Study("rotor in field", rotor, 0.02, 20_000, 20_000)]
    lattice = systems.multipole_lattice(ctx.seed)
    if long:
        return [Study("rotor in field", rotor, 0.02, 10_000_000, 200_000), Study("64-rotor multipole lattice", lattice, 0.01, 1_000_000, 4_000)]
    return [Study("rotor in field", rotor, 0.02, 10_000_000, 200_000), Study("64-rotor multipole lattice", lattice, 0.01, 200_000, 4_000)]


@dataclass
class Outcome:
    study: Study
    cost: dict[str, float]
    dts: dict[str, float]
    points: list[grid.Point]
    curves: dict[str, accuracy.Curve]
    crossovers: dict[tuple[str, str], float | None]


def measure(study: Study, out: Path, client) -> Outcome:
    schemes = systems.SCHEMES
    cost = accuracy.costs(study.scene, schemes, study.dt0, study.cost_steps, out=out / "costs", client=client)
    dts = accuracy.equal_cost_dts(cost, study.dt0)
    span = study.dt0 * study.steps
    specs = [grid.Spec(label, schemes[label], dt, max(1, round(span / dt))) for label, dt in dts.items()]
    points = grid.run(study.scene, specs, out=out / "runs", samples=SAMPLES, client=client)
    found = accuracy.curves(points, span, SAMPLES)
    crossovers = {(s, g): accuracy.crossover(found[s], found[g]) for s in systems.SYMPLECTIC for g in systems.GEAR}
    return Outcome(study, cost, dts, points, found, crossovers)


def table(o: Outcome) -> str:
    span = o.study.dt0 * o.study.steps
    lines = [
        f"### {o.study.name}: time span {span:g} ({o.study.steps:.0e} steps of the cheapest scheme at dt {o.study.dt0:g})",
        "",
        "| scheme | CPU us per step | equal-cost dt | steps | status | energy error up to t = span/1000, span/100, span/10, span |",
        "|---|---|---|---|---|---|",
    ]
    n = len(next(iter(o.curves.values())).times)
    marks = [n // 1000 - 1, n // 100 - 1, n // 10 - 1, n - 1]
    for p in o.points:
        c = o.curves[p.label]
        errors = ", ".join(fmt(float(c.error[max(m, 0)])) for m in marks)
        lines.append(f"| {p.label} | {o.cost[p.label] * 1e6:.3g} | {p.dt:.4g} | {p.steps} | {p.status} | {errors} |")
    lines += ["", "Crossover times (symplectic scheme more accurate in energy than the Gear scheme from then on, at equal cost):", ""]
    lines += ["| symplectic \\ Gear | " + " | ".join(systems.GEAR) + " |", "|---|" + "---|" * len(systems.GEAR)]
    for s in systems.SYMPLECTIC:
        cells = []
        for g in systems.GEAR:
            t = o.crossovers[(s, g)]
            cells.append("not within the run" if t is None else f"t = {t:.4g} ({t / o.dts[s]:.3g} of its steps)")
        lines.append(f"| {s} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


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


def plot(outcomes: list[Outcome], out_dir: Path, name: str = "accuracy_at_length.png") -> Path:
    """Energy error (running maximum) against run length, per study."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(outcomes), figsize=(6 * len(outcomes), 4.5), squeeze=False)
    for ax, o in zip(axes[0], outcomes):
        for label, c in o.curves.items():
            style = "-" if label in systems.SYMPLECTIC else ("--" if label in systems.GEAR else ":")
            ax.plot(c.times / o.study.dt0, c.error, style, label=f"{label} (dt {o.dts[label]:.3g})")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(f"run length (steps of dt = {o.study.dt0:g}; equal cost for every scheme)")
        ax.set_ylabel("max |E - E0| / K0 up to then")
        ax.set_title(o.study.name, fontsize=9)
        ax.legend(fontsize=6)
    fig.tight_layout()
    path = out_dir / name
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


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
    (ctx.out_dir / "accuracy_at_length.md").write_text("# Accuracy per second against run length\n\n" + "\n".join(table(o) for o in outcomes))
    checks = []
    for o in outcomes:
        found = checks_for(o)
        found[0].details = (found[0].details + "\n\n" if found[0].details else "") + table(o)
        checks += found
    if not ctx.quick:
        checks[0].plots.append(plot(outcomes, ctx.out_dir))
    return checks
