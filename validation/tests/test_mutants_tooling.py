"""The mutation-testing tooling (`make mutants`): its groups cover the
physics files, and its ledger, driver and report keep, resume and count runs as documented. The runs
themselves take hours and are not part of `make test`."""

from __future__ import annotations

import json
import stat
import sys
import threading
import time
import tomllib
from pathlib import Path

import pytest

from mutants import ledger, report, staged, worktree

ROOT = Path(__file__).resolve().parents[2]


def _mutants_out(folder: Path, fates: dict[str, str], diffs: dict[str, str] | None = None, torn: bool = False) -> Path:
    """A cargo-mutants output folder (mutants.json with the diffs,
    outcomes.json with the summaries); ``torn``: outcomes.json caught in
    the middle of a rewrite."""
    folder.mkdir(parents=True, exist_ok=True)
    diffs = diffs or {}
    listing = [{"name": n, "diff": diffs.get(n, f"diff of {n}")} for n in fates]
    (folder / "mutants.json").write_text(json.dumps(listing))
    outcomes = [{"scenario": "Baseline", "summary": "Success", "phase_results": []}]
    outcomes += [
        {"scenario": {"Mutant": {"name": n, "file": n.split(":", 1)[0]}}, "summary": s, "phase_results": [{"duration": 10.0}]}
        for n, s in fates.items()
    ]
    text = json.dumps({"outcomes": outcomes, "cargo_mutants_version": "27.1.0"})
    (folder / "outcomes.json").write_text(text[: len(text) // 2] if torn else text)
    return folder


def _keys(*names: str, changed: str | None = None) -> dict[str, str]:
    """The current mutants, name to diff hash (``changed``: its code changed)."""
    return ledger.hashes({n: f"diff of {n}" + (" (changed)" if n == changed else "") for n in names})


A, B, C, D = (f"src/quaternion.rs:{k}:1: replace x" for k in range(1, 5))


def test_every_examined_file_is_in_exactly_one_group():
    groups = staged.groups()  # refuses a file in no group or in two
    examined = tomllib.loads((ROOT / ".cargo" / "mutants.toml").read_text())["examine_globs"]
    assert sorted(glob for g in groups for glob in g.files) == sorted(examined)


def test_every_focused_test_target_exists():
    for group in staged.groups():
        for target in group.tests:
            assert (ROOT / "tests" / f"{target}.rs").is_file(), f"{group.name}: no test target {target}"


def test_a_wider_pass_settles_a_miss_a_narrower_miss_replaces_nothing_and_a_settled_outcome_stands(tmp_path):
    book = ledger.Ledger(tmp_path / "g.json")
    key = ledger.mutant_key(A, "x")
    book.record(A, key, "missed", "unit")
    book.record(A, key, "missed", "focused")
    assert book.entries[A].pass_ == "unit"
    book.record(A, key, "caught", "suite")
    assert (book.entries[A].outcome, book.entries[A].pass_) == ("caught", "suite")
    book.record(A, key, "missed", "python")
    assert book.entries[A].outcome == "caught"
    # The same name with other code is another mutant.
    book.record(A, ledger.mutant_key(A, "y"), "missed", "focused")
    assert (book.entries[A].outcome, book.entries[A].diff) == ("missed", ledger.mutant_key(A, "y"))
    with pytest.raises(ValueError, match="unknown outcome"):
        book.record(B, key, "survived", "focused")


def test_the_ledger_round_trips_and_drops_mutants_whose_code_changed(tmp_path):
    book = ledger.Ledger(tmp_path / "g.json")
    book.harvest(_mutants_out(tmp_path / "out", {A: "CaughtMutant", B: "Unviable", C: "MissedMutant"}), "focused")
    book.save()
    again = ledger.Ledger(tmp_path / "g.json")
    assert again.entries == book.entries and again.cargo_mutants_version == "27.1.0"
    assert again.entries[A].seconds == 10.0
    again.save(_keys(A, C, changed=C))
    assert set(ledger.Ledger(tmp_path / "g.json").entries) == {A}
    # Dropped for good: a later save without the listing does not bring them back.
    again.save()
    assert set(ledger.Ledger(tmp_path / "g.json").entries) == {A}


MOVED = "--- src/quaternion.rs\n+++ replace * with / in f\n@@ -{line},4 +{line},4 @@\n fn f() -> f64 {{\n-    a * 2.0\n+    a / 2.0\n }}\n"


def test_a_mutant_that_only_moved_keeps_its_outcome_under_its_new_name(tmp_path):
    before, after = "src/quaternion.rs:3:7: replace * with / in f", "src/quaternion.rs:5:7: replace * with / in f"
    book = ledger.Ledger(tmp_path / "g.json")
    book.harvest(_mutants_out(tmp_path / "out", {before: "CaughtMutant"}, {before: MOVED.format(line=1)}), "focused")
    # Two lines added above f: the same change in the same code, two lines down.
    moved = ledger.hashes({after: MOVED.format(line=3)})
    assert book.current(moved)[after].outcome == "caught"
    book.save(moved)
    assert set(ledger.Ledger(tmp_path / "g.json").entries) == {after}
    # Its code changed: a new mutant, whatever its place.
    changed = ledger.hashes({after: MOVED.format(line=3).replace("a * 2.0", "b * 2.0")})
    assert book.current(changed) == {}


def test_mutants_alike_but_for_their_place_are_told_apart_in_the_order_of_the_file(tmp_path):
    first, second = "src/quaternion.rs:9:7: replace * with / in f", "src/quaternion.rs:10:7: replace * with / in f"
    same = MOVED.format(line=1)
    keys = ledger.hashes({second: same, first: same})
    assert keys[second] == keys[first] + "#2"
    # A shard that tested only the second records it as the second.
    book = ledger.Ledger(tmp_path / "g.json")
    book.harvest(_mutants_out(tmp_path / "out", {second: "CaughtMutant"}, {second: same}), "focused", keys)
    assert set(book.current(keys)) == {second}
    with pytest.raises(ValueError, match="not a cargo-mutants mutant name"):
        ledger.mutant_key("replace * with / in f", same)


def test_a_half_written_outcomes_file_is_read_at_the_next_harvest(tmp_path):
    book = ledger.Ledger(tmp_path / "g.json")
    out = _mutants_out(tmp_path / "out", {A: "CaughtMutant"}, torn=True)
    assert book.harvest(out, "focused") == 0 and not book.entries
    _mutants_out(out, {A: "CaughtMutant"})
    assert book.harvest(out, "focused") == 1 and book.entries[A].outcome == "caught"


def test_the_report_counts_from_the_ledgers_and_leaves_out_changed_code(tmp_path):
    book = ledger.Ledger(tmp_path / "g.json")
    book.harvest(_mutants_out(tmp_path / "f", {A: "MissedMutant", B: "CaughtMutant", C: "Unviable", D: "MissedMutant"}), "focused")
    book.harvest(_mutants_out(tmp_path / "s", {A: "MissedMutant"}), "suite")
    book.harvest(_mutants_out(tmp_path / "p", {A: "CaughtMutant"}), "python")
    # A: caught by Python; B: caught; C: unviable; D: missed by the focused
    # tests only (pending).
    text, unexplained = report.render([(book, _keys(A, B, C, D))])
    assert unexplained == 0
    assert "| **all** | 4 | 1 | 1 | 1 | 1 | 0 | 0 | 100.0 % |" in text
    # B's code changed since: pending again.
    text, _ = report.render([(book, _keys(A, B, C, D, changed=B))])
    assert "| **all** | 4 | 2 | 1 | 0 | 1 | 0 | 0 | 100.0 % |" in text


def test_a_survivor_without_a_recorded_reason_is_counted_unexplained(tmp_path):
    name = "src/quaternion.rs:9999:1: replace nothing with something"
    book = ledger.Ledger(tmp_path / "g.json")
    book.harvest(_mutants_out(tmp_path / "s", {name: "MissedMutant"}), "suite")
    text, unexplained = report.render([(book, _keys(name))])
    assert unexplained == 1
    assert f"| `{name}` | Rust (Python not run) | **unexplained** |" in text
    assert "| **all** | 1 | 0 | 0 | 0 | 0 | 0 | 1 | 0.0 % |" in text


@pytest.mark.parametrize("unknown", [["no_such_group"], ["quaternion", "no_such_group"]])
def test_an_unknown_group_is_refused(monkeypatch, unknown):
    argv = ["staged", "--cargo-mutants", "x", "--out", "y"] + [a for g in unknown for a in ("--group", g)]
    monkeypatch.setattr("sys.argv", argv)
    with pytest.raises(SystemExit, match="unknown group"):
        staged.main()


def test_the_file_of_in_diff_is_made_absolute_for_the_work_trees():
    absolute = str(ROOT / "change.diff")
    assert staged.rooted(["--in-diff", "change.diff", "-v"]) == ["--in-diff", absolute, "-v"]
    assert staged.rooted(["--in-diff=change.diff"]) == [f"--in-diff={absolute}"]
    assert staged.rooted(["--in-diff", absolute]) == ["--in-diff", absolute]


def test_a_work_tree_is_brought_up_to_date_and_a_restored_file_is_newer_than_its_build(tmp_path):
    tree = worktree.sync_tree(tmp_path / "tree")
    for name in ("Cargo.toml", "src/quaternion.rs", "mutants/groups.toml"):
        assert (tree / name).read_bytes() == (ROOT / name).read_bytes()
    untouched = (tree / "Cargo.toml").stat().st_mtime_ns
    mutated = tree / "src" / "quaternion.rs"
    mutated.write_text("mutated")
    built = time.time_ns()  # a build after the mutant
    time.sleep(0.01)
    worktree.sync_tree(tree)
    assert mutated.read_bytes() == (ROOT / "src" / "quaternion.rs").read_bytes()
    assert mutated.stat().st_mtime_ns > built, "a restored file older than the build would keep the mutant's build"
    assert (tree / "Cargo.toml").stat().st_mtime_ns == untouched


FAKE_CARGO_MUTANTS = '''#!{python}
"""Stands in for cargo-mutants: lists the mutants of names.json (with
--json, each with its diff from diffs.json), and on a pass in a work tree
writes mutants.json and outcomes.json for its shard of the mutants not in
previously_caught.txt, each caught by the first pass named for it in
fates.json (else missed), logging them; with stop.json, it ends (as a
killed run would) after that many mutants."""
import json, sys
from pathlib import Path
here = Path(__file__).parent
names = json.loads((here / "names.json").read_text())
diffs = json.loads((here / "diffs.json").read_text())
if "--list" in sys.argv:
    if "--json" in sys.argv:
        print(json.dumps([{{"name": n, "diff": diffs.get(n, "diff of " + n)}} for n in names]))
    else:
        print("\\n".join(names))
    sys.exit(0)
assert "--in-place" in sys.argv
out = Path(sys.argv[sys.argv.index("--output") + 1]) / "mutants.out"
skip = set((out / "previously_caught.txt").read_text().split("\\n"))
k, n = map(int, next(a for a in sys.argv if a.startswith("--shard=")).split("=")[1].split("/"))
cargo = [a for a in sys.argv if a.startswith("--cargo-arg=")]
label = "suite" if not cargo else ("unit" if "--cargo-arg=--lib" in cargo else "focused")
# How many more times shard k's baseline fails: a file of its own, since
# the shards run side by side (one file shared by both raced: a shard read
# it while the other rewrote it).
baseline = here / f"baseline_failures_{{k}}.json"
left = json.loads(baseline.read_text()) if baseline.exists() else 0
if left > 0:
    baseline.write_text(json.dumps(left - 1))
    sys.exit(4)
fates = json.loads((here / "fates.json").read_text())
tested = [m for m in names if m not in skip][k::n]
stop = here / "stop.json"
if stop.exists():
    tested = tested[: json.loads(stop.read_text())]
with open(here / "log.txt", "a") as log:
    log.write(json.dumps([label, tested]) + "\\n")
(out / "mutants.json").write_text(json.dumps([{{"name": m, "diff": diffs.get(m, "diff of " + m)}} for m in tested]))
outcomes = [{{"scenario": {{"Mutant": {{"name": m, "file": "src/quaternion.rs"}}}},
             "summary": "CaughtMutant" if label in fates.get(m, []) else "MissedMutant",
             "phase_results": [{{"duration": 1.0}}]}} for m in tested]
(out / "outcomes.json").write_text(json.dumps({{"outcomes": outcomes}}))
if stop.exists():
    sys.exit(137)
sys.exit(2 if any(o["summary"] == "MissedMutant" for o in outcomes) else 0)
'''


class Fake:
    """A stand-in cargo-mutants and a group run driven by it, in two work trees."""

    def __init__(self, tmp_path: Path, monkeypatch, names: list[str], fates: dict[str, list[str]]):
        self.dir = tmp_path
        fake = tmp_path / "cargo-mutants"
        fake.write_text(FAKE_CARGO_MUTANTS.format(python=sys.executable))
        fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
        self.set(names=names, fates=fates, diffs={})
        monkeypatch.setattr(staged, "sync_tree", lambda tree: tree.mkdir(parents=True, exist_ok=True))
        monkeypatch.setattr(staged, "POLL_SECONDS", 0.01)
        self.cleaned: list[Path] = []
        monkeypatch.setattr(staged, "clean_build", self.cleaned.append)
        group = staged.Group(name="quaternion", files=["src/quaternion.rs"], tests=["t"])
        self.book = ledger.Ledger(tmp_path / "quaternion.json")
        self.run = staged.GroupRun(fake, tmp_path / "out", group, [group], [], 2, self.book, tmp_path / "trees")

    def set(self, **files) -> None:
        for name, value in files.items():
            (self.dir / f"{name}.json").write_text(json.dumps(value))

    def go(self) -> list[list]:
        """Runs the passes; what each cargo-mutants process tested."""
        self.run.run(ledger.hashes(self.run.listing()))
        return self.log()

    def log(self) -> list[list]:
        """What each cargo-mutants process tested since the last look."""
        log = self.dir / "log.txt"
        lines = log.read_text().splitlines() if log.exists() else []
        log.unlink(missing_ok=True)
        return [json.loads(line) for line in lines]


def _passes(log: list[list]) -> list[tuple[str, list[str]]]:
    """The log's shards put together: each pass and what it tested."""
    merged: dict[str, list[str]] = {}
    for label, tested in log:
        merged.setdefault(label, []).extend(tested)
    return [(label, sorted(tested)) for label, tested in merged.items()]


def test_each_pass_tests_only_what_the_narrower_ones_missed_and_a_missed_mutant_is_not_tested_again(tmp_path, monkeypatch):
    fake = Fake(tmp_path, monkeypatch, [A, B, C], {A: ["focused", "unit", "suite"], B: ["unit", "suite"]})
    log = fake.go()
    assert _passes(log) == [("focused", [A, B, C]), ("unit", [B, C]), ("suite", [C])]
    assert len(log) == 6, "one process a work tree and pass"
    assert {n: (e.outcome, e.pass_) for n, e in fake.book.entries.items()} == {
        A: ("caught", "focused"), B: ("caught", "unit"), C: ("missed", "suite")}
    # A new mutant opens every pass again; C, missed by the whole suite, is
    # not tested again by any of them; a mutant whose code changed is new.
    fake.set(names=[A, B, C, D], diffs={A: "A's code changed"})
    assert _passes(fake.go()) == [("focused", [A, D]), ("unit", [D]), ("suite", [D])]
    # After new tests, --retest-missed sends the missed ones through again.
    fake.book.forget_missed()
    assert _passes(fake.go()) == [("focused", [C, D]), ("unit", [C, D]), ("suite", [C, D])]
    assert _passes(fake.go()) == []


def test_a_run_from_the_unit_pass_leaves_the_focused_pass_out(tmp_path, monkeypatch):
    fake = Fake(tmp_path, monkeypatch, [A, B, C], {A: ["focused", "unit", "suite"], B: ["unit", "suite"]})
    fake.run.first_pass = "unit"
    assert _passes(fake.go()) == [("unit", [A, B, C]), ("suite", [C])]
    assert {n: (e.outcome, e.pass_) for n, e in fake.book.entries.items()} == {
        A: ("caught", "unit"), B: ("caught", "unit"), C: ("missed", "suite")}


def test_an_interrupted_pass_keeps_what_it_tested_and_resumes_with_the_rest(tmp_path, monkeypatch):
    fake = Fake(tmp_path, monkeypatch, [A, B, C, D], {A: ["focused", "unit", "suite"], C: ["unit", "suite"]})
    fake.set(stop=1)  # each shard's process dies after its first mutant
    with pytest.raises(SystemExit, match="cargo-mutants failed"):
        fake.go()
    assert _passes(fake.log()) == [("focused", [A, B])]
    assert {n: e.outcome for n, e in fake.book.entries.items()} == {A: "caught", B: "missed"}
    (tmp_path / "stop.json").unlink()
    assert _passes(fake.go()) == [("focused", [C, D]), ("unit", [B, C, D]), ("suite", [B, D])]


def test_an_explanation_whose_mutant_no_longer_survives_is_listed_for_pruning(tmp_path, monkeypatch):
    explanations = tmp_path / "explanations.toml"
    explanations.write_text(f'[survivors]\n"{A}" = "equivalent"\n"{B}" = "equivalent"\n')
    monkeypatch.setattr(report, "EXPLANATIONS", explanations)
    book = ledger.Ledger(tmp_path / "g.json")
    book.harvest(_mutants_out(tmp_path / "s", {A: "MissedMutant", B: "CaughtMutant"}), "suite")
    text, unexplained = report.render([(book, _keys(A, B))])
    assert unexplained == 0
    assert f"| `{A}` | Rust (Python not run) | equivalent |" in text
    assert f"## Explanations with no survivor (1: " in text and f"- `{B}`" in text


def test_the_python_stage_tries_each_mutant_the_whole_rust_suite_missed_and_records_it(tmp_path, monkeypatch):
    from mutants import python_stage

    tree = tmp_path / "tree"
    original = "fn f() -> f64 {\n    let a = 1.0;\n    a * 2.0\n}\n"

    def fresh_tree(_):
        (tree / "src").mkdir(parents=True, exist_ok=True)
        (tree / "src" / "quaternion.rs").write_text(original)
        return tree

    def build_and_test(_scratch, built, _timeout):
        """The Python tests fail when the mutated line is there."""
        return "failed" if "a / 2.0" in (built / "src" / "quaternion.rs").read_text() else "passed"

    monkeypatch.setattr(python_stage, "sync_tree", fresh_tree)
    monkeypatch.setattr(python_stage, "_build_and_test", build_and_test)
    # A cargo-mutants diff: the file on the --- line, the mutant on the +++ line.
    diff = (
        "--- src/quaternion.rs\n+++ replace * with / in f\n@@ -1,4 +1,4 @@\n fn f() -> f64 {\n"
        "     let a = 1.0;\n-    a * 2.0\n+    a / 2.0\n }\n"
    )
    listing = {A: diff, B: "diff of B", C: "diff of C"}
    book = ledger.Ledger(tmp_path / "g.json")
    book.record(A, ledger.mutant_key(A, diff), "missed", "suite")
    book.record(B, ledger.mutant_key(B, "diff of B"), "missed", "focused")  # not through every Rust pass yet
    book.record(C, ledger.mutant_key(C, "diff of C"), "caught", "unit")
    assert python_stage.run([(book, listing)]) == 0
    assert (book.entries[A].outcome, book.entries[A].pass_) == ("caught", "python")
    assert (book.entries[B].outcome, book.entries[B].pass_) == ("missed", "focused")
    assert ledger.Ledger(tmp_path / "g.json").entries[A].outcome == "caught", "written as it comes"
    tried = []
    monkeypatch.setattr(python_stage, "_build_and_test", lambda *a: tried.append(a) or "passed")
    assert python_stage.run([(book, listing)]) == 0 and not tried, "a mutant with a Python result is not tried again"
    # A diff that no longer applies is an error, not a silent miss.
    book.record(D, ledger.mutant_key(D, diff.replace("a * 2.0", "b * 2.0")), "missed", "suite")
    with pytest.raises(SystemExit, match="does not apply"):
        python_stage.run([(book, {D: diff.replace("a * 2.0", "b * 2.0")})])


def test_python_stage_workers_share_one_queue_each_in_its_own_scratch_directory(tmp_path, monkeypatch):
    from mutants import python_stage

    original = "fn f() -> f64 {\n    a * 2.0\n}\n"
    diff = "--- src/quaternion.rs\n+++ replace * with / in f\n@@ -1,3 +1,3 @@\n fn f() -> f64 {\n-    a * 2.0\n+    a / 2.0\n }\n"

    def fresh_tree(tree):
        (tree / "src").mkdir(parents=True, exist_ok=True)
        (tree / "src" / "quaternion.rs").write_text(original)
        return tree

    lock, running, most, scratches = threading.Lock(), [0], [0], []

    def build_and_test(scratch, built, _timeout):
        """Mutated trees fail; each call holds its worker a moment so that both run."""
        with lock:
            running[0] += 1
            most[0] = max(most[0], running[0])
            scratches.append(scratch)
        time.sleep(0.2)
        with lock:
            running[0] -= 1
        return "failed" if "a / 2.0" in (built / "src" / "quaternion.rs").read_text() else "passed"

    monkeypatch.setattr(python_stage, "ROOT", tmp_path)
    monkeypatch.setattr(python_stage, "sync_tree", fresh_tree)
    monkeypatch.setattr(python_stage, "_build_and_test", build_and_test)
    names = [f"src/quaternion.rs:2:{k}: replace * with / in f (mutant {k})" for k in range(1, 7)]
    book = ledger.Ledger(tmp_path / "g.json")
    for n in names:
        book.record(n, ledger.mutant_key(n, diff), "missed", "suite")
    assert python_stage.run([(book, {n: diff for n in names})], jobs=2) == 0
    assert all((book.entries[n].outcome, book.entries[n].pass_) == ("caught", "python") for n in names)
    assert len(scratches) == 1 + len(names), "the baseline, then each mutant once"
    assert len(set(scratches)) == 2 and most[0] == 2, "two workers, side by side, in two scratch directories"
    assert all(str(tmp_path / "target") in str(s) for s in scratches), "scratch under the project's target"
    # A diff that no longer applies stops the run with its name, from whichever worker meets it.
    broken = diff.replace("a * 2.0", "b * 2.0")
    book.record(D, ledger.mutant_key(D, broken), "missed", "suite")
    with pytest.raises(SystemExit, match="does not apply"):
        python_stage.run([(book, {D: broken})], jobs=2)


def test_a_shard_whose_baseline_fails_is_cleaned_and_run_again_once(tmp_path, monkeypatch):
    fake = Fake(tmp_path, monkeypatch, [A, B, C, D], {A: ["focused", "unit", "suite"], B: ["focused"]})
    fake.set(baseline_failures_1=1)  # a stale cache in tree 1: its first baseline fails
    assert _passes(fake.go()) == [("focused", [A, B, C, D]), ("unit", [C, D]), ("suite", [C, D])]
    assert fake.cleaned == [tmp_path / "trees" / "1"]
    assert (tmp_path / "out" / "quaternion" / "shard-1-baseline-failed.log").exists()
    # A source that does not build fails again after the cleaning: the run stops.
    fake.book.forget_missed()
    fake.set(baseline_failures_0=2)
    with pytest.raises(SystemExit, match="cargo-mutants failed \\(exit 4"):
        fake.go()
    assert fake.cleaned[-1] == tmp_path / "trees" / "0"


def test_forgetting_misses_keeps_those_of_mutants_not_chosen(tmp_path):
    book = ledger.Ledger(tmp_path / "g.json")
    for name, outcome in ((A, "missed"), (B, "missed"), (C, "caught")):
        book.record(name, ledger.mutant_key(name, "diff of " + name), outcome, "suite")
    book.forget_missed({ledger.mutant_key(A, "diff of " + A), ledger.mutant_key(C, "diff of " + C)})
    assert {n: e.outcome for n, e in book.entries.items()} == {B: "missed", C: "caught"}
    book.forget_missed()
    assert {n: e.outcome for n, e in book.entries.items()} == {C: "caught"}


@pytest.mark.parametrize("narrowing", ["--file src/quaternion.rs", "-f src/quaternion.rs", "--file=src/quaternion.rs"])
def test_a_file_option_is_refused_as_it_would_choose_every_file(monkeypatch, narrowing):
    # --extra=VALUE, as the Makefile passes it (a value that starts with a
    # dash and has no space would be taken for an option of its own).
    monkeypatch.setattr("sys.argv", ["staged", "--cargo-mutants", "x", "--out", "y", f"--extra={narrowing}"])
    with pytest.raises(SystemExit, match="use --re or --exclude"):
        staged.main()

