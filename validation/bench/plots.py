"""The benchmark's figures (PNG)."""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from validation.bench.analysis import TARGETS, by_scheme  # noqa: E402
from validation.shared.benchmark_scenes import LATTICE_SCENE  # noqa: E402

MARKERS = "osD^v<>ph*xX"


def _series(ax, runs, x_key, label, marker, style="-"):
    pts = sorted((r[x_key], r["error"]) for r in runs if math.isfinite(r.get(x_key, math.nan)) and r.get("error", 0) > 0 and math.isfinite(r["error"]))
    if pts:
        x, y = zip(*pts)
        ax.loglog(x, y, style, marker=marker, ms=4, label=label)


def work_precision(studies: list[dict], lammps: list[dict], out: Path) -> Path:
    """Error at the final time against loop wall time, one panel per scene."""
    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    for ax, study in zip(axes.flat, studies):
        for k, (scheme, runs) in enumerate(by_scheme(study["runs"]).items()):
            _series(ax, runs, "wall_median", scheme, MARKERS[k % len(MARKERS)])
        if study["scene"] == LATTICE_SCENE:
            for k, (scheme, runs) in enumerate(by_scheme(lammps).items()):
                _series(ax, runs, "wall_median", scheme, "X+"[k % 2], style="--")
        for t in TARGETS:
            ax.axhline(t, color="grey", lw=0.5, ls=":")
        ax.set_title(f"{study['scene']} (t = {study['time']:g}; reference: {study['reference']['kind']})", fontsize=9)
        ax.set_xlabel("loop wall time, 1 thread [s] (median)")
        ax.set_ylabel("orientation error [rad]" if study["system"]["rotors"] == 1 else "max axis error [rad]")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    path = out / "work_precision.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def error_vs_dt(studies: list[dict], out: Path) -> Path:
    """Error against time step (the observed orders)."""
    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    for ax, study in zip(axes.flat, studies):
        for k, (scheme, runs) in enumerate(by_scheme(study["runs"]).items()):
            _series(ax, runs, "dt", f"{scheme} (p = {study['orders'].get(scheme, math.nan):.2f})", MARKERS[k % len(MARKERS)])
        ax.set_title(study["scene"], fontsize=9)
        ax.set_xlabel("dt")
        ax.set_ylabel("error [rad]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    path = out / "error_vs_dt.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def scaling(rows: list[dict], out: Path) -> Path:
    """Time per step against N, 1 and 2 threads, with the linear reference;
    and the pair-list build time against N."""
    fig, (ax, build) = plt.subplots(1, 2, figsize=(11, 4.5))
    for threads, marker in ((1, "o"), (2, "s")):
        pts = sorted((r["rotors"], r["seconds_per_step"]) for r in rows if r["threads"] == threads)
        if pts:
            n, t = map(np.array, zip(*pts))
            ax.loglog(n, t, marker=marker, label=f"{threads} thread{'s' if threads > 1 else ''}")
            if threads == 1:
                ax.loglog(n, t[-1] * n / n[-1], "k:", lw=0.8, label="linear in N")
    ax.set_xlabel("rotors N (sc lattice, cutoff 3.1)")
    ax.set_ylabel("seconds per step (NO_SQUISH)")
    ax.grid(True, alpha=0.3)
    ax.legend()
    pts = sorted((r["rotors"], r["pair_list_seconds"]) for r in rows if r["threads"] == 1 and r["pair_list_seconds"] > 0)
    if pts:
        n, t = map(np.array, zip(*pts))
        build.loglog(n, t, marker="o", label="pair-list build")
        build.loglog(n, t[-1] * n / n[-1], "k:", lw=0.8, label="linear in N")
    build.set_xlabel("rotors N")
    build.set_ylabel("seconds (once per potential)")
    build.grid(True, alpha=0.3)
    build.legend()
    fig.tight_layout()
    path = out / "scaling.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def stability(rows: list[dict], out: Path) -> Path:
    """Largest stable time step per scheme and scene. A scheme stable at every
    step of the grid (`capped`) has only a lower bound: its bar is hatched
    and topped by an upward arrow, labelled ">=", not a measurement."""
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    schemes = list(dict.fromkeys(r["scheme"] for r in rows))
    fig, ax = plt.subplots(figsize=(10, 4.5))
    width = 0.8 / len(scenes)
    for k, scene in enumerate(scenes):
        found = [next((r for r in rows if r["scene"] == scene and r["scheme"] == s), None) for s in schemes]
        values = [(r["largest_stable_dt"] or math.nan) if r else math.nan for r in found]
        capped = [bool(r and r.get("capped")) for r in found]
        x = np.arange(len(schemes)) + k * width
        bars = ax.bar(x, values, width, label=scene)
        for bar, xk, v, c in zip(bars, x, values, capped):
            if c and math.isfinite(v):
                bar.set_hatch("//")
                ax.annotate(">=", (xk, v), xytext=(0, 10), textcoords="offset points", ha="center", fontsize=6,
                            arrowprops=dict(arrowstyle="<-", lw=0.8))
    ax.set_yscale("log")
    ax.margins(y=0.12)
    ax.set_title("hatched with >=: stable at every step of the grid (a lower bound, not a measurement)", fontsize=8)
    ax.set_xticks(np.arange(len(schemes)) + 0.4 - width / 2, schemes, rotation=30, fontsize=7)
    ax.set_ylabel("largest stable dt")
    ax.legend(fontsize=7)
    fig.tight_layout()
    path = out / "stability.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
