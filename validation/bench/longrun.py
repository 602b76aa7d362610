"""`python -m validation.bench.longrun --out benchmarks`: `make bench`'s
long-run mode (issue 15). The note's correction experiment at 1e5 steps
(`validation.checks.long_runs`: every configuration, every step of its grid,
the largest stable step against run length) and accuracy per second against
run length at the longest lengths (`validation.checks.accuracy_at_length`:
1e7 steps of the single rotor, 1e6 of the 64-rotor lattice), each grid a
`quatrot.sweep` on a local Dask cluster of two workers (or `--scheduler`).
Writes the `long_runs` key of `<out>/results.json` and its section of
`<out>/RESULTS.md`; the sweeps' folders (`--sweeps`) are resumed when run
again."""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import quatrot

from validation.bench import results_md
from validation.checks import accuracy_at_length, long_runs
from validation.checks.base import Context
from validation.longrun import grid

BEGIN = "<!-- make bench: long-run section begin -->"
END = "<!-- make bench: long-run section end -->"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    parser.add_argument("--sweeps", type=Path, default=Path("target/bench/longrun"), help="the sweeps' folders (resumed)")
    parser.add_argument("--scheduler", help="a Dask scheduler's address (default: a local cluster of 2 workers)")
    parser.add_argument("--quick", action="store_true", help="the machinery only (make test's lengths), to check the pipeline")
    args = parser.parse_args(argv)
    ctx = Context(out_dir=args.sweeps, quick=args.quick)
    steps = 2_000 if args.quick else long_runs.STEPS
    machine = results_md.machine()
    started = time.perf_counter()
    sections = ["# The correction experiment at production lengths\n"]
    figures = {}
    with grid.connect(args.scheduler) as client:
        experiment = []
        for s in long_runs.systems_for(ctx, long=True):
            print(f"correction experiment, {s.name} ...", flush=True)
            points = long_runs.run_system(s, steps, args.sweeps / "experiment", client)
            _, lines = long_runs.verdicts(s, points, steps)
            sections += [long_runs.table(s, points, steps), "Verdicts:\n", "\n".join(lines) + "\n"]
            experiment.append((s, points, steps))
        figures["stability"] = long_runs.plot(experiment, args.out).name
        outcomes = []
        for study in accuracy_at_length.studies(ctx, long=True):
            print(f"accuracy at length, {study.name}: {study.steps} steps ...", flush=True)
            outcomes.append(accuracy_at_length.measure(study, args.sweeps / "accuracy" / study.name.replace(" ", "_"), client))
    figures["accuracy"] = accuracy_at_length.plot(outcomes, args.out).name
    seconds = time.perf_counter() - started
    result = {
        "machine": machine,
        "versions": {"quatrot": quatrot.__version__, **results_md.toolchain()},
        "seconds": seconds,
        "experiment": [
            {"system": s.name, "steps": n, "points": [{k: v for k, v in dataclasses.asdict(p).items() if k not in ("series", "outputs")} for p in points]}
            for s, points, n in experiment
        ],
        "accuracy": [
            {"study": o.study.name, "dt0": o.study.dt0, "steps": o.study.steps, "cost_per_step": o.cost, "dts": o.dts,
             "crossovers": {f"{a} vs {b}": t for (a, b), t in o.crossovers.items()}}
            for o in outcomes
        ],
        "figures": figures,
    }
    results_md.update_json(args.out / "results.json", {"long_runs_at_length": result})
    body = [
        BEGIN,
        "## Long runs: verdicts at 1e5 to 1e7 steps (issue 15, `python -m validation.bench.longrun`)",
        "",
        f"- Machine: {machine['cpu']}, {machine['cpus']} CPUs; load average {machine['load_average']:.1f} when it started (shared machine). "
        f"Date: {machine['date']}. quatrot {quatrot.__version__}. Wall time {seconds / 60:.1f} min.",
        "- Every grid is a `quatrot.sweep` on a local Dask cluster of 2 workers; each row states its run length.",
        "",
        "\n".join(sections).replace("# The correction", "### The correction").replace("\n### ", "\n#### "),
        f"![largest stable dt against run length]({figures['stability']})",
        "",
        "### Accuracy per second against run length",
        "",
        "\n".join(accuracy_at_length.table(o).replace("### ", "#### ") for o in outcomes),
        f"![energy error against run length at equal cost]({figures['accuracy']})",
        END,
        "",
    ]
    results_md.replace_section(args.out / "RESULTS.md", BEGIN, END, "\n".join(body))
    print(f"wrote the long-run section of {args.out / 'RESULTS.md'} ({seconds / 60:.1f} min)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
