"""`python -m validation.bench.sweep --out benchmarks`: the sweep's piece of
`make bench`. Times 200 short runs (a grid of integrators, time steps and
seeds on the 256-rotor quadrupole lattice) done serially in this process,
then as a sweep on a local Dask cluster of one and of two worker processes;
measures what a run costs a worker in memory (peak RSS, for each built-in
scene at its own length); writes the `sweep` key of `<out>/results.json` and
its section of `<out>/RESULTS.md`."""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import distributed
import quatrot
import quatrot.sweep
from quatrot.sweep.task import run_task

from validation.bench import results_md

BEGIN = "<!-- make bench: sweep section begin -->"
END = "<!-- make bench: sweep section end -->"

SCENE = "quadrupole_lattice_fcc"
GRID = {
    "integrator.kind": ["gear_a", "gear_b", "no_squish", "dlm", "richardson"],
    "run.dt": [0.001, 0.002, 0.003, 0.004],
    "initial.seed": list(range(1, 11)),
}
STEPS = 200
#: Timed rounds (serial, 1 worker, 2 workers in turn); the best of each is kept.
ROUNDS = 3

#: Run in a fresh interpreter: a worker-like process (quatrot, Dask and
#: distributed imported) runs one scene as a task; its resident set before
#: the run, and its peak during the run (Linux: the high-water mark `VmHWM`,
#: reset just before the run through `/proc/self/clear_refs`).
MEMORY_PROBE = """
import json, sys, tempfile, tomllib
import quatrot, quatrot.sweep
from quatrot.sweep.task import run_task

def status_kib(field):
    for line in open("/proc/self/status"):
        if line.startswith(field + ":"):
            return int(line.split()[1])

scene = tomllib.loads(quatrot.builtin_scenes()[sys.argv[1]])
with tempfile.TemporaryDirectory() as d:
    before = status_kib("VmRSS")
    open("/proc/self/clear_refs", "w").write("5")
    row = run_task(d + "/run", scene, 1)
    peak = status_kib("VmHWM")
print(json.dumps({"before_kib": before, "peak_kib": peak, "status": row["status"], "task_seconds": row["task_seconds"]}))
"""


def base_scene() -> dict:
    scene = quatrot.sweep.load_base(SCENE)
    return quatrot.sweep.apply(scene, {"run.steps": STEPS, "record.energy_error_threshold": None})


def serial(runs, folder: Path) -> tuple[float, float]:
    """The runs one after another in this process, as the tasks do them:
    wall time, and the cores it had on average (CPU time / wall time)."""
    start, cpu = time.perf_counter(), time.process_time()
    for r in runs:
        run_task(str(folder / r.id), r.scene, 1)
    wall = time.perf_counter() - start
    return wall, (time.process_time() - cpu) / wall


def swept(scene: dict, client: distributed.Client, folder: Path) -> tuple[float, float, list[dict]]:
    """The runs as a sweep: wall time, the cores its tasks had on average
    (their CPU time / wall time), and the rows."""
    start = time.perf_counter()
    results = quatrot.sweep.run(scene, GRID, out=folder, client=client)
    wall = time.perf_counter() - start
    assert results.submitted == len(results.rows) and not results.unfinished()
    return wall, sum(float(r["cpu_seconds"]) for r in results.rows) / wall, results.rows


def memory() -> list[dict]:
    rows = []
    for name in quatrot.builtin_scenes():
        out = subprocess.run([sys.executable, "-c", MEMORY_PROBE, name], capture_output=True, text=True, check=True)
        m = json.loads(out.stdout)
        rows.append({"scene": name, **m, "run_mib": (m["peak_kib"] - m["before_kib"]) / 1024})
    return rows


def idle_worker_mib(client: distributed.Client) -> float:
    import psutil

    rss = client.run(lambda: psutil.Process().memory_info().rss)
    return max(rss.values()) / 2**20


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    args = parser.parse_args(argv)
    machine = results_md.machine()
    scene = base_scene()
    runs = quatrot.sweep.expand(scene, GRID)
    times = {"serial": [], "1 worker": [], "2 workers": []}
    cores = {k: [] for k in times}
    startup = {}
    work = Path(tempfile.mkdtemp(prefix="quatrot-sweep-bench-"))
    try:
        clusters = {}
        for n in (1, 2):
            start = time.perf_counter()
            cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None)
            clusters[n] = (cluster, distributed.Client(cluster))
            startup[f"{n} worker{'s' if n > 1 else ''}"] = time.perf_counter() - start
        idle = idle_worker_mib(clusters[2][1])
        for k in range(ROUNDS):
            print(f"round {k + 1}/{ROUNDS}: {len(runs)} runs serially, on 1 worker, on 2 workers ...", flush=True)
            wall, used = serial(runs, work / f"serial{k}")
            times["serial"].append(wall)
            cores["serial"].append(used)
            for n, label in ((1, "1 worker"), (2, "2 workers")):
                wall, used, rows = swept(scene, clusters[n][1], work / f"sweep{n}-{k}")
                times[label].append(wall)
                cores[label].append(used)
        for cluster, client in clusters.values():
            client.close()
            cluster.close()
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("memory per run of each built-in scene ...", flush=True)
    per_run = memory()
    best = {k: min(v) for k, v in times.items()}
    task_seconds = [float(r["task_seconds"]) for r in rows]
    result = {
        "machine": machine,
        "versions": {"quatrot": quatrot.__version__, "dask": distributed.__version__, **results_md.toolchain()},
        "scene": SCENE,
        "steps": STEPS,
        "grid": GRID,
        "runs": len(runs),
        "seconds": times,
        "cores_used": cores,
        "best_seconds": best,
        "mean_task_seconds": sum(task_seconds) / len(task_seconds),
        "overhead_per_run_seconds": (best["1 worker"] - best["serial"]) / len(runs),
        "speedup_2_workers": best["serial"] / best["2 workers"],
        "efficiency_2_workers": best["serial"] / (2 * best["2 workers"]),
        "cluster_startup_seconds": startup,
        "idle_worker_mib": idle,
        "memory": per_run,
    }
    results_md.update_json(args.out / "results.json", {"sweep": result})
    results_md.replace_section(args.out / "RESULTS.md", BEGIN, END, section(result))
    print(f"efficiency on 2 workers {result['efficiency_2_workers']:.2f}; wrote the sweep section of {args.out / 'RESULTS.md'}")
    return 0


def section(r: dict) -> str:
    m, b = r["machine"], r["best_seconds"]
    n = r["runs"]
    grid = "; ".join(f"`{p}` in {v if len(v) < 6 else f'{v[0]}..{v[-1]} ({len(v)} values)'}" for p, v in r["grid"].items())
    lines = [
        BEGIN,
        "## Sweeps on Dask (issue 18: `quatrot.sweep`)",
        "",
        f"- Machine: {m['cpu']}, {m['cpus']} CPUs; load average {m['load_average']:.1f} when it started (shared machine).",
        f"- Date: {m['date']}. quatrot {r['versions']['quatrot']}, dask/distributed {r['versions']['dask']}, Python {r['versions']['python']}.",
        "- Command: `python -m validation.bench.sweep --out benchmarks` (the last step of `make bench`).",
        f"- Runs: {n} runs of the built-in `{r['scene']}` (256 quadrupoles, fcc, periodic) for {r['steps']} steps, energies every 10 steps, "
        f"over the grid {grid}; mean task time {r['mean_task_seconds'] * 1e3:.0f} ms (run, outputs, `result.json`). "
        f"Each way of running them is timed {len(r['seconds']['serial'])} times in turn; the best is kept.",
        "",
        "Cores used: the CPU time of the runs (of the serial process; of the tasks, from the table's `cpu_seconds`) over the wall "
        "time, in each round: on an idle machine 1 for the serial loop and the 1-worker sweep and 2 for 2 workers; less when other "
        "work shares the cores.",
        "",
        "| how | wall time (best) | all rounds | cores used, each round | per run |",
        "|---|---|---|---|---|",
    ]
    for how, label in (("serial", "serially in one process (the task function in a loop)"), ("1 worker", "sweep, local cluster of 1 worker"), ("2 workers", "sweep, local cluster of 2 workers")):
        rounds = ", ".join(f"{s:.2f}" for s in r["seconds"][how])
        used = ", ".join(f"{c:.2f}" for c in r["cores_used"][how])
        lines.append(f"| {label} | {b[how]:.2f} s | {rounds} s | {used} | {b[how] / n * 1e3:.1f} ms |")
    lines += [
        "",
        f"Parallel efficiency on 2 workers: serial / (2 x sweep) = **{r['efficiency_2_workers']:.2f}** "
        f"(speed-up {r['speedup_2_workers']:.2f}). The sweep's own cost per run (1 worker against the serial loop: scheduling, "
        f"moving the scene and the row, rewriting the table atomically after each run) is {r['overhead_per_run_seconds'] * 1e3:.1f} ms. "
        f"Starting the local cluster (not in the times above) takes {r['cluster_startup_seconds']['1 worker']:.1f} s for 1 worker and "
        f"{r['cluster_startup_seconds']['2 workers']:.1f} s for 2.",
        "",
        f"Memory: an idle worker process holds {r['idle_worker_mib']:.0f} MiB (Python, numpy, Dask, quatrot). A run raises its resident set "
        "to a peak above that by the run's cost (fresh worker-like process; each built-in scene at its own length, run as a task "
        "with its recorded series and trajectory; Linux `VmHWM` reset before the run):",
        "",
        "| scene | resident before the run | peak during the run | the run's cost |",
        "|---|---|---|---|",
    ]
    for row in r["memory"]:
        lines.append(f"| {row['scene']} | {row['before_kib'] / 1024:.0f} MiB | {row['peak_kib'] / 1024:.0f} MiB | {row['run_mib']:.1f} MiB |")
    lines += [END, ""]
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
