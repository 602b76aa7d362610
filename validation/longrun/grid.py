"""A grid of points (integrator configuration, time step, run length) on one
system, run as a `quatrot.sweep` (one scene run per point, a Dask task each)
and read back: each run's table row and its energy series.

Each run records the energy error `(E - E_0) / s` (`s`: the initial kinetic
energy; `|E_0|` for rotors starting at rest) and `|Q.Q'|` (eq 15a) at
`samples` points, and stops as a blow-up (non-finite state, or an energy
error above `threshold`), checked every `check_every` steps; the step it
stopped at is its failure step.
"""

from __future__ import annotations

import contextlib
import csv
import math
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import quatrot.sweep

#: What each run records (quantity names of the scene's `[[record.series]]`).
QUANTITIES = ("energy_error", "q_dot_q")


@dataclass
class Point:
    """One run of the grid: its configuration's label, step, length and outcome."""

    label: str
    dt: float
    steps: int
    status: str
    error: str
    #: The last step of the run: `steps` when it completed, else the step at
    #: which the blow-up guard stopped it.
    last_step: int
    wall_seconds: float
    outputs: Path
    series: dict[str, np.ndarray] = field(default_factory=dict, repr=False)

    @property
    def survived(self) -> int:
        """Steps run before the failure (all of them when it completed)."""
        return self.steps if self.status == "completed" else self.last_step

    def load(self) -> dict[str, np.ndarray]:
        """The energy series (`step`, `time` and `QUANTITIES` columns), read once."""
        if not self.series:
            self.series = read_series(self.outputs / "energies.csv")
        return self.series


def read_series(path: Path) -> dict[str, np.ndarray]:
    """A series CSV as columns (empty columns when the file has no rows)."""
    with path.open() as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    values = np.array([[float(x) for x in r] for r in body]) if body else np.zeros((0, len(header)))
    return {name: values[:, k] for k, name in enumerate(header)}


def record(steps: int, samples: int, threshold: float | None, check_every: int, quantities=QUANTITIES) -> dict[str, Any]:
    """The `[record]` table of a grid run: `samples` samples of `quantities` over `steps`."""
    every = max(1, steps // samples)
    table: dict[str, Any] = {
        "check_every": min(check_every, steps),
        "series": [{"name": "energies", "every": every, "quantities": list(quantities)}],
    }
    if threshold is not None:
        table["energy_error_threshold"] = threshold
    return table


@dataclass(frozen=True)
class Spec:
    """A point of a grid before it runs: a configuration (its label and
    `[integrator]` table), a time step and a run length."""

    label: str
    integrator: Mapping[str, Any]
    dt: float
    steps: int


def product(configurations: Mapping[str, Mapping[str, Any]], dts: Iterable[float], steps: int) -> list[Spec]:
    """Every configuration (label -> `[integrator]` table) at every step, `steps` steps each."""
    dts = list(dts)
    return [Spec(label, integrator, dt, steps) for label, integrator in configurations.items() for dt in dts]


def run(
    scene: dict[str, Any],
    specs: list[Spec],
    *,
    out: Path,
    samples: int = 1000,
    threshold: float | None = None,
    check_every: int = 10,
    quantities=QUANTITIES,
    client=None,
    workers: int = 2,
) -> list[Point]:
    """Runs every point of `specs` on `scene` as one sweep into `out`
    (resumed if `out` holds finished runs); returns the points in order.
    `client` as `quatrot.sweep.run` (None: a local cluster of `workers`)."""
    base = quatrot.sweep.apply(scene, {"run.time": None})
    cases = [
        {"integrator": dict(s.integrator), "run.dt": s.dt, "run.steps": s.steps, "record": record(s.steps, samples, threshold, check_every, quantities)}
        for s in specs
    ]
    runs = quatrot.sweep.expand(base, cases=cases)
    if len(runs) != len(cases):
        raise ValueError("grid: two points give the same scene")
    kwargs = {"client": client} if client is not None else {"workers": workers}
    results = quatrot.sweep.run(base, cases=cases, out=out, **kwargs)
    return [
        Point(
            label=s.label,
            dt=s.dt,
            steps=s.steps,
            status=row["status"],
            error=row["error"],
            last_step=int(row["last_step"]) if row["last_step"] else 0,
            wall_seconds=float(row["wall_seconds"]) if row["wall_seconds"] else math.nan,
            outputs=out / row["outputs"],
        )
        for s, row in zip(specs, results.rows)
    ]


@contextlib.contextmanager
def connect(scheduler: str | None = None) -> Iterator:
    """A client of the scheduler at `scheduler`, or of a local cluster of two
    single-threaded worker processes (started and stopped here)."""
    import distributed

    if scheduler:
        with distributed.Client(scheduler) as client:
            yield client
        return
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            yield client
