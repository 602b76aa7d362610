"""Orientation error against run length (issue 15, item 2): each scheme at
its time step of equal cost per unit time (those of the energy comparison,
`validation.longrun.accuracy`, rounded to a multiple of the reference step),
its orientations at log-spaced times compared with a reference's at the same
times.

The error of a run at time `t` is the rotation angle between its `Q` and the
reference's, `2 acos|Q.Q_ref|` (blind to the sign of either quaternion),
evaluated as `4 asin(|Q - s Q_ref| / 2)` with `s = sign(Q.Q_ref)` so that it
keeps its precision at small angles (`acos` near 1 resolves no angle below
~1e-8); on a lattice, the root mean square over the rotors.

The reference is quatrot's fifth-order scheme B with the higher-derivative
corrections at `u = dt0 / REFINE` (`dt0`: the cheapest scheme's step); its
own error is estimated by the same scheme at `u / 2`, and, since B +higher
is one of the schemes compared, its errors are measured against scheme A at
`u` instead. On the single rotor, scipy's DOP853 at rtol 1e-13
(`validation.shared.rotor_reference`, nothing from quatrot) checks the reference
over a shorter span. On a chaotic system (the lattice) two trajectories that
start 1e-12 apart separate as `exp(t / t_L)` until they are O(1) apart:
the reference pair's separation gives the Lyapunov time `t_L`, and the
orientation error stops meaning anything once the reference's own error
estimate reaches the errors it is meant to measure.

Orientations are taken at full precision from the runs' returned frames
(`quatrot.run`'s in-memory trajectory, float64), not from trajectory files
(DCD and GSD are float32). Each run is a chain of `quatrot.run` calls, each
restarting from the previous one's checkpoint (bit for bit the
uninterrupted run, `tests/run_scenes.rs::restart_from_checkpoint_is_bit_for_bit`)
and ending at the next sample step, so the samples cost nothing beyond the
run itself. Each chain is one task on the Dask cluster of the energy runs
(not a `quatrot.sweep` run: a sweep run keeps only its files).
"""

from __future__ import annotations

import math
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import quatrot
import quatrot.sweep

#: The reference's step is the cheapest scheme's over this.
REFINE = 8
#: The reference scheme, and the one that replaces it for that scheme itself.
REFERENCE = "B +higher"
ALTERNATE = "A"
#: Sample times per decade of run length.
PER_DECADE = 5
#: The first sample time, in steps of the cheapest scheme.
FIRST = 10


def equal_cost_steps(dts: Mapping[str, float], unit: float) -> dict[str, int]:
    """Each scheme's equal-cost step as a whole number of `unit` (at least 1)."""
    return {label: max(1, round(dt / unit)) for label, dt in dts.items()}


def sample_times(dt0: float, span: float) -> np.ndarray:
    """Log-spaced target times from `FIRST` steps of `dt0` to `span`."""
    count = max(2, int(round(PER_DECADE * math.log10(span / (FIRST * dt0)))) + 1)
    return np.geomspace(FIRST * dt0, span, count)


def sample_steps(times: np.ndarray, dt: float) -> np.ndarray:
    """The steps of a run at `dt` nearest to `times` (distinct, at least 1)."""
    return np.unique(np.maximum(1, np.round(times / dt)).astype(np.int64))


def chain(scene: dict[str, Any], integrator: Mapping[str, Any], dt: float, steps: list[int]) -> dict[str, Any]:
    """Runs `scene` with `integrator` at `dt` to each of `steps` in turn
    (each segment restarting from the previous one's checkpoint, one thread);
    returns the orientations there (`(len(steps), n, 4)`, NaN from a blow-up
    on), the steps, the CPU seconds and the blow-up's message, if any. A Dask task."""
    import time

    started = time.process_time()
    base = quatrot.sweep.apply(scene, {"integrator": dict(integrator), "run.dt": dt, "run.time": None, "record": None})
    rotors = 0
    out: list[np.ndarray] = []
    error = ""
    with tempfile.TemporaryDirectory(prefix="quatrot-orientation-") as tmp:
        restart = None
        for k, target in enumerate(steps):
            folder = Path(tmp) / str(k % 2)
            run_scene = quatrot.sweep.apply(
                base, {"run.steps": int(target), "record": {"trajectory": {"every": int(target)}, "checkpoint_every": int(target)}}
            )
            try:
                result = quatrot.run(run_scene, out_dir=str(folder), restart=restart, threads=1)
            except quatrot.BlowUpError as e:
                error = str(e)
                rotors = len(e.result["initial_orientations"])
                break
            frames = result["trajectory"]
            at = np.nonzero(frames["step"] == target)[0]
            if len(at) != 1:
                raise RuntimeError(f"orientation chain: no frame at step {target} (frames {frames['step']})")
            out.append(np.array(frames["orientations"][at[0]], dtype=np.float64))
            restart = str(folder / "checkpoint.json")
    out += [np.full((rotors, 4), np.nan)] * (len(steps) - len(out))
    return {"steps": list(steps), "orientations": np.array(out), "cpu_seconds": time.process_time() - started, "error": error}


def angles(q: np.ndarray, q_ref: np.ndarray) -> np.ndarray:
    """The rotation angle taking `q_ref` to `q`, per row (last axis 4): `2 acos|Q.Q_ref|`
    as `4 asin(|Q - s Q_ref| / 2)`, `s = sign(Q.Q_ref)`, after normalising both."""
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    r = q_ref / np.linalg.norm(q_ref, axis=-1, keepdims=True)
    s = np.where(np.sum(q * r, axis=-1) < 0, -1.0, 1.0)[..., None]
    chord = np.linalg.norm(q - s * r, axis=-1)
    return 4.0 * np.arcsin(np.minimum(chord / 2.0, 1.0))


def rms(a: np.ndarray) -> np.ndarray:
    """Root mean square over the last axis (the rotors)."""
    return np.sqrt(np.mean(a**2, axis=-1))


@dataclass
class Curve:
    """A scheme's orientation error at its sample times."""

    label: str
    dt: float
    times: np.ndarray
    error: np.ndarray
    #: The reference's own error estimate at the same times.
    reference_error: np.ndarray
    cpu_seconds: float
    blew_up: str = ""


@dataclass
class Outcome:
    """The orientation comparison of one study."""

    name: str
    dt0: float
    span: float
    unit: float
    steps_of_unit: dict[str, int]
    curves: dict[str, Curve]
    #: The reference pair (`u` and `u / 2`) and the alternate reference (A at `u`): separations at the reference's samples.
    pair_times: np.ndarray
    pair_separation: np.ndarray
    alternate_separation: np.ndarray
    reference_cpu_seconds: float
    lyapunov_time: float | None = None
    #: The time from which the reference's error estimate exceeds a tenth of every scheme's error.
    meaningless_after: float | None = None
    dop853: dict[str, Any] = field(default_factory=dict)
    #: The reference's orientations at `pair_times` (`(samples, n, 4)`).
    reference_q: np.ndarray | None = field(default=None, repr=False)


def lyapunov_time(times: np.ndarray, separation: np.ndarray, low: float = 1e-9, high: float = 1e-2) -> float | None:
    """`1 / slope` of `log(separation)` against time where the separation
    grows from `low` to `high`, if that growth is exponential: None with
    fewer than 3 samples there, a slope that is not positive, or a power law
    in time that fits `log(separation)` better (a regular system's phase
    error grows as a power of t, a chaotic one's exponentially)."""
    keep = (separation > low) & (separation < high) & np.isfinite(separation) & (times > 0)
    if np.count_nonzero(keep) < 3:
        return None
    t, y = times[keep], np.log(separation[keep])
    exponential, residual_exp, *_ = np.polyfit(t, y, 1, full=True)
    _, residual_power, *_ = np.polyfit(np.log(t), y, 1, full=True)
    worse = float(residual_exp[0]) if len(residual_exp) else 0.0
    better = float(residual_power[0]) if len(residual_power) else 0.0
    slope = exponential[0]
    return float(1.0 / slope) if slope > 0 and worse <= better else None


def measure(
    name: str,
    scene: dict[str, Any],
    schemes: Mapping[str, Mapping[str, Any]],
    dts: Mapping[str, float],
    dt0: float,
    span: float,
    client,
) -> Outcome:
    """Every scheme of `schemes` at its equal-cost step (`dts`, rounded to a
    multiple of `dt0 / REFINE`) over `span`, against the reference chains;
    one Dask task per chain on `client`."""
    unit = dt0 / REFINE
    m = equal_cost_steps({k: dts[k] for k in schemes}, unit)
    targets = sample_times(dt0, span)
    per_scheme = {label: sample_steps(targets, m[label] * unit) for label in schemes}
    # The reference's samples: every scheme's sample times, in steps of `unit`.
    ref_steps = np.unique(np.concatenate([per_scheme[k] * m[k] for k in schemes]))
    futures = {
        label: client.submit(chain, scene, schemes[label], m[label] * unit, per_scheme[label].tolist(), pure=False)
        for label in schemes
    }
    futures["reference"] = client.submit(chain, scene, schemes[REFERENCE], unit, ref_steps.tolist(), pure=False)
    futures["reference/2"] = client.submit(chain, scene, schemes[REFERENCE], unit / 2, (2 * ref_steps).tolist(), pure=False)
    futures["alternate"] = client.submit(chain, scene, schemes[ALTERNATE], unit, ref_steps.tolist(), pure=False)
    done = {k: f.result() for k, f in futures.items()}
    index = {int(s): i for i, s in enumerate(ref_steps)}
    ref, fine, alt = (done[k]["orientations"] for k in ("reference", "reference/2", "alternate"))
    pair = rms(angles(ref, fine))
    alternate = rms(angles(alt, ref))
    curves = {}
    for label in schemes:
        rows = [index[int(s * m[label])] for s in per_scheme[label]]
        against, estimate = (alt, alternate) if label == REFERENCE else (ref, pair)
        err = rms(angles(done[label]["orientations"], against[rows]))
        curves[label] = Curve(
            label, m[label] * unit, per_scheme[label] * m[label] * unit, err, estimate[rows], done[label]["cpu_seconds"], done[label]["error"]
        )
    pair_times = ref_steps * unit
    outcome = Outcome(
        name, dt0, span, unit, m, curves, pair_times, pair, alternate,
        sum(done[k]["cpu_seconds"] for k in ("reference", "reference/2", "alternate")),
    )
    outcome.reference_q = ref
    outcome.lyapunov_time = lyapunov_time(pair_times, pair)
    outcome.meaningless_after = meaningless_after(outcome)
    return outcome


def meaningless_after(o: Outcome) -> float | None:
    """The first time from which the reference's error estimate (the larger of
    the step pair's and the alternate's separation) is above a tenth of the
    smallest scheme error there, to the end; None if it never is."""
    smallest = np.full(len(o.pair_times), np.inf)
    for c in o.curves.values():
        at = np.searchsorted(o.pair_times, c.times)
        np.minimum.at(smallest, np.clip(at, 0, len(smallest) - 1), np.where(np.isfinite(c.error), c.error, np.inf))
    estimate = np.maximum(o.pair_separation, o.alternate_separation)
    sampled = np.isfinite(smallest)
    bad = sampled & (estimate > 0.1 * smallest)
    good = np.nonzero(sampled & ~bad)[0]
    if not bad.any():
        return None
    last_good = good[-1] if len(good) else -1
    after = np.nonzero(bad & (np.arange(len(bad)) > last_good))[0]
    return float(o.pair_times[after[0]]) if len(after) else None


#: An orientation error above this (rad) means the orientation is lost (a
#: random rotation is 2.3 rad away in RMS): errors are compared below it only.
LOST = 1.0


def comparable_until(o: "Outcome", first: Curve, second: Curve) -> float:
    """The end of the window in which two schemes' errors are compared: the
    span, or earlier the time from which errors mean nothing, or the first
    sample at which either error is above `LOST`."""
    end = o.span if o.meaningless_after is None else o.meaningless_after
    for c in (first, second):
        lost = np.nonzero(~(c.error <= LOST))[0]
        if len(lost):
            end = min(end, float(c.times[lost[0]]))
    return end


def crossover(first: Curve, second: Curve, until: float | None = None) -> float | None:
    """The first time from which `first`'s orientation error stays below
    `second`'s (interpolated in log time on `first`'s samples) up to `until`
    (default: the end); None if it is not below at the last sample before `until`."""
    if until is not None:
        keep = first.times < until
        if not keep.any():
            return None
        first = Curve(first.label, first.dt, first.times[keep], first.error[keep], first.reference_error[keep], first.cpu_seconds)
    t = first.times
    other = np.interp(np.log(t), np.log(second.times), np.log(np.where(second.error > 0, second.error, 1e-300)))
    mine = np.log(np.where(first.error > 0, first.error, 1e-300))
    mine = np.where(np.isfinite(first.error), mine, np.inf)
    worse = np.nonzero(mine >= other)[0]
    if len(worse) == 0:
        return float(t[0])
    last = worse[-1]
    return None if last == len(t) - 1 else float(t[last + 1])
