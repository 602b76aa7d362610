"""Runs ``make mutants``: every mutant of the physics files through the passes
of ``mutants/groups.toml`` (focused tests, then unit tests, then the whole
Rust suite), then the Python stage on what the Rust tests miss, then the
report.

What became of each mutant is kept in ``mutants/outcomes/<group>.json``
(``mutants/ledger.py``), a file committed with the project: a pass tests
only the mutants of the group that no pass has settled (caught, unviable or
timed out) and that no pass as wide or wider has missed, and it records
each outcome as cargo-mutants reports it, so a run stopped at any point (a
session's end, another machine) resumes where it stopped. A mutant whose
code or context changed is tested again. ``--retest-missed`` forgets the
misses of the mutants the run chooses (after new tests; ``--extra`` options
such as ``--exclude`` or ``--in-diff`` narrow it). ``--group NAME`` limits a run to some groups.

cargo-mutants mutates in place (``--in-place``) in ``--jobs`` work trees of
its own under ``target/mutants-trees``, each a copy of the tracked files
whose build stays warm from pass to pass and group to group, each taking
one round-robin shard of the pass's mutants; a copy is brought up to date
by rewriting only the files that differ, so cargo rebuilds only what
changed.
"""

from __future__ import annotations

import argparse
import fnmatch
import json
import shlex
import shutil
import signal
import subprocess
import sys
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

from mutants import python_stage, report
from mutants.ledger import PASSES, Ledger, diffs, hashes
from mutants.worktree import sync_tree

ROOT = Path(__file__).resolve().parent.parent
GROUPS = Path(__file__).resolve().parent / "groups.toml"
CONFIG = ROOT / ".cargo" / "mutants.toml"
TREES = ROOT / "target" / "mutants-trees"
# cargo's target arguments of each Rust pass, from the group's tests.
TARGETS = {
    "focused": lambda tests: [f"--test={t}" for t in tests],
    "unit": lambda tests: ["--lib", *(f"--test={t}" for t in tests)],
    "suite": lambda tests: [],
}
assert tuple(TARGETS) == PASSES[:-1]
# cargo-mutants' exit codes that are results: none missed, some missed,
# some timed out.
RESULTS = (0, 2, 3)
# cargo-mutants' exit code when the unmutated tree does not build or pass.
BASELINE_FAILED = 4
# How often a running pass's outcomes are written to the ledger, and how
# often the driver looks whether its cargo-mutants processes have ended.
HARVEST_SECONDS = 30.0
POLL_SECONDS = 1.0


def clean_build(tree: Path) -> None:
    """Removes the project's own build products of the mutation profile from
    a work tree (its dependencies stay built)."""
    profile = tomllib.loads(CONFIG.read_text())["profile"]
    subprocess.run(["cargo", "clean", "--quiet", "-p", "quatrot", "--profile", profile], cwd=tree, check=True)


def rooted(extra: list[str]) -> list[str]:
    """The extra cargo-mutants options with the file of ``--in-diff`` made
    absolute: the passes run in the work trees, not in the source tree."""
    out, follows = [], False
    for arg in extra:
        if follows:
            arg = str((ROOT / arg).resolve())
        elif arg.startswith("--in-diff="):
            arg = "--in-diff=" + str((ROOT / arg.split("=", 1)[1]).resolve())
        follows = arg == "--in-diff"
        out.append(arg)
    return out


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
    """One group's passes, recorded in its ledger."""

    def __init__(self, cargo_mutants: Path, out: Path, group: Group, others: list[Group], extra: list[str], jobs: int,
                 ledger: Ledger | None = None, trees: Path = TREES, first_pass: str = PASSES[0]):
        self.cargo_mutants, self.group, self.extra, self.jobs = cargo_mutants.resolve(), group, extra, jobs
        # The Rust passes before this one are left out: each pass runs the
        # narrower passes' tests too, so starting later misses nothing.
        self.first_pass = first_pass
        # The configuration's examine_globs add to --file, so the group is
        # chosen by leaving the other groups' files out.
        self.excluded = [glob for other in others if other is not group for glob in other.files]
        self.dir = out.resolve() / group.name
        self.ledger = ledger or Ledger.of_group(group.name)
        self.trees = [trees / str(k) for k in range(jobs)]
        self.keys: dict[str, str] = {}  # the group's mutants now, name to key (set by run)

    def _argv(self, *args: str) -> list[str]:
        excluded = [f"--exclude={glob}" for glob in self.excluded]
        return [str(self.cargo_mutants), "mutants", *excluded, *args]

    def listing(self) -> dict[str, str]:
        """Every mutant the group has now, name to diff (no build)."""
        listed = subprocess.run(self._argv("--list", "--json"), cwd=ROOT, check=True, capture_output=True, text=True)
        return diffs(json.loads(listed.stdout))

    def chosen(self) -> list[str]:
        """The mutants this run may test: all of the group's, or those the
        extra options (e.g. ``--in-diff``) choose."""
        listed = subprocess.run(self._argv(*self.extra, "--list"), cwd=ROOT, check=True, capture_output=True, text=True)
        return sorted(filter(None, listed.stdout.splitlines()))

    def to_test(self, label: str, keys: dict[str, str], chosen: list[str]) -> list[str]:
        """The chosen mutants pass ``label`` must try: not settled, and not
        missed by it or a wider pass."""
        current = self.ledger.current(keys)
        return [n for n in chosen if n not in current or not (current[n].settled() or current[n].missed_by_at_least(label))]

    def run(self, keys: dict[str, str]) -> None:
        """The group's Rust passes, each on what the ones before left;
        ``keys``, the group's mutants now, name to diff hash."""
        chosen = self.chosen()
        self.keys = keys
        self.ledger.save(keys)  # drops the outcomes of mutants since changed
        for label, targets in TARGETS.items():
            if PASSES.index(label) < PASSES.index(self.first_pass):
                continue
            still = self.to_test(label, keys, chosen)
            if not still:
                print(f"{self.group.name}: {label}: nothing left to test", flush=True)
                continue
            print(f"{self.group.name}: {label}: {len(still)} mutants", flush=True)
            self._pass(label, targets(self.group.tests), sorted(set(keys) - set(still)))

    def _pass(self, label: str, targets: list[str], skip: list[str]) -> None:
        """One cargo-mutants process a work tree, each on its shard of the
        mutants not in ``skip``, their outcomes written to the ledger as
        they come. A shard whose unmutated baseline does not build or pass is run
        once more after its tree's own build is cleaned: in a tree kept warm
        for hours the incremental cache can go stale (seen: the link of a
        test failing on an undefined ``anon.*.llvm`` symbol of the library),
        while a source that does not build or pass fails again and stops the
        run."""
        failed = self._shards(label, targets, skip, range(self.jobs))
        stale = [k for k, code in failed.items() if code == BASELINE_FAILED]
        if stale:
            for k in stale:
                log = self.dir / f"shard-{k}" / "driver.log"
                log.replace(self.dir / f"shard-{k}-baseline-failed.log")
                print(f"  shard {k}: the baseline failed; cleaning {self.trees[k]} and trying again", flush=True)
                clean_build(self.trees[k])
            retried = self._shards(label, targets, skip, stale)
            failed = {k: code for k, code in failed.items() if k not in stale} | retried
        for k, code in sorted(failed.items()):
            raise SystemExit(f"{self.group.name}: {label}: cargo-mutants failed (exit {code}, {self.dir}/shard-{k}/driver.log)")

    def _shards(self, label: str, targets: list[str], skip: list[str], shards) -> dict[int, int]:
        """Runs cargo-mutants on ``shards`` side by side; the exit codes of
        those that did not end with a result."""
        processes, outs = {}, []
        for k in shards:
            tree = self.trees[k]
            sync_tree(tree)
            out = self.dir / f"shard-{k}"
            shutil.rmtree(out, ignore_errors=True)
            # cargo-mutants' --iterate skips the names in this file.
            (out / "mutants.out").mkdir(parents=True)
            (out / "mutants.out" / "previously_caught.txt").write_text("".join(f"{n}\n" for n in skip))
            argv = self._argv(*self.extra, "--in-place", "--output", str(out.resolve()), "--iterate",
                              f"--shard={k}/{self.jobs}", "--sharding=round-robin",
                              *(f"--cargo-arg={a}" for a in targets))
            print("  " + shlex.join(argv), flush=True)
            with open(out / "driver.log", "w") as log:
                processes[k] = subprocess.Popen(argv, cwd=tree, stdout=log, stderr=subprocess.STDOUT)
            outs.append(out / "mutants.out")
        try:
            harvested = time.monotonic()
            while any(p.poll() is None for p in processes.values()):
                time.sleep(POLL_SECONDS)
                if time.monotonic() - harvested >= HARVEST_SECONDS:
                    self._harvest(outs, label)
                    harvested = time.monotonic()
        finally:
            for p in processes.values():  # stopped early (a mutated file left in a tree is restored by its next sync)
                if p.poll() is None:
                    p.terminate()
                    p.wait()
            self._harvest(outs, label)
        return {k: p.returncode for k, p in processes.items() if p.returncode not in RESULTS}

    def _harvest(self, outs: list[Path], label: str) -> None:
        for out in outs:
            self.ledger.harvest(out, label, self.keys)
        self.ledger.save()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cargo-mutants", type=Path, required=True, help="the pinned cargo-mutants binary")
    parser.add_argument("--out", type=Path, required=True, help="cargo-mutants' output folders (one subfolder per group)")
    parser.add_argument("--group", action="append", help="run only these groups (default: all)")
    parser.add_argument("--jobs", type=int, default=1, help="work trees, each running cargo-mutants on a shard; as many Python-stage workers")
    parser.add_argument("--extra", default="", help="more cargo-mutants options, e.g. '--in-diff change.diff'")
    parser.add_argument("--rust-only", action="store_true", help="leave out the Python stage")
    parser.add_argument("--report-only", action="store_true", help="write the report from the ledgers, run nothing")
    parser.add_argument("--import", dest="imports", action="append", default=[], metavar="FOLDER=PASS",
                        help="record an earlier run's mutants.out folder as pass PASS of every chosen group")
    parser.add_argument("--from-pass", choices=PASSES[:-1], default=PASSES[0],
                        help="start at this Rust pass (it runs the narrower passes' tests too): 'unit' for files "
                             "whose own unit tests are their best tests, where a miss of the focused pass costs "
                             "the whole focused suite")
    parser.add_argument("--retest-missed", action="store_true",
                        help="test the missed mutants this run chooses through every pass again (after new tests)")
    parser.add_argument("--report", type=Path, default=ROOT / "mutants" / "REPORT.md")
    args = parser.parse_args()
    # A run stopped by SIGTERM (or SIGINT, which a shell's background job
    # ignores) stops its cargo-mutants processes and keeps their outcomes.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(128 + signal.SIGTERM))
    every = groups()
    chosen = [g for g in every if not args.group or g.name in args.group]
    if args.group and len(chosen) != len(set(args.group)):
        raise SystemExit(f"unknown group in {args.group}; the groups are in {GROUPS}")
    if args.jobs < 1:
        raise SystemExit(f"--jobs must be at least 1, got {args.jobs}")
    extra = shlex.split(args.extra)
    if any(a in ("-f", "--file") or a.startswith("--file=") for a in extra):
        # cargo-mutants adds --file to the configured examine_globs: it would
        # choose every file, and --retest-missed would forget every miss.
        raise SystemExit("--extra: --file does not narrow a run (it adds to examine_globs); use --re or --exclude")
    runs = [GroupRun(args.cargo_mutants, args.out, g, every, rooted(extra), args.jobs, first_pass=args.from_pass)
            for g in chosen]
    listings = {run.group.name: run.listing() for run in runs}
    keys = {name: hashes(d) for name, d in listings.items()}
    for run in runs:
        for spec in args.imports:
            folder, _, label = spec.rpartition("=")
            if label not in PASSES:
                raise SystemExit(f"--import {spec}: the pass must be one of {', '.join(PASSES)}")
            run.ledger.harvest(Path(folder), label, keys[run.group.name])
            run.ledger.save(keys[run.group.name])
        if args.retest_missed:
            run.ledger.forget_missed({keys[run.group.name][n] for n in run.chosen()})
            run.ledger.save()
        if not args.report_only:
            run.run(keys[run.group.name])
    if not (args.rust_only or args.report_only):
        status = python_stage.run([(run.ledger, listings[run.group.name]) for run in runs], args.jobs)
        if status:
            return status
    # The report covers every group, run now or before.
    ledgers = {run.group.name: run.ledger for run in runs}
    for g in every:
        if g.name not in ledgers:
            other = GroupRun(args.cargo_mutants, args.out, g, every, [], 1)
            ledgers[g.name], keys[g.name] = other.ledger, hashes(other.listing())
    return report.write([(ledgers[g.name], keys[g.name]) for g in every], args.report)


if __name__ == "__main__":
    sys.exit(main())
