"""The rigid-water verdicts' bookkeeping (validation.bench.water): a run
that reached its last sample is complete whatever the time step. At 3 fs a
run of 10 ps takes round(10000 / 3) = 3,333 steps sampled every round(20 /
3) = 7, so its last sample is step 3,332, 9,996 fs: the bench once called
every such run unstable because it asked for a sample at 10,000 fs (seen
in session 36 on all five integrators)."""

import math

import numpy as np
import pytest

from validation.bench import water
from validation.shared import water_box_runs as runs


def found(times_fs, failed_at=math.nan):
    """A run's record with its energy off by 2 kcal/mol per molecule after the
    first sample: unstable, so measure stops after the completeness."""
    total = np.full(len(times_fs), 2.0 * water.STABLE_MOVE)
    total[0] = 0.0
    return {"time_ps": np.asarray(times_fs) / 1000, "total_per_molecule": total,
            "failed_at_fs": failed_at, "cpu_seconds": 1.0}


def test_the_last_sample_at_3_fs_is_step_3332():
    samples = runs.sample_steps(3.0, 10000.0, water.SAMPLE_FS)
    assert (samples.step, samples[-1], len(samples)) == (7, 3332, 477)


@pytest.mark.parametrize("dt", water.STEPS_FS)
def test_a_run_to_its_last_sample_is_complete_and_one_short_of_it_is_not(dt):
    times = [step * dt for step in runs.sample_steps(dt, 10000.0, water.SAMPLE_FS)]
    measured = water.measure(found(times), 30.0, 10000.0, dt)
    assert measured["completed"]
    assert not water.measure(found(times[:-1]), 30.0, 10000.0, dt)["completed"]
    assert not water.measure(found(times, failed_at=times[-1]), 30.0, 10000.0, dt)["completed"]


def test_the_3_fs_run_ends_at_9996_fs():
    times = [3.0 * k for k in range(0, 3333, 7)]
    assert times[-1] == 9996.0
    assert water.measure(found(times), 30.0, 10000.0, 3.0)["completed"]
