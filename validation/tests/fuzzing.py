"""The seeded fuzz of the Python tests (issue 37, item 10), shared by
`test_fuzz_analysis.py`, `test_fuzz_sweep_cli.py` and
`test_fuzz_output_links.py`: the seed and the number of cases, hostile
values, the report of a failing case, a tiny scene and snapshots of
folder trees.

Each case draws from its own generator, seeded by (seed, test, case), so a
failing case is reproduced by its seed alone: `QUATROT_FUZZ_SEED` sets the
seed (default `DEFAULT_SEED`) and `QUATROT_FUZZ_SCALE` multiplies every
test's number of cases (`make test` runs them at 1, `make validate` at 10).
"""

from __future__ import annotations

import hashlib
import os
import re
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import quatrot

DEFAULT_SEED = 37
SEED = int(os.environ.get("QUATROT_FUZZ_SEED", DEFAULT_SEED))
SCALE = int(os.environ.get("QUATROT_FUZZ_SCALE", 1))


def cases(test: str, count: int) -> Iterator[tuple[int, np.random.Generator]]:
    """`count` x `SCALE` cases of `test`, each with its own generator."""
    salt = zlib.crc32(test.encode())
    for case in range(count * SCALE):
        yield case, np.random.default_rng([SEED, salt, case])


class Failures:
    """The failing cases of a test, reported together at its end, each
    naming the seed and the case."""

    #: Failures shown in the report (the count says how many there were).
    SHOWN = 10

    def __init__(self):
        self.found: list[str] = []

    def add(self, case: int, why: str, detail: Any = "") -> None:
        self.found.append(f"fuzz seed {SEED} (QUATROT_FUZZ_SEED), case {case}: {why}\n{detail}")

    def report(self) -> None:
        if self.found:
            shown = "\n\n".join(self.found[: self.SHOWN])
            pytest.fail(f"{len(self.found)} failing cases; the first:\n{shown}", pytrace=False)


#: Numbers a user should not give: zeros, signs, subnormals, extremes and
#: non-finite values.
HOSTILE_FLOATS = (0.0, -0.0, -1.0, 5e-324, 1e-320, 1e-300, 1e-9, 0.5, 1e10, 1e300, 1e308, -1e308, np.nan, np.inf, -np.inf)
HOSTILE_INTS = (0, -1, 1, 2, 3, 2**31 - 1, 2**32, 2**53 + 1, 2**63 - 1, 2**63, 2**64, 2**70, -(2**70))
HOSTILE_TEXT = ("", " ", "0.1", "nan", "../../x", "/tmp/abs", "a\x1b[31mb\n", "\x00", "bad\ud800text", "x" * 5000, "é")


def pick(rng: np.random.Generator, items) -> Any:
    return items[int(rng.integers(len(items)))]


def hostile_scalar(rng: np.random.Generator) -> Any:
    """A number or text of any kind, or something that is neither."""
    kind = int(rng.integers(9))
    if kind < 3:
        return pick(rng, HOSTILE_FLOATS)
    if kind < 5:
        return pick(rng, HOSTILE_INTS)
    if kind == 5:
        return pick(rng, HOSTILE_TEXT)
    if kind == 6:
        return pick(rng, (None, True, False, np.float32(0.1), np.int64(-3), 1 + 2j))
    if kind == 7:
        return pick(rng, ([], [1.0], {"a": 1}, (), b"bytes"))
    return object()


#: The scene of the fuzz's runs and sweeps: the built-in dipole in a field,
#: 20 steps, energies every 5.
TINY = re.sub(r"(?m)^steps = \d+$", "steps = 20", quatrot.builtin_scenes()["dipole_in_field"]).replace("every = 10", "every = 5")
assert "steps = 20" in TINY and "every = 5" in TINY


def tree(root: Path, skip: Path | None = None) -> dict[str, str]:
    """What is under `root` (itself included, `skip` and what is under it
    left out), without following links: each path's kind and mode with a
    file's SHA-256 or a link's target."""
    out = {}
    stack = [root]
    while stack:
        path = stack.pop()
        if skip is not None and path == skip:
            continue
        st = os.lstat(path)
        name = str(path.relative_to(root))
        if path.is_symlink():
            out[name] = f"link {os.readlink(path)}"
        elif path.is_dir():
            out[name] = f"dir {st.st_mode:o}"
            stack.extend(path.iterdir())
        else:
            out[name] = f"file {st.st_mode:o} {hashlib.sha256(path.read_bytes()).hexdigest()}"
    return out


def changes(before: dict[str, str], after: dict[str, str]) -> list[str]:
    """The paths that appeared, went or changed between two `tree`s."""
    return sorted(p for p in before.keys() | after.keys() if before.get(p) != after.get(p))
