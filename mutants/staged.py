"""Runs ``make mutants``: every mutant of the physics files through the passes
of ``mutants/groups.toml`` (focused tests, then unit tests, then the whole
Rust suite), then the Python stage on what the Rust tests miss, then the
report.

Each group has its own cargo-mutants output folder under ``--out``. A pass
runs cargo-mutants with ``--iterate`` on the folder the pass before left, so
it tests only what is still missed (and any mutant not tested yet): the
driver lists every mutant its kept outcomes settle (caught or unviable) for
cargo-mutants to skip. Before each run the folder's outcomes are kept under
``history/`` (cargo-mutants replaces ``mutants.out`` on every run), and the
report merges them in order; ``--import`` adds another run's outcomes (a
change's mutants run apart) the same way.
A pass is recorded as done with the list of mutants it covered; an
interrupted run, started again, resumes where it stopped, and a pass whose
mutants have changed since (the source changed) runs again on the new and
the missed ones. A mutant a pass missed is not tested again by that pass or
a narrower one (its tests are a subset), even when the run was interrupted:
the pass under way is recorded before cargo-mutants starts. After new tests,
``--retest-missed`` forgets which passes missed what. So the full set, a day
of one machine, can be run a piece at a time: ``--group NAME`` limits a run
to some groups.
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import shlex
import shutil
import subprocess
import sys
import tomllib
from dataclasses import dataclass
from pathlib import Path

from mutants import python_stage, report
from mutants.outcomes import PYTHON_STAGE_FILE, Mutant, merged, read

ROOT = Path(__file__).resolve().parent.parent
GROUPS = Path(__file__).resolve().parent / "groups.toml"
CONFIG = ROOT / ".cargo" / "mutants.toml"
# The passes, cheapest first: cargo's target arguments from the group's tests.
PASSES = {
    "focused": lambda tests: [f"--test={t}" for t in tests],
    "unit": lambda tests: ["--lib", *(f"--test={t}" for t in tests)],
    "suite": lambda tests: [],
}
# cargo-mutants' exit codes that are results: none missed, some missed,
# some timed out.
RESULTS = (0, 2, 3)


@dataclass
class Group:
    name: str
    files: list[str]
    tests: list[str]


def groups() -> list[Group]:
    """The groups, checked to cover every examined file exactly once."""
    found = [Group(**g) for g in tomllib.loads(GROUPS.read_text())["group"]]
    examined = tomllib.loads(CONFIG.read_text())["examine_globs"]
    sources = [str(p.relative_to(ROOT)) for p in sorted((ROOT / "src").rglob("*.rs"))]
    for source in sources:
        if not any(fnmatch.fnmatch(source, glob) for glob in examined):
            continue
        owners = [g.name for g in found if any(fnmatch.fnmatch(source, glob) for glob in g.files)]
        if len(owners) != 1:
            raise SystemExit(f"{GROUPS}: {source} is in {len(owners)} groups ({', '.join(owners) or 'none'}); it must be in one")
    return found


class GroupRun:
    """One group's output folder: its cargo-mutants runs and their history."""

    def __init__(self, cargo_mutants: Path, out: Path, group: Group, others: list[Group], extra: list[str], jobs: int):
        self.cargo_mutants, self.group, self.extra, self.jobs = cargo_mutants, group, extra, jobs
        # The configuration's examine_globs add to --file, so the group is
        # chosen by leaving the other groups' files out.
        self.excluded = [glob for other in others if other is not group for glob in other.files]
        self.dir = out / group.name
        self.state_path = self.dir / "state.json"

    def _argv(self, *args: str) -> list[str]:
        excluded = [f"--exclude={glob}" for glob in self.excluded]
        return [str(self.cargo_mutants), "mutants", *excluded, *self.extra, *args]

    def mutant_names(self) -> list[str]:
        """The mutants the group has now (cargo-mutants' list, no build)."""
        listed = subprocess.run(self._argv("--list"), cwd=ROOT, check=True, capture_output=True, text=True)
        return sorted(filter(None, listed.stdout.splitlines()))

    def folders(self) -> list[Path]:
        """The kept outcomes in order, then the current ones."""
        kept = sorted((self.dir / "history").glob("*")) if (self.dir / "history").exists() else []
        current = self.dir / "mutants.out"
        return kept + ([current] if (current / "outcomes.json").exists() else [])

    def _keep(self, label: str, current: Path | None = None) -> None:
        """Copies the current outcomes (not the build logs), or another
        folder's, into history/."""
        current = current or self.dir / "mutants.out"
        if not (current / "outcomes.json").exists():
            return
        history = self.dir / "history"
        target = history / f"{len(list(history.glob('*'))) if history.exists() else 0:03d}-{label}"
        target.mkdir(parents=True)
        for name in ("outcomes.json", PYTHON_STAGE_FILE):
            if (current / name).exists():
                shutil.copy2(current / name, target / name)
        if (current / "diff").exists():
            shutil.copytree(current / "diff", target / "diff")

    def import_outcomes(self, folder: Path) -> None:
        """Counts another run's outcomes (e.g. of a change's mutants) as kept
        ones of this group, once."""
        state = self._state()
        key = str(folder.resolve())
        if key in state.get("imported", []):
            return
        self._keep("imported", folder)
        state.setdefault("imported", []).append(key)
        self._save(state)

    def _state(self) -> dict:
        return json.loads(self.state_path.read_text()) if self.state_path.exists() else {}

    def _save(self, state: dict) -> None:
        self.dir.mkdir(parents=True, exist_ok=True)
        self.state_path.write_text(json.dumps(state, indent=1))

    def forget_missed(self) -> None:
        """Forgets which passes missed which mutants and which passes are
        done, so that the missed ones meet every pass again (after new tests)."""
        state = self._state()
        for key in ("missed_by", "running", *PASSES):
            state.pop(key, None)
        self._save(state)

    def _record_missed(self, state: dict, label: str) -> None:
        """Notes the mutants the last cargo-mutants run (pass `label`)
        missed, keeping the widest pass that missed each."""
        current = self.dir / "mutants.out"
        if not (current / "outcomes.json").exists():
            return
        missed_by = state.setdefault("missed_by", {})
        rank = list(PASSES)
        for m in read(current):
            earlier = missed_by.get(m.name)
            if m.summary == "MissedMutant" and (earlier is None or rank.index(earlier) < rank.index(label)):
                missed_by[m.name] = label

    def run(self) -> None:
        """The group's passes that are not done for its current mutants."""
        names = self.mutant_names()
        state = self._state()
        if "running" in state:  # an interrupted pass: count what it missed
            self._record_missed(state, state.pop("running"))
            self._save(state)
        rank = list(PASSES)
        for label, targets in PASSES.items():
            if state.get(label) == names:
                continue
            missed_by = state.get("missed_by", {})
            settled = self.settled() | {n for n, by in missed_by.items() if rank.index(by) >= rank.index(label)}
            still = [n for n in names if n not in settled]
            if not still:
                print(f"{self.group.name}: {label}: nothing left to test", flush=True)
            else:
                print(f"{self.group.name}: {label}: {len(still)} mutants", flush=True)
                self._keep(f"before-{label}")
                # cargo-mutants' --iterate skips the names in this file (and
                # in its last run's caught and unviable lists).
                current = self.dir / "mutants.out"
                current.mkdir(parents=True, exist_ok=True)
                (current / "previously_caught.txt").write_text("".join(f"{n}\n" for n in sorted(settled)))
                cargo_args = [f"--cargo-arg={a}" for a in targets(self.group.tests)]
                argv = self._argv("--output", str(self.dir), "-j", str(self.jobs), *cargo_args, "--iterate")
                print("  " + shlex.join(argv), flush=True)
                state["running"] = label
                self._save(state)
                status = subprocess.run(argv, cwd=ROOT).returncode
                if status not in RESULTS:
                    raise SystemExit(f"{self.group.name}: {label}: cargo-mutants failed (exit {status})")
                self._record_missed(state, state.pop("running"))
            state[label] = names
            self._save(state)

    def settled(self) -> set[str]:
        """The mutants a kept run caught or found unviable."""
        return {m.name for m in merged(self.folders()) if m.summary in ("CaughtMutant", "Unviable", "Failure")}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cargo-mutants", type=Path, required=True, help="the pinned cargo-mutants binary")
    parser.add_argument("--out", type=Path, required=True, help="output folder (one subfolder per group)")
    parser.add_argument("--group", action="append", help="run only these groups (default: all)")
    parser.add_argument("--jobs", type=int, default=1, help="cargo-mutants' parallel builds")
    parser.add_argument("--extra", default="", help="more cargo-mutants options, e.g. '--in-diff change.diff'")
    parser.add_argument("--rust-only", action="store_true", help="leave out the Python stage")
    parser.add_argument("--import", dest="imports", type=Path, action="append", default=[],
                        help="another run's outcome folder whose results count (kept once)")
    parser.add_argument("--retest-missed", action="store_true",
                        help="test the missed mutants through every pass again (after new tests)")
    parser.add_argument("--report", type=Path, default=ROOT / "mutants" / "REPORT.md")
    args = parser.parse_args()
    every = groups()
    chosen = [g for g in every if not args.group or g.name in args.group]
    if args.group and len(chosen) != len(set(args.group)):
        raise SystemExit(f"unknown group in {args.group}; the groups are in {GROUPS}")
    extra = shlex.split(args.extra)
    runs = [GroupRun(args.cargo_mutants, args.out, g, every, extra, args.jobs) for g in chosen]
    for run in runs:
        if args.retest_missed:
            run.forget_missed()
        for folder in args.imports:
            run.import_outcomes(folder)
        run.run()
    folders = [f for run in runs for f in run.folders()]
    names = [n for run in runs for n in run.mutant_names()]
    if not args.rust_only:
        status = python_stage.run(folders)
        if status:
            return status
    described = f"groups {', '.join(g.name for g in chosen)}" + (f", {args.extra}" if args.extra else "")
    return report.write(folders, args.report, described, names)


if __name__ == "__main__":
    sys.exit(main())
