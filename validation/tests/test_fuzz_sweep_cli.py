"""A seeded fuzz of the sweep's command line (issue 37, item 10): random
base scenes (built-in, a file, missing, malformed), grids and cases (hostile
paths and TOML literals, empty and huge grids, values of the wrong type),
option values (thread and worker counts, unknown options, bad folders),
mostly as `--dry-run`, and real runs of tiny grids on one in-process Dask
scheduler. Most cases call `quatrot.sweep.cli.main` in this process; every
`SUBPROCESS_EVERY`-th runs `quatrot sweep` as a user does (argv bytes that
are not UTF-8 included).

Asserted for every case: no exception escapes `main` and no stderr holds a
traceback; its exit code is a documented one (0; 1 only for runs that
`failed`, which these grids must not make: every error a scene causes is a
final `scene_error`; 2 for a bad command line, its stderr ending in an
`error:` line); no case takes longer than its bound; nothing outside the
sweep's folder changes; a results table that exists is whole (every row has
every column, one row per run, statuses known). Sizes and seed: `fuzzing`."""

from __future__ import annotations

import contextlib
import csv
import io
import os
import subprocess
import sys
import time
from pathlib import Path

import distributed
import pytest

from fuzzing import TINY, Failures, cases, changes, pick, tree
from quatrot.sweep.cli import main as sweep_main
from quatrot.sweep.table import FINISHED, HEAD, TAIL

CASES = 80
#: Every this many cases runs as a separate `quatrot sweep` process.
SUBPROCESS_EVERY = 40
#: The longest a dry run or a refusal may take, and a real run of a grid of
#: at most five runs of 20 steps (seconds; the slowest seen take 2 s and 4 s).
DRY_BOUND, REAL_BOUND = 30.0, 60.0


#: Scene field paths, and words that are not paths.
PATHS = (
    "run.dt", "run.steps", "run.time", "initial.seed", "initial.kind", "initial.temperature", "integrator.kind",
    "integrator.substeps", "fields.uniform", "rotors.default.inertia", "rotors.sites[0].position", "rotors.sites[5]",
    "name", "version", "run", "record.series[0].every", "run.dt", "initial.seed", "run.steps", "integrator.kind",
    "a..b", "bad path", "", "x[99]", "run.dt[0]", "é", "a\x1b[31mb",
)
#: Values a TOML literal or a bare word gives: numbers, text and tables of
#: every type a scene field may refuse.
LITERALS = (
    "0.01", "0.005", "1e-320", "1e308", "nan", "inf", "-1", "0", "20", "1.5", "true", '"s"', "[0.0, 0.0, 1.0]", "[]",
    '{ kind = "dlm" }', "gear_b", "dlm", "no_squish", "random", "3/16", "9" * 400, "-0.0", "2", "[[[[1]]]]",
    '"a\\u001b[31mb"', '"\\u0000"', "é", "x" * 5000, '"../../x"', '"/tmp/abs"',
)
#: Words that are neither (refused with exit 2).
BROKEN = ("", "'", "[", '"unterminated', "1e999", "{ = }", "a\x1b[31mb\n", "\x00", "bad\ud800text", " ")
OPTION_VALUES = ("1", "2", "0", "-1", "1025", "1000000000", "99999999999999999999", "1.5", "x", "", "١")


def literal(rng) -> str:
    return pick(rng, BROKEN if rng.random() < 0.03 else LITERALS)


def values(rng, most: int) -> str:
    return ",".join(literal(rng) for _ in range(int(rng.integers(1, most + 1))))


def command_line(rng, real: bool) -> tuple[list[str], str]:
    """A random command line and its `--out`; `real` ones run a small grid
    of `TINY`."""
    scene = "tiny.toml" if real else pick(
        rng, ("dipole_in_field", "tiny.toml", "missing.toml", "", "bad.toml", "folder", "no_such_scene", "tiny.toml")
    )
    argv = [scene] if rng.random() > 0.03 else []
    for _ in range(int(rng.integers(0, 3 if real else 4))):
        argv += ["--set", f"{pick(rng, PATHS)}={values(rng, 2 if real else 5)}"]
    if rng.random() < 0.3:
        argv += ["--case", ";".join(f"{pick(rng, PATHS)}={literal(rng)}" for _ in range(int(rng.integers(0, 3))))]
    if not real and rng.random() < 0.1:  # a huge grid: refused before anything is made
        argv += ["--set", "initial.seed=" + ",".join(map(str, range(1000))), "--set", "run.steps=" + ",".join(map(str, range(1, 400)))]
    out = pick(rng, ("out", "out", "deep/er/out", "file.txt", "file.txt/out", "", "."))
    if rng.random() > 0.03:
        argv += ["--out", out]
    if real:
        out = pick(rng, ("out", "deep/er/out", ""))
        return argv + ["--out", out], out
    for option in ("--threads-per-run", "--workers"):
        if rng.random() < 0.2:
            argv += [option, pick(rng, OPTION_VALUES)]
    if rng.random() < 0.05:
        argv += [pick(rng, ("--frobnicate", "-x", "--set", "--dry-run=yes", "--scheduler"))]
    return argv + ["--dry-run"], out


def run_in_process(argv: list[str]) -> tuple[int, str, str]:
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        try:
            code = sweep_main(argv)
        except SystemExit as e:  # argparse: --help, or a bad option
            code = e.code
    return code, stdout.getvalue(), stderr.getvalue()


def run_as_user(argv: list[str], work: Path, rng) -> tuple[int, str, str]:
    """`quatrot sweep ARGV` or `python -m quatrot.sweep ARGV`, sometimes
    with a word that is not UTF-8 (as a shell may pass)."""
    args = [os.fsencode(a) for a in argv]
    if rng.random() < 0.5:
        args.insert(int(rng.integers(len(args) + 1)), b"--set=run.dt=\xff\xfe")
    command = pick(rng, (["-m", "quatrot", "sweep"], ["-m", "quatrot.sweep"]))
    env = {**os.environ, "QUATROT_PYTHON": sys.executable}
    p = subprocess.run([sys.executable, *command, *args], cwd=work, env=env, capture_output=True, timeout=DRY_BOUND * 2)
    return p.returncode, p.stdout.decode(errors="replace"), p.stderr.decode(errors="replace")


def table_problems(out: Path, stdout: str) -> list[str]:
    """What is wrong with the sweep's table, if it exists."""
    path = out / "results.csv"
    if not path.exists():
        return []
    with path.open(newline="") as f:
        rows = list(csv.reader(f))
    head, body = rows[0], rows[1:]
    problems = [f"row {k + 1} has {len(r)} cells for {len(head)} columns" for k, r in enumerate(body) if len(r) != len(head)]
    if head[:3] != list(HEAD) or head[-len(TAIL) :] != list(TAIL):
        problems.append(f"columns {head}")
    statuses = {r[1] for r in body}
    if not statuses <= FINISHED | {"failed"}:
        problems.append(f"statuses {statuses}")
    listed = [line for line in stdout.splitlines() if " runs (" in line]
    if listed and int(listed[-1].split()[0]) != len(body):
        problems.append(f"{len(body)} rows where the command said {listed[-1]}")
    return problems


def judge(code, stdout: str, stderr: str, real: bool) -> str | None:
    if "Traceback" in stderr:
        return "a traceback reached the user"
    if code == 1 and real:
        return "exit 1: a run failed (every error a scene causes must be a final scene_error)"
    if code not in (0, 1, 2):
        return f"exit code {code!r}"
    if any(not c.isprintable() for c in stderr.replace("\n", "")):
        return "control characters in stderr"
    if code == 2 and not [line for line in stderr.splitlines() if "error:" in line]:
        return "exit 2 without an error line"
    if code == 0 and stderr.strip() and not real:
        return "a dry run that succeeded printed to stderr"
    return None


@pytest.fixture(scope="module")
def scheduler():
    """One scheduler with one in-process worker thread for the real runs."""
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        yield cluster.scheduler_address


def test_random_sweep_command_lines_end_with_a_documented_exit_and_no_traceback(tmp_path: Path, scheduler):
    failures, home = Failures(), os.getcwd()
    for case, rng in cases("sweep_cli", CASES):
        work = tmp_path / f"case{case}"
        work.mkdir()
        (work / "tiny.toml").write_text(TINY)
        (work / "bad.toml").write_text(TINY.replace("[run]", "[run]\ndt = 3") if rng.random() < 0.5 else "version = [")
        (work / "file.txt").write_text("a user's file")
        (work / "folder").mkdir()
        real = case % 4 == 3
        argv, out = command_line(rng, real)
        if real:
            argv += ["--scheduler", scheduler]
        folder = work / out if out else None  # "" must be refused, not be `work`
        before = tree(work, skip=folder)
        os.chdir(work)
        start = time.perf_counter()
        try:
            as_user = case % SUBPROCESS_EVERY == SUBPROCESS_EVERY - 1
            code, stdout, stderr = run_as_user(argv, work, rng) if as_user else run_in_process(argv)
        except Exception as e:  # noqa: BLE001 (the failure is that it escaped)
            failures.add(case, f"{type(e).__name__} escaped: {e}", argv)
            continue
        finally:
            os.chdir(home)
        seconds = time.perf_counter() - start
        shown = f"argv: {argv}\nexit {code}\nstdout: {stdout[-2000:]}\nstderr: {stderr[-3000:]}"
        why = judge(code, stdout, stderr, real)
        if why:
            failures.add(case, why, shown)
        if seconds > (REAL_BOUND if real else DRY_BOUND):
            failures.add(case, f"took {seconds:.1f} s", shown)
        parents = {str(p) for p in Path(out).parents}  # made for the folder
        outside = [p for p in changes(before, tree(work, skip=folder)) if p not in parents]
        if outside:
            failures.add(case, f"changed outside the sweep's folder: {outside}", shown)
        problems = table_problems(folder, stdout) if folder else []
        if problems:
            failures.add(case, f"the table is not whole: {problems}", shown)
    failures.report()
