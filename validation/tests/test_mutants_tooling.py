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
