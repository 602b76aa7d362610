"""`python -m validation.bench.mesh --out benchmarks [--raw target/bench/raw]`:
issue 40's mesh Ewald (PME) benchmark, after `cargo bench --bench ewald`
(whose quatrot timings it reads): PME's time per evaluation at accuracy
1e-5 from 1,000 to 1,000,000 dipoles with its fitted exponent, the
crossover with the direct Ewald sum at 1e-4 to 1e-6 (dipoles, and linear
quadrupoles on the same sites) measured and as the automatic choice's cost
models give it, the models' calibration (measured over estimated seconds),
and at 10,000 dipoles the side by side
with LAMMPS `pppm/dipole` at the same measured accuracy (one thread each).
Times compared are process CPU times: LAMMPS runs in this process, its
steps' time being that of a run of the steps less that of a run of none.

The configurations are fluid-like: a simple-cubic lattice of unit spacing,
each site displaced uniformly within +-0.25 per axis (irregular, no two
sites closer than 0.5), random dipole directions of unit length. The Rust
bench times its own configuration of that kind; this script measures the
errors on another (the cost of a sum does not depend on the particular
configuration, its error statistics do not either). Errors are RMS torques
against quatrot's PME at 1e-10, five decades finer than the cases compared:
the direct Ewald sum at 1e-12 would hold 9e7 real-space pairs (20 GB) for
10,000 dipoles, and the test suite checks PME's error at each requested
accuracy against that direct sum on smaller configurations. Writes the `mesh` entry of
`<out>/results.json` and its section of `<out>/RESULTS.md`."""

from __future__ import annotations

import json
import os
import sys
import time

import numpy as np

import quatrot
from validation.bench import results_md
from validation.bench.ewald import fit_exponent
from validation.shared.lammps_driver import DipoleSystem, lammps_version, quatrot_rotor, sample_and_time

BEGIN = "<!-- make bench: mesh section begin -->"
END = "<!-- make bench: mesh section end -->"
SEED = 20261128
CELLS, KEEP = 22, 10_000  # 22^3 jittered sites, 10,000 kept at random
LAMMPS_CUTOFF = 3.0  # pair lj/cut/dipole/long's real-space cutoff (LAMMPS sets g_ewald from it)
LAMMPS_ACCURACIES = (1e-4, 1e-5)
LAMMPS_STEPS = 5
CONVERGED = 1e-10  # PME's finest accuracy (module doc)


def configuration(seed: int) -> tuple[np.ndarray, np.ndarray, float]:
    """Sites, unit dipoles and the box edge of the 10,000-dipole configuration."""
    rng = np.random.default_rng(seed)
    cells = np.stack(np.meshgrid(*[np.arange(CELLS)] * 3, indexing="ij"), -1).reshape(-1, 3)
    sites = cells + 0.5 + rng.uniform(-0.25, 0.25, cells.shape)
    sites = sites[np.sort(rng.choice(len(sites), KEEP, replace=False))]
    dipoles = rng.normal(size=(KEEP, 3))
    dipoles /= np.linalg.norm(dipoles, axis=1)[:, None]
    return sites, dipoles, float(CELLS)


def quatrot_torques(sites, dipoles, edge, accuracy, method) -> np.ndarray:
    q = np.array([quatrot_rotor(m, np.zeros(3))[0] for m in dipoles])
    body = np.tile([0.0, 0.0, 1.0], (len(sites), 1))
    _, _, torques = quatrot.multipole_evaluate(
        sites, q, dipoles_body=body, box_lengths=np.full(3, edge), sum="ewald", accuracy=accuracy, method=method
    )
    return np.asarray(torques)


def rms(a: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum(a**2, axis=1))))


def lammps_cpu_seconds(system: DipoleSystem) -> tuple[float, np.ndarray, float]:
    """`sample_and_time` of `LAMMPS_STEPS` steps with the process CPU time
    of the steps: that of a run of the steps less that of a run of none
    (LAMMPS runs in this process; both runs pay the same set-up), so that
    LAMMPS's time is measured as quatrot's is, in process CPU time."""
    start = time.process_time()
    energy, torque, _ = sample_and_time(system, 1e-4, LAMMPS_STEPS)
    with_steps = time.process_time() - start
    start = time.process_time()
    sample_and_time(system, 1e-4, 0)
    return energy, torque, with_steps - (time.process_time() - start)


def side_by_side(raw: dict) -> dict:
    """Errors of quatrot's PME (at the accuracies the Rust bench timed) and
    LAMMPS pppm/dipole, and LAMMPS's time per step."""
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    sites, dipoles, edge = configuration(SEED)
    print("reference PME at 1e-10 ...", flush=True)
    reference = quatrot_torques(sites, dipoles, edge, CONVERGED, "pme")
    scale = rms(reference)
    quatrot_rows = []
    for case in raw["mesh_10000"]:
        t = quatrot_torques(sites, dipoles, edge, case["accuracy"], "pme")
        quatrot_rows.append({**case, "rms_torque_error": rms(t - reference), "relative_error": rms(t - reference) / scale})
        print(quatrot_rows[-1], flush=True)
    lammps_rows = []
    for accuracy in LAMMPS_ACCURACIES:
        system = DipoleSystem(
            sites=sites, dipoles=dipoles, omega=np.zeros_like(sites), box=edge, cutoff=LAMMPS_CUTOFF, kspace=("pppm/dipole", accuracy)
        )
        print(f"LAMMPS pppm/dipole {accuracy:g} ...", flush=True)
        _, torque, seconds = lammps_cpu_seconds(system)
        error = rms(torque - reference)
        lammps_rows.append(
            {"accuracy": accuracy, "seconds_per_step": seconds / LAMMPS_STEPS, "rms_torque_error": error, "relative_error": error / scale}
        )
        print(lammps_rows[-1], flush=True)
    return {"reference_rms_torque": scale, "quatrot": quatrot_rows, "lammps": lammps_rows}


def matched(r: dict) -> list[dict]:
    """For each LAMMPS run, the cheapest quatrot PME case at least as accurate (measured)."""
    out = []
    for l in r["side_by_side"]["lammps"]:
        good = [q for q in r["side_by_side"]["quatrot"] if q["rms_torque_error"] <= l["rms_torque_error"]]
        best = min(good, key=lambda q: q["median_cpu_seconds"]) if good else None
        out.append({"lammps": l, "quatrot": best, "ratio": l["seconds_per_step"] / best["median_cpu_seconds"] if best else None})
    return out


def carrying(rows: list[dict], carries: str) -> list[dict]:
    """The rows of sites carrying `carries` (rows written before quadrupoles were timed carry dipoles)."""
    return [c for c in rows if c.get("carries", "dipoles") == carries]


def crossover(cases: list[dict]) -> float | None:
    """The N where the direct and mesh sums cost the same, by log-log
    interpolation of each (None when one is cheaper throughout)."""
    direct = sorted((c["rotors"], c["median_cpu_seconds"]) for c in cases if c["method"] == "direct")
    mesh = {c["rotors"]: c["median_cpu_seconds"] for c in cases if c["method"] == "pme"}
    return interpolated([(n, t, mesh[n]) for n, t in direct if n in mesh])


def model_crossover(choices: list[dict], accuracy: float) -> float | None:
    """The N where `method = "auto"`'s cost models (src/potential/multipole/auto_choice.rs)
    price both sums the same at `accuracy` (among the sizes where both can be built)."""
    rows = sorted((c["rotors"], c["direct_seconds"], c["pme_seconds"]) for c in choices
                  if c["accuracy"] == accuracy and None not in (c["direct_seconds"], c["pme_seconds"]))
    return interpolated(rows)


def timed_cases(raw: dict, carries: str, accuracy: float) -> list[dict]:
    """The timed direct and PME cases of sites carrying `carries` at `accuracy`."""
    cases = raw["crossover"] + (raw["mesh_scaling"] if accuracy == 1e-5 else [])
    return [c for c in carrying(cases, carries) if c["accuracy"] == accuracy]


def crossovers(raw: dict) -> list[dict]:
    """Measured and modelled crossovers of dipoles and of quadrupoles at 1e-4, 1e-5 and 1e-6."""
    out = []
    for carries in ("dipoles", "quadrupoles"):
        choices = carrying(raw["auto_choices"], carries)
        for accuracy in (1e-4, 1e-5, 1e-6):
            cases = timed_cases(raw, carries, accuracy)
            if cases:
                out.append({"carries": carries, "accuracy": accuracy, "measured": crossover(cases),
                            "model": model_crossover(choices, accuracy)})
    return out


def calibration(raw: dict) -> list[dict]:
    """How far the cost models' seconds are from the measured ones: for each
    kind of site and each path, the ratios of the measured CPU time per
    evaluation to the model's estimate of the same configuration (the auto
    choice's of the same size and accuracy), their geometric mean and range.
    The geometric means are what the times per unit of auto_choice.rs are
    scaled by when they are refitted."""
    estimates = {(c.get("carries", "dipoles"), c["rotors"], c["accuracy"]): c for c in raw["auto_choices"]}
    out = []
    for carries in ("dipoles", "quadrupoles"):
        for method, key in (("direct", "direct_seconds"), ("pme", "pme_seconds")):
            ratios = []
            for accuracy in (1e-4, 1e-5, 1e-6):
                for c in timed_cases(raw, carries, accuracy):
                    model = estimates.get((carries, c["rotors"], accuracy), {}).get(key)
                    if c["method"] == method and model:
                        ratios.append(c["median_cpu_seconds"] / model)
            if ratios:
                out.append({"carries": carries, "method": method, "cases": len(ratios),
                            "geometric_mean": float(np.exp(np.mean(np.log(ratios)))),
                            "least": min(ratios), "most": max(ratios)})
    return out


def interpolated(shared: list[tuple[float, float, float]]) -> float | None:
    """The N where the two times of `(N, direct, mesh)` rows (sorted by N) cross, log-log."""
    for (n0, d0, m0), (n1, d1, m1) in zip(shared, shared[1:]):
        if (d0 - m0) * (d1 - m1) <= 0:
            g0, g1 = np.log(d0 / m0), np.log(d1 / m1)
            return float(np.exp(np.log(n0) + (np.log(n1) - np.log(n0)) * g0 / (g0 - g1)))
    return None


def section(r: dict) -> str:
    m = r["machine"]
    cases = r["quatrot"]["mesh_scaling"]
    mesh = sorted((c for c in cases if c["method"] == "pme"), key=lambda c: c["rotors"])
    direct = sorted((c for c in cases if c["method"] == "direct"), key=lambda c: c["rotors"])
    lines = [
        BEGIN,
        "## Mesh Ewald (issue 40: `benches/ewald.rs`, `python -m validation.bench.mesh`)",
        "",
        f"- Machine: {m['cpu']}, {m['cpus']} CPUs; load average {m['load_average']:.1f} when the analysis started"
        f"{' (**not idle**: absolute times are inflated, ratios measured side by side hold better)' if m['load_average'] > 0.5 * m['cpus'] else ''}. Date: {m['date']}.",
        f"- quatrot {r['quatrot']['quatrot']} (one thread), LAMMPS {r['lammps_version']} (`OMP_NUM_THREADS=1`, one MPI rank), same `make bench` run.",
        "- Configurations: jittered simple-cubic sites of unit spacing (+-0.25 per axis), random unit dipoles (module doc of `validation.bench.mesh`).",
        "- Times are process CPU times (the machine is shared: wall times follow the other jobs). quatrot: one energy + eq 14 "
        "gradient evaluation, set-up excluded (median of repeats); LAMMPS: its `run` of "
        f"{LAMMPS_STEPS} steps (pinned dipoles) less a run of none, divided by the steps.",
        "",
        "PME and direct Ewald at accuracy 1e-5:",
        "",
        "| N | sum | alpha | r_c | mesh | order | set-up s (wall) | CPU time per evaluation | CPU us per dipole |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for c in mesh + direct:
        p = c.get("parameters") or {}
        grid = "x".join(str(k) for k in p.get("grid", [])) or "-"
        lines.append(
            f"| {c['rotors']} | {c['method']} | {p.get('alpha', float('nan')):.3f} | {p.get('real_cutoff', float('nan')):.3f} | {grid} | {p.get('order', '-')} "
            f"| {c['setup_seconds']:.3g} | {c['median_cpu_seconds'] * 1e3:.4g} ms | {c['median_cpu_seconds'] / c['rotors'] * 1e6:.3g} |"
        )
    exponent = r["mesh_exponent"]
    lines += [
        "",
        f"Fitted exponent of PME's time against N (1e3 to 1e6): {exponent:.3f}; target (issue 40) at most 1.15: "
        f"{'met' if exponent <= 1.15 else 'missed'}.",
        f"Crossover N where PME becomes cheaper than the direct sum at 1e-5: {r['crossover']:.0f}." if r["crossover"] else
        "No crossover inside the sizes timed.",
        "",
        "Crossover N of the two sums measured (125 to 8,000 dipoles; 125 to 2,197 linear quadrupoles on the same sites) "
        "and priced by `method = \"auto\"`'s cost models (src/potential/multipole/auto_choice.rs), which choose the path:",
        "",
        "| sites carry | accuracy | measured | model |",
        "|---|---|---|---|",
    ]
    for c in r["crossovers"]:
        shown = [f"{c[k]:.0f}" if c[k] else "none inside the sizes" for k in ("measured", "model")]
        lines.append(f"| {c['carries']} | {c['accuracy']:g} | {shown[0]} | {shown[1]} |")
    lines += [
        "",
        "The models' calibration: measured CPU time per evaluation over the model's estimate of the same case "
        "(every size and accuracy above; the times per unit in auto_choice.rs are scaled by the geometric means when refitted):",
        "",
        "| sites carry | sum | cases | geometric mean | range |",
        "|---|---|---|---|---|",
    ]
    for c in r["calibration"]:
        lines.append(f"| {c['carries']} | {c['method']} | {c['cases']} | {c['geometric_mean']:.3f} | {c['least']:.2f} to {c['most']:.2f} |")
    lines += [
        "",
        f"10,000 dipoles (22^3 jittered sites less 648, box 22): RMS torque errors against PME at 1e-10 (RMS torque {r['side_by_side']['reference_rms_torque']:.3g}):",
        "",
        "| code | requested accuracy | CPU time per evaluation / step | RMS torque error | relative |",
        "|---|---|---|---|---|",
    ]
    for q in r["side_by_side"]["quatrot"]:
        lines.append(f"| quatrot PME | {q['accuracy']:g} | {q['median_cpu_seconds'] * 1e3:.4g} ms | {q['rms_torque_error']:.3g} | {q['relative_error']:.2g} |")
    for l in r["side_by_side"]["lammps"]:
        lines.append(
            f"| LAMMPS pppm/dipole (cutoff {LAMMPS_CUTOFF:g}) | {l['accuracy']:g} | {l['seconds_per_step'] * 1e3:.4g} ms | {l['rms_torque_error']:.3g} | {l['relative_error']:.2g} |"
        )
    lines += ["", "At the same measured accuracy (the cheapest quatrot case at least as accurate as LAMMPS's run):", ""]
    for mt in r["matched"]:
        if mt["quatrot"] is None:
            lines.append(f"- LAMMPS at {mt['lammps']['accuracy']:g}: no quatrot case timed was as accurate.")
        else:
            verdict = "met" if mt["ratio"] >= 10 else "missed"
            lines.append(
                f"- LAMMPS at {mt['lammps']['accuracy']:g} against quatrot at {mt['quatrot']['accuracy']:g}: LAMMPS / quatrot = {mt['ratio']:.3g} "
                f"(target at least 10: {verdict})."
            )
    lines.append(END)
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    args = results_md.arguments(__doc__, argv)
    raw = json.loads((args.raw / "ewald.json").read_text())
    machine = results_md.machine()
    mesh = [c for c in raw["mesh_scaling"] if c["method"] == "pme"]
    result = {
        "machine": machine,
        "quatrot": raw,
        "lammps_version": lammps_version(),
        "side_by_side": side_by_side(raw),
        "mesh_exponent": fit_exponent([c["rotors"] for c in mesh], [c["median_cpu_seconds"] for c in mesh]),
        "crossover": crossover(raw["mesh_scaling"]),
        "crossovers": crossovers(raw),
        "calibration": calibration(raw),
    }
    result["matched"] = matched(result)
    results_md.publish(args.out, "mesh", result, (BEGIN, END), section(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
