"""The mutation-testing tooling (`make mutants`): its groups cover the
physics files, and its report merges runs and passes as documented. The runs
themselves take hours and are not part of `make test`."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest

from mutants import report, staged

ROOT = Path(__file__).resolve().parents[2]


def _outcomes(folder: Path, fates: dict[str, str]) -> Path:
    """A cargo-mutants outcome folder with the given summaries."""
    folder.mkdir(parents=True)
    outcomes = [{"scenario": "Baseline", "summary": "Success", "phase_results": []}]
    for name, summary in fates.items():
        outcomes.append(
            {
                "scenario": {"Mutant": {"name": name, "file": name.split(":", 1)[0]}},
                "summary": summary,
                "phase_results": [{"duration": 10.0}],
            }
        )
    (folder / "outcomes.json").write_text(json.dumps({"outcomes": outcomes, "cargo_mutants_version": "27.1.0"}))
    return folder


def test_every_examined_file_is_in_exactly_one_group():
    groups = staged.groups()  # refuses a file in no group or in two
    examined = tomllib.loads((ROOT / ".cargo" / "mutants.toml").read_text())["examine_globs"]
    assert sorted(glob for g in groups for glob in g.files) == sorted(examined)


def test_every_focused_test_target_exists():
    for group in staged.groups():
        for target in group.tests:
            assert (ROOT / "tests" / f"{target}.rs").is_file(), f"{group.name}: no test target {target}"


def test_a_later_pass_replaces_an_earlier_outcome_and_stale_mutants_are_left_out(tmp_path):
    a, b, c, d = (f"src/quaternion.rs:{k}:1: replace x" for k in range(1, 5))
    first = _outcomes(tmp_path / "first", {a: "MissedMutant", b: "CaughtMutant", c: "Unviable"})
    second = _outcomes(tmp_path / "second", {a: "CaughtMutant"})
    text, unexplained = report.render([first, second], "test")
    assert unexplained == 0
    assert "| **all** | 3 | 0 | 1 | 2 | 0 | 0 | 0 | 100.0 % |" in text
    # The source now has b and d: c is stale, d not yet tested.
    text, _ = report.render([first, second], "test", names=[b, d])
    assert "| **all** | 2 | 1 | 0 | 1 | 0 | 0 | 0 | 100.0 % |" in text


def test_a_survivor_without_a_recorded_reason_is_counted_unexplained(tmp_path):
    name = "src/quaternion.rs:9999:1: replace nothing with something"
    text, unexplained = report.render([_outcomes(tmp_path / "run", {name: "MissedMutant"})], "test")
    assert unexplained == 1
    assert f"| `{name}` | **unexplained** |" in text


def test_imported_and_kept_outcomes_settle_mutants_for_the_next_pass(tmp_path):
    group = staged.Group(name="quaternion", files=["src/quaternion.rs"], tests=[])
    run = staged.GroupRun(Path("cargo-mutants"), tmp_path / "out", group, [group], [], 1)
    caught, unviable, missed = (f"src/quaternion.rs:{k}:1: replace x" for k in range(1, 4))
    run.import_outcomes(_outcomes(tmp_path / "change", {caught: "CaughtMutant", missed: "MissedMutant"}))
    run.import_outcomes(tmp_path / "change")  # kept once
    assert len(list((tmp_path / "out" / "quaternion" / "history").iterdir())) == 1
    _outcomes(tmp_path / "out" / "quaternion" / "mutants.out", {unviable: "Unviable"})
    assert run.settled() == {caught, unviable}


@pytest.mark.parametrize("unknown", [["no_such_group"], ["quaternion", "no_such_group"]])
def test_an_unknown_group_is_refused(monkeypatch, unknown):
    argv = ["staged", "--cargo-mutants", "x", "--out", "y"] + [a for g in unknown for a in ("--group", g)]
    monkeypatch.setattr("sys.argv", argv)
    with pytest.raises(SystemExit, match="unknown group"):
        staged.main()


FAKE_CARGO_MUTANTS = '''#!{python}
"""Stands in for cargo-mutants: lists the mutants of names.json, and on a
pass writes outcomes for the ones not in previously_caught.txt, each caught
by the first pass named for it in fates.json (else missed), logging them."""
import json, sys
from pathlib import Path
here = Path(__file__).parent
names = json.loads((here / "names.json").read_text())
if "--list" in sys.argv:
    print("\\n".join(names))
    sys.exit(0)
out = Path(sys.argv[sys.argv.index("--output") + 1]) / "mutants.out"
skip = set((out / "previously_caught.txt").read_text().split("\\n"))
cargo = [a for a in sys.argv if a.startswith("--cargo-arg=")]
label = "suite" if not cargo else ("unit" if "--cargo-arg=--lib" in cargo else "focused")
fates = json.loads((here / "fates.json").read_text())
tested = [n for n in names if n not in skip]
with open(here / "log.txt", "a") as log:
    log.write(json.dumps([label, tested]) + "\\n")
outcomes = [{{"scenario": {{"Mutant": {{"name": n, "file": "src/quaternion.rs"}}}},
             "summary": "CaughtMutant" if label in fates.get(n, []) else "MissedMutant",
             "phase_results": []}} for n in tested]
out.mkdir(parents=True, exist_ok=True)
(out / "outcomes.json").write_text(json.dumps({{"outcomes": outcomes}}))
sys.exit(2 if any(o["summary"] == "MissedMutant" for o in outcomes) else 0)
'''


def _fake_cargo_mutants(tmp_path: Path, names: list[str], fates: dict[str, list[str]]) -> Path:
    import stat
    import sys

    fake = tmp_path / "cargo-mutants"
    fake.write_text(FAKE_CARGO_MUTANTS.format(python=sys.executable))
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    (tmp_path / "names.json").write_text(json.dumps(names))
    (tmp_path / "fates.json").write_text(json.dumps(fates))
    return fake


def _log(tmp_path: Path) -> list[list]:
    lines = (tmp_path / "log.txt").read_text().splitlines() if (tmp_path / "log.txt").exists() else []
    (tmp_path / "log.txt").unlink(missing_ok=True)
    return [json.loads(line) for line in lines]


def test_each_pass_tests_only_what_the_narrower_ones_missed_and_a_missed_mutant_is_not_tested_again(tmp_path):
    a, b, c, d = (f"src/quaternion.rs:{k}:1: replace x" for k in range(1, 5))
    fake = _fake_cargo_mutants(tmp_path, [a, b, c], {a: ["focused", "unit", "suite"], b: ["unit", "suite"]})
    group = staged.Group(name="quaternion", files=["src/quaternion.rs"], tests=["t"])
    run = staged.GroupRun(fake, tmp_path / "out", group, [group], [], 1)
    run.run()
    assert _log(tmp_path) == [["focused", [a, b, c]], ["unit", [b, c]], ["suite", [c]]]
    # A new mutant reopens every pass; c, missed by the whole suite, is not
    # tested again by any of them.
    (tmp_path / "names.json").write_text(json.dumps([a, b, c, d]))
    run.run()
    assert _log(tmp_path) == [["focused", [d]], ["unit", [d]], ["suite", [d]]]
    # After new tests, --retest-missed sends the missed ones through again.
    run.forget_missed()
    run.run()
    assert _log(tmp_path) == [["focused", [c, d]], ["unit", [c, d]], ["suite", [c, d]]]


def test_an_interrupted_pass_resumes_without_testing_again_what_it_missed(tmp_path):
    a, b, c = (f"src/quaternion.rs:{k}:1: replace x" for k in range(1, 4))
    fake = _fake_cargo_mutants(tmp_path, [a, b, c], {a: ["focused", "unit", "suite"], c: ["unit", "suite"]})
    group = staged.Group(name="quaternion", files=["src/quaternion.rs"], tests=["t"])
    run = staged.GroupRun(fake, tmp_path / "out", group, [group], [], 1)
    # The focused pass was stopped after testing a (caught) and b (missed).
    _outcomes(tmp_path / "out" / "quaternion" / "mutants.out", {a: "CaughtMutant", b: "MissedMutant"})
    (tmp_path / "out" / "quaternion" / "state.json").write_text(json.dumps({"running": "focused"}))
    run.run()
    assert _log(tmp_path) == [["focused", [c]], ["unit", [b, c]], ["suite", [b]]]
