"""The note's correction experiment as scenes: its systems (the single
asymmetric rotor in a field and the 4 x 4 x 4 multipole lattice of
`validation.shared.gear_systems`, and the built-in 1000-dipole lattice)
and its configurations (the rows of `experiments::gear_corrections`) as
`[integrator]` tables, so that each (configuration, dt, length) is one scene
run of a sweep."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import quatrot

from validation.shared import gear_systems

#: The experiment's configurations (label -> scene `[integrator]` table), in
#: the table's order, read from the file `experiments::gear_corrections::variants`
#: reads (`src/experiments/gear_corrections.toml`): the one list.
CONFIGURATIONS_FILE = Path(__file__).resolve().parents[2] / "src" / "experiments" / "gear_corrections.toml"
CONFIGURATIONS: dict[str, dict[str, Any]] = {
    c["label"]: c["integrator"] for c in tomllib.loads(CONFIGURATIONS_FILE.read_text())["configuration"]
}

#: The baselines (second order, one torque evaluation per step), as the benchmark names them.
BASELINES: dict[str, dict[str, Any]] = {
    "NO_SQUISH": {"kind": "no_squish"},
    "DLM": {"kind": "dlm"},
    "Richardson": {"kind": "richardson"},
}

#: Symplectic schemes of `SCHEMES` (the crossover is measured against these).
SYMPLECTIC = ("NO_SQUISH", "NO_SQUISH x10", "DLM")


def _scene_of_arrays(name: str, arrays: dict, options: dict) -> dict[str, Any]:
    """A scene dict of pinned rotors given as the experiment's arrays."""
    n = len(arrays["sites"])
    sites = []
    for i in range(n):
        inertia = arrays["inertia"][i]
        site = {"position": [float(x) for x in arrays["sites"][i]]}
        site["inertia"] = float(inertia[0]) if np.all(inertia == inertia[0]) else [float(x) for x in inertia]
        if "dipoles" in options:
            site["dipole"] = [float(x) for x in options["dipoles"][i]]
        if "quadrupoles" in options:
            site["quadrupole"] = [[float(x) for x in row] for row in options["quadrupoles"][i]]
        sites.append(site)
    scene: dict[str, Any] = {
        "version": 1,
        "name": name,
        "rotors": {"kind": "sites", "sites": sites},
        "initial": {
            "kind": "explicit",
            "orientations": [[float(x) for x in q] for q in arrays["orientations"]],
            "omega_body": [[float(x) for x in w] for w in arrays["omega_body"]],
        },
        "integrator": {"kind": "gear_a"},
        "run": {"dt": float(options["dt"]), "steps": 1},
    }
    if "field" in options:
        scene["fields"] = {"uniform": [float(x) for x in options["field"]]}
    if "box_lengths" in options:
        scene["interactions"] = {
            "boundary": {"kind": "periodic", "cutoff": float(options["cutoff"]), "box": [float(x) for x in options["box_lengths"]]}
        }
    return scene


def rotor_in_field() -> dict[str, Any]:
    """The experiment's single asymmetric top with a dipole in a uniform field (dt 0.05)."""
    arrays, options = gear_systems.rotor_in_field(quick=True)
    return _scene_of_arrays("rotor_in_field", arrays, options)


def multipole_lattice(seed: int) -> dict[str, Any]:
    """The experiment's periodic 4 x 4 x 4 lattice of dipolar and quadrupolar
    tops (64 rotors, cutoff 2, T = 0.5 from `seed`; dt 0.01)."""
    arrays, options = gear_systems.lattice(seed)
    return _scene_of_arrays("multipole_lattice_4x4x4", arrays, options)


def dipole_lattice() -> dict[str, Any]:
    """The built-in 1000-dipole simple-cubic lattice (cutoff 3.1, T = 1, dt 0.002), without its outputs."""
    scene = tomllib.loads(quatrot.builtin_scenes()["dipole_lattice_sc_cutoff"])
    scene.pop("record", None)
    return scene


#: Every scheme of the benchmark, in its plotting order and with its labels
#: (`benches/performance/schemes.rs`, whose work-precision scan stays in Rust).
BENCH_SCHEMES: dict[str, dict[str, Any]] = {
    "A": CONFIGURATIONS["A (renormalised)"],
    "B": CONFIGURATIONS["B, torque + velocity + renormalisation"],
    "B c0=3/20": CONFIGURATIONS["B, all, c0 = 3/20"],
    "B +higher": CONFIGURATIONS["B, all + higher derivatives"],
    "B bare": CONFIGURATIONS["B, no correction"],
    "NO_SQUISH": BASELINES["NO_SQUISH"],
    "NO_SQUISH x10": {"kind": "no_squish", "substeps": 10},
    "DLM": BASELINES["DLM"],
    "Richardson": BASELINES["Richardson"],
}

#: The schemes of the accuracy comparison: the Gear schemes that have a
#: stable step (`GEAR`) and the baselines.
SCHEMES: dict[str, dict[str, Any]] = {k: v for k, v in BENCH_SCHEMES.items() if k not in ("B c0=3/20", "B bare")}

#: Gear schemes (fifth order, not symplectic) of `SCHEMES`.
GEAR = ("A", "B", "B +higher")
