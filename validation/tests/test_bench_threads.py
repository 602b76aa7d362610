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


def _probe(gb_1, gb_2, gflops_1=10.0, gflops_2=20.0):
    return {"gb_per_s_1": gb_1, "gb_per_s_2": gb_2, "gflops_1": gflops_1, "gflops_2": gflops_2}


def test_each_pair_takes_the_mean_ratios_of_the_probes_around_it(tmp_path):
    probes = [_probe(10.0, 15.0, 10.0, 10.0), _probe(10.0, 20.0, 10.0, 20.0), _probe(20.0, 20.0, 10.0, 20.0)]
    assert threads.pair_ratios(probes, "triad") == [1.75, 1.5]
    assert threads.pair_ratios(probes, "arithmetic") == [1.5, 2.0]
    assert threads.pair_ratios([probes[0], None], "triad") is None
    assert threads.probe_host(tmp_path / "missing") is None


def _large_row(speedups: list[float], triads: list[float], arithmetic: list[float]) -> dict:
    row = _row(0.01)
    return {**row, "rotors": 64_000, "wall": {**row["wall"], "pair_ratios": speedups},
            "probes": [_probe(10.0, 15.0)] * (len(speedups) + 1), "triad_ratios": triads,
            "arithmetic_ratios": arithmetic}


def test_the_probe_lines_set_the_large_rows_pairs_against_each_ratio():
    small = {**_row(0.01), "probes": [_probe(25.0, 50.0, 8.0, 9.0)], "triad_ratios": [1.1, 1.2],
             "arithmetic_ratios": [1.0, 1.0]}
    lines = threads.probe_lines([_large_row([1.5, 1.6, 1.9], [1.3, 1.4, 2.0], [1.9, 1.8, 1.2]), small])
    assert "triad 10.0-25.0 and 15.0-50.0 GB/s, 1.50-2.00x" in lines[0]
    assert "arithmetic 8.0-10.0 and 9.0-20.0 GFLOP/s, 1.12-2.00x" in lines[0]
    # The 1,000-rotor row's pairs are left out: 3 pairs each.
    triad, arithmetic = lines[1], lines[2]
    assert "The 3 pairs" in triad and "triad's ratio: Spearman rank correlation 1.00" in triad
    assert "triad ratio at least 1.8x: median speed-up 1.90x (1 pair); below 1.8x: median speed-up 1.55x (2 pairs)" in triad
    assert "arithmetic's ratio: Spearman rank correlation -1.00" in arithmetic
    assert "arithmetic ratio at least 1.8x: median speed-up 1.55x (2 pairs)" in arithmetic
    assert threads.probe_lines([_row(0.01)]) == ["- Host probe: not run (no `examples/host_probe` binary)."]


def test_an_older_probe_without_arithmetic_says_so():
    old = {"gb_per_s_1": 10.0, "gb_per_s_2": 15.0}
    assert "arithmetic not measured" in threads.probe_lines([{**_row(0.01), "probes": [old]}])[0]


def test_the_table_gives_each_rows_ratios():
    machine = {"cpu": "test", "cpus": 2, "platform": "test", "date": "today"}
    text = threads.section({"machine": machine, "seconds": 1.0, "argv": [],
                            "rows": [_large_row([1.5, 1.6, 1.9], [1.3, 1.4, 2.0], [1.9, 1.8, 1.2])]})
    assert "| 1.40x (1.30-2.00) | 1.80x (1.20-1.90) |" in text
    assert "| - | - |" in threads.section({"machine": machine, "rows": [_row(0.01)], "seconds": 1.0, "argv": []})
