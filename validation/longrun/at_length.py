"""Accuracy per second against run length (issue 15, item 2): the studies
(the experiment's single rotor in a field and its 64-rotor multipole lattice
at the report's or `make bench`'s lengths), each scheme at the step of equal
cost per unit time, the energy-error curves and their crossovers, the
orientation comparison (with scipy's DOP853 on the rotor), their tables and
plots. Run by the ``accuracy_at_length`` check and by
``python -m validation.bench.longrun``."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from validation.longrun import accuracy, grid, orientation, systems
from validation.longrun.experiment import fmt
from validation.shared import gear_systems
from validation.shared import rotor_reference as reference
from validation.shared.check import Context

#: Samples of each run's energy error (and points of the curves).
SAMPLES = 2_000
#: The schemes whose orientations are compared (issue 15: A, B, B +higher, NO_SQUISH, DLM).
ORIENTATION_SCHEMES = {k: systems.SCHEMES[k] for k in ("A", "B", "B +higher", "NO_SQUISH", "DLM")}
#: scipy's DOP853 tolerance for the rotor's independent check of the reference.
DOP853_RTOL = 1e-13


@dataclass
class Study:
    name: str
    scene: dict
    #: The cheapest scheme's step; the others get equal-cost steps from it.
    dt0: float
    #: Steps of the cheapest scheme (the time span is `dt0 * steps`).
    steps: int
    #: Steps of the cost runs (`n` and `2n`).
    cost_steps: int
    #: Steps of the cheapest scheme over which orientations are compared (the
    #: references cost 32 times a scheme's run: steps dt0/8, dt0/16 and the alternate).
    orientation_steps: int = 0
    #: The span (time) over which scipy's DOP853 checks the reference (rotor only).
    dop853_span: float = 0.0


def studies(ctx: Context, long: bool = False) -> list[Study]:
    """The validation report's lengths (quick: the machinery only); `long`:
    `make bench`'s long-run mode (1e7 steps of the rotor, 1e6 of the lattice)."""
    rotor = systems.rotor_in_field()
    if ctx.quick:
        # Cost runs of 2e5 and 4e5 steps (0.2 and 0.4 s): at 2e4 the CPU-time
        # difference is at the level of a loaded machine's noise, and the
        # equal-cost steps came out several times too large (make test, load 15).
        return [Study("rotor in field", rotor, 0.02, 20_000, 200_000, orientation_steps=2_000, dop853_span=10.0)]
    lattice = systems.multipole_lattice(ctx.seed)
    if long:
        return [
            Study("rotor in field", rotor, 0.02, 10_000_000, 200_000, orientation_steps=ORIENTATION_STEPS_LONG["rotor"], dop853_span=1_000.0),
            Study("64-rotor multipole lattice", lattice, 0.01, 1_000_000, 4_000, orientation_steps=ORIENTATION_STEPS_LONG["lattice"]),
        ]
    return [
        Study("rotor in field", rotor, 0.02, 10_000_000, 200_000, orientation_steps=ORIENTATION_STEPS["rotor"], dop853_span=200.0),
        Study("64-rotor multipole lattice", lattice, 0.01, 200_000, 4_000, orientation_steps=ORIENTATION_STEPS["lattice"]),
    ]


#: Orientation spans (steps of dt0) of the validation report and of `make
#: bench`'s long-run mode. The lattice's orientation errors saturate within
#: a few Lyapunov times (a few hundred time units at most), so its spans are shorter.
ORIENTATION_STEPS = {"rotor": 1_000_000, "lattice": 10_000}
ORIENTATION_STEPS_LONG = {"rotor": 10_000_000, "lattice": 50_000}


@dataclass
class Outcome:
    study: Study
    cost: dict[str, float]
    dts: dict[str, float]
    points: list[grid.Point]
    curves: dict[str, accuracy.Curve]
    crossovers: dict[tuple[str, str], float | None]
    orientation: orientation.Outcome | None = None
    #: Symplectic x Gear crossover times in orientation error.
    orientation_crossovers: dict[tuple[str, str], tuple[float | None, float]] = dataclasses.field(default_factory=dict)


def measure(study: Study, out: Path, client) -> Outcome:
    schemes = systems.SCHEMES
    cost = accuracy.costs(study.scene, schemes, study.dt0, study.cost_steps, out=out / "costs", client=client)
    dts = accuracy.equal_cost_dts(cost, study.dt0)
    span = study.dt0 * study.steps
    specs = [grid.Spec(label, schemes[label], dt, max(1, round(span / dt))) for label, dt in dts.items()]
    points = grid.run(study.scene, specs, out=out / "runs", samples=SAMPLES, client=client)
    found = accuracy.curves(points, span, SAMPLES)
    crossovers = {(s, g): accuracy.crossover(found[s], found[g]) for s in systems.SYMPLECTIC for g in systems.GEAR}
    outcome = Outcome(study, cost, dts, points, found, crossovers)
    if study.orientation_steps:
        outcome.orientation = measure_orientation(study, dts, client)
        curves = outcome.orientation.curves
        outcome.orientation_crossovers = orientation_crossovers(outcome.orientation)
    return outcome


def orientation_crossovers(r: orientation.Outcome) -> dict[tuple[str, str], tuple[float | None, float]]:
    """(crossover time, end of the window compared) of each symplectic x Gear pair."""
    out = {}
    for s in ORIENTATION_SYMPLECTIC:
        for g in ORIENTATION_GEAR:
            until = orientation.comparable_until(r, r.curves[s], r.curves[g])
            out[(s, g)] = (orientation.crossover(r.curves[s], r.curves[g], until), until)
    return out


ORIENTATION_SYMPLECTIC = tuple(k for k in ORIENTATION_SCHEMES if k in systems.SYMPLECTIC)
ORIENTATION_GEAR = tuple(k for k in ORIENTATION_SCHEMES if k in systems.GEAR)


def measure_orientation(study: Study, dts: dict[str, float], client) -> orientation.Outcome:
    """The orientation comparison of `study` at the energy comparison's equal-cost steps;
    on the rotor, the reference checked against scipy's DOP853 over `study.dop853_span`."""
    found = orientation.measure(
        study.name, study.scene, ORIENTATION_SCHEMES, dts, study.dt0, study.dt0 * study.orientation_steps, client
    )
    if study.dop853_span:
        arrays, options = gear_systems.rotor_in_field(quick=True)
        keep = found.pair_times <= study.dop853_span
        times = found.pair_times[keep]
        exact = reference.single_rotor_path(
            arrays["inertia"][0], options["dipoles"][0], options["field"], arrays["orientations"][0], arrays["omega_body"][0],
            times, rtol=DOP853_RTOL, atol=1e-15,
        )
        distance = orientation.angles(found.reference_q[keep][:, 0, :], exact)
        # A chain that blew up has NaN errors from then on: the smallest of the others.
        smallest = np.nanmin([np.interp(times, c.times, c.error) for c in found.curves.values()], axis=0)
        found.dop853 = {
            "span": study.dop853_span,
            "rtol": DOP853_RTOL,
            "samples": int(len(times)),
            "max_distance": float(np.max(distance)),
            "max_fraction": float(np.max(distance / smallest)),
            "pair_max": float(np.max(found.pair_separation[keep])),
        }
    return found


def table(o: Outcome) -> str:
    span = o.study.dt0 * o.study.steps
    lines = [
        f"### {o.study.name}: time span {span:g} ({o.study.steps:.0e} steps of the cheapest scheme at dt {o.study.dt0:g})",
        "",
        "| scheme | CPU us per step | equal-cost dt | steps | status | energy error up to t = span/1000, span/100, span/10, span |",
        "|---|---|---|---|---|---|",
    ]
    n = len(next(iter(o.curves.values())).times)
    marks = [n // 1000 - 1, n // 100 - 1, n // 10 - 1, n - 1]
    for p in o.points:
        c = o.curves[p.label]
        errors = ", ".join(fmt(float(c.error[max(m, 0)])) for m in marks)
        lines.append(f"| {p.label} | {o.cost[p.label] * 1e6:.3g} | {p.dt:.4g} | {p.steps} | {p.status} | {errors} |")
    lines += ["", "Crossover times (symplectic scheme more accurate in energy than the Gear scheme from then on, at equal cost):", ""]
    lines += ["| symplectic \\ Gear | " + " | ".join(systems.GEAR) + " |", "|---|" + "---|" * len(systems.GEAR)]
    for s in systems.SYMPLECTIC:
        cells = []
        for g in systems.GEAR:
            t = o.crossovers[(s, g)]
            cells.append("not within the run" if t is None else f"t = {t:.4g} ({t / o.dts[s]:.3g} of its steps)")
        lines.append(f"| {s} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _at(c: orientation.Curve, t: float) -> float:
    """A curve's error at its last sample at or before `t` (NaN before its first)."""
    k = np.searchsorted(c.times, t * (1 + 1e-9), side="right") - 1
    return float(c.error[k]) if k >= 0 else math.nan


def orientation_table(o: Outcome) -> str:
    """Markdown: the orientation errors of each scheme at four run lengths,
    the reference's error estimates there, the crossovers, the Lyapunov time."""
    r = o.orientation
    if r is None:
        return ""
    span = r.span
    marks = [span / 1000, span / 100, span / 10, span]
    lines = [
        f"#### {o.study.name}: orientation error, time span {span:g} ({o.study.orientation_steps:.0e} steps of dt {o.study.dt0:g})",
        "",
        f"RMS over the rotors of the rotation angle `2 acos|Q.Q_ref|` (rad). Reference: scheme {orientation.REFERENCE} at "
        f"u = dt0/{orientation.REFINE} = {r.unit:g} ({orientation.ALTERNATE} at u for {orientation.REFERENCE} itself); its own error "
        f"estimated by {orientation.REFERENCE} at u/2; each scheme's equal-cost dt rounded to a multiple of u. "
        f"Reference CPU time {r.reference_cpu_seconds:.0f} s.",
        "",
        "| scheme | dt (equal-cost dt) | CPU s | error at t = " + ", ".join(f"{t:.4g}" for t in marks) + " |",
        "|---|---|---|---|",
    ]
    for label, c in r.curves.items():
        errors = ", ".join(fmt(_at(c, t)) for t in marks)
        note = f" (blew up: {c.blew_up})" if c.blew_up else ""
        lines.append(f"| {label} | {c.dt:.4g} ({o.dts[label]:.4g}) | {c.cpu_seconds:.1f} | {errors}{note} |")
    pair = orientation.Curve("pair", r.unit, r.pair_times, r.pair_separation, r.pair_separation, 0.0)
    alt = orientation.Curve("alt", r.unit, r.pair_times, r.alternate_separation, r.alternate_separation, 0.0)
    lines.append(f"| reference error estimate (u vs u/2) | - | - | {', '.join(fmt(_at(pair, t)) for t in marks)} |")
    lines.append(f"| reference vs {orientation.ALTERNATE} at u | - | - | {', '.join(fmt(_at(alt, t)) for t in marks)} |")
    lines.append("")
    if r.dop853:
        d = r.dop853
        lines.append(
            f"scipy DOP853 (rtol {d['rtol']:g}) against the reference over t <= {d['span']:g} ({d['samples']} samples): "
            f"largest angle {d['max_distance']:.2e} rad, at most {d['max_fraction']:.2e} of the smallest scheme error there."
        )
    lines.append(
        "Lyapunov time of the reference pair (exponential separation between 1e-9 and 1e-2 rad): "
        + ("none found (no exponential separation over the span)" if r.lyapunov_time is None else f"{r.lyapunov_time:.3g}")
        + ". Orientation errors are "
        + (
            "meaningful over the whole span (the reference's error estimate stays below a tenth of every scheme's error)."
            if r.meaningless_after is None
            else f"meaningless from t = {r.meaningless_after:.4g} ({r.meaningless_after / o.study.dt0:.3g} steps of dt {o.study.dt0:g}) on: "
            "the reference's own error estimate exceeds a tenth of the smallest scheme error from then on."
        )
    )
    lines += [
        "",
        f"Crossover times in orientation error (symplectic scheme more accurate from then on, at equal cost), compared while "
        f"both errors are below {orientation.LOST:g} rad (beyond, the orientation is lost) and the reference is meaningful:",
        "",
    ]
    lines += ["| symplectic \\ Gear | " + " | ".join(ORIENTATION_GEAR) + " |", "|---|" + "---|" * len(ORIENTATION_GEAR)]
    for sy in ORIENTATION_SYMPLECTIC:
        cells = []
        for g in ORIENTATION_GEAR:
            t, until = o.orientation_crossovers[(sy, g)]
            cells.append(f"none before t = {until:.4g}" if t is None else f"t = {t:.4g} (compared to t = {until:.4g})")
        lines.append(f"| {sy} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def plot(outcomes: list[Outcome], out_dir: Path, name: str = "accuracy_at_length.png") -> Path:
    """Energy error (running maximum, top row) and orientation error (bottom
    row, with the reference's error estimate) against run length, per study."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = 2 if any(o.orientation for o in outcomes) else 1
    fig, axes = plt.subplots(rows, len(outcomes), figsize=(6 * len(outcomes), 4.5 * rows), squeeze=False)
    for ax, o in zip(axes[-1], outcomes):
        if rows == 2:
            _plot_orientation(ax, o)
    for ax, o in zip(axes[0], outcomes):
        for label, c in o.curves.items():
            style = "-" if label in systems.SYMPLECTIC else ("--" if label in systems.GEAR else ":")
            ax.plot(c.times / o.study.dt0, c.error, style, label=f"{label} (dt {o.dts[label]:.3g})")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(f"run length (steps of dt = {o.study.dt0:g}; equal cost for every scheme)")
        ax.set_ylabel("max |E - E0| / K0 up to then")
        ax.set_title(f"{o.study.name}: energy error, {o.study.steps:.0e} steps of dt {o.study.dt0:g}", fontsize=9)
        ax.legend(fontsize=6)
    fig.tight_layout()
    path = out_dir / name
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def orientation_plot(outcomes: list[Outcome], out_dir: Path, name: str = "orientation_at_length.png") -> Path:
    """Orientation error against run length alone, per study."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(outcomes), figsize=(6 * len(outcomes), 4.5), squeeze=False)
    for ax, o in zip(axes[0], outcomes):
        _plot_orientation(ax, o)
    fig.tight_layout()
    path = out_dir / name
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _plot_orientation(ax, o: Outcome) -> None:
    """Orientation error against run length, the reference's error estimate
    and (if any) the time from which the errors mean nothing."""
    r = o.orientation
    if r is None:
        ax.set_visible(False)
        return
    for label, c in r.curves.items():
        style = "-" if label in systems.SYMPLECTIC else "--"
        ax.plot(c.times / o.study.dt0, c.error, style, marker=".", label=f"{label} (dt {c.dt:.3g})")
    estimate = np.maximum(r.pair_separation, r.alternate_separation)
    ax.plot(r.pair_times / o.study.dt0, estimate, ":", color="gray", label="reference's error estimate")
    if r.meaningless_after is not None:
        ax.axvline(r.meaningless_after / o.study.dt0, color="red", lw=0.8, label="errors meaningless from here")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(f"run length (steps of dt = {o.study.dt0:g}; equal cost for every scheme)")
    ax.set_ylabel("orientation error, RMS 2 acos|Q.Q_ref| (rad)")
    lyap = "" if r.lyapunov_time is None else f"; Lyapunov time {r.lyapunov_time:.3g}"
    ax.set_title(f"{o.study.name}: orientation error, {o.study.orientation_steps:.0e} steps of dt {o.study.dt0:g}{lyap}", fontsize=9)
    ax.legend(fontsize=6)
