"""What scenes ask for and record, end to end through ``quatrot.run``: the
periodic boundary's default Ewald sum against the closed form of aligned
cubic dipole lattices (with the path and parameters summary.json records);
the multipole quantities (M, M2, P1 and P2 with their directors) against
scipy's rotations and numpy's eigensolver on the run's own quaternions; the
GSD trajectory read back with the gsd package; the dielectric constant of a
run (``quatrot.run_dielectric_constant``) against the ideal dipolar gas and
against the formula applied by hand to a run's files.

References: the Lorentz energy ``-(2 pi / 3) n mu^2`` per dipole of a fully
aligned sc, bcc or fcc lattice in conducting surroundings, plus
``2 pi |M|^2 / (3 V)`` in vacuum; scipy ``Rotation`` and numpy ``eigh``
(``validation/shared/output_readers.py``, sharing no code with quatrot's
observables); ``gsd.hoomd``; for the ideal dipolar gas (independent,
uniformly oriented dipoles) ``eps - 1 = 4 pi n mu^2 / (3 T)`` (conducting)
and ``Var |M|^2 = 2/3 N (N - 1) mu^4`` for its error. Passing proves that
the scene layer hands the physics the sum it names and records what the
docs define; it says nothing about the accuracy of the Ewald sum itself
beyond the closed forms (that is ``ewald_numpy``, ``ewald_openmm`` and
``ewald_lammps``)."""

from __future__ import annotations

import gsd.version
import numpy as np
import scipy

import quatrot
from validation.shared.check import Check, Context
from validation.shared.output_readers import column_differences, expected_columns, gsd_differences
from validation.shared.scene_runs import body_multipoles, variant

# Lattice sums whose absolute sum is ~20 times their total, each term
# rounded to ~1e-16, and the kinetic energy (zero) subtracted: relative.
LATTICE_ROUND_OFF = 1e-13
# The default Ewald sum is truncated at the default accuracy 1e-12 (the
# error of its fields relative to a neighbour's, so of the energy relative
# to the lattice energy); the closed form must agree to that.
DEFAULT_ACCURACY = 1e-12
# The eps of the same series with the mean temperature summed in another
# order (numpy's pairwise sum against a sequential one): round-off.
SUMMATION_ORDER = 1e-12
# Rotations and 3x3 eigen decompositions in double precision, of sums of up
# to 1000 unit-scale terms, relative to the column's scale.
DOUBLE_TOLERANCE = 1e-12
# GSD stores float32: relative rounding 6e-8 on unit-scale numbers.
FLOAT32_TOLERANCE = 3e-7
# |eps - exact| / error: two-sided normal probability 6e-5.
Z_MAX = 4.0
# The blocking error against the exact one from 20000 independent frames
# (its own scatter ~1 %); a factor 2 fails.
EPS_ERROR_TOLERANCE = 0.10
MULTIPOLE_QUANTITIES = ("M", "M2", "P1_dipole", "P2_dipole", "P2_quadrupole")


def _aligned(lattice: str, cells: int, spacing: float, boundary: dict) -> dict:
    return {
        "version": 1,
        "name": f"aligned_{lattice}",
        "rotors": {"kind": "lattice", "lattice": lattice, "cells": cells, "spacing": spacing, "default": {"inertia": 0.1, "dipole": [0.0, 0.0, 1.0]}},
        "interactions": {"boundary": boundary},
        "initial": {"kind": "uniform", "orientation": [1.0, 0.0, 0.0, 0.0], "omega_body": [0.0, 0.0, 0.0]},
        "integrator": {"kind": "dlm"},
        "run": {"dt": 0.001, "steps": 1},
        "record": {"series": [{"name": "e", "every": 1, "quantities": ["potential_energy"]}]},
    }


def _closed_forms(ctx: Context, refs: dict) -> list[Check]:
    errors = {"default": [], "tight": []}
    paths, rows = set(), []
    for lattice, per_cell, cells in (("simple_cubic", 1, 4), ("bcc", 2, 3), ("fcc", 4, 3)):
        spacing = 1.3
        n = per_cell * cells**3
        volume = (cells * spacing) ** 3
        lorentz = -(2 * np.pi / 3) * (n / volume) * n
        for kind, boundary, expected in (
            ("default", {"kind": "periodic"}, lorentz),
            ("tight", {"kind": "periodic", "sum": "ewald", "surface": "vacuum", "accuracy": 1e-14}, lorentz + 2 * np.pi * n * n / (3 * volume)),
        ):
            out = quatrot.run(_aligned(lattice, cells, spacing, boundary))
            energy = float(out["series"]["e"]["potential_energy"][0])
            errors[kind].append(abs(energy - expected) / abs(lorentz))
            recorded = out["summary"]["interactions"]
            paths.add(recorded["path"])
            rows.append(f"{lattice} {recorded['surface']} {recorded['accuracy']:g}: {errors[kind][-1]:.1e} (alpha {recorded['ewald']['alpha']:.3f}, estimated {recorded['ewald']['estimated_error']:.1e})")
    details = f"paths {sorted(paths)}; " + "; ".join(rows) + "; largest relative error."
    return [
        Check(
            "scene Ewald default vs the Lorentz energy",
            "A periodic boundary without `sum` is the Ewald sum (conducting, accuracy 1e-12): aligned sc, bcc and fcc dipole lattices run from scenes have the Lorentz energy -(2 pi/3) n mu^2 per dipole within the accuracy asked, on the path summary.json records.",
            DEFAULT_ACCURACY,
            max(errors["default"]),
            refs,
            details,
        ),
        Check(
            "scene Ewald vacuum at 1e-14 vs the closed form",
            "surface = \"vacuum\" adds 2 pi |M|^2/(3V) to the Lorentz energy, to round-off at accuracy 1e-14.",
            LATTICE_ROUND_OFF,
            max(errors["tight"]),
            refs,
            details,
        ),
    ]


def _quantities(ctx: Context, refs: dict) -> list[Check]:
    steps, every = (40, 10) if ctx.quick else (500, 10)
    checks = []
    for name, cells, quantities in (
        ("dipole_lattice_sc", 3 if ctx.quick else None, ("M", "M2", "P1_dipole", "P2_dipole")),
        ("multipole_tops_bcc", 2 if ctx.quick else None, MULTIPOLE_QUANTITIES),
    ):
        scene = variant(name, cells=cells, every=every, quantities=quantities)
        ctx.progress(f"multipole quantities: {name}, {steps} steps")
        out = quatrot.run(scene, steps=steps)
        q = out["trajectory"]["orientations"]
        mu, theta = body_multipoles(scene, q.shape[1])
        expected = expected_columns(q, mu, None if "P2_quadrupole" not in quantities else theta)
        differences = column_differences(out["series"]["samples"], expected)
        relative = {k: v / max(1.0, float(np.max(np.abs(expected[k])))) for k, v in differences.items()}
        worst = max(relative, key=relative.get)
        p2 = expected["P2_dipole"]
        checks.append(
            Check(
                f"recorded M, M2, P1, P2 vs numpy ({name})",
                "Every column of the recorded multipole quantities (total dipole, its square, polar and nematic order of the dipole axes and, for quadrupoles, of the quadrupole axes, with the directors) equals scipy's rotations and numpy's eigh on the quaternions of the same run at every sample.",
                DOUBLE_TOLERANCE,
                relative[worst],
                refs,
                f"{q.shape[1]} rotors, {q.shape[0]} samples, columns {', '.join(expected)}; P2_dipole from {p2.min():.3f} to {p2.max():.3f}; largest relative difference ({worst}).",
            )
        )
    return checks


def _gsd(ctx: Context, refs: dict) -> list[Check]:
    steps = 50 if ctx.quick else 500
    worst, rows = 0.0, []
    for label, scene, box in (
        ("periodic Ewald lattice", variant("dipole_lattice_sc", cells=3 if ctx.quick else None, every=10), np.full(3, 3.0 if ctx.quick else 10.0)),
        ("open cluster of tops", variant("multipole_tops_bcc", every=10), None),
    ):
        scene["record"]["trajectory"] = {"every": 10, "format": "gsd"}
        directory = ctx.out_dir / f"scene_outputs_gsd_{'periodic' if box is not None else 'open'}"
        out = quatrot.run(scene, steps=steps, out_dir=directory)
        d = gsd_differences(directory / "trajectory.gsd", out, box)
        exact = d["frames"] + d["step"]
        worst = max(worst, d["box"], d["position"], d["orientation"], np.inf if exact else 0.0)
        rows.append(f"{label}: {len(out['trajectory']['step'])} frames, box {d['box']:.1e}, positions {d['position']:.1e}, orientations {d['orientation']:.1e}")
    return [
        Check(
            "GSD trajectory read by gsd.hoomd vs the run",
            "A scene's format = \"gsd\" trajectory read with the gsd package has the run's frame count and steps exactly, and its box, its positions (wrapped into HOOMD's centred box) and its normalised orientation quaternions to float32 precision.",
            FLOAT32_TOLERANCE,
            float(worst),
            refs,
            "; ".join(rows) + "; largest difference relative to the box for lengths.",
        )
    ]


def _ideal_gas(ctx: Context, refs: dict) -> list[Check]:
    frames, n, mu, temperature, box = 20000, 64, 1.2, 1.5, 8.0
    rng = np.random.default_rng(ctx.seed)
    u = rng.normal(size=(frames, n, 3))
    m = mu * np.sum(u / np.linalg.norm(u, axis=-1, keepdims=True), axis=1)
    interactions = {"boundary": "periodic", "box": [box] * 3, "sum": "ewald", "accuracy": 1e-12, "surface": "conducting", "path": "ewald_direct"}
    series = {"M_x": m[:, 0], "M_y": m[:, 1], "M_z": m[:, 2], "temperature": np.full(frames, temperature)}
    eps = quatrot.run_dielectric_constant({"summary": {"interactions": interactions}, "series": {"synthetic": series}})
    scale = 4 * np.pi / (3 * box**3 * temperature)
    exact = 1 + scale * n * mu**2
    exact_error = scale * np.sqrt(2 / 3 * n * (n - 1) / frames) * mu**2
    where = f"{frames} synthetic frames of {n} independent dipoles (mu {mu}, T {temperature}, V {box**3:g}, seed {ctx.seed}): eps = {eps['epsilon']:.5f} +- {eps['error']:.5f}, exact {exact:.5f} +- {exact_error:.5f}"
    return [
        Check(
            "run eps of the ideal dipolar gas",
            "The dielectric constant of a run dict (conducting Ewald summary, box, M and temperature series) agrees with 1 + 4 pi n mu^2/(3T) within 4 of its blocking error.",
            Z_MAX,
            abs(eps["epsilon"] - exact) / eps["error"],
            refs,
            f"{where}; |z|.",
        ),
        Check(
            "run eps error of the ideal dipolar gas",
            "Its blocking error matches the exact spread of independent frames within 10 %.",
            EPS_ERROR_TOLERANCE,
            abs(eps["error"] / exact_error - 1),
            refs,
            f"{where}; |error / exact error - 1|.",
        ),
    ]


def _run_files(ctx: Context, refs: dict) -> list[Check]:
    steps = 40 if ctx.quick else 2000
    directory = ctx.out_dir / "scene_outputs_eps_run"
    scene = variant("dipole_lattice_sc", cells=3 if ctx.quick else None, every=2 if ctx.quick else 10, quantities=("M", "temperature"))
    ctx.progress(f"dielectric constant of the Ewald lattice, {steps} steps")
    out = quatrot.run(scene, steps=steps, out_dir=directory)
    from_dir = quatrot.run_dielectric_constant(directory)
    from_dict = quatrot.run_dielectric_constant(out)
    s = out["series"]["samples"]
    box = np.asarray(out["summary"]["interactions"]["box"])
    by_hand = quatrot.dielectric_constant(np.column_stack([s["M_x"], s["M_y"], s["M_z"]]), float(np.prod(box)), float(np.mean(s["temperature"])), boundary="conducting")
    same = from_dir["epsilon"] == from_dict["epsilon"] and from_dir["error"] == from_dict["error"]
    by_hand_difference = max(abs(from_dict["epsilon"] / by_hand["epsilon"] - 1), abs(from_dict["error"] / by_hand["error"] - 1))
    mismatch = by_hand_difference if same else float("inf")
    try:
        quatrot.run_dielectric_constant(quatrot.run(variant("dipole_lattice_sc_cutoff", cells=3, every=2, quantities=("M", "temperature")), steps=4))
    except ValueError as e:
        refused = 0.0 if str(e).startswith("boundary: cutoff: no fluctuation formula") else 1.0
    else:
        refused = 1.0
    return [
        Check(
            "run eps from files = from memory = the formula by hand",
            "The dielectric constant of an Ewald lattice run read from its output directory (summary.json, CSV) equals the one from quatrot.run's dict exactly, and the conducting formula applied by hand (box volume, numpy's mean of the recorded temperature) to round-off; the truncated variant of the scene is refused with the reason.",
            SUMMATION_ORDER,
            mismatch + refused,
            refs,
            f"{s['M_x'].size} samples of {out['summary']['rotors']} dipoles: eps = {from_dict['epsilon']:.4f} +- {from_dict['error']:.4f} (an NVE run of {steps} steps; a number, not a measurement of the lattice's eps); cutoff refusal {'ok' if not refused else 'MISSING'}.",
        )
    ]


def run(ctx: Context) -> list[Check]:
    ctx.out_dir.mkdir(parents=True, exist_ok=True)
    refs = {"quatrot": quatrot.__version__, "numpy": np.__version__, "scipy": scipy.__version__}
    gsd_refs = refs | {"gsd": gsd.version.version}
    return _closed_forms(ctx, refs) + _quantities(ctx, refs) + _gsd(ctx, gsd_refs) + _ideal_gas(ctx, refs) + _run_files(ctx, refs)
