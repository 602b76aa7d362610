"""Second stage of ``make mutants``: every mutant that survives the Rust tests
against the quick Python checks.

For each mutant cargo-mutants reports as missed, the tracked source tree is
copied to a scratch directory, the mutant's diff applied, the extension built
from it (maturin, release, one cargo target directory for all mutants so that
only quatrot itself is rebuilt), installed into a scratch site directory, and
the Python tests run with that directory first on the path. A failing run
catches the mutant. The unmutated tree goes first, as cargo-mutants' baseline
does: it must pass, and its duration sets the timeout.

Results: ``python_stage.json`` in the outcome folder each mutant comes from;
a mutant that already has a result there is not tried again, so an
interrupted stage resumes.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

from mutants.outcomes import PYTHON_STAGE_FILE, Mutant, merged, read_python_stage

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


def _copy_tree(scratch: Path) -> Path:
    """A fresh copy of the files git tracks, at the same path every time."""
    tree = scratch / "tree"
    shutil.rmtree(tree, ignore_errors=True)
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, check=True, capture_output=True, text=True).stdout
    for name in filter(None, files.split("\0")):
        target = tree / name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, target)
    return tree


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


def _apply(tree: Path, mutant: Mutant) -> bool:
    """Applies the mutant's diff to its file (cargo-mutants' diffs name the
    file on the `---` line only, so the file is given to patch)."""
    if mutant.diff_path is None:
        return False
    return _run(["patch", "--quiet", "--forward", mutant.file, str(mutant.diff_path)], tree)


def run(out_dirs: list[Path]) -> int:
    """The Python checks on every mutant the merged Rust outcomes of
    ``out_dirs`` leave missed and that has no result yet; 0 unless the
    unmutated tree fails them."""
    out_dirs = [d.resolve() for d in out_dirs]
    records = {d: read_python_stage(d) for d in out_dirs}
    done = {name for r in records.values() for name in r["mutants"]}
    missed: list[Mutant] = [m for m in merged(out_dirs) if m.summary == "MissedMutant" and m.name not in done]
    if not missed:
        print("python stage: no mutant left to try")
        return 0
    scratch = ROOT / "target" / "mutants-python-scratch"
    start = time.monotonic()
    baseline = _build_and_test(scratch, _copy_tree(scratch), None)
    baseline_seconds = time.monotonic() - start
    if baseline != "passed":
        print(f"python stage: the unmutated tree does not pass ({baseline})", file=sys.stderr)
        return 1
    timeout = max(MINIMUM_TIMEOUT, TIMEOUT_MULTIPLIER * baseline_seconds)
    print(f"python stage: baseline {baseline_seconds:.0f} s; {len(missed)} mutants, timeout {timeout:.0f} s each")
    for k, mutant in enumerate(missed, 1):
        start = time.monotonic()
        tree = _copy_tree(scratch)
        if not _apply(tree, mutant):
            outcome = "unapplied"
        else:
            outcome = OUTCOMES[_build_and_test(scratch, tree, timeout)]
        seconds = time.monotonic() - start
        record = records[mutant.folder]
        record["baseline_seconds"] = baseline_seconds
        record["mutants"][mutant.name] = {"outcome": outcome, "seconds": seconds}
        print(f"  [{k}/{len(missed)}] {outcome:9} {seconds:5.0f} s  {mutant.name}", flush=True)
        (mutant.folder / PYTHON_STAGE_FILE).write_text(json.dumps(record, indent=1))
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dirs", type=Path, nargs="+", help="cargo-mutants' outcome folders, in order")
    args = parser.parse_args()
    return run([d.resolve() for d in args.out_dirs])


if __name__ == "__main__":
    sys.exit(main())
