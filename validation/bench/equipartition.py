"""`python -m validation.bench.equipartition --out benchmarks`: issue 39's
equipartition verdict at production length, a step of `make bench`. Each of
the five integrators runs each body built-in at constant energy for 1e5
steps of its dt (`validation.shared.equipartition_runs`: thermostat removed, the
first fifth left out); the section gives <T_rot> / <T_trans> with its error
from block averages and a verdict per run stating its length, and how far
the run's temperature and energy moved over the averaged part (both
built-ins conserve energy: the Stockmayer fluid's dipoles are
shifted-force). `make validate`'s
check runs the same protocol at 2e4 steps.

Each run's series is kept in `--cache`, named after the scene it ran (a
hash of its table), and read back when run again: delete the folder after
changing the engine. `--scene` runs one built-in's five runs only (two such
processes share a 2-core machine); the section is written when every run
is in the cache."""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import time
from pathlib import Path

import numpy as np

import quatrot
from validation.bench import results_md
from validation.shared import equipartition_runs as ep

BEGIN = "<!-- make bench: equipartition section begin -->"
END = "<!-- make bench: equipartition section end -->"
STEPS = 100_000
EVERY = 50
LEFT_OUT = 0.2


def cached_series(scene_name: str, integrator: str, steps: int, cache: Path) -> dict:
    """The run's series and wall time, from `cache` when it holds this exact scene."""
    scene = ep.nve_scene(scene_name, integrator, steps, EVERY)
    key = hashlib.sha256(json.dumps(scene, sort_keys=True).encode()).hexdigest()[:16]
    path = cache / f"{scene_name}_{integrator}_{key}.json"
    if path.exists():
        return json.loads(path.read_text())
    started = time.perf_counter()
    series = ep.run_series(scene)
    found = {"wall_seconds": time.perf_counter() - started, "dt": scene["run"]["dt"],
             **{k: v.tolist() for k, v in series.items()}}
    cache.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(found))
    return found


def verdict(m: dict) -> str:
    """One line: equal within Z_MAX sigma, or by how much not."""
    if m["z"] <= ep.Z_MAX:
        return f"equal (z = {m['z']:.2f} <= {ep.Z_MAX:g})"
    return f"**differ** by {m['z']:.1f} sigma (ratio - 1 = {m['ratio'] - 1:+.4f})"


def table(rows: list[dict], steps: int) -> str:
    lines = [
        "| built-in | integrator | steps (dt) | <T_trans> | <T_rot> | T_rot / T_trans | verdict at this length | T_trans first -> last tenth | E/N first -> last tenth | wall |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        m, n = r["measured"], r["bodies"]
        lines.append(
            f"| {r['scene']} | {r['integrator']} | {steps:,} ({r['dt']}) | {m['T_trans']:.4f} | {m['T_rot']:.4f} | "
            f"{m['ratio']:.4f} +- {m['ratio_error']:.4f}{'' if m['converged'] else ' (blocking not converged)'} | {verdict(m)} | "
            f"{m['T_trans_first_tenth']:.3f} -> {m['T_trans_last_tenth']:.3f} | "
            f"{m['energy_first_tenth'] / n:.4f} -> {m['energy_last_tenth'] / n:.4f} | {r['wall_seconds'] / 60:.1f} min |"
        )
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    parser.add_argument("--cache", type=Path, default=Path("target/bench/equipartition"))
    parser.add_argument("--scene", choices=ep.SCENES, action="append", help="only this built-in's runs, no section")
    parser.add_argument("--quick", action="store_true", help="2,000 steps per run, to check the pipeline")
    args = parser.parse_args(argv)
    steps = 2_000 if args.quick else STEPS
    machine = results_md.machine()
    rows = []
    for scene_name in args.scene or ep.SCENES:
        bodies = sum(ep.nve_scene(scene_name, "no_squish", 1, 1)["bodies"]["counts"])
        for integrator in ep.INTEGRATORS:
            print(f"equipartition, {scene_name} with {integrator}: {steps} steps ...", flush=True)
            found = cached_series(scene_name, integrator, steps, args.cache)
            measured = ep.measure({k: np.asarray(v) for k, v in found.items() if isinstance(v, list)}, LEFT_OUT)
            rows.append({"scene": scene_name, "integrator": integrator, "bodies": bodies, "dt": found["dt"],
                         "wall_seconds": found["wall_seconds"], "measured": measured})
            print(f"  {verdict(measured)}, {found['wall_seconds'] / 60:.0f} min", flush=True)
    if args.scene:
        return 0
    result = {"machine": machine, "versions": {"quatrot": quatrot.__version__}, "steps": steps, "left_out": LEFT_OUT,
              "z_max": ep.Z_MAX, "runs": rows}
    text = "\n".join([
        BEGIN,
        "## Equipartition of moving bodies at production length (issue 39, `python -m validation.bench.equipartition`)",
        "",
        f"- Machine: {machine['cpu']}, {machine['cpus']} CPUs; load average {machine['load_average']:.1f} when the section "
        f"was written (shared machine; the runs' wall times are in the table). Date: {machine['date']}. quatrot {quatrot.__version__}.",
        f"- Each run: the built-in with the integrator swapped and its thermostat removed, at constant energy from its fcc "
        f"start, {steps:,} steps, T_trans and T_rot every {EVERY} steps; the first {LEFT_OUT:.0%} (the melt) left out. "
        f"<T_rot - T_trans> is block averaged (Flyvbjerg-Petersen); the verdict is z = |<T_rot - T_trans>| / sigma against "
        f"{ep.Z_MAX:g}, and the ratio's error is sigma / <T_trans>. Degrees of freedom as quatrot counts them: 3N - 3 "
        "translational; 2 rotational per Stockmayer sphere (no torque reaches the spin about its dipole), 3 per o-terphenyl.",
        "- Constant energy, not constant temperature: the Stockmayer fluid's dipoles are shifted-force at 2.5 and the "
        "o-terphenyl liquid's Lennard-Jones force-shifted, so both conserve their energy (the E/N column shows how well); "
        "without the built-ins' thermostats their lattice starts heat as they melt, and each verdict is at the liquid's "
        "temperature in the T_trans column.",
        "- `make validate`'s `equipartition_bodies` check runs the same protocol at 20,000 steps per run.",
        "",
        table(rows, steps),
        "",
        END,
        "",
    ])
    results_md.publish(args.out, "equipartition", result, (BEGIN, END), text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
