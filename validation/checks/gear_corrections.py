"""The note's experiment: scheme A against scheme B with each of its
corrections, for a single asymmetric rotor in a uniform field and
(full mode) a periodic 4 x 4 x 4 simple-cubic lattice of dipolar and
quadrupolar rotors. The table comes from ``quatrot.gear_corrections_table``
(Rust: ``experiments::gear_corrections``); this module writes it as
``gear_corrections.md`` and turns the note's two claims into checks with
verdicts:

1. scheme B "only becomes competitive (as far as energy conservation is
   concerned) when the corrections are incorporated";
2. "merely correcting the torque is itself insufficient: Q' must be made
   orthogonal to Q".
"""

from __future__ import annotations

import numpy as np

import quatrot
from validation.shared.check import Check, Context
from validation.shared.gear_systems import lattice, rotor_in_field

EXPECTED_ORDER = 5.0  # both schemes: see tests/gear_references.rs
ORDER_TOLERANCE = 0.3  # an order observed over a factor 4 in dt carries higher-order terms
COMPETITIVE_FACTOR = 10.0  # "competitive": energy drift within 10x of scheme A's
ROUNDING = 1e-12  # |Q.Q'| at rounding level (|Q|, |Q'| ~ 1)

LABEL_A = "A (renormalised)"
LABEL_NONE = "B, no correction"
LABEL_TORQUE = "B, torque only"
LABEL_FULL = "B, torque + velocity + renormalisation"


def markdown(title: str, rows: list[dict]) -> str:
    def fmt(x):
        return "-" if x is None else f"{x:.3g}"

    lines = [
        f"### {title}",
        "",
        "| configuration | drift / <K> per unit time | fluctuation / <K> | global error (rad) | order | largest stable dt | max abs Q.Q' | max abs Q.N |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['label']} | {fmt(r['drift'])} | {fmt(r['fluctuation'])} | {fmt(r['global_error'])} | {fmt(r['order'])} "
            f"| {fmt(r['largest_stable_dt'])} | {fmt(r['max_q_dot_q_dot'])} | {fmt(r['max_q_dot_force'])} |"
        )
    return "\n".join(lines) + "\n"


def checks_for(system: str, rows: list[dict], dt: float) -> list[Check]:
    by = {r["label"]: r for r in rows}
    a, none, torque, full = by[LABEL_A], by[LABEL_NONE], by[LABEL_TORQUE], by[LABEL_FULL]
    refs = {"quatrot experiments::gear_corrections": quatrot.__version__}
    drift_ratio = abs(full["drift"]) / max(abs(a["drift"]), 1e-300)
    torque_ratio = abs(torque["drift"]) / max(abs(full["drift"]), 1e-300)
    claim2 = (
        "holds" if torque_ratio > COMPETITIVE_FACTOR else "does not hold for the energy over this run"
    ) + (
        f": torque-only drift is {torque_ratio:.3g}x the fully corrected drift, while |Q.Q'| grows to "
        f"{torque['max_q_dot_q_dot']:.2e} (velocity projection: {full['max_q_dot_q_dot']:.2e})"
    )
    none_stable = none["largest_stable_dt"]
    claim1 = (
        f"without any correction B has {'no stable step' if none_stable is None else f'largest stable dt {none_stable:.3g}'}"
        f" (|Q.N| up to {none['max_q_dot_force']:.2e}); with both corrections its drift is {drift_ratio:.3g}x scheme A's"
    )
    return [
        Check(
            name=f"gear corrections {system}: scheme A order",
            proves=f"scheme A converges at the expected order {EXPECTED_ORDER} on this system (not its error constant)",
            tolerance=ORDER_TOLERANCE,
            measured=abs(a["order"] - EXPECTED_ORDER),
            references=refs,
            details=f"observed order {a['order']:.3f} from dt = {dt} and {dt / 4} (the least-squares slope over dt, dt/2, dt/4)",
        ),
        Check(
            name=f"gear corrections {system}: scheme B order",
            proves=f"scheme B with the note's corrections converges at order {EXPECTED_ORDER}",
            tolerance=ORDER_TOLERANCE,
            measured=abs(full["order"] - EXPECTED_ORDER),
            references=refs,
            details=f"observed order {full['order']:.3f}",
        ),
        Check(
            name=f"gear corrections {system}: claim 1 (B competitive with corrections)",
            proves="with torque and velocity projections and renormalisation, B's energy drift is within "
            f"{COMPETITIVE_FACTOR}x of A's; the details state what happens without them",
            tolerance=COMPETITIVE_FACTOR,
            measured=drift_ratio,
            references=refs,
            details="verdict: " + claim1,
        ),
        Check(
            name=f"gear corrections {system}: claim 2 (velocity projection)",
            proves="the velocity projection keeps Q.Q' at rounding level; the details give the verdict on "
            "whether the torque projection alone is insufficient",
            tolerance=ROUNDING,
            measured=full["max_q_dot_q_dot"],
            references=refs,
            details="verdict: " + claim2,
        ),
    ]


def plot(tables: list[tuple[str, list[dict]]], out_dir) -> "Path":
    """Per system, one bar per configuration: |energy drift| / <K> per unit
    time, global error and max |Q.Q'|; unstable configurations are marked."""
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    columns = [("drift", "|energy drift| / <K> per unit time"), ("global_error", "global error (rad)"), ("max_q_dot_q_dot", "max |Q.Q'|")]
    fig, axes = plt.subplots(len(tables), len(columns), figsize=(14, 3.6 * len(tables)), squeeze=False)
    for row_axes, (system, rows) in zip(axes, tables):
        labels = [r["label"] for r in rows]
        for ax, (key, title) in zip(row_axes, columns):
            values = [abs(r[key]) if r[key] is not None and np.isfinite(r[key]) else np.nan for r in rows]
            finite = [v for v in values if np.isfinite(v) and v > 0]
            floor = min(finite) / 10 if finite else 1e-16
            bars = [v if np.isfinite(v) and v > 0 else floor for v in values]
            colors = ["tab:red" if not np.isfinite(v) else ("tab:blue" if r["label"] == LABEL_A else "tab:green") for v, r in zip(values, rows)]
            ax.barh(range(len(rows)), bars, color=colors)
            ax.set_xscale("log")
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_yticks(range(len(rows)))
            ax.set_yticklabels(labels if ax is row_axes[0] else [], fontsize=7)
            ax.invert_yaxis()
            ax.set_title(f"{system}: {title}", fontsize=8)
    fig.text(0.01, 0.005, "red: not finite (unstable); blue: scheme A; green: scheme B variants", fontsize=7)
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    path = out_dir / "gear_corrections.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def run(ctx: Context) -> list[Check]:
    systems = [("rotor in field", *rotor_in_field(ctx.quick))]
    if not ctx.quick:
        systems.append(("4x4x4 multipole lattice", *lattice(ctx.seed)))
    checks, tables = [], []
    report = ["# Scheme A against scheme B and its corrections\n"]
    for name, arrays, options in systems:
        rows = quatrot.gear_corrections_table(**arrays, **options)
        report.append(markdown(name, rows))
        checks += checks_for(name, rows, options["dt"])
        tables.append((name, rows))
    ctx.out_dir.mkdir(parents=True, exist_ok=True)
    (ctx.out_dir / "gear_corrections.md").write_text("\n".join(report))
    if not ctx.quick:
        checks[0].plots.append(plot(tables, ctx.out_dir))
    return checks
