"""The committed record of what became of each mutant: one JSON file a group,
``mutants/outcomes/<group>.json``, kept in git so that the full set, a day
of one machine, accumulates across sessions and machines (cargo-mutants'
own output lives under ``target/`` and goes with the machine).

A mutant is keyed by its place-free identity: the SHA-256 of cargo-mutants'
name without its line and column (file, function, change) and of its diff
(the changed line with its context) without the ``@@`` line-number headers.
A mutant whose code or context changed is a new mutant, and its old outcome
no longer counts; a mutant that only moved (lines added or removed above
it) keeps its outcome, recorded under its new name. Each entry holds the
outcome (``caught``, ``unviable``, ``timeout`` or ``missed``), the widest
pass that reached it (``focused`` < ``unit`` < ``suite`` < ``python``, a
pass's tests include the one before's) and the seconds cargo-mutants spent on it.
"""

from __future__ import annotations

import hashlib
import json
import re
from dataclasses import asdict, dataclass
from pathlib import Path

FOLDER = Path(__file__).resolve().parent / "outcomes"
# The passes, narrowest first; each one's tests include the one before's.
PASSES = ("focused", "unit", "suite", "python")
# Outcomes that no wider pass changes.
SETTLED = ("caught", "unviable", "timeout")
# cargo-mutants' summaries in outcomes.json.
SUMMARIES = {"CaughtMutant": "caught", "MissedMutant": "missed", "Unviable": "unviable", "Failure": "unviable", "Timeout": "timeout"}


# The line and column in a cargo-mutants name ("file:line:col: change").
PLACE = re.compile(r"^([^:]+):(\d+):(\d+): ")


def _place(name: str) -> tuple[str, int, int, str]:
    """A name's file, line, column and change, for ordering by place."""
    found = PLACE.match(name)
    if found is None:
        raise ValueError(f"not a cargo-mutants mutant name (file:line:col: change): {name!r}")
    return found[1], int(found[2]), int(found[3]), name[found.end():]


def mutant_key(name: str, diff: str) -> str:
    """A mutant's place-free key: the SHA-256, shortened, of its name without
    line and column and of its diff without the ``@@`` line-number headers."""
    file, _, _, change = _place(name)
    body = "".join(line for line in diff.splitlines(keepends=True) if not line.startswith("@@"))
    return hashlib.sha256(f"{file}: {change}\n{body}".encode()).hexdigest()[:16]


def diffs(mutants_json: list[dict]) -> dict[str, str]:
    """Name to diff, from cargo-mutants' JSON listing (``--list --json`` or
    ``mutants.out/mutants.json``)."""
    return {m["name"]: m["diff"] for m in mutants_json}


def hashes(named_diffs: dict[str, str]) -> dict[str, str]:
    """Name to key (``mutant_key``). Mutants alike in all but place (the same
    change with the same context twice in a file) are told apart by their
    order in the file: the second's key gets "#2", and so on."""
    keys, seen = {}, {}
    for name in sorted(named_diffs, key=_place):
        key = mutant_key(name, named_diffs[name])
        seen[key] = seen.get(key, 0) + 1
        keys[name] = key if seen[key] == 1 else f"{key}#{seen[key]}"
    return keys


@dataclass
class Entry:
    outcome: str
    pass_: str
    diff: str
    seconds: float | None = None

    def settled(self) -> bool:
        return self.outcome in SETTLED

    def missed_by_at_least(self, label: str) -> bool:
        """Missed by pass ``label`` or a wider one (so ``label`` need not try it)."""
        return self.outcome == "missed" and PASSES.index(self.pass_) >= PASSES.index(label)


class Ledger:
    """One group's outcomes, read from and written to its JSON file."""

    def __init__(self, path: Path):
        self.path = path
        data = json.loads(path.read_text()) if path.exists() else {}
        self.cargo_mutants_version: str | None = data.get("cargo_mutants_version")
        self.entries: dict[str, Entry] = {
            name: Entry(e["outcome"], e["pass"], e["diff"], e.get("seconds")) for name, e in data.get("mutants", {}).items()
        }

    @classmethod
    def of_group(cls, group: str, folder: Path = FOLDER) -> "Ledger":
        return cls(folder / f"{group}.json")

    def record(self, name: str, diff: str, outcome: str, label: str, seconds: float | None = None) -> None:
        """Notes what pass ``label`` made of the mutant. A settled outcome of
        the same code stands; a miss by a narrower pass than one recorded
        does not replace it."""
        if outcome not in (*SETTLED, "missed") or label not in PASSES:
            raise ValueError(f"{name}: unknown outcome {outcome!r} or pass {label!r}")
        old = self.entries.get(name)
        if old is not None and old.diff == diff:
            if old.settled() or (outcome == "missed" and PASSES.index(old.pass_) > PASSES.index(label)):
                return
        self.entries[name] = Entry(outcome, label, diff, seconds)

    def current(self, hashes: dict[str, str]) -> dict[str, Entry]:
        """The entries of the mutants the source has now (name to key), under
        their names now: a mutant that moved keeps its outcome."""
        names = {key: name for name, key in hashes.items()}
        found = {names[e.diff]: e for e in self.entries.values() if e.diff in names}
        # An entry under the name it has now wins over one it had before.
        found.update({n: e for n, e in self.entries.items() if hashes.get(n) == e.diff})
        return found

    def forget_missed(self, keys: set[str] | None = None) -> None:
        """Drops the misses of the mutants with these keys (every miss
        without keys), so that they meet every pass again (after new tests)."""
        self.entries = {
            n: e for n, e in self.entries.items() if e.outcome != "missed" or (keys is not None and e.diff not in keys)
        }

    def harvest(self, out: Path, label: str, group: dict[str, str] | None = None) -> int:
        """Records what a cargo-mutants output folder (``mutants.out``) says,
        as pass ``label``; ``group``, the keys of all the group's mutants
        now (a shard lists only some, and the order of mutants alike but for
        their place is the group's). cargo-mutants rewrites its
        ``outcomes.json`` as each mutant ends, so a running pass can be read
        (a file caught in the middle of a rewrite is read at the next call).
        The number of mutants read."""
        group = group or {}
        try:
            keys = {n: mutant_key(n, d) for n, d in diffs(json.loads((out / "mutants.json").read_text())).items()}
            data = json.loads((out / "outcomes.json").read_text())
        except (FileNotFoundError, json.JSONDecodeError):
            return 0
        self.cargo_mutants_version = data.get("cargo_mutants_version", self.cargo_mutants_version)
        seen = 0
        for o in data["outcomes"]:
            scenario = o["scenario"]
            if not isinstance(scenario, dict) or "Mutant" not in scenario or o["summary"] not in SUMMARIES:
                continue
            name = scenario["Mutant"]["name"]
            seconds = round(sum(p["duration"] for p in o.get("phase_results", [])), 1)
            own, listed = keys[name], group.get(name, keys[name])
            # The group's key (ordinal included) while the code is the one listed.
            key = listed if listed.split("#")[0] == own else own
            self.record(name, key, SUMMARIES[o["summary"]], label, seconds)
            seen += 1
        return seen

    def save(self, hashes: dict[str, str] | None = None) -> None:
        """Writes the file (sorted, one entry a line for readable diffs);
        with ``hashes``, the entries of mutants the source no longer has are
        dropped."""
        if hashes is not None:
            self.entries = self.current(hashes)
        entries = self.entries
        self.path.parent.mkdir(parents=True, exist_ok=True)
        lines = [
            f"  {json.dumps(name)}: {json.dumps({k.rstrip('_'): v for k, v in asdict(e).items() if v is not None})}"
            for name, e in sorted(entries.items())
        ]
        head = json.dumps({"cargo_mutants_version": self.cargo_mutants_version})[1:-1]
        text = "{" + head + ',\n "mutants": {\n' + ",\n".join(lines) + "\n }\n}\n"
        tmp = self.path.with_suffix(".tmp")
        tmp.write_text(text)
        tmp.replace(self.path)
