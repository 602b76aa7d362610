"""The thread benchmark's protocol (`validation/bench/threads.py`): run
lengths, the share of the machine other processes took, and the idle
verdict of its section."""

import time

from validation.bench import threads


def test_periodic_runs_are_never_shorter_than_the_dipole_lattices_own_length():
    periodic = {"interactions": {"boundary": {"kind": "periodic"}}}
    assert threads.steps_for(periodic, 1_000) == 4_000
    assert threads.steps_for(periodic, 8_000) == threads.MIN_PERIODIC_STEPS == 500
    assert threads.steps_for(periodic, 64_000) == 500


def test_open_clusters_keep_a_fixed_pair_work():
    open_cluster = {"interactions": {"boundary": {"kind": "open"}}}
    assert threads.steps_for(open_cluster, 1_024) == round(threads.PAIR_STEPS / (1_024**2 / 2))
    assert threads.steps_for(open_cluster, 100_000) == threads.MIN_STEPS


def test_others_share_is_the_busy_time_not_ours():
    assert threads.others_share(busy=3.0, own=2.0, wall=1.0, cores=2) == 0.5
    assert threads.others_share(busy=1.9, own=2.0, wall=1.0, cores=2) == 0.0


def test_a_busy_loop_of_our_own_is_counted_as_ours():
    busy, own, wall = threads.busy_seconds(), threads.own_seconds(), time.perf_counter()
    clock = time.process_time()
    spun = 0
    # 0.2 s of this process's CPU, however long a shared machine takes to
    # give it (make test runs pytest beside the Rust tests).
    while time.process_time() - clock < 0.2:
        spun += 1
    clock = time.process_time() - clock
    busy, own, wall = threads.busy_seconds() - busy, threads.own_seconds() - own, time.perf_counter() - wall
    # Our CPU time, as the process clock counts it; the machine's busy time
    # holds it too (10 ms ticks), so subtracting it takes our share off the
    # others', whatever other processes did meanwhile.
    assert abs(own - clock) <= 0.02
    assert busy >= own - 0.05
    assert threads.others_share(busy, own, wall, 1) <= threads.others_share(busy, 0.0, wall, 1) - 0.8 * own / wall


def _row(others: float) -> dict:
    timing = {"median_1": 1.0, "median_2": 0.6, "speedup": 1.0 / 0.6, "pair_ratios": [1.6, 1.7], "efficiency": 0.83}
    return {
        "scene": "dipole_lattice_sc",
        "rotors": 1_000,
        "steps": 4_000,
        "repeats": 2,
        "wall": timing,
        "loop": timing,
        "set_up": timing,
        "load_averages": [1.5],
        "others_share": others,
    }


def test_the_section_says_idle_from_the_others_share_not_the_load_average():
    machine = {"cpu": "test", "cpus": 2, "platform": "test", "date": "today"}
    idle = threads.section({"machine": machine, "rows": [_row(0.01)], "seconds": 1.0, "argv": []})
    busy = threads.section({"machine": machine, "rows": [_row(0.3)], "seconds": 1.0, "argv": []})
    assert "The machine was idle" in idle and "not idle" not in idle
    assert "**The machine was not idle**" in busy and "30.0 %" in busy


def test_the_bandwidth_line_gives_both_probes_and_their_ratio(tmp_path):
    line = threads.bandwidth_line([{"gb_per_s_1": 10.0, "gb_per_s_2": 15.0}, None,
                                   {"gb_per_s_1": 12.0, "gb_per_s_2": 24.0}])
    assert "10.0 and 15.0 GB/s (1.50x); 12.0 and 24.0 GB/s (2.00x)" in line
    assert "not measured" in threads.bandwidth_line([None, None])
    assert threads.bandwidth(tmp_path / "missing") is None
