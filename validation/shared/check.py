"""The check record (`Check`: a measured error against a tolerance, with
provenance) and where and how checks run (`Context`): used by every check
module, the report and the long-run studies that checks and benchmarks share."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path


@dataclass
class Context:
    """Where and how checks run. ``quick`` selects the few-second subset used
    by ``make test``; ``seed`` makes every random input reproducible."""

    out_dir: Path
    quick: bool = False
    seed: int = 20261121

    def progress(self, message: str) -> None:
        """One indented line on the terminal for a long step (silent in quick mode)."""
        if not self.quick:
            print(f"      {message}", flush=True)


@dataclass
class Check:
    """One check: a measured error against a tolerance, with provenance."""

    name: str  # short and unique, e.g. "eq7 matrix vs scipy"
    proves: str  # one sentence: what passing proves, and what it does not
    tolerance: float
    measured: float
    references: dict[str, str]  # code compared with -> its version
    details: str = ""
    plots: list[Path] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return math.isfinite(self.measured) and self.measured <= self.tolerance
