"""`python -m validation.bench --out benchmarks [--raw target/bench/raw]`:
the Python half of `make bench`. Reads the Rust driver's measurements
(`cargo bench --bench performance`), adds the references (scipy DOP853 for
single rotors; the lattices' own fine-step reference), runs the scans that
are grids of scene runs (largest stable step, long runs, stress at length) as
sweeps on a local Dask cluster of two workers (`scans`), runs LAMMPS on the
dipole lattice side by side, and writes `<out>/results.json`, the figures and
this benchmark's section of `<out>/RESULTS.md`."""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from validation.bench import analysis, plots, profile, results_md, scans
from validation.longrun import grid
from validation.shared.benchmark_scenes import LATTICE_SCENE


def _clean(x):
    """JSON-safe copies (NaN -> None, numpy -> Python)."""
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    if isinstance(x, np.ndarray):
        return _clean(x.tolist())
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, np.integer):
        return int(x)
    return x


def _nan(x):
    return math.nan if x is None else x


def _restore_nans(runs: list[dict]) -> None:
    for r in runs:
        for k in ("wall_median", "energy_error_max", "energy_drift_per_time", "energy_error_final", "norm_error_max"):
            r[k] = _nan(r.get(k))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    parser.add_argument("--raw", type=Path, default=Path("target/bench/raw"), help="the Rust driver's section files")
    parser.add_argument("--no-lammps", action="store_true", help="skip LAMMPS (pipeline tests)")
    parser.add_argument("--no-profile", action="store_true", help="skip the perf profile")
    parser.add_argument("--sweeps", type=Path, default=Path("target/bench/sweeps"), help="the scans' sweep folders (resumed)")
    parser.add_argument("--scheduler", help="a Dask scheduler's address for the scans (default: a local cluster of 2 workers)")
    args = parser.parse_args(argv)
    raw = read_sections(args.raw)
    args.out.mkdir(parents=True, exist_ok=True)
    print("scans as sweeps (stability, long runs, stress at length) ...", flush=True)
    with grid.connect(args.scheduler) as client:
        raw["stability"] = scans.stability(args.sweeps, client, raw["quick"])
        raw["long_runs"] = scans.long_runs(args.sweeps, client, raw["quick"])
        raw["stress_at_length"] = scans.stress_at_length(raw["stress"], args.sweeps, client, raw["quick"])

    studies = raw["work_precision"]
    lammps, lammps_version, side_by_side = [], None, {}
    for study in studies:
        _restore_nans(study["runs"])
        study["reference"] = analysis.add_errors(study)
        study["orders"] = {s: analysis.observed_order(rs) for s, rs in analysis.by_scheme(study["runs"]).items()}
        study["throughput"] = analysis.throughput(study)
        if study["scene"] == LATTICE_SCENE and not args.no_lammps:
            print("LAMMPS on the dipole lattice ...", flush=True)
            lammps, lammps_version = lammps_runs(study)
            from validation.bench import lammps_runs as lr

            side_by_side = lr.side_by_side(study, cutoff=3.1)
        study["targets"] = analysis.target_table(study, lammps if study["scene"] == LATTICE_SCENE else [])
    analysis.stress_errors(raw["stress"])
    scaling_fit = analysis.scaling_fit(raw["scaling"])
    figures = {
        "work_precision": plots.work_precision(studies, lammps, args.out),
        "error_vs_dt": plots.error_vs_dt(studies, args.out),
        "stability": plots.stability(raw["stability"], args.out),
        "scaling": plots.scaling(raw["scaling"], args.out),
    }
    hot = None if args.no_profile else profile.hot_functions()
    lammps_throughput = {r["scheme"]: r["rotor_steps_per_second"] for r in lammps if r["dt"] == min(x["dt"] for x in lammps)}

    results = {
        "quick": raw["quick"],
        "machine": results_md.machine(),
        "versions": {"quatrot": raw["quatrot"], "lammps": lammps_version, **results_md.toolchain()},
        "rust_seconds": raw["seconds"],
        "rust_section_seconds": raw["section_seconds"],
        "studies": [
            {
                "scene": s["scene"],
                "time": s["time"],
                "rotors": s["system"]["rotors"],
                "reference": {k: v for k, v in s["reference"].items() if k != "axes"},
                "orders": s["orders"],
                "throughput": s["throughput"],
                "targets": s["targets"],
                "runs": [{k: v for k, v in r.items() if k != "final_orientations"} for r in s["runs"]],
            }
            for s in studies
        ],
        "lammps": {"runs": lammps, "throughput": lammps_throughput, "side_by_side": side_by_side},
        "stability": raw["stability"],
        "long_runs": raw["long_runs"],
        "stress": [{k: v for k, v in r.items() if k != "final_orientations"} for r in raw["stress"]],
        "stress_at_length": raw["stress_at_length"],
        "scaling": {"rows": raw["scaling"], "fit": scaling_fit},
        "profile": hot,
        "figures": {k: v.name for k, v in figures.items()},
    }
    results = _clean(results)
    results_md.update_json(args.out / "results.json", results)
    results_md.write_section(args.out / "RESULTS.md", results)
    print(f"wrote {args.out / 'results.json'} and the benchmark section of {args.out / 'RESULTS.md'}")
    return 0


SECTIONS = ("work_precision", "stress", "scaling")


def read_sections(folder: Path) -> dict:
    """The sections written by `cargo bench --bench performance`, merged."""
    raw = {"seconds": 0.0, "section_seconds": {}}
    for name in SECTIONS:
        part = json.loads((folder / f"{name}.json").read_text())
        raw[name] = part["data"]
        raw["seconds"] += part["seconds"]
        raw["section_seconds"][name] = part["seconds"]
        raw["quick"], raw["quatrot"] = part["quick"], part["quatrot"]
    return raw


def lammps_runs(study: dict):
    from validation.bench import lammps_runs as lr

    return lr.runs(study, study["reference"]["axes"], cutoff=3.1)


if __name__ == "__main__":
    sys.exit(main())
