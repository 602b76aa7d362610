"""`python -m validation.bench.longrun --out benchmarks`: `make bench`'s
long-run mode (issue 15). The note's correction experiment at 1e5 steps
(`validation.longrun.experiment`, as the `long_runs` check does at the
report's lengths: every configuration, every step of its grid, the largest
stable step against run length) and accuracy per second against run length
at the longest lengths (`validation.longrun.at_length`, as the
`accuracy_at_length` check: 1e7 steps of the single rotor, 1e6 of the
64-rotor lattice), each grid a `quatrot.sweep` on a local Dask cluster of two
workers (or `--scheduler`). Writes the `long_runs` key of
`<out>/results.json` and its section of `<out>/RESULTS.md`; the sweeps'
folders (`--sweeps`) are resumed when run again."""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path

import quatrot

from validation.bench import results_md
from validation.longrun import accuracy, at_length, experiment, grid, orientation, systems
from validation.shared.check import Context

BEGIN = "<!-- make bench: long-run section begin -->"
END = "<!-- make bench: long-run section end -->"
BEGIN_ORIENTATION = "<!-- make bench: orientation section begin -->"
END_ORIENTATION = "<!-- make bench: orientation section end -->"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    parser.add_argument("--sweeps", type=Path, default=Path("target/bench/longrun"), help="the sweeps' folders (resumed)")
    parser.add_argument("--scheduler", help="a Dask scheduler's address (default: a local cluster of 2 workers)")
    parser.add_argument("--quick", action="store_true", help="the machinery only (make test's lengths), to check the pipeline")
    parser.add_argument(
        "--orientation-only",
        action="store_true",
        help="only the orientation error against run length (costs measured again, no energy grids): its own section",
    )
    parser.add_argument(
        "--rebuild",
        action="store_true",
        help="with --orientation-only: rewrite its section and figure from the curves recorded in <out>/results.json (no runs)",
    )
    args = parser.parse_args(argv)
    if args.orientation_only:
        return orientation_only(args)
    ctx = Context(out_dir=args.sweeps, quick=args.quick)
    steps = 2_000 if args.quick else experiment.STEPS
    machine = results_md.machine()
    started = time.perf_counter()
    sections = ["# The correction experiment at production lengths\n"]
    figures = {}
    with grid.connect(args.scheduler) as client:
        systems_run = []
        for s in experiment.systems_for(ctx, long=True):
            print(f"correction experiment, {s.name} ...", flush=True)
            points = experiment.run_system(s, steps, args.sweeps / "experiment", client)
            _, lines = experiment.verdicts(s, points, steps)
            sections += [experiment.table(s, points, steps), "Verdicts:\n", "\n".join(lines) + "\n"]
            systems_run.append((s, points, steps))
        figures["stability"] = experiment.plot(systems_run, args.out).name
        outcomes = []
        for study in at_length.studies(ctx, long=True):
            print(f"accuracy at length, {study.name}: {study.steps} steps ...", flush=True)
            outcomes.append(at_length.measure(study, args.sweeps / "accuracy" / study.name.replace(" ", "_"), client))
    figures["accuracy"] = at_length.plot(outcomes, args.out).name
    seconds = time.perf_counter() - started
    result = {
        "machine": machine,
        "versions": {"quatrot": quatrot.__version__, **results_md.toolchain()},
        "seconds": seconds,
        "experiment": [
            {"system": s.name, "steps": n, "points": [{k: v for k, v in dataclasses.asdict(p).items() if k not in ("series", "outputs")} for p in points]}
            for s, points, n in systems_run
        ],
        "accuracy": [
            {"study": o.study.name, "dt0": o.study.dt0, "steps": o.study.steps, "cost_per_step": o.cost, "dts": o.dts,
             "crossovers": {f"{a} vs {b}": t for (a, b), t in o.crossovers.items()},
             "orientation": None if o.orientation is None else _orientation_json(o)}
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
        "\n".join(at_length.table(o).replace("### ", "#### ") + "\n" + at_length.orientation_table(o) for o in outcomes),
        f"![energy error (top) and orientation error (bottom) against run length at equal cost]({figures['accuracy']})",
        END,
        "",
    ]
    results_md.replace_section(args.out / "RESULTS.md", BEGIN, END, "\n".join(body))
    print(f"wrote the long-run section of {args.out / 'RESULTS.md'} ({seconds / 60:.1f} min)")
    return 0


def orientation_only(args) -> int:
    """The orientation comparison of `make bench`'s long-run mode alone: each
    study's costs (a sweep), then its orientation chains, in a section of its own."""
    ctx = Context(out_dir=args.sweeps, quick=args.quick)
    if args.rebuild:
        recorded = json.loads((args.out / "results.json").read_text())["orientation_at_length"]
        studies = {s.name: s for s in at_length.studies(ctx, long=True)}
        outcomes = [_orientation_outcome(studies[r["study"]], r) for r in recorded["studies"]]
        return _write_orientation(args, recorded["machine"], recorded["seconds"], outcomes)
    machine = results_md.machine()
    started = time.perf_counter()
    outcomes = []
    with grid.connect(args.scheduler) as client:
        for study in at_length.studies(ctx, long=True):
            print(f"orientation at length, {study.name}: {study.orientation_steps} steps ...", flush=True)
            folder = args.sweeps / "accuracy" / study.name.replace(" ", "_") / "costs"
            cost = accuracy.costs(study.scene, systems.SCHEMES, study.dt0, study.cost_steps, out=folder, client=client)
            dts = accuracy.equal_cost_dts(cost, study.dt0)
            found = at_length.Outcome(study, cost, dts, [], {}, {})
            found.orientation = at_length.measure_orientation(study, dts, client)
            found.orientation_crossovers = at_length.orientation_crossovers(found.orientation)
            outcomes.append(found)
    return _write_orientation(args, machine, time.perf_counter() - started, outcomes)


def _orientation_outcome(study, r: dict):
    """An orientation study's outcome rebuilt from its `results.json` record."""
    import numpy as np

    curves = {
        k: orientation.Curve(k, c["dt"], np.array(c["times"]), np.array(c["error"]), np.array(c["error"]) * np.nan, c["cpu_seconds"])
        for k, c in r["curves"].items()
    }
    e = r["reference_error_estimate"]
    found = orientation.Outcome(
        study.name, r["dt0"], r["dt0"] * r["steps"], r["reference_step"],
        {k: round(c.dt / r["reference_step"]) for k, c in curves.items()}, curves,
        np.array(e["times"]), np.array(e["step_pair"]), np.array(e["alternate"]), r["reference_cpu_seconds"],
        dop853=r["dop853"],
    )
    found.lyapunov_time = orientation.lyapunov_time(found.pair_times, found.pair_separation)
    found.meaningless_after = orientation.meaningless_after(found)
    outcome = at_length.Outcome(study, r["cost_per_step"], r["dts"], [], {}, {})
    outcome.orientation = found
    outcome.orientation_crossovers = at_length.orientation_crossovers(found)
    return outcome


def _write_orientation(args, machine: dict, seconds: float, outcomes: list) -> int:
    figure = at_length.orientation_plot(outcomes, args.out).name
    results_md.update_json(
        args.out / "results.json",
        {"orientation_at_length": {"machine": machine, "seconds": seconds, "studies": [_orientation_json(o) for o in outcomes]}},
    )
    body = [
        BEGIN_ORIENTATION,
        "## Orientation error against run length (issue 15, `python -m validation.bench.longrun --orientation-only`)",
        "",
        f"- Machine: {machine['cpu']}, {machine['cpus']} CPUs; load average {machine['load_average']:.1f} when it started (shared machine; "
        f"the costs behind the equal-cost steps were measured side by side in one sweep). Date: {machine['date']}. quatrot {quatrot.__version__}. "
        f"Wall time {seconds / 60:.1f} min.",
        "- Each scheme at its equal-cost step (CPU per step measured as in the long-run section), orientations at log-spaced "
        "times from restart chains (`validation/longrun/orientation.py`), one Dask task per chain on a local cluster of 2 workers.",
        "",
        "\n".join(at_length.orientation_table(o) for o in outcomes),
        f"![orientation error against run length at equal cost]({figure})",
        END_ORIENTATION,
        "",
    ]
    results_md.replace_section(args.out / "RESULTS.md", BEGIN_ORIENTATION, END_ORIENTATION, "\n".join(body))
    print(f"wrote the orientation section of {args.out / 'RESULTS.md'} ({seconds / 60:.1f} min)")
    return 0


def _orientation_json(o) -> dict:
    r = o.orientation
    return {
        "study": o.study.name, "dt0": o.study.dt0, "steps": o.study.orientation_steps, "cost_per_step": o.cost, "dts": o.dts,
        "reference_step": r.unit, "reference_cpu_seconds": r.reference_cpu_seconds,
        "lyapunov_time": r.lyapunov_time, "meaningless_after": r.meaningless_after, "dop853": r.dop853,
        "curves": {k: {"dt": c.dt, "times": c.times.tolist(), "error": c.error.tolist(), "cpu_seconds": c.cpu_seconds}
                   for k, c in r.curves.items()},
        "reference_error_estimate": {"times": r.pair_times.tolist(), "step_pair": r.pair_separation.tolist(),
                                     "alternate": r.alternate_separation.tolist()},
        "crossovers": {f"{a} vs {b}": {"time": t, "compared_until": until} for (a, b), (t, until) in o.orientation_crossovers.items()},
    }


if __name__ == "__main__":
    sys.exit(main())
