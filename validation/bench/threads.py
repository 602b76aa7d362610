"""`python -m validation.bench.threads --out benchmarks` (`make bench-threads`):
whole-run speed-up of 2 threads over 1 for every built-in lattice scene at
about 1,000, 8,000 and 64,000 rotors, through the `quatrot` CLI
(`target/release/quatrot`, `--threads 1` against `--threads 2`). Each pair of
runs is timed side by side, the order alternating from repeat to repeat;
the medians, the spread and the efficiency `t1 / (2 t2)` go into
`<out>/results.json` (key `threads`) and this benchmark's section of
`<out>/RESULTS.md`. The load average is read before and after every pair:
the section says when the machine was not idle. Before every pair and after
a row's last, `examples/host_probe.rs` measures what a second thread adds to
the host's memory bandwidth (a triad) and to its arithmetic (register-only
chains) (`--probe`, 1 s): each pair gets the mean 2-thread/1-thread ratios
of the two probes around it, and the section sets the pairs' speed-ups
against them."""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import scipy.stats

from validation.bench import results_md

BEGIN = "<!-- make bench-threads: threads section begin -->"
END = "<!-- make bench-threads: threads section end -->"
CLI = Path("target/release/quatrot")
# examples/host_probe.rs (`make bench-threads` builds it).
HOST_PROBE = Path("target/release/examples/host_probe")
#: The probe's measurements: (name, unit, its keys at 1 and 2 threads).
PROBES = (("triad", "GB/s", "gb_per_s_1", "gb_per_s_2"), ("arithmetic", "GFLOP/s", "gflops_1", "gflops_2"))
SCENES = Path("scenes")

#: Sites per cell of each lattice kind.
SITES_PER_CELL = {"simple_cubic": 1, "bcc": 2, "fcc": 4}
#: The system sizes asked for (cells chosen to come closest).
TARGET_ROTORS = (1_000, 8_000, 64_000)
#: Rotor-steps per run of a periodic scene (cost linear in N): about a
#: second on one thread of this machine for the dipole lattices.
ROTOR_STEPS = 4e6
#: Pair-steps per run of an open cluster (cost quadratic in N).
PAIR_STEPS = 2e8
#: Fewest steps per run of an open cluster.
MIN_STEPS = 2
#: Fewest steps per run of a periodic scene: the run length of the dipole
#: lattice scenes as written (`run.steps = 500`). Shorter runs are dominated
#: by what is done once (the Gear start-up alone takes 65 evaluations, as
#: many as 65 steps): at 64,000 rotors the fixed work of `ROTOR_STEPS` gave
#: 62 steps, and the set-up was half the run.
MIN_PERIODIC_STEPS = 500
#: The largest open cluster measured: its sum is O(N^2) (about 0.8 s an
#: evaluation at 8,000 rotors, 50 s at 64,000: "Build, test and command
#: times"), and its Gear start-up takes 65 evaluations a run.
MAX_OPEN_ROTORS = 2_000
#: The machine was idle during a run when other processes (and the
#: hypervisor's steal) took at most this share of its cores' time. The
#: kernel's writeback of the runs' own output files lands there too: 1 to
#: 6 % of a 2-core machine on the 0.5 s runs with nothing else running
#: (2026-12-01).
IDLE_SHARE = 0.1


def lattice_scenes() -> list[tuple[str, dict]]:
    """The built-in scenes whose rotors are a lattice, parsed."""
    out = []
    for path in sorted(SCENES.glob("*.toml")):
        scene = tomllib.loads(path.read_text())
        if scene.get("rotors", {}).get("kind") == "lattice":
            out.append((path.stem, scene))
    return out


def cells_for(scene: dict, rotors: int) -> int:
    """The cells per edge whose lattice comes closest to `rotors` sites."""
    per_cell = SITES_PER_CELL[scene["rotors"]["lattice"]]
    return min(range(1, 200), key=lambda c: abs(per_cell * c**3 - rotors))


def periodic(scene: dict) -> bool:
    return scene.get("interactions", {}).get("boundary", {}).get("kind") == "periodic"


def steps_for(scene: dict, rotors: int) -> int:
    """Steps of one run: a fixed work per run (module constants), at least
    `MIN_PERIODIC_STEPS` for a periodic scene and `MIN_STEPS` for an open one."""
    if periodic(scene):
        return max(MIN_PERIODIC_STEPS, round(ROTOR_STEPS / rotors))
    return max(MIN_STEPS, round(PAIR_STEPS / (rotors * rotors / 2)))


def busy_seconds() -> float:
    """CPU seconds the whole machine has spent busy since boot (all cores:
    user, nice, system, interrupts and the hypervisor's steal), from
    `/proc/stat`."""
    fields = Path("/proc/stat").read_text().split("\n", 1)[0].split()
    user, nice, system, _idle, _iowait, irq, softirq, steal = (int(v) for v in fields[1:9])
    return (user + nice + system + irq + softirq + steal) / os.sysconf("SC_CLK_TCK")


def own_seconds() -> float:
    """CPU seconds of this process and its finished children."""
    me, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + children.ru_utime + children.ru_stime


def others_share(busy: float, own: float, wall: float, cores: int) -> float:
    """The share of the cores' time over `wall` seconds that went to other
    processes (or the hypervisor): the machine's busy CPU seconds less ours,
    over `cores * wall`; never below 0 (the two clocks tick differently)."""
    return max(0.0, busy - own) / (cores * wall)


def scene_text(scene: dict, cells: int) -> str:
    """The scene's TOML with `cells` cells (written by hand: tomllib reads only)."""
    return _toml({**scene, "rotors": {**scene["rotors"], "cells": cells}})


def _toml(table: dict, prefix: str = "") -> str:
    """A minimal TOML writer for the built-in scenes' tables."""
    lines, subtables = [], []
    for key, value in table.items():
        if isinstance(value, dict):
            subtables.append((key, value))
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            subtables.append((key, value))
        else:
            lines.append(f"{key} = {_value(value)}")
    text = "\n".join(lines) + "\n"
    for key, value in subtables:
        name = f"{prefix}.{key}" if prefix else key
        if isinstance(value, list):
            for item in value:
                text += f"\n[[{name}]]\n" + _toml(item, name)
        else:
            text += f"\n[{name}]\n" + _toml(value, name)
    return text


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(f"cannot write {v!r} as TOML")


def timed_run(cli: Path, scene_file: Path, steps: int, threads: int, out: Path) -> dict:
    """One CLI run: the process's wall time, the loop's (summary) and the
    share of the machine that other processes took meanwhile."""
    env = {k: v for k, v in os.environ.items() if k != "RAYON_NUM_THREADS"}
    busy, own = busy_seconds(), own_seconds()
    started = time.perf_counter()
    subprocess.run(
        [str(cli), "run", str(scene_file), "--steps", str(steps), "--threads", str(threads), "--out", str(out)],
        check=True,
        capture_output=True,
        env=env,
    )
    wall = time.perf_counter() - started
    others = others_share(busy_seconds() - busy, own_seconds() - own, wall, os.cpu_count() or 1)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["threads"]["count"] == threads, summary["threads"]
    return {"wall": wall, "loop": summary["wall_seconds"], "others": others}


def measure(cli: Path, name: str, scene: dict, rotors: int, repeats: int, work: Path, probe: Path) -> dict:
    """`repeats` pairs of runs on 1 and 2 threads, the order alternating,
    the host probed before each pair and after the last."""
    cells = cells_for(scene, rotors)
    n = SITES_PER_CELL[scene["rotors"]["lattice"]] * cells**3
    steps = steps_for(scene, n)
    scene_file = work / f"{name}_{cells}.toml"
    scene_file.write_text(scene_text(scene, cells))
    times: dict[int, list[dict]] = {1: [], 2: []}
    loads = [os.getloadavg()[0]]
    probes = [probe_host(probe)]
    for repeat in range(repeats):
        for threads in (1, 2) if repeat % 2 == 0 else (2, 1):
            times[threads].append(timed_run(cli, scene_file, steps, threads, work / f"out_{threads}"))
        probes.append(probe_host(probe))
        loads.append(os.getloadavg()[0])
    row = {
        "scene": name,
        "cells": cells,
        "rotors": n,
        "steps": steps,
        "repeats": repeats,
        "load_averages": loads,
        "others_share": max(t["others"] for t in times[1] + times[2]),
        "probes": probes,
        **{f"{name}_ratios": pair_ratios(probes, name) for name, *_ in PROBES},
    }
    for key in ("wall", "loop", "set_up"):
        t1 = [t["wall"] - t["loop"] if key == "set_up" else t[key] for t in times[1]]
        t2 = [t["wall"] - t["loop"] if key == "set_up" else t[key] for t in times[2]]
        ratios = [a / b for a, b in zip(t1, t2)]
        row[key] = {
            "seconds_1": t1,
            "seconds_2": t2,
            "median_1": statistics.median(t1),
            "median_2": statistics.median(t2),
            "speedup": statistics.median(t1) / statistics.median(t2),
            "pair_ratios": ratios,
            "efficiency": statistics.median(t1) / (2 * statistics.median(t2)),
        }
    print(
        f"  {name} N = {n}: {row['wall']['median_1']:.3f} s / {row['wall']['median_2']:.3f} s, "
        f"x{row['wall']['speedup']:.2f} (pairs {min(row['wall']['pair_ratios']):.2f}-{max(row['wall']['pair_ratios']):.2f}), "
        f"others {100 * row['others_share']:.1f} %",
        flush=True,
    )
    return row


def probe_host(probe: Path) -> dict | None:
    """The probe's measurements at 1 and 2 threads, or None without the
    probe."""
    if not probe.exists():
        return None
    done = subprocess.run([str(probe)], check=True, capture_output=True, text=True, timeout=600)
    return json.loads(done.stdout)


def ratio(probe: dict, name: str) -> float:
    """What a second thread adds to the probe's measurement `name` (2 threads over 1)."""
    _, _, one, two = next(m for m in PROBES if m[0] == name)
    return probe[two] / probe[one]


def pair_ratios(probes: list[dict | None], name: str) -> list[float] | None:
    """Each pair's ratio of measurement `name`: the mean of the probes before
    and after it (`probes` has one more entry than there are pairs); None
    without the probe."""
    if any(p is None for p in probes):
        return None
    ratios = [ratio(p, name) for p in probes]
    return [(a + b) / 2 for a, b in zip(ratios, ratios[1:])]


#: Rows from this size on stream more than the caches hold (the 8,000-rotor
#: lattices' pair tables and grids are tens of MB) and have sections long
#: enough to share evenly, so their speed-up can follow the host.
LARGE_ROTORS = 8_000
#: Pairs whose probe gains at least this much from a second thread are the
#: ones with the host's resources to spare.
RATIO_SPLIT = 1.8


def probe_lines(rows: list[dict]) -> list[str]:
    """The section's lines on the host probe: each measurement's range and,
    over the pairs of the large rows, their speed-ups against its ratios."""
    probes = [p for r in rows for p in r.get("probes") or [] if p]
    if not probes:
        return ["- Host probe: not run (no `examples/host_probe` binary)."]
    lines = [f"- Host probe (`examples/host_probe.rs` before every pair and after each row's last, {len(probes)} "
             "probes), 1 thread, 2 threads and their ratio: "
             + "; ".join(_probe_range(probes, m) for m in PROBES)
             + ". A step that streams its data gains at most about the triad's ratio, one that computes in "
             "registers about the arithmetic's; the columns `triad` and `arithmetic` give each row's pairs' ratios."]
    for name, *_ in PROBES:
        pairs = [(s, t) for r in rows if r["rotors"] >= LARGE_ROTORS and r.get(f"{name}_ratios")
                 for s, t in zip(r["wall"]["pair_ratios"], r[f"{name}_ratios"])]
        if len(pairs) < 3:
            continue
        rho = scipy.stats.spearmanr([s for s, _ in pairs], [t for _, t in pairs]).statistic
        split = "; ".join(
            f"{label} {RATIO_SPLIT}x: median speed-up {statistics.median(group):.2f}x "
            f"({len(group)} pair{'' if len(group) == 1 else 's'})"
            for label, group in (("at least", [s for s, t in pairs if t >= RATIO_SPLIT]),
                                 ("below", [s for s, t in pairs if t < RATIO_SPLIT])) if group)
        lines.append(f"- The {len(pairs)} pairs of the rows from {LARGE_ROTORS:,} rotors against the {name}'s ratio: "
                     f"Spearman rank correlation {rho:.2f} with the whole-run speed-up; {name} ratio {split}.")
    return lines


def _probe_range(probes: list[dict], measurement: tuple) -> str:
    name, unit, one, two = measurement
    found = [p for p in probes if one in p and two in p]
    if not found:
        return f"{name} not measured"
    a, b, r = [p[one] for p in found], [p[two] for p in found], [ratio(p, name) for p in found]
    return (f"{name} {min(a):.1f}-{max(a):.1f} and {min(b):.1f}-{max(b):.1f} {unit}, "
            f"{min(r):.2f}-{max(r):.2f}x (median {statistics.median(r):.2f}x)")


def section(result: dict) -> str:
    m = result["machine"]
    cores = m["cpus"] or 1
    busiest = max(r["others_share"] for r in result["rows"])
    idle = busiest <= IDLE_SHARE
    lines = [
        BEGIN,
        "## Threads: whole runs on 1 and 2 threads (issue 38, `make bench-threads`)",
        "",
        f"- Machine: {m['cpu']}, {cores} hardware threads, {m['platform']}; {m['date']}.",
        f"- Command: `python -m validation.bench.threads {' '.join(result['argv'])}` (`make bench-threads` runs it "
        f"with `--out benchmarks`), {result['seconds']:.0f} s.",
        (
            f"- The machine was idle: other processes and the hypervisor's steal took at most {100 * busiest:.1f} % "
            f"of the {cores} cores' time during any run (`/proc/stat`'s busy time less the benchmark's own CPU time)."
            if idle
            else f"- **The machine was not idle**: other processes and the hypervisor's steal took up to "
            f"{100 * busiest:.1f} % of the {cores} cores' time during a run (`/proc/stat`'s busy time less the "
            "benchmark's own CPU time), so the speed-ups below understate what an idle machine gives and their "
            "spread is wide."
        ),
        *probe_lines(result["rows"]),
        "- Each built-in lattice scene as written (its integrator, thermostat, sum and recording), its `cells` "
        "set for about 1,000, 8,000 and 64,000 rotors, through the CLI (`--threads 1`, `--threads 2`); "
        f"{ROTOR_STEPS:.0e} rotor-steps per periodic run but at least {MIN_PERIODIC_STEPS} steps (the dipole "
        f"lattices' own run length), {PAIR_STEPS:.0e} pair-steps per open-cluster run (at least {MIN_STEPS} steps); "
        f"open clusters (O(N^2)) up to {MAX_OPEN_ROTORS:,} rotors. Each repeat runs the pair side by side, the order "
        "alternating; medians over the repeats. Whole run: the process's wall time (set-up, start-up, outputs "
        "included); loop: the run loop (`wall_seconds` of `summary.json`); set-up: the whole run less the loop "
        "(scene, sums, Gear start-up, opening and closing the outputs). Efficiency `t1 / (2 t2)`; pairs: the range "
        "of the repeats' ratios; others: the largest share of the cores' time that other processes took during a "
        "run of the row.",
        "",
        "| scene | N | steps | repeats | 1 thread s | 2 threads s | speed-up (pairs) | efficiency | loop speed-up "
        "| set-up s (1 / 2 threads) | triad (pairs) | arithmetic (pairs) | others |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in result["rows"]:
        w, lp, su = r["wall"], r["loop"], r["set_up"]
        triad, arithmetic = (_ratio_cell(r.get(f"{name}_ratios")) for name, *_ in PROBES)
        lines.append(
            f"| `{r['scene']}` | {r['rotors']:,} | {r['steps']} | {r['repeats']} | {w['median_1']:.3f} | {w['median_2']:.3f} | "
            f"{w['speedup']:.2f}x ({min(w['pair_ratios']):.2f}-{max(w['pair_ratios']):.2f}) | {w['efficiency']:.2f} | "
            f"{lp['speedup']:.2f}x | {su['median_1']:.3f} / {su['median_2']:.3f} | {triad} | {arithmetic} | {100 * r['others_share']:.1f} % |"
        )
    lines += ["", END]
    return "\n".join(lines) + "\n"


def _ratio_cell(ratios: list[float] | None) -> str:
    return f"{statistics.median(ratios):.2f}x ({min(ratios):.2f}-{max(ratios):.2f})" if ratios else "-"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    parser.add_argument("--repeats", type=int, default=5, help="pairs of runs per case (default 5)")
    parser.add_argument("--sizes", type=int, nargs="+", default=list(TARGET_ROTORS), help="rotor counts asked for")
    parser.add_argument("--scenes", nargs="+", help="only these built-in scenes")
    parser.add_argument("--cli", type=Path, default=CLI, help=f"the quatrot binary (default {CLI})")
    parser.add_argument("--probe", type=Path, default=HOST_PROBE,
                        help=f"the host probe (default {HOST_PROBE}; skipped if missing)")
    args = parser.parse_args(argv)
    if not args.cli.exists():
        sys.exit(f"{args.cli} is missing: run `cargo build --release` first")
    started = time.perf_counter()
    machine = results_md.machine()
    busy, wall = busy_seconds(), time.perf_counter()
    time.sleep(1.0)
    share = others_share(busy_seconds() - busy, 0.0, time.perf_counter() - wall, machine["cpus"] or 1)
    if share > IDLE_SHARE:
        print(f"warning: the machine is not idle (other processes took {100 * share:.0f} % of it)", flush=True)
    rows = []
    with tempfile.TemporaryDirectory(prefix="quatrot-threads-") as tmp:
        for name, scene in lattice_scenes():
            if args.scenes and name not in args.scenes:
                continue
            for rotors in args.sizes:
                if periodic(scene) or rotors <= MAX_OPEN_ROTORS:
                    rows.append(measure(args.cli, name, scene, rotors, args.repeats, Path(tmp), args.probe))
    result = {"machine": machine, "rows": rows, "seconds": time.perf_counter() - started, "argv": sys.argv[1:] if argv is None else argv}
    args.out.mkdir(parents=True, exist_ok=True)
    results_md.update_json(args.out / "results.json", {"threads": result})
    results_md.replace_section(args.out / "RESULTS.md", BEGIN, END, section(result))
    print(f"wrote the threads entry of {args.out / 'results.json'} and its section of {args.out / 'RESULTS.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
