"""This benchmark's section of `benchmarks/RESULTS.md` (other sections, owned
by other benchmarks, are kept as they are)."""

from __future__ import annotations

import datetime
import json
import os
import platform
import subprocess
from pathlib import Path

from validation.bench import scans
from validation.shared.benchmark_scenes import LATTICE_SCENE

BEGIN = "<!-- make bench: performance section begin -->"
END = "<!-- make bench: performance section end -->"


def machine() -> dict:
    model = "unknown"
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name:"):
                model = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return {
        "cpu": model,
        "cpus": os.cpu_count(),
        "load_average": os.getloadavg()[0],
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "platform": platform.platform(),
    }


def toolchain() -> dict:
    import numpy
    import scipy

    try:
        rustc = subprocess.run(["rustc", "--version"], capture_output=True, text=True).stdout.strip()
    except OSError:
        rustc = "unknown"
    return {"rustc": rustc, "python": platform.python_version(), "numpy": numpy.__version__, "scipy": scipy.__version__}


def _g(x, digits=3) -> str:
    return "n/a" if x is None else f"{x:.{digits}g}"


def _run_cell(b) -> str:
    if not b:
        return "not reached"
    return f"{b['scheme']}, dt {b['dt']:g}: {_g(b['wall'] * 1e3)} ms ({b['torque_evaluations']} torque evals, err {_g(b['error'], 2)})"


def _throughput(results) -> list[str]:
    lattice = next(s for s in results["studies"] if s["scene"] == LATTICE_SCENE)
    lammps = results["lammps"]["throughput"]
    dlm = lammps.get("LAMMPS dipole/dlm")
    lines = [
        "| code, scheme | rotor-steps / s / thread | ratio to LAMMPS dipole/dlm |",
        "|---|---|---|",
    ]
    for scheme, rate in sorted(lattice["throughput"].items(), key=lambda kv: -(kv[1] or 0)):
        lines.append(f"| quatrot {scheme} | {_g(rate)} | {_g(rate / dlm if dlm and rate else None)} |")
    for scheme, rate in lammps.items():
        lines.append(f"| {scheme} | {_g(rate)} | {_g(rate / dlm if dlm else None)} |")
    return lines


def _side_by_side(results) -> list[str]:
    sbs = results["lammps"].get("side_by_side") or {}
    rates = sbs.get("rotor_steps_per_second", {})
    dlm = rates.get("LAMMPS dipole/dlm")
    if not rates:
        return []
    lines = [
        "",
        f"Side by side, in alternation ({len(next(iter(sbs['seconds'].values())))} rounds, medians): {sbs['steps']} steps of the "
        f"{sbs['rotors']}-rotor lattice at dt = {sbs['dt']:g}, one thread each; quatrot through its CLI on the built-in scene "
        "with the recording removed (`RAYON_NUM_THREADS=1`), LAMMPS through its Python module (`OMP_NUM_THREADS=1`, one `run`). "
        "LAMMPS's time is its `run` (set-up excluded); quatrot's is given both as its step loop (set-up excluded, like for like) "
        "and as the whole process (start, scene, pair list, the Gear start-up, loop, outputs).",
        "",
        "| run | rotor-steps / s / thread | ratio to LAMMPS dipole/dlm | target (>= 10) |",
        "|---|---|---|---|",
    ]
    for k, v in rates.items():
        ratio = v / dlm if dlm else None
        verdict = "" if k.startswith("LAMMPS") or ratio is None else ("met" if ratio >= 10 else f"missed by {10 / ratio:.2g}x")
        lines.append(f"| {k} | {_g(v)} | {_g(ratio)} | {verdict} |")
    return lines


def _targets(study) -> list[str]:
    lattice = study["scene"] == LATTICE_SCENE
    head = "| target error | fastest quatrot run |"
    rule = "|---|---|"
    if lattice:
        head += " LAMMPS dipole/dlm | LAMMPS dipole | LAMMPS dlm time / quatrot time | quatrot < 1/10 of LAMMPS dlm? |"
        rule += "---|---|---|---|"
    lines = [head, rule]
    for row in study["targets"]:
        line = f"| {row['target']:g} | {_run_cell(row['quatrot'])} |"
        if lattice:
            verdict = row.get("meets_10x")
            verdict = "yes" if verdict is True else "no" if verdict is False else (verdict or "n/a")
            dlm = _run_cell(row.get("LAMMPS dipole/dlm"))
            if row.get("dlm_extrapolated") and row.get("dlm_wall") is not None:
                dlm += f"; extrapolated {_g(row['dlm_wall'] * 1e3)} ms"
            ratio = _g(row.get("ratio_vs_dlm")) + (" (extrapolated)" if row.get("dlm_extrapolated") and row.get("ratio_vs_dlm") else "")
            line += f" {dlm} | {_run_cell(row.get('LAMMPS dipole'))} | {ratio} | {verdict} |"
        lines.append(line)
    return lines


def _orders_energy(study) -> list[str]:
    lines = [
        "| scheme | observed order | max \\|dE\\|/KE0 (largest dt -> smallest) | drift per unit time at the smallest dt | torque evals per step |",
        "|---|---|---|---|---|",
    ]
    schemes = list(dict.fromkeys(r["scheme"] for r in study["runs"]))
    for s in schemes:
        runs = sorted((r for r in study["runs"] if r["scheme"] == s), key=lambda r: -r["dt"])
        big, small = runs[0], runs[-1]
        per_step = (small["torque_evaluations"] - big["torque_evaluations"]) / max(1, small["steps"] - big["steps"])
        lines.append(
            f"| {s} | {_g(study['orders'].get(s), 2)} | {_g(big['energy_error_max'], 2)} -> {_g(small['energy_error_max'], 2)} | "
            f"{_g(small['energy_drift_per_time'], 2)} | {_g(per_step, 3)} |"
        )
    return lines


def _stability(rows) -> list[str]:
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    schemes = list(dict.fromkeys(r["scheme"] for r in rows))
    lines = ["| scheme | " + " | ".join(scenes) + " |", "|---|" + "---|" * len(scenes)]
    for s in schemes:
        cells = []
        for scene in scenes:
            r = next(x for x in rows if x["scene"] == scene and x["scheme"] == s)
            cap = " (cap: stable at every step tried)" if r.get("capped") else ""
            cells.append(f"{_g(r['largest_stable_dt'])}{cap}")
        lines.append(f"| {s} | " + " | ".join(cells) + " |")
    return lines


def _long_runs(rows) -> list[str]:
    lines = [
        "| scene | scheme | steps x dt | final dE/KE0 | max \\|dE\\|/KE0 | drift per unit time | max \\| \\|Q\\|-1 \\| | loop s | failure |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['scene']} | {r['scheme']} | {r['steps']} x {r['dt']:g} | {_g(r['energy_error_final'], 2)} | {_g(r['energy_error_max'], 2)} | "
            f"{_g(r['energy_drift_per_time'], 2)} | {_g(r['norm_error_max'], 2)} | {_g(r['wall_seconds'])} | {r['failure'] or ''} |"
        )
    return lines


def _stress(rows) -> list[str]:
    cases = list(dict.fromkeys(r["case"] for r in rows))
    schemes = list(dict.fromkeys(r["scheme"] for r in rows))
    lines = [
        "Orientation error at the final time against scipy DOP853 (rad) / max |dE|/E-scale; FAIL names the failure.",
        "",
        "| case (dt, time) | " + " | ".join(schemes) + " |",
        "|---|" + "---|" * len(schemes),
    ]
    failures = []
    for c in cases:
        cells = []
        first = next(r for r in rows if r["case"] == c)
        for s in schemes:
            r = next(x for x in rows if x["case"] == c and x["scheme"] == s)
            if r["failure"]:
                cells.append("FAIL")
                failures.append(f"- {c}, {s}: {r['failure']}")
            else:
                cells.append(f"{_g(r['error'], 2)} / {_g(r['energy_error_max'], 2)}")
        lines.append(f"| {c} ({first['dt']:g}, {first['time']:g}) | " + " | ".join(cells) + " |")
    return lines + ([""] + failures if failures else [])


def _scaling(scaling) -> list[str]:
    rows = scaling["rows"]
    fit = scaling["fit"]
    per_step = {(r["rotors"], r["threads"]): r["seconds_per_step"] for r in rows}
    lines = [
        "| cells | N | pairs per rotor | pair-list build s | steps | s per step, 1 thread | ns per rotor-step, 1 thread | s per step, 2 threads | 2-thread efficiency |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in (r for r in rows if r["threads"] == 1):
        n = r["rotors"]
        t2 = per_step.get((n, 2))
        eff = fit["efficiency"].get(str(n))  # JSON keys are strings
        lines.append(
            f"| {r['cells']} | {n} | {_g(r['pairs'] / n, 3)} | {_g(r['pair_list_seconds'])} | {r['steps']} | {_g(r['seconds_per_step'])} | "
            f"{_g(r['seconds_per_step'] / n * 1e9)} | {_g(t2) if t2 else '-'} | {_g(eff, 2) if eff else '-'} |"
        )

    def exponents(key: str) -> str:
        return ", ".join(f"{t} thread(s) {_g(e)}" for t, e in fit[key].items())

    per_rotor = ", ".join(sorted({_g(r["pairs"] / r["rotors"], 3) for r in rows}))
    lines += [
        "",
        f"Pairs per rotor: {per_rotor} (the whole cutoff sphere at every size: below 7^3 rotors the cutoff exceeds half the box, "
        "and the lattice sum runs over several images of a pair and over each rotor's own images). "
        "Fitted exponent of time per step against N (1 = linear): all sizes, "
        + exponents("exponent")
        + f"; N >= {fit.get('large_n', 1000)}, "
        + exponents("exponent_large")
        + f". Pair-list build time against N (N >= {fit.get('large_n', 1000)}): exponent {_g(fit.get('build_exponent'))}. "
        "2-thread efficiency is t1 / (2 t2) at the same N.",
    ]
    return lines


def section(results: dict) -> str:
    m, v = results["machine"], results["versions"]
    studies = results["studies"]
    lines = [
        BEGIN,
        "## Work-precision, stability, scaling, and LAMMPS side by side (`make bench`)",
        "",
        f"- Machine: {m['cpu']}, {m['cpus']} CPUs; load average {m['load_average']:.1f} when the analysis started "
        "(the machine is shared: timings are medians of repeats, and ratios are measured side by side in one run).",
        f"- Date: {m['date']}. quatrot {v['quatrot']}, {v['rustc']}, LAMMPS {v['lammps']}, Python {v['python']}, numpy {v['numpy']}, scipy {v['scipy']}.",
        "- Command: `make bench` (`cargo bench`, whose `performance` target is `benches/performance/`, then "
        "`python -m validation.bench --out benchmarks`, which writes `benchmarks/results.json`, the PNGs and this section). "
        f"The Rust driver took {results['rust_seconds']:.0f} s ("
        + ", ".join(f"{k} {v:.0f} s" for k, v in results.get("rust_section_seconds", {}).items())
        + ").",
        "- Path measured: work-precision, stability, long and stress runs go through the user's path (validated scene -> "
        "`run::execute` -> the runner, nothing recorded for the timed repeats; a second, recording run of the same scene gives the "
        "energies, norms, final orientations and torque-evaluation count). Scaling is a kernel measurement (bare library API). "
        "Times are loop times on 1 thread; the Gear schemes' consistent start-up (65 torque evaluations once per run, plus one gradient in scheme B's setup) "
        "is excluded from them and included in the torque-evaluation counts.",
        "- Error measures: single rotors, the angle of the rotation between the final orientation and scipy DOP853 (rtol 1e-12) "
        "of the same equations; lattices, the largest angle between a rotor's body-z axis (its dipole or quadrupole axis: the "
        "only orientation LAMMPS has) and the reference's. Energy error: (E - E0) / KE0 (|E0| for the dipole starting at rest).",
    ]
    if results["quick"]:
        lines += ["", "**Quick mode (pipeline test): the numbers below are not measurements.**"]
    lines += ["", "### Throughput on the 1000-rotor dipole lattice (1 thread)", ""]
    lines += ["From the work-precision runs (longest run per scheme; LAMMPS timed in the same `make bench`, a few minutes later):", ""]
    lines += _throughput(results) + _side_by_side(results)
    lines += ["", "![work-precision](work_precision.png)", "", "![error vs dt](error_vs_dt.png)"]
    for s in studies:
        ref = s["reference"]
        conv = (
            f" Its own convergence: the run at dt = {ref['self_error_dt']:g} differs from it by {_g(ref['self_error'], 2)} rad."
            if ref.get("self_error") is not None
            else ""
        )
        lines += [
            "",
            f"### {s['scene']} ({s['rotors']} rotor{'s' if s['rotors'] > 1 else ''}, error at t = {s['time']:g})",
            "",
            f"Reference: {ref['kind']}.{conv}",
            "",
        ]
        lines += _targets(s) + [""] + _orders_energy(s)
    lines += [
        "",
        "### Largest stable time step",
        "",
        "Stable: |E - E0| < 0.1 KE0 (|E0| for the dipole starting at rest) at every check over the fixed time "
        "(single rotors: t = 20 and 10, checked every step; lattices: t = 2, every 2 steps). A grid of steps, "
        "2^(1/4) (19 %) apart from 1/8 of the scene's starting step up to time/10, every point a scene run of a "
        "`quatrot.sweep` (`validation/bench/scans.py`); the largest stable step is the largest of the grid at which "
        "it and every smaller step stayed stable.",
        "",
    ]
    lines += _stability(results["stability"]) + ["", "![stability](stability.png)"]
    failures = [r for r in results["stability"] if r.get("failure")]
    if failures:
        lines += ["", "How each scheme fails just above its largest stable step:", ""]
        lines += [f"- {r['scene']}, {r['scheme']} at dt {_g(r['first_unstable_dt'])}: {r['failure']}" for r in failures]
    lines += ["", "### Long runs (scene time steps)", ""] + _long_runs(results["long_runs"])
    lines += ["", "### Stress cases (single rotors)", ""] + _stress(results["stress"])
    lines += ["", "### Stress cases at length (sweep)", ""] + scans.lengths_table(results["stress_at_length"])
    lines += ["", "### Scaling (periodic sc dipole lattice, cutoff 3.1, NO_SQUISH)", "", "![scaling](scaling.png)", ""] + _scaling(results["scaling"])
    prof = results.get("profile")
    if prof:
        lines += ["", "### Profile of a lattice step (1 thread)", "", f"`{prof['command']}`", "", "| share of samples | function |", "|---|---|"]
        lines += [f"| {p:.1f} % | `{f[:110]}` |" for p, f in prof["functions"]]
    lines.append(END)
    return "\n".join(lines) + "\n"


def write_section(path: Path, results: dict) -> None:
    """Replaces this benchmark's section (between its markers) or appends it."""
    replace_section(path, BEGIN, END, section(results))


def arguments(doc: str, argv=None):
    """The command line of a bench module that reads a Rust bench's raw
    results: ``--out`` (default ``benchmarks``) and ``--raw`` (default
    ``target/bench/raw``), described by the first paragraph of ``doc``."""
    import argparse

    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    parser.add_argument("--raw", type=Path, default=Path("target/bench/raw"))
    return parser.parse_args(argv)


def publish(out: Path, key: str, result: dict, markers: tuple[str, str], text: str) -> None:
    """Writes `result` as the `key` entry of `<out>/results.json` and `text`
    as its section (between `markers`) of `<out>/RESULTS.md`."""
    out.mkdir(parents=True, exist_ok=True)
    update_json(out / "results.json", {key: result})
    replace_section(out / "RESULTS.md", *markers, text)
    print(f"wrote the {key} entry of {out / 'results.json'} and its section of {out / 'RESULTS.md'}")


def update_json(path: Path, results: dict) -> None:
    """Writes `results`' top-level keys into the JSON file `path`, keeping the
    keys of the other benchmarks (each owns its own keys)."""
    merged = json.loads(path.read_text()) if path.exists() else {}
    merged.update(results)
    path.write_text(json.dumps(merged, indent=1) + "\n")


def replace_section(path: Path, begin: str, end: str, new: str) -> None:
    """Replaces the text from the line `begin` to the line `end` of `path` by
    `new` (which starts with `begin` and ends with `end`), or appends it."""
    text = path.read_text() if path.exists() else "# Benchmark results\n"
    if begin in text and end in text:
        head, rest = text.split(begin, 1)
        tail = rest.split(end, 1)[1].lstrip("\n")
        text = head + new + ("\n" + tail if tail else "")
    else:
        text = text.rstrip("\n") + "\n\n" + new
    path.write_text(text)
