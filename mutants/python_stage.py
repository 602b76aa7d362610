"""Second stage of ``make mutants``: every mutant that survives the Rust tests
against the quick Python checks.

For each mutant cargo-mutants reports as missed, the tracked source tree is
copied to a scratch directory, the mutant's diff applied, the extension built
from it (maturin, release, one cargo target directory for all mutants so that
only quatrot itself is rebuilt), installed into a scratch site directory, and
the Python tests run with that directory first on the path. A failing run
catches the mutant. The unmutated tree goes first, as cargo-mutants' baseline
does: it must pass, and its duration sets the timeout.

Results go to the group's ledger (``mutants/ledger.py``) as pass
``python``; a mutant that already has one is not tried again, so an
interrupted stage resumes.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
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


def _run(argv: list[str], cwd: Path, env: dict | None = None, timeout: float | None = None) -> bool:
    """Runs ``argv``; true when it exits 0 (output to the terminal's log)."""
    result = subprocess.run(argv, cwd=cwd, env=env, timeout=timeout, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return result.returncode == 0


def _build_and_test(scratch: Path, tree: Path, timeout: float | None) -> str:
    """Builds the extension from ``tree`` and runs the Python tests against it:
    "passed", "failed", "unviable" (no build) or "timeout"."""
    wheels, site = scratch / "wheels", scratch / "site"
    for d in (wheels, site):
        shutil.rmtree(d, ignore_errors=True)
    env = dict(os.environ, CARGO_TARGET_DIR=str(ROOT / "target" / "mutants-python"))
    deadline = None if timeout is None else time.monotonic() + timeout

    def left() -> float | None:
        return None if deadline is None else max(1.0, deadline - time.monotonic())

    try:
        built = _run(["maturin", "build", "--release", "--quiet", "--out", str(wheels)], tree, env, left())
        wheel = next(wheels.glob("*.whl"), None)
        if not built or wheel is None:
            return "unviable"
        if not _run([sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--target", str(site), str(wheel)], ROOT, env, left()):
            return "unviable"
        env["PYTHONPATH"] = os.pathsep.join([str(site), str(ROOT)])
        passed = _run([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", *PYTHON_TESTS], ROOT, env, left())
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


def run(groups: list[tuple[Ledger, dict[str, str]]]) -> int:
    """The Python checks on every mutant of each group (its ledger, and its
    mutants now, name to diff) that the whole Rust suite missed and that
    has no Python result yet; each outcome written to the ledger as pass
    ``python``. 0 unless the unmutated tree fails them."""
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
    scratch = ROOT / "target" / "mutants-python-scratch"
    start = time.monotonic()
    baseline = _build_and_test(scratch, sync_tree(scratch / "tree"), None)
    baseline_seconds = time.monotonic() - start
    if baseline != "passed":
        print(f"python stage: the unmutated tree does not pass ({baseline})", file=sys.stderr)
        return 1
    timeout = max(MINIMUM_TIMEOUT, TIMEOUT_MULTIPLIER * baseline_seconds)
    print(f"python stage: baseline {baseline_seconds:.0f} s; {len(missed)} mutants, timeout {timeout:.0f} s each")
    for k, (ledger, name, diff, key) in enumerate(missed, 1):
        start = time.monotonic()
        tree = sync_tree(scratch / "tree")
        if not _apply(tree, name, diff):
            raise SystemExit(f"python stage: the diff of {name} does not apply to the source")
        outcome = OUTCOMES[_build_and_test(scratch, tree, timeout)]
        seconds = time.monotonic() - start
        ledger.record(name, key, outcome, "python", round(seconds, 1))
        ledger.save()
        print(f"  [{k}/{len(missed)}] {outcome:9} {seconds:5.0f} s  {name}", flush=True)
    return 0
