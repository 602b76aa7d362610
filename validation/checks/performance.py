"""Performance: work-precision of every scheme on the built-in scenes, with
LAMMPS (`fix nve/sphere update dipole` and `dipole/dlm`) placed on the same
plot for the 1000-rotor dipole lattice; the largest stable steps, long runs,
stress cases and scaling. The numbers come from the last `make bench`
(`benchmarks/results.json`, section of `benchmarks/RESULTS.md`); this module
does not time anything. It checks that the results file is complete, that its
target-error table follows from its own runs, that the recorded runs meet
the two throughput targets against LAMMPS, and the accuracy-only facts it records:
the observed global order of the second-order baselines."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

from validation.shared.benchmark_scenes import LATTICE_SCENE
from validation.shared.check import Check, Context

RESULTS = Path(__file__).resolve().parents[2] / "benchmarks" / "results.json"
SECTIONS = ("studies", "lammps", "stability", "long_runs", "stress", "scaling", "machine", "versions")
# Second-order methods (NO_SQUISH, DLM, Richardson: symmetric splittings):
# the fitted slope over three halvings of dt is 2 up to higher-order terms.
ORDER_TOL = 0.3
SECOND_ORDER = ("NO_SQUISH", "DLM", "Richardson")
# The throughput target: quatrot at least this many times faster than LAMMPS dipole/dlm.
THROUGHPUT_RATIO = 10.0


def _load() -> dict | None:
    return json.loads(RESULTS.read_text()) if RESULTS.exists() else None


def _fastest(runs, target):
    ok = [r for r in runs if not r["failure"] and r.get("error") is not None and r["error"] <= target and r.get("wall_median") is not None]
    return min(ok, key=lambda r: r["wall_median"]) if ok else None


def _table_inconsistencies(results: dict) -> list[str]:
    bad = []
    for s in results["studies"]:
        for row in s["targets"]:
            best = _fastest(s["runs"], row["target"])
            claimed = row["quatrot"]
            if (best is None) != (claimed is None) or (best and (best["scheme"], best["dt"]) != (claimed["scheme"], claimed["dt"])):
                bad.append(f"{s['scene']} at {row['target']:g}: table says {claimed}, runs give {best and (best['scheme'], best['dt'])}")
    return bad


def _figures(results: dict, out: Path) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for name in results.get("figures", {}).values():
        src = RESULTS.parent / name
        if src.exists():
            paths.append(Path(shutil.copy(src, out / name)))
    return paths


def run(ctx: Context) -> list[Check]:
    results = _load()
    versions = {}
    missing = list(SECTIONS) if results is None else [k for k in SECTIONS if k not in results]
    if results is not None:
        versions = {"scipy": results["versions"].get("scipy", "?"), "LAMMPS": str(results["versions"].get("lammps", "?"))}
    checks = [
        Check(
            name="benchmark results file complete",
            proves="benchmarks/results.json from the last `make bench` parses and holds every section; it does not prove the numbers are current.",
            tolerance=0.0,
            measured=float(len(missing)),
            references=versions,
            details=("Missing: " + ", ".join(missing)) if missing else _summary(results),
            plots=[] if results is None else _figures(results, ctx.out_dir),
        )
    ]
    if results is None:
        return checks
    bad = _table_inconsistencies(results)
    checks.append(
        Check(
            name="target-error table follows from the runs",
            proves="Each 'fastest scheme at target error' entry is the least-time run whose error (against scipy or the lattice reference) is at most the target.",
            tolerance=0.0,
            measured=float(len(bad)),
            references=versions,
            details="\n".join(f"- {b}" for b in bad),
        )
    )
    checks += _throughput_targets(results, versions)
    free = next((s for s in results["studies"] if s["scene"] == "free_asymmetric_top"), None)
    if free is not None:
        orders = {k: free["orders"].get(k) for k in SECOND_ORDER}
        worst = max((abs(v - 2.0) if v is not None else math.inf) for v in orders.values())
        checks.append(
            Check(
                name="second-order baselines: observed order 2 (free asymmetric top vs scipy)",
                proves="NO_SQUISH, DLM and Richardson converge at second order to scipy's DOP853 solution, as symmetric splittings must.",
                tolerance=ORDER_TOL,
                measured=worst,
                references=versions,
                details=", ".join(f"{k}: {v:.2f}" if v is not None else f"{k}: n/a" for k, v in orders.items()),
            )
        )
    return checks


def _throughput_targets(results: dict, versions: dict) -> list[Check]:
    """The two throughput targets against LAMMPS, as the last `make bench` recorded them (no timing
    here): the side-by-side throughput of every quatrot CLI run at least
    THROUGHPUT_RATIO times LAMMPS dipole/dlm's per thread, and each target
    error reached by quatrot in under 1/THROUGHPUT_RATIO of LAMMPS dipole/dlm's
    time (measured, or extrapolated along LAMMPS's own error-cost line)."""
    rates = (results["lammps"].get("side_by_side") or {}).get("rotor_steps_per_second", {})
    lattice = next((s for s in results["studies"] if s["scene"] == LATTICE_SCENE), None)
    if not rates or lattice is None or "LAMMPS dipole/dlm" not in rates:
        return []
    dlm = rates["LAMMPS dipole/dlm"]
    ratios = {k: v / dlm for k, v in rates.items() if k.startswith("quatrot")}
    speedups = {row["target"]: row.get("ratio_vs_dlm") for row in lattice["targets"]}
    return [
        Check(
            name="throughput: quatrot CLI / LAMMPS dipole/dlm per thread, side by side (lattice)",
            proves="Every quatrot CLI run (step loop and whole process, NO_SQUISH and scheme B) did at least 10x LAMMPS dipole/dlm's rotor-steps per second on one thread, in alternation in the last `make bench`.",
            tolerance=0.0,
            measured=max(0.0, THROUGHPUT_RATIO - min(ratios.values())),
            references=versions,
            details=", ".join(f"{k}: {v:.3g}x" for k, v in ratios.items()),
        ),
        Check(
            name="work-precision: quatrot reaches each target error in < 1/10 of LAMMPS dipole/dlm's time (lattice)",
            proves="For target errors 1e-4, 1e-6, 1e-8 the fastest quatrot run took under a tenth of LAMMPS dipole/dlm's time to reach the same error (LAMMPS's time extrapolated where it does not reach the target in the tested steps).",
            tolerance=0.0,
            measured=float(sum(1 for v in speedups.values() if v is None or v < THROUGHPUT_RATIO)),
            references=versions,
            details=", ".join(f"{t:g}: {v:.3g}x" if v else f"{t:g}: not reached" for t, v in speedups.items()),
        ),
    ]


def _summary(results: dict) -> str:
    lattice = next((s for s in results["studies"] if s["scene"] == LATTICE_SCENE), None)
    lines = [f"Measured {results['machine']['date']} on {results['machine']['cpu']} (quick mode: {results['quick']})."]
    if lattice:
        lam = results["lammps"]["throughput"]
        best = max(lattice["throughput"].items(), key=lambda kv: kv[1] or 0)
        lines.append(
            f"Dipole lattice, 1 thread: quatrot {best[0]} {best[1]:.3g} rotor-steps/s; "
            + ", ".join(f"{k} {v:.3g}" for k, v in lam.items() if v)
            + "."
        )
        sbs = (results["lammps"].get("side_by_side") or {}).get("rotor_steps_per_second", {})
        if sbs:
            lines.append("Side by side (CLI vs LAMMPS, alternating): " + ", ".join(f"{k} {v:.3g}" for k, v in sbs.items()) + " rotor-steps/s.")
        for row in lattice["targets"]:
            q = row["quatrot"]
            lines.append(f"- target {row['target']:g}: " + (f"{q['scheme']} dt {q['dt']:g}, {q['wall'] * 1e3:.3g} ms" if q else "not reached") + f"; ratio LAMMPS dlm / quatrot: {row.get('ratio_vs_dlm')}")
    lines.append("Tables and discussion: benchmarks/RESULTS.md.")
    return "\n".join(lines)
