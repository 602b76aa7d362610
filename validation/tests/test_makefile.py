"""The Makefile's targets set themselves up (the brief's fresh machine): a
target whose recipe runs the virtual environment's Python depends, directly
or through its prerequisites, on the environment, and one that imports the
extension (the validation harness, pytest, stubtest, Sphinx) on `develop`,
which builds it. `make bench-threads` alone once failed on a fresh clone
for want of `develop`."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# Modules run with the environment's Python that import quatrot.
NEEDS_EXTENSION = re.compile(r"\$\(SPHINX\)|\$\(PY\) -m (validation|pytest|mypy)")


def rules(text: str) -> dict[str, tuple[list[str], list[str]]]:
    """target -> (prerequisites, recipe lines) of the Makefile's rules (line
    continuations joined; variables and pattern rules left out)."""
    text = text.replace("\\\n", " ")
    found, current = {}, None
    for line in text.splitlines():
        if line.startswith("\t") and current is not None:
            found[current][1].append(line.strip())
            continue
        match = re.match(r"^([^\s:=#][^:=]*?)\s*:(?!=)\s*(.*)$", line)
        current = None
        if match and not match.group(1).startswith("."):
            for target in match.group(1).split():
                found[target] = (match.group(2).split(), [])
                current = target
    return found


def reaches(target: str, goal: str, table, seen=None) -> bool:
    seen = seen if seen is not None else set()
    if target == goal:
        return True
    seen.add(target)
    return any(reaches(p, goal, table, seen) for p in table.get(target, ([], []))[0] if p not in seen)


def test_targets_that_run_the_environment_depend_on_its_set_up():
    table = rules((ROOT / "Makefile").read_text())
    assert {"test", "validate", "bench", "bench-threads", "develop"} <= set(table)
    wrong = []
    for target, (_, recipe) in table.items():
        # A recipe's own `$(MAKE) other` hands the set-up to that target.
        own = [line for line in recipe if "$(MAKE)" not in line]
        if any(NEEDS_EXTENSION.search(line) for line in own) and not reaches(target, "develop", table):
            wrong.append(f"{target}: runs the extension without depending on develop")
        elif any("$(PY)" in line or "$(VENV)/bin" in line for line in own) and not (
                reaches(target, "$(STAMP_VENV)", table) or reaches(target, "develop", table)):
            wrong.append(f"{target}: runs the environment without depending on it")
    assert not wrong, wrong


def test_the_parser_sees_a_missing_dependency():
    text = "develop: $(STAMP_VENV)\n\tmaturin\nbench-threads:\n\tcargo build\n\t$(PY) -m validation.bench.threads\n"
    table = rules(text)
    assert table["bench-threads"] == ([], ["cargo build", "$(PY) -m validation.bench.threads"])
    assert not reaches("bench-threads", "develop", table)
    assert reaches("develop", "$(STAMP_VENV)", table)
