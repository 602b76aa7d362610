"""The small scenes of the Python tests that no built-in scene of `scenes/`
gives, written once here: two interacting tops (the run API's scene, as
TOML text, since the API takes text as well as dicts and paths) and a bcc
lattice of asymmetric tops whose runs feed the trajectory readers."""

from __future__ import annotations

#: Two interacting asymmetric tops carrying unit dipoles, 1.2 apart with no
#: boundary, random start at T = 1 from seed 5, 40 steps of scheme B
#: recording its energies and Q.N every 5 steps.
TWO_TOPS_TOML = """
version = 1
name = "two_tops"

[rotors]
kind = "sites"
sites = [{ position = [0.0, 0.0, 0.0] }, { position = [1.2, 0.0, 0.0] }]
default = { inertia = [0.1, 0.2, 0.3], dipole = [0.0, 0.0, 1.0] }

[interactions]
boundary = { kind = "open" }

[initial]
kind = "random"
seed = 5
temperature = 1.0

[integrator]
kind = "gear_b"

[run]
dt = 0.001
steps = 40

[[record.series]]
name = "energies"
every = 5
quantities = ["kinetic_energy", "potential_energy", "total_energy", "energy_error", "q_dot_n"]
"""


def tops_bcc(integrator: str, boundary: dict, trajectory: dict) -> dict:
    """16 asymmetric tops (inertia 0.1, 0.15, 0.2) carrying unit dipoles on a
    bcc lattice of 2 x 2 x 2 cells of 1.5, random start at T = 1 from seed
    11, 60 steps of 0.002 by `integrator` (a kind) under `boundary` (the
    `interactions.boundary` table), recording the trajectory table
    `trajectory` only."""
    return {
        "version": 1,
        "name": "tops_bcc",
        "rotors": {
            "kind": "lattice",
            "lattice": "bcc",
            "cells": 2,
            "spacing": 1.5,
            "default": {"inertia": [0.1, 0.15, 0.2], "dipole": [0.0, 0.0, 1.0]},
        },
        "interactions": {"boundary": boundary},
        "initial": {"kind": "random", "seed": 11, "temperature": 1.0},
        "integrator": {"kind": integrator},
        "run": {"dt": 0.002, "steps": 60},
        "record": {"trajectory": trajectory},
    }
