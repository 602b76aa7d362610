"""A seeded fuzz of output folders seeded with symbolic links (issue 37,
item 10): each case replaces a random subset of the names a run or a sweep
writes (the outputs, their `.partial` names, the lock, a sweep's `runs/`,
its table and the run folders in `runs/`) by links to files and folders
outside the folder, dangling links and links to links, then runs, restarts,
sweeps or resumes a sweep in it. Asserted for every case: nothing outside
the folder changes (its tree hashed before and after); the program either
succeeds (replacing the links it writes at) or refuses naming a planted
name (a run: exit 2; a sweep: exit 2, or 1 with the refused runs `failed`
naming theirs); no traceback or panic. Sizes and seed: `fuzzing`."""

from __future__ import annotations

import contextlib
import csv
import io
import os
import subprocess
import sys
from pathlib import Path

import distributed
import pytest

import quatrot.sweep
from fuzzing import TINY, Failures, cases, changes, pick, tree
from quatrot.sweep.cli import main as sweep_main

CASES = 16
#: Seconds a run or a sweep of this test may take (the slowest seen: 3 s).
BOUND = 60

#: `TINY` writing every kind of output: a trajectory and checkpoints.
SCENE = TINY + """[record]
checkpoint_every = 10
[record.trajectory]
every = 5
format = "FORMAT"
"""
RUN_NAMES = (
    "energies.csv", "topology.pdb", "trajectory.dcd", "trajectory.gsd", "checkpoint.json", "summary.json",
    "checkpoint.json.partial", "summary.json.partial", "trajectory.gsd.partial", ".quatrot.lock",
    "summary.until-10.json", "restart-10",
)
SWEEP_NAMES = ("results.csv", ".quatrot.lock", "runs", "runs/{id}", "runs/{id}/result.json", "runs/{id}/energies.csv", "runs/{id}/.quatrot.lock")
GRID = ["--set", "run.dt=0.01,0.005"]


def outside(work: Path) -> Path:
    """The files and folders the links point at, beside the output folder."""
    there = work / "outside"
    (there / "folder").mkdir(parents=True)
    (there / "folder" / "keep.txt").write_text("a user's file in a folder")
    (there / "victim.txt").write_text("a user's file")
    (there / "link-to-victim").symlink_to(there / "victim.txt")
    return there


def plant(rng, folder: Path, names: list[str], there: Path) -> list[str]:
    """Replaces a random subset of `names` in `folder` by links; returns them."""
    chosen = [n for n in names if rng.random() < 0.3] or [pick(rng, names)]
    planted = []
    for name in chosen:
        path = folder / name
        if any(p.is_symlink() for p in path.parents) or (path.is_dir() and not path.is_symlink()):
            continue  # under a planted link; or a real folder of outputs, whose files may be planted
        if path.is_symlink() or path.is_file():
            path.unlink()
        path.parent.mkdir(parents=True, exist_ok=True)
        planted.append(name)
        path.symlink_to(pick(rng, (there / "victim.txt", there / "folder", there / "missing", there / "link-to-victim", there / "missing-folder/x")))
    return planted


def quatrot_run(work: Path, *args: str) -> tuple[int, str]:
    p = subprocess.run([sys.executable, "-m", "quatrot", "run", *args], cwd=work, capture_output=True, text=True, timeout=BOUND)
    return p.returncode, p.stderr


def sweep(argv: list[str]) -> tuple[int, str]:
    stderr = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(stderr):
        code = sweep_main(argv)
    return code, stderr.getvalue()


def run_case(rng, work: Path, there: Path, restart: bool) -> tuple[int, str, list[str], Path]:
    scene = work / "scene.toml"
    scene.write_text(SCENE.replace("FORMAT", pick(rng, ("dcd", "gsd"))))
    out = work / "out"
    out.mkdir()
    if restart:
        code, stderr = quatrot_run(work, str(scene), "--out", str(out))
        assert code == 0, stderr
    planted = plant(rng, out, list(RUN_NAMES), there)
    args = ["--restart", str(out / "checkpoint.json")] if restart else []
    code, stderr = quatrot_run(work, str(scene), "--out", str(out), *args)
    return code, stderr, planted, out


def sweep_case(rng, work: Path, there: Path, resume: bool, scheduler: str) -> tuple[int, str, list[str], Path]:
    (work / "tiny.toml").write_text(TINY)
    out = work / "sweep"
    argv = [str(work / "tiny.toml"), *GRID, "--out", str(out), "--scheduler", scheduler]
    if resume:
        code, stderr = sweep(argv)
        assert code == 0, stderr
    ids = [r.id for r in quatrot.sweep.expand(TINY, {"run.dt": [0.01, 0.005]})]
    names = [n.format(id=pick(rng, ids)) for n in SWEEP_NAMES]
    out.mkdir(exist_ok=True)
    planted = plant(rng, out, names, there)
    code, stderr = sweep(argv)
    return code, stderr, planted, out


def failed_rows_name_links(out: Path, planted: list[str]) -> bool:
    """Whether every `failed` row of the table names a planted link."""
    with (out / "results.csv").open(newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "failed"]
    return bool(rows) and all(any(p.split("/")[-1] in r["error"] for p in planted) for r in rows)


@pytest.fixture(scope="module")
def scheduler():
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        yield cluster.scheduler_address


def test_links_planted_in_output_folders_are_refused_or_replaced_never_followed(tmp_path: Path, scheduler):
    failures = Failures()
    for case, rng in cases("output_links", CASES):
        work = tmp_path / f"case{case}"
        there = outside(work)
        before = tree(there)
        kind = ("run", "restart", "sweep", "resume")[case % 4]
        if kind in ("run", "restart"):
            code, stderr, planted, out = run_case(rng, work, there, kind == "restart")
        else:
            code, stderr, planted, out = sweep_case(rng, work, there, kind == "resume", scheduler)
        shown = f"{kind}, links at {planted}: exit {code}\n{stderr[-3000:]}"
        names_one = any(p.split("/")[-1] in stderr for p in planted)
        if changes(before, tree(there)):
            failures.add(case, f"changed outside the folder: {changes(before, tree(there))}", shown)
        elif "Traceback" in stderr or "panicked" in stderr:
            failures.add(case, "a traceback or a panic", shown)
        elif code == 2 and not names_one:
            failures.add(case, "refused without naming a planted link", shown)
        elif code == 1 and not (kind in ("sweep", "resume") and failed_rows_name_links(out, planted)):
            failures.add(case, "exit 1 with a failed run that names no link", shown)
        elif code not in (0, 1, 2):
            failures.add(case, f"exit code {code}", shown)
    failures.report()
