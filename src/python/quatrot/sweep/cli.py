"""`python -m quatrot.sweep` (and `quatrot sweep`, which runs it): the sweep
from the command line. Values are TOML literals (`0.01`, `true`, `"gear_b"`,
`[0.0, 0.0, 1.0]`, `{ kind = "dlm" }`); a bare word that is not one, such as
`gear_b` or `3/16`, is a string.

Exit codes: 0 when every run has a final status (completed, blew up or scene
error: see the table), 1 when some runs failed (lost workers, I/O; run the
same command again to retry them), 2 for a bad command line or base scene,
130 when interrupted (Ctrl-C; the table keeps what finished).
"""

from __future__ import annotations

import argparse
import re
import sys
import tomllib
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import quatrot
from quatrot.sweep.execute import run
from quatrot.sweep.folder import sweep_folder
from quatrot.sweep.plan import Run, format_overrides, iter_runs, printable
from quatrot.sweep.table import NAME, Table

EXIT_UNFINISHED = 1
EXIT_USAGE = 2
EXIT_INTERRUPTED = 130

_BARE_WORD = re.compile(r"[^\s\"'\[\]{},;=]+")

EPILOG = """\
examples:
  python -m quatrot.sweep dipole_in_field --set integrator.kind=gear_b,dlm \\
      --set run.dt=0.01,0.005,0.0025 --out sweeps/dipole
  python -m quatrot.sweep scene.toml --set initial.seed=1,2,3 \\
      --case 'integrator.kind=no_squish;integrator.substeps=10' \\
      --out sweeps/seeds --scheduler tcp://scheduler-host:8786

Each run's outputs go to DIR/runs/<id>/ (the id hashes the run's resolved
scene); DIR/results.csv has one row per run. Running the same command again
runs only what is not finished.
"""


def split_top_level(text: str, separator: str) -> list[str]:
    """`text` split at each `separator` outside quotes, brackets and braces."""
    items, depth, quote, start, k = [], 0, None, 0, 0
    while k < len(text):
        c = text[k]
        if quote:
            if c == "\\" and quote == '"':
                k += 1
            elif c == quote:
                quote = None
        elif c in "\"'":
            quote = c
        elif c in "[{":
            depth += 1
        elif c in "]}":
            depth -= 1
        elif c == separator and depth == 0:
            items.append(text[start:k])
            start = k + 1
        k += 1
    items.append(text[start:])
    return [i.strip() for i in items]


def parse_value(text: str) -> Any:
    """A TOML literal, or a bare word as a string."""
    try:
        return tomllib.loads(f"value = {text}")["value"]
    except tomllib.TOMLDecodeError:
        if _BARE_WORD.fullmatch(text):
            return text
        raise ValueError(f"`{printable(text)}` is neither a TOML value nor a bare word") from None


def _assignment(text: str, many: bool) -> tuple[str, Any]:
    path, sep, values = text.partition("=")
    if not sep or not path.strip():
        raise ValueError(f"`{printable(text)}`: expected PATH=VALUE{',VALUE...' if many else ''}")
    if many:
        return path.strip(), [parse_value(v) for v in split_top_level(values, ",")]
    return path.strip(), parse_value(values.strip())


def parse_grid(entries: list[str]) -> dict[str, list[Any]]:
    """`--set PATH=V1,V2,...` entries as a grid (a path given twice is an error)."""
    grid: dict[str, list[Any]] = {}
    for entry in entries:
        path, values = _assignment(entry, many=True)
        if path in grid:
            raise ValueError(f"--set {printable(path)}: given twice")
        grid[path] = values
    return grid


def parse_case(text: str) -> dict[str, Any]:
    """A `--case 'PATH=V;PATH=V'` entry as an override dict."""
    return dict(_assignment(item, many=False) for item in split_top_level(text, ";") if item)


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="python -m quatrot.sweep",
        description="Run a grid of quatrot scenes as Dask tasks: on a local cluster by default, "
        "on an existing one with --scheduler.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("scene", help="base scene: a built-in name (`quatrot scenes`) or a .toml file")
    p.add_argument(
        "--set",
        dest="grid",
        action="append",
        default=[],
        metavar="PATH=V1,V2,...",
        help="a grid axis: the scene field PATH (dotted keys, `[n]` for array items, e.g. run.dt, "
        "integrator.kind, initial.seed, rotors.cells) takes each value in turn; the runs are every "
        "combination of the --set axes. Repeat for more axes",
    )
    p.add_argument(
        "--case",
        dest="cases",
        action="append",
        default=[],
        metavar="PATH=V;PATH=V",
        help="one more run with these overrides (for combinations that are not a grid). Repeatable",
    )
    p.add_argument("--out", required=True, metavar="DIR", help="the sweep's folder (results.csv, runs/<id>/)")
    where = p.add_mutually_exclusive_group()
    where.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="a running Dask scheduler (e.g. tcp://host:8786); its workers must see DIR at the same path",
    )
    where.add_argument(
        "--workers", type=int, metavar="N", help="workers of the local cluster (default: cores / threads per run)"
    )
    p.add_argument(
        "--threads-per-run",
        type=int,
        default=1,
        metavar="N",
        help="threads of each run (default 1; a run's last bits depend on it, so it is part of what is resumed)",
    )
    p.add_argument("--dry-run", action="store_true", help="list the runs (id, done or to do, overrides) and stop")
    return p


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        grid = parse_grid(args.grid)
        cases = [parse_case(c) for c in args.cases]
        if args.dry_run:
            return _dry_run(iter_runs(args.scene, grid, cases), args)
        counter = _Progress()
        results = run(
            args.scene,
            grid,
            cases,
            out=args.out,
            client=args.scheduler,
            workers=args.workers,
            threads_per_run=args.threads_per_run,
            on_result=counter,
        )
    except (ValueError, TypeError, quatrot.SceneError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(f"interrupted: {Path(args.out) / NAME} holds the runs finished so far; the same command resumes", file=sys.stderr)
        return EXIT_INTERRUPTED
    return _report(results, counter.done)


class _Progress:
    """Prints one line per recorded run."""

    def __init__(self):
        self.done = 0

    def __call__(self, r: Run, row: dict[str, str]) -> None:
        self.done += 1
        seconds = f" ({float(row['task_seconds']):.2f} s)" if row.get("task_seconds") else ""
        print(f"[{self.done}] {r.id} {row['status']}{seconds} {format_overrides(r.overrides)}", flush=True)


def _dry_run(runs: Iterable[Run], args) -> int:
    """Lists the runs as they are made (a grid is refused past
    `plan.MAX_RUNS` before the first)."""
    path = sweep_folder(args.out) / NAME
    table = Table(path) if path.exists() else None
    for r in runs:
        done = table is not None and table.finished(r.id, args.threads_per_run)
        print(f"{r.id} {'done' if done else 'to do'} {format_overrides(r.overrides)}")
    return 0


def _report(results, ran: int) -> int:
    counts: dict[str, int] = {}
    for row in results.rows:
        counts[row["status"]] = counts.get(row["status"], 0) + 1
    summary = ", ".join(f"{n} {status}" for status, n in sorted(counts.items()))
    print(f"{len(results.rows)} runs ({ran} run now, {len(results.rows) - results.submitted} already done): {summary}")
    for r, row in zip(results.runs, results.rows):
        if row["status"] != "completed":
            print(f"  {r.id} {format_overrides(r.overrides)} {row['status']}: {row['error']}")
    print(f"table: {results.table}")
    return EXIT_UNFINISHED if results.unfinished() else 0
