"""Issue 19 in Python: Ctrl-C stops `quatrot.run` promptly at the end of a
step and raises KeyboardInterrupt with the partial result reachable; sizes
decided by arguments are refused with a ValueError before allocation (not a
PanicException or an abort)."""

import _thread
import json
import signal
import threading
import time
import tomllib

import numpy as np
import pytest

import quatrot

# A run of the 1000-rotor lattice of 1e7 steps takes hours; Ctrl-C must end it
# within this many seconds (the poll is 20 ms, a step about 1 ms).
PROMPT_SECONDS = 30.0


@pytest.fixture
def ctrl_c_handled():
    """Python's own Ctrl-C handler for the test: a shell's background job
    (a suite started with `&` or nohup) inherits SIGINT ignored, where
    interrupt_main does nothing and the 1e7-step run would go on for hours."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_ctrl_c_stops_the_run_and_keeps_the_partial_result(tmp_path, ctrl_c_handled):
    scene = tomllib.loads(quatrot.builtin_scenes()["dipole_lattice_sc"])
    del scene["record"]["trajectory"]
    steps = 10**7
    timer = threading.Timer(1.0, _thread.interrupt_main)
    timer.start()
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt) as caught:
        quatrot.run(scene, steps=steps, out_dir=str(tmp_path))
    elapsed = time.monotonic() - started
    timer.cancel()
    assert elapsed < PROMPT_SECONDS
    result = caught.value.result
    assert result["summary"]["status"] == "interrupted"
    last = result["summary"]["last_step"]
    assert 0 < last < steps
    energies = result["series"]["energies"]
    assert energies["step"][-1] <= last
    on_disk = json.loads((tmp_path / "summary.json").read_text())
    assert on_disk["status"] == "interrupted"
    assert (tmp_path / "energies.csv").read_text().endswith("\n")


def test_dlm_dipoles_refuses_a_step_count_too_large_for_memory():
    args = dict(
        sites=np.zeros((1, 3)),
        dipoles_body=np.array([[0.0, 0.0, 1.0]]),
        inertia=np.array([0.1]),
        orientations=np.array([[1.0, 0.0, 0.0, 0.0]]),
        omega_body=np.array([[0.3, -0.2, 0.5]]),
        field=None,
        dt=0.01,
        split=False,
    )
    for steps in (2**64 - 1, 10**12):
        with pytest.raises(ValueError, match="steps: needs about"):
            quatrot.dlm_dipoles(steps=steps, **args)
