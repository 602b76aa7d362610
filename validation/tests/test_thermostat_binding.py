"""Canonical runs from Python: the canonical built-in runs through
`quatrot.run` with its conserved energy and thermostat seed; a thermostat
given in a dict reproduces bit for bit from its seed; its bad options and an
integrator that cannot carry it raise `quatrot.SceneError` naming the field."""

import tomllib

import numpy as np
import pytest
import quatrot


def canonical(steps: int = 200) -> dict:
    scene = tomllib.loads(quatrot.builtin_scenes()["dipole_lattice_sc_langevin"])
    scene["rotors"]["cells"] = 4
    scene["run"]["steps"] = steps
    scene.pop("record")
    scene["record"] = {"series": [{"name": "e", "every": 10, "quantities": ["total_energy", "conserved_energy", "temperature"]}]}
    return scene


def test_canonical_builtin_runs_from_python():
    result = quatrot.run("dipole_lattice_sc_langevin", steps=20)
    summary = result["summary"]
    assert summary["thermostat_seed"] == 1  # the seed of its random [initial]
    assert summary["definition"]["thermostat"] == {"kind": "langevin", "temperature": 1.0, "friction": 1.0}
    energies = summary["final_energies"]
    assert energies["conserved"] != energies["total"]
    e = result["series"]["energies"]
    assert np.all(np.isfinite(e["conserved_energy"]))


def test_thermostat_in_a_dict_reproduces_from_its_seed():
    scene = canonical()
    scene["thermostat"] = {"kind": "bussi", "temperature": 1.0, "tau": 0.1, "seed": 42}
    a = quatrot.run(scene)["series"]["e"]
    b = quatrot.run(scene)["series"]["e"]
    assert all(np.array_equal(a[k], b[k]) for k in a)
    scene["thermostat"]["seed"] = 43
    c = quatrot.run(scene)["series"]["e"]
    assert not np.array_equal(a["total_energy"], c["total_energy"])
    # The conserved energy moves far less than the total energy.
    assert np.ptp(a["conserved_energy"]) < 0.01 * np.ptp(a["total_energy"])


@pytest.mark.parametrize(
    ("thermostat", "integrator", "message"),
    [
        ({"kind": "langevin", "temperature": 1.0, "friction": 0.0}, "dlm", "thermostat.friction: must be > 0, got 0"),
        ({"kind": "nose_hoover", "temperature": 1.0, "tau": 0.5, "chain": 0}, "dlm", "thermostat.chain: must be >= 1, got 0"),
        (
            {"kind": "bussi", "temperature": 1.0, "tau": 0.1},
            "gear_b",
            'thermostat.kind: "bussi" cannot run with integrator gear_b (scheme B has no angular momenta to thermostat); use no_squish or dlm',
        ),
    ],
)
def test_bad_thermostats_name_the_field(thermostat, integrator, message):
    scene = canonical(10)
    scene["thermostat"] = thermostat
    scene["integrator"] = {"kind": integrator}
    with pytest.raises(quatrot.SceneError) as error:
        quatrot.run(scene)
    assert str(error.value) == message
