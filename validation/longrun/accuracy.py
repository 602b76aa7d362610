"""Accuracy per second against run length (issue 15, item 2): each scheme at
the time step of equal cost per unit time, all run over the same time span,
their energy errors compared at each time.

Costs are measured side by side in one sweep: each scheme runs `n` and `2n`
steps with nothing recorded, and its cost per step is the difference of the
two tasks' CPU times over `n` (the run's set-up, the Gear start-up and the
task's fixed costs cancel; CPU time rather than wall time, since the cores
are shared). A scheme of cost `c` per step then gets `dt = dt0 c / c_min`,
so that every scheme spends the same CPU time per unit of simulated time as
the cheapest one at `dt0`.

The energy error of a run up to time `t` is the largest `|E - E_0| / K_0`
over its samples up to `t` (its running maximum). A symplectic scheme's
error stays bounded; a Gear scheme's grows with its drift. The crossover
time of a (symplectic, Gear) pair is the first sample time from which the
symplectic scheme's error stays below the Gear scheme's to the end of the run.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import quatrot.sweep

from validation.longrun import grid


def costs(
    scene: dict[str, Any],
    schemes: Mapping[str, dict[str, Any]],
    dt: float,
    steps: int,
    *,
    out: Path,
    client,
) -> dict[str, float]:
    """CPU seconds per step of each scheme (label -> `[integrator]` table) on
    `scene` at `dt`, from runs of `steps` and `2 steps` with nothing recorded."""
    base = quatrot.sweep.apply(scene, {"run.time": None, "run.dt": dt, "record": None})
    cases = [{"integrator": integrator, "run.steps": n} for integrator in schemes.values() for n in (steps, 2 * steps)]
    results = quatrot.sweep.run(base, cases=cases, out=out, client=client)
    cpu = [float(row["cpu_seconds"]) for row in results.rows]
    bad = [row for row in results.rows if row["status"] != "completed"]
    if bad:
        raise RuntimeError(f"cost runs did not complete: {[(r['id'], r['status'], r['error']) for r in bad]}")
    return {label: max(cpu[2 * k + 1] - cpu[2 * k], 0.0) / steps for k, label in enumerate(schemes)}


def equal_cost_dts(cost: Mapping[str, float], dt0: float) -> dict[str, float]:
    """The step of each scheme at which it costs what the cheapest costs at `dt0` per unit time."""
    cheapest = min(cost.values())
    return {label: dt0 * c / cheapest for label, c in cost.items()}


@dataclass
class Curve:
    """A scheme's running-maximum energy error on the common time grid."""

    label: str
    dt: float
    steps: int
    times: np.ndarray
    error: np.ndarray


def curves(points: list[grid.Point], span: float, samples: int) -> dict[str, Curve]:
    """The running maximum of each point's |energy error| at `samples` times in (0, span]
    (a run that failed has an infinite error from its failure on)."""
    times = span * np.arange(1, samples + 1) / samples
    out = {}
    for p in points:
        s = p.load()
        running = np.maximum.accumulate(np.abs(s["energy_error"]))
        # the running maximum at the last sample at or before each time
        idx = np.searchsorted(s["time"], times * (1 + 1e-12), side="right") - 1
        error = np.where(idx >= 0, running[np.clip(idx, 0, None)], 0.0)
        if p.status != "completed":
            error = np.where(times > p.survived * p.dt, np.inf, error)
        out[p.label] = Curve(p.label, p.dt, p.steps, times, error)
    return out


def crossover(symplectic: Curve, gear: Curve) -> float | None:
    """The first time from which `symplectic`'s error stays below `gear`'s to
    the end (the first time of the grid if it always is; None if it never ends below)."""
    worse = np.nonzero(symplectic.error >= gear.error)[0]
    if len(worse) == 0:
        return float(symplectic.times[0])
    last = worse[-1]
    return None if last == len(symplectic.times) - 1 else float(symplectic.times[last + 1])
