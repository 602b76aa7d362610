"""`python -m validation.bench.water --out benchmarks`: issue 41's verdicts on
rigid water, integrator x dt x run length. From one equilibrated state of
the SPC/E built-in (validation/shared/water_box_runs.py), every quatrot
integrator and each peer method (OpenMM SETTLE + VerletIntegrator, LAMMPS
``fix rigid/nve/small`` and ``fix rattle`` + ``nve``) runs at constant
energy at dt 0.5, 1, 2, 3 and 4 fs for ``--length-ps`` (default 1000: the
issue's 1 ns). Per run: whether it completed (finite energy, no blow-up),
the energy drift per ns (least-squares slope of the total energy per
molecule), ``T_rot / T_trans`` with its block error, the largest
difference of the O-O radial distribution from the reference run's
(quatrot NO_SQUISH at the smallest dt), the self-diffusion coefficient
(Einstein, from the oxygens' mean-squared displacement between 20 % and
60 % of the run) and the CPU time per ps. The largest stable dt of each
method is stated with its run length.

Runs are cached in ``--cache`` by their parameters (delete after changing
the engine). The section is published when every run is in the cache;
``--method`` runs one method only (several processes can share the
work). ``--quick`` checks the pipeline: 2 ps at dt 1 and 2 fs."""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from pathlib import Path

import numpy as np

import quatrot
from validation.bench import results_md
from validation.shared import water_box_runs as runs

BEGIN = "<!-- make bench: water section begin -->"
END = "<!-- make bench: water section end -->"
INTEGRATORS = ("no_squish", "dlm", "richardson", "gear_a", "gear_b")
PEERS = ("openmm_settle", "lammps_rigid", "lammps_rattle")
STEPS_FS = (0.5, 1.0, 2.0, 3.0, 4.0)
SAMPLE_FS = 20.0
FRAME_FS = 200.0
# A run whose total energy per molecule moved by more than this from its
# start (kcal/mol; kT at 298 K is 0.59) is called unstable.
STABLE_MOVE = 1.0
DIFFUSION_WINDOW = (0.2, 0.6)


def run_one(method: str, dt: float, length_fs: float, state, cache: Path) -> dict:
    key = hashlib.sha256(json.dumps([method, dt, length_fs, SAMPLE_FS, FRAME_FS, state.box,
                                     state.centres[0].tolist()]).encode()).hexdigest()[:16]
    path = cache / f"{method}_{dt:g}fs_{key}.npz"
    if not path.exists():
        if method in INTEGRATORS:
            found = runs.quatrot_run(state, method, dt, length_fs, SAMPLE_FS, FRAME_FS, cache / f"{path.stem}_out")
        elif method == "openmm_settle":
            found = runs.openmm_run(state, dt, length_fs, SAMPLE_FS, FRAME_FS)
        else:
            found = runs.lammps_run(state, dt, length_fs, SAMPLE_FS, FRAME_FS, method.split("_")[1])
        found["failed_at_fs"] = np.nan if found["failed_at_fs"] is None else found["failed_at_fs"]
        cache.mkdir(parents=True, exist_ok=True)
        np.savez(path, **found)
    return dict(np.load(path))


def measure(found: dict, box: float, length_fs: float, dt: float, reference_g=None) -> dict:
    times, total = found["time_ps"], found["total_per_molecule"]
    last_fs = runs.sample_steps(dt, length_fs, SAMPLE_FS)[-1] * dt
    completed = bool(np.isnan(found["failed_at_fs"]) and len(times) and times[-1] * 1000 >= last_fs - 1e-9)
    stable = bool(completed and np.all(np.isfinite(total)) and np.abs(total - total[0]).max() <= STABLE_MOVE)
    out = {"stable": stable, "completed": completed, "cpu_per_ps": float(found["cpu_seconds"]) / max(times[-1], 1e-12)}
    if not stable:
        return out
    out["drift_per_ns"] = float(np.polyfit(times, total, 1)[0] * 1000)
    ratio = found["T_rot"] / found["T_trans"]
    block = quatrot.block_average(ratio)
    out.update(ratio=float(block["mean"]), ratio_error=float(block["error"]),
               T_trans=float(found["T_trans"].mean()), T_rot=float(found["T_rot"].mean()))
    oxygens = found["oxygens"]
    g = quatrot.radial_distribution(oxygens, [box] * 3, r_max=min(10.0, box / 2), bins=100)
    out["g"] = g["g"].tolist()
    if reference_g is not None:
        out["g_difference"] = float(np.abs(g["g"] - reference_g).max())
    span = (oxygens.shape[0] - 1) * FRAME_FS / 1000
    if oxygens.shape[0] >= 6:
        window = (DIFFUSION_WINDOW[0] * span, DIFFUSION_WINDOW[1] * span)
        msd = quatrot.mean_squared_displacement(oxygens, FRAME_FS / 1000, fit_window=window)
        out["diffusion_1e5_cm2_s"] = float(msd["diffusion"]["coefficient"]) * 10  # A^2/ps = 1e-4 cm^2/s
    return out


def cell(value, fmt) -> str:
    return "-" if value is None else format(value, fmt)


def table(rows: list[dict], length_ps: float) -> str:
    lines = [
        "| method | dt fs | run ps | stable | drift kcal/mol/molecule/ns | T_rot / T_trans | max abs g_OO - g_ref | "
        "D 1e-5 cm^2/s | CPU s per ps |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        m = r["measured"]
        ratio = f"{m['ratio']:.4f} +- {m['ratio_error']:.4f}" if "ratio" in m else "-"
        lines.append(
            f"| {r['method']} | {r['dt']:g} | {length_ps:g} | {'yes' if m['stable'] else '**no**'} | "
            f"{cell(m.get('drift_per_ns'), '+.4f')} | {ratio} | {cell(m.get('g_difference'), '.3f')} | "
            f"{cell(m.get('diffusion_1e5_cm2_s'), '.3f')} | {m['cpu_per_ps']:.3g} |"
        )
    return "\n".join(lines)


def largest_stable(rows: list[dict], length_ps: float) -> list[str]:
    lines = []
    for method in dict.fromkeys(r["method"] for r in rows):
        stable = [r["dt"] for r in rows if r["method"] == method and r["measured"]["stable"]]
        largest = f"{max(stable):g} fs" if stable else "none of those tried"
        lines.append(f"- {method}: largest stable dt {largest} at {length_ps:g} ps.")
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    parser.add_argument("--cache", type=Path, default=Path("target/bench/water"))
    parser.add_argument("--length-ps", type=float, default=1000.0)
    parser.add_argument("--method", choices=INTEGRATORS + PEERS, action="append",
                        help="only this method's runs, no section")
    parser.add_argument("--quick", action="store_true", help="2 ps at dt 1 and 2 fs, to check the pipeline")
    args = parser.parse_args(argv)
    length_ps = 2.0 if args.quick else args.length_ps
    steps_fs = (1.0, 2.0) if args.quick else STEPS_FS
    state = runs.equilibrated_state(args.cache, steps=200 if args.quick else None)
    methods = args.method or INTEGRATORS + PEERS
    reference = None
    rows = []
    for method in ("no_squish",) + tuple(m for m in methods if m != "no_squish"):
        for dt in steps_fs:
            print(f"water, {method} at {dt:g} fs: {length_ps:g} ps ...", flush=True)
            found = run_one(method, dt, length_ps * 1000, state, args.cache)
            measured = measure(found, state.box, length_ps * 1000, dt, reference)
            if reference is None and measured["stable"]:
                reference = np.asarray(measured["g"])
            rows.append({"method": method, "dt": dt, "measured": measured})
            print(f"  stable: {measured['stable']}, CPU {measured['cpu_per_ps']:.3g} s/ps", flush=True)
    if args.method:
        return 0
    machine = results_md.machine()
    result = {"machine": machine, "versions": {"quatrot": quatrot.__version__}, "length_ps": length_ps,
              "runs": [{**r, "measured": {k: v for k, v in r["measured"].items() if k != "g"}} for r in rows]}
    text = "\n".join([
        BEGIN,
        "## Rigid water: integrator x dt x run length (issue 41, `python -m validation.bench.water`)",
        "",
        f"- Machine: {machine['cpu']}, {machine['cpus']} CPUs; load average {machine['load_average']:.1f} when the "
        f"section was written. Date: {machine['date']}. quatrot {quatrot.__version__}, one thread; OpenMM CPU "
        "platform (single precision), one thread; LAMMPS serial.",
        f"- Every run starts from the same equilibrated state of `spce_water_512` and runs at constant energy for "
        f"{length_ps:g} ps (module doc of `validation.bench.water` and `validation.shared.water_box_runs`); stable: "
        f"completed with the energy per molecule within {STABLE_MOVE:g} kcal/mol of its start. The reference g_OO is "
        "quatrot NO_SQUISH's at the smallest dt.",
        "",
        table(rows, length_ps),
        "",
        *largest_stable(rows, length_ps),
        "",
        END,
        "",
    ])
    results_md.publish(args.out, "water", result, (BEGIN, END), text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
