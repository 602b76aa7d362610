"""`python -m validation.bench.thermostats --out benchmarks [--quick]`: the
time-step bias of the thermostats. For every thermostat and integrator
pair, one asymmetric top carrying a dipole in a uniform field (ergodic with
every thermostat; x = mu E / T = 2) is run for a long time at several time
steps, and two temperatures are measured against the set one: the kinetic
temperature ``2 <K_th> / N_f`` of the thermostatted degrees of freedom and the
configurational temperature ``<|grad V|^2> / <lap V>`` (for a dipole,
``<|mu x E|^2> / <2 mu.E>``: the rotational Laplacian of ``mu.E`` is
``-2 mu.E``). Their relative bias is fitted to ``c dt^p`` over the steps
where it is resolved (more than three block errors). Writes the
`thermostats` entry of `<out>/results.json`, its section of
`<out>/RESULTS.md` and `<out>/thermostat_bias.png`."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import quatrot
from validation.bench import results_md

BEGIN = "<!-- make bench: thermostats section begin -->"
END = "<!-- make bench: thermostats section end -->"
T = 0.8
FIELD = 2.0 * T
INERTIA = np.array([0.1, 0.15, 0.25])
PAIRS = [
    ("langevin", {"kind": "langevin", "temperature": T, "friction": 2.0}, "dlm", {"kind": "dlm"}),
    ("langevin", {"kind": "langevin", "temperature": T, "friction": 2.0}, "no_squish", {"kind": "no_squish"}),
    ("bussi", {"kind": "bussi", "temperature": T, "tau": 0.1}, "dlm", {"kind": "dlm"}),
    ("bussi", {"kind": "bussi", "temperature": T, "tau": 0.1}, "no_squish", {"kind": "no_squish"}),
    ("nose_hoover", {"kind": "nose_hoover", "temperature": T, "tau": 0.4}, "dlm", {"kind": "dlm"}),
    ("nose_hoover", {"kind": "nose_hoover", "temperature": T, "tau": 0.4}, "no_squish", {"kind": "no_squish"}),
    ("nose_hoover", {"kind": "nose_hoover", "temperature": T, "tau": 0.4}, "gear_a", {"kind": "gear_a"}),
]
STEPS = [0.005, 0.01, 0.02, 0.04]


def scene(thermostat: dict, integrator: dict, dt: float, time: float, every: int) -> dict:
    return {
        "version": 1,
        "name": "thermostat_bias",
        "rotors": {"kind": "sites", "sites": [{"position": [0.0, 0.0, 0.0]}], "default": {"inertia": INERTIA.tolist(), "dipole": [0.0, 0.0, 1.0]}},
        "fields": {"uniform": [0.0, 0.0, FIELD]},
        "initial": {"kind": "random", "seed": 11, "temperature": T},
        "integrator": integrator,
        "thermostat": thermostat,
        "run": {"dt": dt, "steps": int(round(time / dt))},
        "record": {"trajectory": {"every": every}},
    }


def temperatures(result: dict, skip: int) -> dict:
    """Kinetic and configurational temperatures of a one-rotor run, with block errors."""
    t = result["trajectory"]
    q = np.asarray(t["orientations"])[skip:, 0]
    w = np.asarray(t["omega_body"])[skip:, 0]
    kinetic = (INERTIA * w * w).sum(axis=1)  # 2 K, three degrees of freedom (no conserved spin here)
    q0, q1, q2, q3 = q.T
    mu = np.stack([2 * (q1 * q3 + q0 * q2), 2 * (q2 * q3 - q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3], -1)
    e = np.array([0.0, 0.0, FIELD])
    torque2 = (np.cross(mu, e) ** 2).sum(axis=1)
    laplacian = 2.0 * mu @ e
    k = quatrot.block_average(kinetic / 3.0)
    g, l = quatrot.block_average(torque2), quatrot.block_average(laplacian)
    conf = g["mean"] / l["mean"]
    conf_error = conf * np.hypot(g["error"] / g["mean"], l["error"] / l["mean"])
    return {"kinetic": float(k["mean"]), "kinetic_error": float(k["error"]), "configurational": float(conf), "configurational_error": float(conf_error)}


def fitted_order(dts, bias, errors) -> float | None:
    """The exponent of |bias| against dt over the resolved points (> 3 errors), if two or more."""
    pts = [(d, abs(b)) for d, b, e in zip(dts, bias, errors) if abs(b) > 3 * e]
    if len(pts) < 2:
        return None
    d, b = np.array(pts).T
    return float(np.polyfit(np.log(d), np.log(b), 1)[0])


def measure(time: float) -> list[dict]:
    rows = []
    for tname, thermostat, iname, integrator in PAIRS:
        points = []
        for dt in STEPS:
            if iname == "gear_a" and dt > 0.01:
                continue  # scheme A's chain is stable only while dt p_j/Q_j stays below ~0.2
            every = max(1, int(round(0.05 / dt)))
            result = quatrot.run(scene(thermostat, integrator, dt, time, every))
            points.append({"dt": dt} | temperatures(result, skip=int(round(20.0 / (dt * every)))))
            print(tname, iname, points[-1], flush=True)
        dts = [p["dt"] for p in points]
        row = {"thermostat": tname, "integrator": iname, "points": points}
        for key in ("kinetic", "configurational"):
            row[f"{key}_order"] = fitted_order(dts, [p[key] / T - 1 for p in points], [p[f"{key}_error"] / T for p in points])
        rows.append(row)
    return rows


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, key, title in ((axes[0], "kinetic", "kinetic temperature"), (axes[1], "configurational", "configurational temperature")):
        for r in rows:
            dts = np.array([p["dt"] for p in r["points"]])
            bias = np.array([abs(p[key] / T - 1) for p in r["points"]])
            err = np.array([p[f"{key}_error"] / T for p in r["points"]])
            ax.errorbar(dts, np.maximum(bias, 1e-6), yerr=err, marker="o", capsize=2, label=f"{r['thermostat']} + {r['integrator']}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("dt")
        ax.set_title(f"|{title} / T - 1|")
    axes[0].set_ylabel("relative bias")
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def section(r: dict) -> str:
    m = r["machine"]
    lines = [
        BEGIN,
        "## Thermostats: time-step bias (`python -m validation.bench.thermostats`)",
        "",
        f"- Machine: {m['cpu']}, {m['cpus']} CPUs; load average {m['load_average']:.1f}. Date: {m['date']}. quatrot {quatrot.__version__}.",
        f"- One asymmetric top (I = {INERTIA.tolist()}) with a unit dipole in a uniform field, x = mu E / T = 2, T = {T}; {r['time']:g} time units per run, the first 20 left out;"
        " samples every 0.05; errors by blocking. Langevin friction 2, Bussi tau 0.1, Nose-Hoover tau 0.4 (chain 3).",
        "- Kinetic temperature: `<I_a w_a^2>` averaged over the three axes; configurational: `<|mu x E|^2> / <2 mu.E>` (exact: both equal T).",
        "- Order: fitted exponent of the relative bias against dt over the points where it exceeds three errors (none: not resolved).",
        "",
        "![time-step bias](thermostat_bias.png)",
        "",
        "| thermostat | integrator | dt | T_kin / T - 1 | T_conf / T - 1 |",
        "|---|---|---|---|---|",
    ]
    for row in r["rows"]:
        for p in row["points"]:
            lines.append(
                f"| {row['thermostat']} | {row['integrator']} | {p['dt']:g} | {p['kinetic'] / T - 1:+.2e} +- {p['kinetic_error'] / T:.1e} | {p['configurational'] / T - 1:+.2e} +- {p['configurational_error'] / T:.1e} |"
            )
    lines += ["", "| thermostat | integrator | order of the kinetic bias | order of the configurational bias |", "|---|---|---|---|"]
    fmt = lambda x: "not resolved" if x is None else f"{x:.2f}"  # noqa: E731
    for row in r["rows"]:
        lines.append(f"| {row['thermostat']} | {row['integrator']} | {fmt(row['kinetic_order'])} | {fmt(row['configurational_order'])} |")
    lines += [END]
    return "\n".join(lines) + "\n"


def write_section(path: Path, text: str) -> None:
    old = path.read_text() if path.exists() else "# Benchmark results\n"
    if BEGIN in old:
        head, rest = old.split(BEGIN, 1)
        old = head + rest.split(END, 1)[1].lstrip("\n")
    path.write_text(old.rstrip("\n") + "\n\n" + text)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    parser.add_argument("--quick", action="store_true", help="short runs (a smoke test of the piece)")
    args = parser.parse_args(argv)
    time = 100.0 if args.quick else 4000.0
    result = {"machine": results_md.machine(), "time": time, "rows": measure(time)}
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "results.json"
    results = json.loads(path.read_text()) if path.exists() else {}
    results["thermostats"] = result
    path.write_text(json.dumps(results, indent=1) + "\n")
    plot(result["rows"], args.out / "thermostat_bias.png")
    write_section(args.out / "RESULTS.md", section(result))
    print(f"wrote the thermostats entry of {path}, its section of {args.out / 'RESULTS.md'} and thermostat_bias.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
