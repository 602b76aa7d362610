"""How long each run of a grid lasts, and what the stability and energy
verdicts are at each run length: a run of `steps` steps that did not fail
contains the runs of every shorter length (the same trajectory's prefix), so
one run per (configuration, dt) answers for every length up to its own."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from validation.longrun.grid import Point

#: The run lengths (steps) at which verdicts are stated.
LENGTHS = (1_000, 10_000, 100_000)


@dataclass
class Stability:
    """The largest stable step of a configuration at one run length."""

    length: int
    #: The largest dt of the grid at which this and every smaller grid step
    #: lasted `length` steps; None when the smallest did not.
    largest: float | None
    #: True when the largest dt of the grid was stable (the true limit is higher).
    capped: bool
    #: The smallest grid dt that failed before `length`, and its failure step.
    first_unstable: float | None
    failed_at: int | None


def stability(points: list[Point], label: str, length: int) -> Stability:
    """The largest stable step of `label`'s points at `length` steps."""
    mine = sorted((p for p in points if p.label == label), key=lambda p: p.dt)
    largest = None
    for p in mine:
        if p.survived < length:
            return Stability(length, largest, False, p.dt, p.survived)
        largest = p.dt
    return Stability(length, largest, True, None, None)


@dataclass
class Window:
    """A run's energy and constraint statistics over its first `length` steps."""

    length: int
    #: Least-squares slope of the energy error against time (per unit time).
    drift: float
    #: Largest |energy error| and |Q.Q'| over the samples.
    max_energy_error: float
    max_q_dot_q: float


def window(point: Point, length: int) -> Window | None:
    """`point`'s statistics over steps 0..`length`, or None when it failed before."""
    if point.survived < length or point.steps < length:
        return None
    s = point.load()
    keep = s["step"] <= length
    t, e = s["time"][keep], s["energy_error"][keep]
    drift = float(np.polyfit(t, e, 1)[0]) if len(t) >= 2 else math.nan
    return Window(length, drift, float(np.max(np.abs(e))), float(np.max(np.abs(s["q_dot_q"][keep]))))
