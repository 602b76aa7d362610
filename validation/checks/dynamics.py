"""Dynamics of all five integrators (Allen's schemes A and B, NO_SQUISH, DLM, the Richardson update of LAMMPS) through ``quatrot.run``: free tops against exact references written here (the spherical and symmetric closed forms, scipy's DOP853 at rtol 1e-12 for the asymmetric top), the observed order of each fitted over a series of time steps, and the energy drift of each on the note's 1000-dipole lattice and on 54 asymmetric tops carrying dipoles and quadrupoles.

The references are independent of quatrot: the closed forms compose scipy
rotations; DOP853 integrates eq 10 (Hamilton product) and Euler's equations
(``validation/shared/free_top.py``). Passing proves the orientations
converge to the true motion at the expected rate and that energy is conserved
to the stated bound; it does not prove anything about interacting rotors
beyond the energy (see the OpenMM and LAMMPS modules for forces)."""

from __future__ import annotations

import numpy as np
import scipy
from scipy.spatial.transform import Rotation

import quatrot
from validation.shared.check import Check, Context
from validation.shared.free_top import integrate
from validation.shared.frames import same_rotation
from validation.shared import scene_runs
from validation.shared.scene_runs import principal_moments, variant

INTEGRATORS = ("gear_a", "gear_b", "no_squish", "dlm", "richardson")
# Global orders: Gear A and B are 5 with the consistent start-up (see
# tests/gear_references.rs); the three baselines are second-order splittings.
EXPECTED_ORDER = {"gear_a": 5.0, "gear_b": 5.0, "no_squish": 2.0, "dlm": 2.0, "richardson": 2.0}
ORDER_TOLERANCE = 0.3  # three step sizes, not exactly asymptotic: higher-order terms shift the fit
# A free spherical top is integrated exactly by the baselines' exact free
# flow: only round-off accumulated over ~1000 steps of unit-scale numbers.
EXACT_TOLERANCE = 1e-12
# The closed forms and DOP853 (rtol 1e-12, atol 1e-14) agree to ~1e-12
# over t = 10: the reference error is below every measured error used in a fit.
REFERENCE_TOLERANCE = 1e-10
# Energy conservation on the dipole lattice and the multipolar tops at the
# scenes' own dt = 0.002: the largest |E(t) - E(0)| over the run relative to the mean kinetic
# energy. 1e-3 is the usual MD criterion (energy conserved to 0.1 % of the
# kinetic energy); measured: ~1e-7 for the Gear schemes, ~3e-5 for the
# second-order baselines (their bounded fluctuation), see the details.
ENERGY_TOLERANCE = 1e-3
T_END = 10.0
# Step counts over t = 10, chosen so every error is between ~1e-3 and ~1e-11
# (asymptotic, above round-off). Scheme A reaches round-off on the spherical
# top by dt = 0.025, hence the larger steps there.
STEPS = {"spherical": (50, 100, 200), "symmetric": (200, 400, 800), "asymmetric": (200, 400, 800)}


def _free_scenes() -> dict[str, dict]:
    """Free tops: spherical and asymmetric built-ins, a symmetric variant."""
    symmetric = variant("free_asymmetric_top")
    symmetric["rotors"]["default"] = {"inertia": [1.0, 1.0, 2.5]}
    symmetric["initial"]["omega_body"] = [0.6, -0.3, 0.9]
    symmetric["initial"]["orientation"] = [0.8, 0.1, -0.3, 0.5]
    symmetric["name"] = "free_symmetric_top"
    return {
        "spherical": variant("free_spherical_top"),
        "symmetric": symmetric,
        "asymmetric": variant("free_asymmetric_top"),
    }


def spherical_reference(q0, omega_body, t):
    """Closed form: constant body angular velocity, R(t) = R(0) Rot(w_b t)."""
    r = Rotation.from_quat(q0, scalar_first=True) * Rotation.from_rotvec(np.asarray(omega_body) * t)
    return r.as_quat(scalar_first=True)


def symmetric_reference(q0, omega_body, inertia, t):
    """Closed form for I1 = I2: precession about the fixed L at |L|/I1 and spin
    about body axis 3 at w3 (1 - I3/I1): R(t) = Rot(L t/I1) R(0) Rot(e3 w3 (1 - I3/I1) t)."""
    i1, _, i3 = inertia
    r0 = Rotation.from_quat(q0, scalar_first=True)
    l_space = r0.apply(np.asarray(inertia) * omega_body)
    spin = omega_body[2] * (1.0 - i3 / i1)
    r = Rotation.from_rotvec(l_space / i1 * t) * r0 * Rotation.from_rotvec([0.0, 0.0, spin * t])
    return r.as_quat(scalar_first=True)


def dop853_reference(q0, omega_body, inertia, t):
    """scipy DOP853 at rtol 1e-12 of eq 10 and Euler's equations (any top)."""
    q, _ = integrate(inertia, q0, omega_body, np.array([0.0, t]))
    return q[-1]


def _reference(kind, scene, q0, w0, t):
    inertia = principal_moments(scene)
    if kind == "spherical":
        return spherical_reference(q0, w0, t)
    if kind == "symmetric":
        return symmetric_reference(q0, w0, inertia, t)
    return dop853_reference(q0, w0, inertia, t)


def _final_error(scene, integrator, steps, reference):
    """Sign-blind error of the final orientation after ``steps`` steps over T_END."""
    s = dict(scene, integrator={"kind": integrator}, record={"trajectory": {"every": steps}}, run={"dt": T_END / steps, "steps": steps})
    result = scene_runs.run(s)
    return same_rotation(result["trajectory"]["orientations"][-1, 0], reference)


def _fitted_order(dts, errors) -> float:
    return float(np.polyfit(np.log(dts), np.log(errors), 1)[0])


def _versions():
    return {"quatrot": quatrot.__version__, "scipy": scipy.__version__}


def _order_plot(table, out_dir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(table), figsize=(4.2 * len(table), 4), sharey=True)
    for ax, (kind, rows) in zip(np.atleast_1d(axes), table.items()):
        for integrator, (dts, errors, order) in rows.items():
            ax.loglog(dts, np.maximum(errors, 1e-16), "o-", label=f"{integrator} ({'exact' if order == 0.0 else f'order {order:.2f}'})")
        ax.set_title(f"free {kind} top, error at t = {T_END:g}")
        ax.set_xlabel("dt")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    np.atleast_1d(axes)[0].set_ylabel("global orientation error (max |Q - Q_ref|, sign-blind)")
    fig.tight_layout()
    path = out_dir / "dynamics_orders.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _energy_plot(series, out_dir):
    """One row per integrator, one column per scene: (E(t) - E(0)) / <K>."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    titles = list(series)
    integrators = list(series[titles[0]])
    fig, axes = plt.subplots(len(integrators), len(titles), figsize=(5.5 * len(titles), 1.8 * len(integrators) + 0.8), sharex="col", squeeze=False)
    for col, title in enumerate(titles):
        axes[0, col].set_title(f"(E(t) - E(0)) / <K>\n{title}", fontsize=9)
        axes[-1, col].set_xlabel("time")
        for row, integrator in enumerate(integrators):
            t, rel = series[title][integrator]
            ax = axes[row, col]
            ax.plot(t, rel, lw=0.8)
            ax.set_ylabel(integrator, fontsize=8)
            ax.grid(True, alpha=0.3)
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 2))
    fig.tight_layout()
    path = out_dir / "dynamics_energy.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def free_top_checks(ctx: Context) -> tuple[list[Check], dict]:
    """Reference sanity, exactness of the baselines on the spherical top, and fitted orders."""
    scenes = _free_scenes()
    kinds = ("spherical", "asymmetric") if ctx.quick else tuple(scenes)
    checks, table = [], {}
    for kind in kinds:
        scene = scenes[kind]
        q0 = np.asarray(scene["initial"]["orientation"], float)
        q0 = q0 / np.linalg.norm(q0)
        w0 = np.asarray(scene["initial"]["omega_body"], float)
        reference = _reference(kind, scene, q0, w0, T_END)
        if kind != "asymmetric":  # the closed form against DOP853, both independent of quatrot
            gap = same_rotation(reference, dop853_reference(q0, w0, principal_moments(scene), T_END))
            checks.append(
                Check(
                    f"free {kind} top: closed form vs scipy DOP853",
                    "The reference used below is right: two independent references of the same motion agree (it says nothing about quatrot).",
                    REFERENCE_TOLERANCE,
                    gap,
                    {"scipy": scipy.__version__},
                    f"t = {T_END:g}, q0 = {np.round(q0, 4).tolist()}, w_b = {w0.tolist()}, I = {principal_moments(scene).tolist()}.",
                )
            )
        integrators = ("gear_a", "gear_b", "dlm") if ctx.quick else INTEGRATORS
        rows = {}
        for integrator in integrators:
            ctx.progress(f"free {kind} top: {integrator}, dt series")
            steps = STEPS[kind][1:] if ctx.quick else STEPS[kind]
            errors = np.array([_final_error(scene, integrator, n, reference) for n in steps])
            dts = T_END / np.array(steps)
            exact = kind == "spherical" and integrator in ("no_squish", "dlm")
            order = float("nan") if exact else _fitted_order(dts, errors)
            rows[integrator] = (dts, errors, 0.0 if exact else order)
            detail = f"dt = {', '.join(f'{d:g}' for d in dts)}: errors {', '.join(f'{e:.3g}' for e in errors)}"
            if exact:
                checks.append(
                    Check(
                        f"free spherical top: {integrator} exact (round-off)",
                        "The baseline's exact free flow integrates a free spherical top exactly at any dt (round-off only).",
                        EXACT_TOLERANCE,
                        float(errors.max()),
                        _versions(),
                        detail + " (closed-form reference).",
                    )
                )
                continue
            expected = EXPECTED_ORDER[integrator]
            if kind == "spherical" and integrator == "gear_a":
                # Zero torque makes the w_b corrector exact; the remaining linear
                # equation Q' = 1/2 Q*(0, w_b) superconverges: assert a lower bound.
                name, measured, how = f"free spherical top: gear_a order at least {expected:g}", max(0.0, expected - order), "max(0, expected - fitted)"
            else:
                name, measured, how = f"free {kind} top: {integrator} observed order (expected {expected:g})", abs(order - expected), "|fitted - expected|"
            checks.append(
                Check(
                    name,
                    "The global error at fixed time falls as dt^p with the scheme's order p against an independent reference; "
                    "it does not bound the error at larger dt or longer times.",
                    ORDER_TOLERANCE,
                    measured,
                    _versions(),
                    f"Measured: {how} of the order; fitted order {order:.3f}. {detail}.",
                )
            )
        table[kind] = rows
    return checks, table


def _energy_scenes(quick: bool):
    """(label, scene, steps): spherical dipoles and asymmetric multipolar tops."""
    quantities = ("kinetic_energy", "total_energy")
    if quick:
        return [("27-dipole open cluster", variant("dipole_lattice_sc", cells=3, open_boundary=True, every=10, quantities=quantities), 500)]
    return [
        ("1000-dipole periodic lattice", variant("dipole_lattice_sc", every=10, quantities=quantities), 5000),
        ("54 asymmetric multipolar tops", variant("multipole_tops_bcc", every=10, quantities=quantities), 5000),
    ]


def energy_checks(ctx: Context):
    """Energy error along a run of each integrator on each energy scene."""
    integrators = ("gear_a", "gear_b", "dlm") if ctx.quick else INTEGRATORS
    checks, series = [], {}
    for label, base, steps in _energy_scenes(ctx.quick):
        base["record"].pop("trajectory")
        title = f"{label} ({base['name']}, dt = {base['run']['dt']:g})"
        series[title] = {}
        for integrator in integrators:
            ctx.progress(f"energy run: {label}, {integrator}, {steps} steps")
            result = scene_runs.run(dict(base, integrator={"kind": integrator}), steps=steps)
            samples = result["series"]["samples"]
            t, e, kinetic = samples["time"], samples["total_energy"], samples["kinetic_energy"]
            rel = (e - e[0]) / kinetic.mean()
            series[title][integrator] = (t, rel)
            fit = np.polyfit(t, rel, 1)
            checks.append(
                Check(
                    f"energy conservation: {integrator}, {label}",
                    "Total energy stays within 0.1 % of the mean kinetic energy over the run; the drift rate and fluctuation in the details "
                    "characterise the scheme but are not asserted.",
                    ENERGY_TOLERANCE,
                    float(np.abs(rel).max()),
                    {"quatrot": quatrot.__version__},
                    f"{title}, {steps} steps: max |E - E0|/<K> = {np.abs(rel).max():.3g}, fitted drift {fit[0]:.3g} per unit time, "
                    f"fluctuation (std after the fit) {np.std(rel - np.polyval(fit, t)):.3g}.",
                )
            )
    return checks, series


def run(ctx: Context) -> list[Check]:
    checks, table = free_top_checks(ctx)
    energy, series = energy_checks(ctx)
    checks += energy
    if not ctx.quick:
        ctx.out_dir.mkdir(parents=True, exist_ok=True)
        checks[-len(energy)].plots.append(_energy_plot(series, ctx.out_dir))
        order_plot = _order_plot(table, ctx.out_dir)
        for c in checks:
            if "observed order" in c.name:
                c.plots.append(order_plot)
                break
    return checks
