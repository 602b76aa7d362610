"""The benchmark's scans as sweeps (issue 18): the largest stable step of
every scheme on every benchmark scene, the long runs at the scenes' own
steps, and the stress cases at length (issue 15, item 3), each a
`quatrot.sweep` grid of scene runs, so the same scan runs on this machine's
local Dask cluster or on any cluster (`client=`). They return the rows the
report (`results_md`, `plots`) reads.

The work-precision scan stays in the Rust driver (`cargo bench --bench
performance`): it times the bare loop (nothing recorded, median of repeats,
one run at a time on an otherwise idle core) and measures final-orientation
errors down to 1e-13 against references; a sweep's runs share the cores
with each other, and their outputs carry orientations in float32
trajectories, not at full precision.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import quatrot

from validation.longrun import grid, systems

#: "Stable" means |E - E_0| < STABLE_ENERGY_ERROR * KE_0 at every check (|E_0|
#: for rotors starting at rest).
STABLE_ENERGY_ERROR = 0.1
#: Grid steps per doubling of dt in the stability scan (2^(1/4): 19 %).
PER_OCTAVE = 4
#: The stability grid spans `dt_start * 2^-OCTAVES_BELOW` .. the cap `time / MIN_STEPS`.
OCTAVES_BELOW = 3
MIN_STEPS = 10.0


@dataclass
class StabilityCase:
    scene: str
    time: float
    dt_start: float
    check_every: int


def stability_cases(quick: bool) -> list[StabilityCase]:
    """The scenes, run times and check intervals of the stability scan."""
    pick = (lambda full, q: q) if quick else (lambda full, q: full)
    return [
        StabilityCase("free_asymmetric_top", pick(20.0, 1.0), 0.05, 1),
        StabilityCase("dipole_in_field", pick(10.0, 1.0), 0.02, 1),
        StabilityCase("dipole_lattice_sc_cutoff", pick(2.0, 0.02), 0.004, 2),
        StabilityCase("quadrupole_lattice_fcc", pick(2.0, 0.02), 0.004, 2),
    ]


def builtin(name: str) -> dict[str, Any]:
    scene = tomllib.loads(quatrot.builtin_scenes()[name])
    scene.pop("record", None)
    return scene


def stability_dts(case: StabilityCase) -> list[float]:
    cap = case.time / MIN_STEPS
    k0 = -OCTAVES_BELOW * PER_OCTAVE
    dts = []
    k = k0
    while case.dt_start * 2 ** (k / PER_OCTAVE) < cap:
        dts.append(case.dt_start * 2 ** (k / PER_OCTAVE))
        k += 1
    return dts + [cap]


def stability(out: Path, client, quick: bool = False) -> list[dict]:
    """The largest stable step of each scheme on each scene: the largest step
    of the grid at which this and every smaller grid step stayed stable over
    the case's time."""
    rows = []
    for case in stability_cases(quick):
        specs = [spec for dt in stability_dts(case) for spec in grid.product(systems.BENCH_SCHEMES, [dt], max(1, round(case.time / dt)))]
        points = grid.run(
            builtin(case.scene),
            specs,
            out=out / "stability" / case.scene,
            samples=1,
            threshold=STABLE_ENERGY_ERROR,
            check_every=case.check_every,
            client=client,
        )
        for label in systems.BENCH_SCHEMES:
            mine = [p for p in points if p.label == label]
            st = _stable(mine)
            rows.append({"scene": case.scene, "scheme": label, "time": case.time, "check_every": case.check_every, **st})
        print(f"  stability {case.scene}: {len(points)} runs", flush=True)
    return rows


def _stable(points: list[grid.Point]) -> dict:
    ordered = sorted(points, key=lambda p: p.dt)
    largest = None
    for p in ordered:
        if p.status != "completed":
            return {"largest_stable_dt": largest, "capped": False, "first_unstable_dt": p.dt, "failure": p.error}
        largest = p.dt
    return {"largest_stable_dt": largest, "capped": True, "first_unstable_dt": None, "failure": None}


#: Long runs: scene, steps (full, quick), energy samples.
LONG_RUNS = (("free_asymmetric_top", 1_000_000, 2_000, 1000), ("dipole_lattice_sc_cutoff", 100_000, 20, 100))


def long_runs(out: Path, client, quick: bool = False) -> list[dict]:
    """Every scheme at the scene's own step: energy error, drift, |Q| error."""
    rows = []
    for name, full, short, samples in LONG_RUNS:
        scene = builtin(name)
        steps = short if quick else full
        points = grid.run(
            scene,
            grid.product(systems.BENCH_SCHEMES, [scene["run"]["dt"]], steps),
            out=out / "long_runs" / name,
            samples=samples,
            quantities=("energy_error", "norm_error"),
            client=client,
        )
        for p in points:
            s = p.load()
            e = s["energy_error"]
            rows.append(
                {
                    "scene": name,
                    "scheme": p.label,
                    "dt": p.dt,
                    "steps": p.steps,
                    "energy_error_final": float(e[-1]) if len(e) else math.nan,
                    "energy_error_max": float(np.max(np.abs(e))) if len(e) else math.nan,
                    "energy_drift_per_time": float(np.polyfit(s["time"], e, 1)[0]) if len(e) > 1 else math.nan,
                    "norm_error_max": float(np.max(np.abs(s["norm_error"]))) if len(e) else math.nan,
                    "failure": None if p.status == "completed" else p.error,
                    "last_step": p.last_step,
                    "wall_seconds": p.wall_seconds,
                }
            )
        print(f"  long runs {name}: {len(points)} runs of {steps} steps", flush=True)
    return rows


#: Stress at length: the steps tried (the case's step times 2^k) and the run length.
STRESS_FACTORS = (0.25, 0.5, 1.0, 2.0, 4.0)
STRESS_STEPS = 100_000


def stress_scene(case: dict) -> dict[str, Any]:
    """A benchmark stress case (a row of the Rust driver's `stress` section) as a scene."""
    inertia = case["inertia"]
    default: dict[str, Any] = {"inertia": inertia[0] if inertia.count(inertia[0]) == 3 else list(inertia)}
    scene: dict[str, Any] = {
        "version": 1,
        "name": "stress",
        "rotors": {"kind": "sites", "sites": [{"position": [0.0, 0.0, 0.0]}], "default": default},
        "initial": {"kind": "uniform", "orientation": list(case["orientation"]), "omega_body": list(case["omega_body"])},
        "integrator": {"kind": "gear_a"},
        "run": {"dt": case["dt"], "steps": 1},
    }
    if case["dipole_body"] is not None:
        default["dipole"] = list(case["dipole_body"])
    if case["field"] is not None:
        scene["fields"] = {"uniform": list(case["field"])}
    return scene


def stress_at_length(stress_rows: list[dict], out: Path, client, quick: bool = False) -> list[dict]:
    """For each stress case, scheme and step (the case's step times
    `STRESS_FACTORS`): the longest run it survives, up to `STRESS_STEPS`
    steps (non-finite state, or |E - E_0| above `STABLE_ENERGY_ERROR` of
    the energy scale, checked every step)."""
    cases = list({r["case"]: r for r in stress_rows}.values())
    steps = 200 if quick else STRESS_STEPS
    rows = []
    for k, case in enumerate(cases):
        dts = [case["dt"] * f for f in STRESS_FACTORS]
        points = grid.run(
            stress_scene(case),
            grid.product(systems.BENCH_SCHEMES, dts, steps),
            out=out / "stress" / f"case{k}",
            samples=100,
            threshold=STABLE_ENERGY_ERROR,
            check_every=1,
            client=client,
        )
        for p in points:
            rows.append({"case": case["case"], "scheme": p.label, "dt": p.dt, "steps": p.steps, "survived": p.survived, "failure": None if p.status == "completed" else p.error})
    print(f"  stress at length: {len(rows)} runs of up to {steps} steps", flush=True)
    return rows


def lengths_table(rows: list[dict]) -> list[str]:
    """Markdown: per stress case and scheme, the steps survived at each dt."""
    cases = list(dict.fromkeys(r["case"] for r in rows))
    schemes = list(dict.fromkeys(r["scheme"] for r in rows))
    steps = rows[0]["steps"] if rows else 0
    lines = [
        f"Steps survived of {steps} (energy error above {STABLE_ENERGY_ERROR} of the energy scale or a non-finite state ends a run; "
        "checked every step), at the case's step times " + ", ".join(f"{f:g}" for f in STRESS_FACTORS) + "; `all` = the whole run.",
        "",
        "| case (dt) | " + " | ".join(schemes) + " |",
        "|---|" + "---|" * len(schemes),
    ]
    for c in cases:
        mine = [r for r in rows if r["case"] == c]
        dts = sorted({r["dt"] for r in mine})
        cells = []
        for s in schemes:
            by_dt = {r["dt"]: r for r in mine if r["scheme"] == s}
            cells.append(" / ".join("all" if by_dt[d]["failure"] is None else str(by_dt[d]["survived"]) for d in dts))
        lines.append(f"| {c} ({' / '.join(f'{d:g}' for d in dts)}) | " + " | ".join(cells) + " |")
    return lines

