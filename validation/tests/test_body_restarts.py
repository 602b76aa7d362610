"""Restarts and blow-ups of runs of moving bodies from Python (issue 39,
item 6 and its Bad input paragraph): a restart of a run recording a GSD
trajectory writes, in its new folder, frames equal to the uninterrupted
run's (read back with the gsd package); a blow-up raises BlowUpError
naming the step, the bodies and their sites."""

import re
import tomllib

import gsd.hoomd
import numpy as np
import pytest

import quatrot

# Every array a frame of bodies holds.
FRAME_ARRAYS = ("position", "orientation", "velocity", "angmom", "image")


def fluid(steps: int, **record) -> dict:
    """The built-in Stockmayer fluid for `steps` steps, with its record
    section replaced by `record`."""
    scene = tomllib.loads(quatrot.builtin_scenes()["stockmayer_fluid"])
    scene["run"]["steps"] = steps
    scene["record"] = record
    return scene


@pytest.mark.parametrize("integrator", ["dlm", "gear_a"])
def test_a_restarted_trajectory_has_the_frames_of_the_uninterrupted_run(tmp_path, integrator):
    """Frames at steps 20 and 30 of a run restarted at step 20 (a new
    folder: a GSD file is never appended to) hold the arrays of the frames
    at those steps of one run of 30 steps, to the last bit of their float32."""
    record = {"checkpoint_every": 10, "trajectory": {"every": 10, "format": "gsd"}}
    full, split = tmp_path / "full", tmp_path / "split"
    quatrot.run(fluid(30, **record), out_dir=str(full), integrator=integrator)
    quatrot.run(fluid(20, **record), out_dir=str(split), integrator=integrator)
    result = quatrot.run(
        fluid(30, **record), out_dir=str(split), integrator=integrator, restart=str(split / "checkpoint.json")
    )
    assert result["summary"]["outputs"] == "new_folder"
    with gsd.hoomd.open(full / "trajectory.gsd") as whole, gsd.hoomd.open(
        split / "restart-20" / "trajectory.gsd"
    ) as rest:
        assert [f.configuration.step for f in rest] == [20, 30]
        by_step = {f.configuration.step: f for f in whole}
        for frame in rest:
            reference = by_step[frame.configuration.step]
            for name in FRAME_ARRAYS:
                np.testing.assert_array_equal(
                    getattr(frame.particles, name), getattr(reference.particles, name), err_msg=name
                )


def test_a_blow_up_of_bodies_raises_naming_the_step_and_the_bodies(tmp_path):
    """A time step 25 times the built-in's, checked every step, blows up: the
    error names the step, the two bodies and their sites, and its result's
    summary records the same message."""
    scene = fluid(400, check_every=1)
    with pytest.raises(quatrot.BlowUpError) as raised:
        quatrot.run(scene, dt=0.05, out_dir=str(tmp_path))
    message = str(raised.value)
    pattern = (
        r"blew up at step (\d+), body (\d+): site 0 of body \2 and site 0 of body (\d+) are [0-9.]+ apart, "
        r"[0-9.]+ of their sigma 1 \(below 0\.5: far inside their repulsive core\)"
    )
    assert re.fullmatch(pattern, message), message
    assert raised.value.result["summary"]["status"] == "blew_up"
    assert raised.value.result["summary"]["message"] == message
