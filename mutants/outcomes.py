"""The outcomes cargo-mutants writes (``mutants.out/outcomes.json``) and the
second stage adds (``mutants.out/python_stage.json``)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

PYTHON_STAGE_FILE = "python_stage.json"


@dataclass
class Mutant:
    """One mutant and what the Rust tests made of it."""

    name: str  # "src/file.rs:line:col: description", cargo-mutants' name
    file: str
    summary: str  # CaughtMutant, MissedMutant, Unviable, Timeout, Failure
    diff_path: Path | None  # absolute path of the mutant's diff
    seconds: float  # build and test time in stage 1
    folder: Path  # the outcomes folder it was read from


def read(out_dir: Path) -> list[Mutant]:
    """Every mutant scenario of a cargo-mutants run (the baseline left out)."""
    out_dir = out_dir.resolve()
    data = json.loads((out_dir / "outcomes.json").read_text())
    mutants = []
    for o in data["outcomes"]:
        scenario = o["scenario"]
        if not isinstance(scenario, dict) or "Mutant" not in scenario:
            continue
        m = scenario["Mutant"]
        diff = o.get("diff_path")
        seconds = sum(p["duration"] for p in o.get("phase_results", []))
        mutants.append(Mutant(m["name"], m["file"], o["summary"], out_dir / diff if diff else None, seconds, out_dir))
    return mutants


def merged(out_dirs: list[Path]) -> list[Mutant]:
    """The mutants of several outcome folders (the shards of a run, or its
    passes in order: a pass with `--iterate` re-tests what the earlier ones
    missed), a later folder's outcome of a mutant replacing an earlier one's."""
    return list({m.name: m for d in out_dirs for m in read(d)}.values())


def read_python_stage(out_dir: Path) -> dict:
    """The second stage's results, or an empty record when it did not run."""
    path = out_dir / PYTHON_STAGE_FILE
    return json.loads(path.read_text()) if path.exists() else {"mutants": {}}
