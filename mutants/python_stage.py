"""Second stage of ``make mutants``: every mutant that survives the Rust tests
against the quick Python checks.

For each mutant cargo-mutants reports as missed, the tracked source tree is
copied to a scratch directory, the mutant's diff applied, the extension built
from it (maturin, release), installed into a scratch site directory, and the
Python tests run with that directory first on the path. A failing run
catches the mutant. The unmutated tree goes first, as cargo-mutants' baseline
does: it must pass, and its duration sets the timeout.

With ``--jobs`` above 1, as many workers take mutants from one queue, each in
its own scratch directory with its own cargo target directory (kept between
runs, so that only quatrot itself is rebuilt): one worker's Python tests,
single-threaded, run while another builds.

Results go to the group's ledger (``mutants/ledger.py``) as pass
``python``; a mutant that already has one is not tried again, so an
interrupted stage resumes.
"""

from __future__ import annotations

import os
import queue
import shutil
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from mutants.ledger import Ledger, hashes
from mutants.worktree import sync_tree

ROOT = Path(__file__).resolve().parent.parent
PYTHON_TESTS = ["validation/tests"]
# A mutant whose build and checks take this many times the baseline's is a
# timeout (as in cargo-mutants' own stage).
TIMEOUT_MULTIPLIER = 5.0
MINIMUM_TIMEOUT = 300.0
# What a build-and-test result makes of a mutant that survived the Rust tests.
OUTCOMES = {"passed": "missed", "failed": "caught", "unviable": "unviable", "timeout": "timeout"}


def _run(argv: list[str], cwd: Path, log: Path, env: dict | None = None, timeout: float | None = None) -> bool:
    """Runs ``argv``, its output appended to ``log``; true when it exits 0."""
    with log.open("a") as out:
        out.write(f"$ {' '.join(argv)}\n")
        out.flush()
        result = subprocess.run(argv, cwd=cwd, env=env, timeout=timeout, stdout=out, stderr=subprocess.STDOUT)
    return result.returncode == 0


def _build_and_test(scratch: Path, tree: Path, timeout: float | None) -> str:
    """Builds the extension from ``tree`` and runs the Python tests against it,
    in the worker's ``scratch`` directory: "passed", "failed", "unviable" (no
    build) or "timeout". The commands' output goes to ``scratch/log`` (the
    last mutant's, or the baseline's when it fails)."""
    wheels, site, log = scratch / "wheels", scratch / "site", scratch / "log"
    for d in (wheels, site):
        shutil.rmtree(d, ignore_errors=True)
    scratch.mkdir(parents=True, exist_ok=True)
    log.unlink(missing_ok=True)
    env = dict(os.environ, CARGO_TARGET_DIR=str(scratch / "target"))
    deadline = None if timeout is None else time.monotonic() + timeout

    def left() -> float | None:
        return None if deadline is None else max(1.0, deadline - time.monotonic())

    try:
        built = _run(["maturin", "build", "--release", "--quiet", "--out", str(wheels)], tree, log, env, left())
        wheel = next(wheels.glob("*.whl"), None)
        if not built or wheel is None:
            return "unviable"
        if not _run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--target", str(site), str(wheel)], ROOT, log, env, left()):
            return "unviable"
        env["PYTHONPATH"] = os.pathsep.join([str(site), str(ROOT)])
        passed = _run([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", *PYTHON_TESTS], ROOT, log, env, left())
    except subprocess.TimeoutExpired:
        return "timeout"
    return "passed" if passed else "failed"


def _apply(tree: Path, name: str, diff: str) -> bool:
    """Applies a mutant's diff to its file (cargo-mutants' diffs name the
    file on the `---` line only, so the file is given to patch)."""
    file = name.split(":", 1)[0]
    result = subprocess.run(["patch", "--quiet", "--forward", file], cwd=tree, input=diff, text=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return result.returncode == 0


def run(groups: list[tuple[Ledger, dict[str, str]]], jobs: int = 1) -> int:
    """The Python checks on every mutant of each group (its ledger, and its
    mutants now, name to diff) that the whole Rust suite missed and that
    has no Python result yet, by ``jobs`` workers; each outcome written to
    the ledger as pass ``python`` as it comes. 0 unless the unmutated tree
    fails them."""
    keyed = [(ledger, listing, hashes(listing)) for ledger, listing in groups]
    missed = [
        (ledger, name, listing[name], keys[name])
        for ledger, listing, keys in keyed
        for name, entry in sorted(ledger.current(keys).items())
        if entry.outcome == "missed" and entry.pass_ == "suite"
    ]
    if not missed:
        print("python stage: no mutant left to try")
        return 0
    scratches = [ROOT / "target" / "mutants-python-scratch" / str(k) for k in range(jobs)]
    start = time.monotonic()
    baseline = _build_and_test(scratches[0], sync_tree(scratches[0] / "tree"), None)
    baseline_seconds = time.monotonic() - start
    if baseline != "passed":
        print(f"python stage: the unmutated tree does not pass ({baseline}): see {scratches[0] / 'log'}", file=sys.stderr)
        return 1
    timeout = max(MINIMUM_TIMEOUT, TIMEOUT_MULTIPLIER * baseline_seconds)
    print(f"python stage: baseline {baseline_seconds:.0f} s; {len(missed)} mutants, {jobs} workers, "
          f"timeout {timeout:.0f} s each")
    waiting: queue.SimpleQueue = queue.SimpleQueue()
    for k, item in enumerate(missed, 1):
        waiting.put((k, item))
    recording, stop = threading.Lock(), threading.Event()

    def work(scratch: Path) -> None:
        while not stop.is_set():
            try:
                k, (ledger, name, diff, key) = waiting.get_nowait()
            except queue.Empty:
                return
            start = time.monotonic()
            tree = sync_tree(scratch / "tree")
            if not _apply(tree, name, diff):
                stop.set()
                raise SystemExit(f"python stage: the diff of {name} does not apply to the source")
            outcome = OUTCOMES[_build_and_test(scratch, tree, timeout)]
            seconds = time.monotonic() - start
            with recording:
                ledger.record(name, key, outcome, "python", round(seconds, 1))
                ledger.save()
                print(f"  [{k}/{len(missed)}] {outcome:9} {seconds:5.0f} s  {name}", flush=True)

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        workers = [pool.submit(work, scratch) for scratch in scratches]
    for worker in workers:
        worker.result()
    return 0
