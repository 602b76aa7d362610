"""`python -m validation.bench.water_nvt --out benchmarks`: issue 41's
thermostatted water against published and peer values, every thermostat
for every model (the check ``water_published`` runs one thermostat per
model at a length ``make validate`` can afford). Each run starts from the
built-in's lattice with the model swapped in, made at the model's liquid
density at coexistence at 300 K (NIST; validation/shared/water_nvt_runs.py),
discards ``--equilibration-ps`` (default 10: from the lattice TIP4P/2005's
energy and pressure drift for 9 to 12 ps under Langevin 0.01/fs) and block
averages the potential energy per molecule and the pressure over the rest
of ``--length-ps``: the pressure against NIST's saturation pressure, the
energy against OpenMM's NVT at the same state (fixtures/water_nvt_openmm.json).

Runs are cached in ``--cache`` by their parameters (delete after changing
the engine); ``--model`` runs one model only (several processes can share
the work); the section is published when every run is in the cache."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

import quatrot
from validation.bench import results_md
from validation.shared import water_nvt_runs as wp

BEGIN = "<!-- make bench: water_nvt section begin -->"
END = "<!-- make bench: water_nvt section end -->"
Z_MAX = 3.0


def run_one(model: str, thermostat: str, steps: int, cache: Path) -> dict:
    state = wp.NIST_COEXISTENCE[model]
    path = cache / f"{model}_{thermostat}_{steps}_{state.temperature:g}K_{state.rho}.npz"
    if not path.exists():
        found = wp.nvt_run(model, thermostat, steps, cache / f"{path.stem}_out", temperature=state.temperature,
                           density=state.rho)
        cache.mkdir(parents=True, exist_ok=True)
        np.savez(path, **found)
    return dict(np.load(path))


def row(model: str, thermostat: str, found: dict, equilibration_ps: float) -> dict:
    measured = wp.averages(found, equilibration_ps)
    return {"model": model, "thermostat": thermostat, "measured": measured,
            "z": wp.z_scores(model, measured), "cpu_ms_per_step": 1000 * float(found["cpu_seconds"]) /
            (len(found["time_ps"]) - 1) / 5}


def verdict(z: float) -> str:
    return f"{z:.2f}" if z <= Z_MAX else f"**{z:.2f}**"


def table(rows: list[dict], length_ps: float, equilibration_ps: float) -> str:
    lines = ["| model | thermostat | run ps, averaged | U kcal/mol/molecule | OpenMM | z | p atm | NIST p_sat | z | "
             "T_trans K | T_rot K | CPU ms/step |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        m, z = r["measured"], r["z"]
        e, p = z["energy"], z["pressure"]
        lines.append(
            f"| {r['model']} | {r['thermostat']} | {length_ps:g}, {equilibration_ps:g}-{length_ps:g} | "
            f"{e['measured']:.3f} +- {e['statistical_error']:.3f} | {e['expected']:.3f} +- {e['reference_error']:.3f} | "
            f"{verdict(e['z'])} | {p['measured']:.0f} +- {p['statistical_error']:.0f} | "
            f"{p['expected']:.0f} +- {p['reference_error']:.0f} | {verdict(p['z'])} | "
            f"{m['T_trans'][0]:.1f} +- {m['T_trans'][1]:.1f} | {m['T_rot'][0]:.1f} +- {m['T_rot'][1]:.1f} | "
            f"{r['cpu_ms_per_step']:.1f} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks"))
    parser.add_argument("--cache", type=Path, default=Path("target/bench/water_nvt"))
    parser.add_argument("--length-ps", type=float, default=50.0)
    parser.add_argument("--equilibration-ps", type=float, default=10.0)
    parser.add_argument("--model", choices=tuple(wp.NIST_COEXISTENCE), action="append", help="only this model, no section")
    args = parser.parse_args(argv)
    steps = round(args.length_ps * 1000 / 2.0)
    rows = []
    for model in args.model or tuple(wp.NIST_COEXISTENCE):
        for thermostat in wp.THERMOSTATS:
            print(f"water NVT, {model} with {thermostat}: {args.length_ps:g} ps ...", flush=True)
            rows.append(row(model, thermostat, run_one(model, thermostat, steps, args.cache), args.equilibration_ps))
            z = rows[-1]["z"]
            print(f"  U z {z['energy']['z']:.2f}, p z {z['pressure']['z']:.2f}", flush=True)
    if args.model:
        return 0
    machine = results_md.machine()
    result = {"machine": machine, "versions": {"quatrot": quatrot.__version__}, "length_ps": args.length_ps,
              "equilibration_ps": args.equilibration_ps, "runs": rows}
    text = "\n".join([
        BEGIN,
        "## Thermostatted water against published and peer values (issue 41, `python -m validation.bench.water_nvt`)",
        "",
        f"- Machine: {machine['cpu']}, {machine['cpus']} CPUs; load average {machine['load_average']:.1f} when the "
        f"section was written. Date: {machine['date']}. quatrot {quatrot.__version__}, one thread (CPU per step is "
        "process CPU time over the run).",
        "- 512 molecules at each model's liquid density at coexistence at 300 K (NIST SAT-TMMC: SPC/E 0.9981, "
        "TIP3P 0.9839, TIP4P/2005 0.9965 g/cm^3; the built-in `spce_water_512` with the model swapped in, its "
        f"lattice made there), NO_SQUISH at 2 fs from the lattice; {args.equilibration_ps:g} ps discarded, the rest "
        "block averaged. Thermostats with a 100 fs time constant (Langevin friction 0.01/fs). References "
        "(`validation/shared/water_nvt_runs.py`): the pressure NIST's saturation pressure (its error from NIST's "
        "density error), the energy OpenMM's NVT at the same state and protocol (`fixtures/water_nvt_openmm.json`); "
        f"z = |measured - reference| / (statistical and reference errors in quadrature), {Z_MAX:g} allowed.",
        "",
        table(rows, args.length_ps, args.equilibration_ps),
        "",
        END,
        "",
    ])
    results_md.publish(args.out, "water_nvt", result, (BEGIN, END), text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
