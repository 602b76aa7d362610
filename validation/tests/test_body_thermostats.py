"""Thermostats on moving bodies (issue 39, item 4) from Python: both built-in
scenes of bodies run with each thermostat and each integrator that carries
it, writing T_trans, T_rot and the conserved energy (total energy plus the
thermostat's share); the pairs bodies cannot run are refused naming
thermostat.kind."""

import tomllib

import numpy as np
import pytest

import quatrot

BODY_SCENES = ["stockmayer_fluid", "lewis_wahnstrom_otp"]
THERMOSTATS = {
    "langevin": {"kind": "langevin", "temperature": 1.0, "friction": 2.0, "seed": 5},
    "bussi": {"kind": "bussi", "temperature": 1.0, "tau": 0.05, "seed": 5},
    "nose_hoover": {"kind": "nose_hoover", "temperature": 1.0, "tau": 0.1},
}
STEPS = 20


def short_run(name: str, integrator: str, thermostat: dict) -> dict:
    """The built-in `name` with `integrator` and `thermostat`, STEPS steps,
    a series of energies and temperatures every 5 steps, no trajectory."""
    scene = tomllib.loads(quatrot.builtin_scenes()[name])
    scene["integrator"] = {"kind": integrator}
    scene["thermostat"] = thermostat
    scene["run"] = {"dt": scene["run"]["dt"], "steps": STEPS}
    scene["record"] = {
        "series": [
            {
                "name": "series",
                "every": 5,
                "quantities": ["total_energy", "conserved_energy", "T_trans", "T_rot"],
            }
        ]
    }
    return scene


@pytest.mark.parametrize("integrator", ["no_squish", "dlm"])
@pytest.mark.parametrize("thermostat", sorted(THERMOSTATS))
@pytest.mark.parametrize("name", BODY_SCENES)
def test_body_builtins_run_with_every_thermostat(name, thermostat, integrator):
    """Every sample has finite, positive temperatures of both kinds; the
    conserved energy starts at the total energy (the thermostat has done
    nothing yet) and then differs from it (the thermostat has exchanged
    energy with the bodies); a stochastic thermostat's seed is recorded."""
    result = quatrot.run(short_run(name, integrator, THERMOSTATS[thermostat]))
    series = result["series"]["series"]
    assert list(series["step"]) == [0, 5, 10, 15, 20]
    for column in ("T_trans", "T_rot"):
        assert np.all(np.isfinite(series[column])) and np.all(series[column] > 0), column
    total, conserved = series["total_energy"], series["conserved_energy"]
    assert conserved[0] == total[0]
    assert np.all(conserved[1:] != total[1:])
    assert result["summary"].get("thermostat_seed") == THERMOSTATS[thermostat].get("seed")


@pytest.mark.parametrize(
    "integrator, thermostat, message",
    [
        ("gear_b", "nose_hoover", '"nose_hoover" cannot run with integrator gear_b for bodies'),
        ("gear_b", "bussi", '"bussi" cannot run with integrator gear_b for bodies'),
        ("richardson", "langevin", '"langevin" cannot run with integrator richardson for bodies'),
    ],
)
def test_pairs_bodies_cannot_run_are_refused(integrator, thermostat, message):
    """The pairs refused for bodies name thermostat.kind, as for rotors."""
    scene = short_run("stockmayer_fluid", integrator, THERMOSTATS[thermostat])
    with pytest.raises(ValueError, match="thermostat.kind") as error:
        quatrot.run(scene)
    assert message in str(error.value)
