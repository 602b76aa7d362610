"""`quatrot.run` accepts a dict, TOML text, a path or a built-in name, gives
the same results for the same scene in every form, and raises exceptions
that name the field."""

import importlib
import threading
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest
import quatrot

from small_scenes import TWO_TOPS_TOML


def test_dict_toml_and_path_give_identical_runs(tmp_path: Path):
    path = tmp_path / "two_tops.toml"
    path.write_text(TWO_TOPS_TOML)
    runs = [
        quatrot.run(TWO_TOPS_TOML),
        quatrot.run(tomllib.loads(TWO_TOPS_TOML)),
        quatrot.run(path),
        quatrot.run(str(path)),
    ]
    first = runs[0]["series"]["energies"]
    assert list(first) == ["step", "time", "kinetic_energy", "potential_energy", "total_energy", "energy_error", "q_dot_n"]
    np.testing.assert_array_equal(first["step"], np.arange(0, 41, 5))
    for other in runs[1:]:
        for column, values in first.items():
            np.testing.assert_array_equal(other["series"]["energies"][column], values)
    assert runs[0]["summary"]["seed"] == 5
    assert runs[0]["summary"]["status"] == "completed"


def test_numpy_values_in_a_dict_are_accepted():
    scene = tomllib.loads(TWO_TOPS_TOML)
    scene["rotors"]["default"]["inertia"] = np.array([0.1, 0.2, 0.3])
    scene["run"]["steps"] = np.int64(40)
    a = quatrot.run(scene)["series"]["energies"]["total_energy"]
    b = quatrot.run(TWO_TOPS_TOML)["series"]["energies"]["total_energy"]
    np.testing.assert_array_equal(a, b)


def test_overrides_replace_the_scene_values():
    r = quatrot.run("dipole_in_field", steps=10, dt=0.002, integrator="dlm")
    assert r["summary"]["last_step"] == 10
    assert r["summary"]["dt"] == 0.002
    assert r["summary"]["integrator"] == "dlm"


def test_no_thermostat_drops_the_scenes_thermostat():
    """The Langevin lattice held at T runs gear_b (which takes no
    thermostat) once the thermostat is dropped, and then keeps its energy
    as the same scene written without a thermostat does, bit for bit."""
    with pytest.raises(quatrot.SceneError, match="gear_b"):
        quatrot.run("dipole_lattice_sc_langevin", steps=2, integrator="gear_b")
    r = quatrot.run("dipole_lattice_sc_langevin", steps=20, integrator="gear_b", no_thermostat=True)
    assert "thermostat" not in r["summary"]["definition"]
    scene = tomllib.loads(quatrot.builtin_scenes()["dipole_lattice_sc_langevin"])
    del scene["thermostat"]
    plain = quatrot.run(scene, steps=20, integrator="gear_b")
    for name, series in r["series"].items():
        for column, values in series.items():
            np.testing.assert_array_equal(values, plain["series"][name][column])


def test_every_builtin_runs_from_python():
    for name in quatrot.builtin_scenes():
        r = quatrot.run(name, steps=3)
        assert r["summary"]["status"] == "completed", name
        assert r["summary"]["last_step"] == 3, name


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda s: s["run"].update(dt=0.0), "run.dt: must be > 0, got 0"),
        (lambda s: s["rotors"]["default"].update(inertia=[0.1, -1.0, 0.3]), "rotors.default.inertia[1]: must be > 0, got -1"),
        (lambda s: s["integrator"].update(kind="leapfrog"), "integrator.kind: unknown variant `leapfrog`"),
        (lambda s: s["initial"].update(seed=None), "initial.seed: None is not allowed (leave the key out)"),
        (lambda s: s.update(colour="red"), "colour: unknown field `colour`"),
        (lambda s: s["rotors"].update(sites=[]), "rotors.sites: must list at least one site (empty system)"),
    ],
)
def test_dict_errors_name_the_field(change, message):
    scene = tomllib.loads(TWO_TOPS_TOML)
    change(scene)
    with pytest.raises(quatrot.SceneError) as info:
        quatrot.run(scene)
    assert str(info.value).startswith(message)
    assert isinstance(info.value, ValueError)


def test_text_and_name_errors():
    with pytest.raises(quatrot.SceneError, match=r"^run\.dt: must be finite, got inf$"):
        quatrot.run(TWO_TOPS_TOML.replace("dt = 0.001", "dt = inf"))
    with pytest.raises(quatrot.SceneError, match=r"^syntax: line \d+, column \d+"):
        quatrot.run(TWO_TOPS_TOML.replace("steps = 40", "steps = = 40"))
    with pytest.raises(quatrot.SceneError, match="no built-in scene or file named `no_such_scene`"):
        quatrot.run("no_such_scene")
    with pytest.raises(quatrot.SceneError, match=r"^run\.steps: must be >= 1, got 0$"):
        quatrot.run(TWO_TOPS_TOML, steps=0)
    # The scene records Q.N, which only scheme B stores.
    with pytest.raises(quatrot.SceneError, match=r"^record\.series\[0\]\.quantities\[4\]: q_dot_n needs"):
        quatrot.run(TWO_TOPS_TOML, integrator="dlm")


def test_blow_up_raises_with_the_partial_result():
    scene = tomllib.loads(quatrot.builtin_scenes()["dipole_in_field"])
    scene["record"] = {
        "energy_error_threshold": 1e-3,
        "check_every": 1,
        "series": [{"every": 1, "quantities": ["energy_error"]}],
    }
    with pytest.raises(quatrot.BlowUpError, match=r"^blew up at step (\d+), rotor 0: energy error") as info:
        quatrot.run(scene, dt=0.2, integrator="gear_a")
    errors = info.value.result["series"]["observables"]["energy_error"]
    # Every recorded error but the last is within the threshold; the last is above it.
    assert np.all(np.abs(errors[:-1]) <= 1e-3) and abs(errors[-1]) > 1e-3
    assert info.value.result["summary"]["status"] == "blew_up"


def test_the_gil_is_released_during_a_run():
    """Another Python thread keeps running while `run` works."""
    ticks = []
    done = threading.Event()

    def work():
        quatrot.run("dipole_lattice_sc", steps=200)
        done.set()

    worker = threading.Thread(target=work)
    worker.start()
    while not done.is_set():
        ticks.append(1)
        time.sleep(0.001)
    worker.join()
    # With the GIL held for the whole run this loop could not tick in between.
    assert len(ticks) > 10


def test_restart_from_a_checkpoint_continues_exactly(tmp_path: Path):
    """Steps 0-40 in one go, and 0-20 then a restart to 40, end bit for bit
    in the same state (the checkpoint stores the integrator's float bits)."""
    scene = tomllib.loads(TWO_TOPS_TOML)
    scene["record"]["checkpoint_every"] = 20
    scene["record"]["trajectory"] = {"every": 20}
    full = quatrot.run(scene, steps=40)
    quatrot.run(scene, steps=20, out_dir=tmp_path)
    rest = quatrot.run(scene, steps=40, restart=tmp_path / "checkpoint.json")
    np.testing.assert_array_equal(rest["trajectory"]["orientations"][-1], full["trajectory"]["orientations"][-1])
    np.testing.assert_array_equal(rest["series"]["energies"]["total_energy"], full["series"]["energies"]["total_energy"][4:])
    assert rest["summary"]["start_step"] == 20


def test_threads_fixes_the_pool_of_a_run():
    """The half-list pair loop of the quadrupole lattice sums its per-thread
    blocks in an order that depends on the thread count: `threads=1` gives
    the same bits every time (here on the 2-core machine, whose shared pool
    has 2 threads), `threads=2` other last bits. Should the kernel become
    independent of the thread count, the second assertion fails and the
    sweep may stop keying finished runs by their thread count. A given
    count is honoured exactly and recorded in the summary."""
    scene = tomllib.loads(quatrot.builtin_scenes()["quadrupole_lattice_fcc"])
    scene["record"] = {"series": [{"every": 1, "quantities": ["total_energy"]}]}
    energy = {t: quatrot.run(scene, steps=5, threads=t)["series"]["observables"]["total_energy"] for t in (1, 2)}
    np.testing.assert_array_equal(quatrot.run(scene, steps=5, threads=1)["series"]["observables"]["total_energy"], energy[1])
    assert not np.array_equal(energy[1], energy[2])
    np.testing.assert_allclose(energy[1], energy[2], rtol=1e-12)
    assert quatrot.run(scene, steps=1, threads=3)["summary"]["threads"] == {
        "count": 3,
        "chosen": "given",
        "reason": "3 threads given",
    }
    for bad in (0, -1):
        with pytest.raises(ValueError, match=rf"^threads: must be between 1 and 1024, got {bad}$"):
            quatrot.run("dipole_in_field", threads=bad)


def test_a_dict_scene_fixes_its_threads_unless_threads_is_given(monkeypatch: pytest.MonkeyPatch):
    """A dict's `run.threads` (an int, numpy's too, or "auto") sizes the run
    and is recorded as the scene's choice; `threads=` overrides it; a bad
    value is refused naming the field."""
    scene = tomllib.loads(TWO_TOPS_TOML)
    scene["run"]["threads"] = np.int64(3)
    assert quatrot.run(scene, steps=1)["summary"]["threads"] == {
        "count": 3,
        "chosen": "scene",
        "reason": "run.threads = 3 in the scene",
    }
    assert quatrot.run(scene, steps=1, threads=2)["summary"]["threads"]["chosen"] == "given"
    monkeypatch.delenv("RAYON_NUM_THREADS", raising=False)
    scene["run"]["threads"] = "auto"
    assert quatrot.run(scene, steps=1)["summary"]["threads"]["chosen"] == "automatic"
    for bad, shown in ((0, "0"), (2.5, "2.5"), ("all", '"all"'), (1025, "1025")):
        scene["run"]["threads"] = bad
        with pytest.raises(ValueError, match=rf'^run\.threads: must be an integer between 1 and 1024 or "auto", got {shown}$'):
            quatrot.run(scene, steps=1)


def test_the_package_reexports_every_native_name():
    """`quatrot` is the pure-Python package around the extension
    `quatrot._native`: each of the extension's public names is the
    package's (its private `_panic_for_tests` is not exported)."""
    from quatrot import _native

    public = [name for name in _native.__all__ if not name.startswith("_")]
    assert public and set(public) <= set(quatrot.__all__)
    assert "_panic_for_tests" not in quatrot.__all__
    for name in public:
        assert getattr(quatrot, name) is getattr(_native, name), name
    assert importlib.import_module("quatrot.quaternion") is _native.quaternion is quatrot.quaternion
    assert quatrot.SceneError.__module__ == "quatrot"
