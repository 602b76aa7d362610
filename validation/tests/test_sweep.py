"""Sweeps on a local Dask cluster of two worker processes: the same numbers
as serial `quatrot.run` calls, bit for bit; a worker killed mid-run loses no
run; a finished sweep started again runs nothing; an invalid combination is
recorded by its overrides while the others run; a sweep killed mid-way
leaves a readable table and resumes with the runs it had not finished;
Ctrl-C prints one line.

The system is the half-list quadrupole lattice, whose pair loop sums its
per-thread blocks in an order that depends on the thread count: the serial
references run on one thread, as the sweep's tasks do."""

import csv
import json
import os
import signal
import subprocess
import sys
import threading
import time
import tomllib
from pathlib import Path

import distributed
import numpy as np
import pytest
import quatrot
import quatrot.sweep
from quatrot.sweep.cli import main as sweep_main

#: 32 quadrupoles (fcc, 2^3 cells, box 3, cutoff 2), energies every 10 steps.
SCENE = tomllib.loads(quatrot.builtin_scenes()["quadrupole_lattice_fcc"])
SCENE["rotors"]["cells"] = 2
SCENE["run"]["steps"] = 60
SCENE["record"] = {"series": [{"name": "energies", "every": 10, "quantities": ["kinetic_energy", "potential_energy", "total_energy", "energy_error"]}]}

#: The summary's physics: everything but the timing.
PHYSICS = ("seed", "integrator", "rotors", "dt", "start_step", "last_step", "status", "message", "initial_energy", "final_energies", "drift", "definition")

#: Seconds a test waits for a sweep's progress before giving up.
PATIENCE = 60


@pytest.fixture(scope="module")
def client():
    """A local cluster of two single-threaded worker processes."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as c:
            yield c


def read_csv(path: Path) -> dict[str, np.ndarray]:
    with path.open() as f:
        rows = list(csv.DictReader(f))
    return {column: np.array([float(r[column]) for r in rows]) for column in rows[0]}


def test_two_workers_give_the_serial_runs_bit_for_bit(client, tmp_path: Path):
    grid = {"integrator.kind": ["gear_b", "dlm"], "run.dt": [0.002, 0.004], "initial.seed": [1, 2]}
    results = quatrot.sweep.run(SCENE, grid, out=tmp_path, client=client)
    assert results.submitted == 8 and len(results.rows) == 8
    assert {r["status"] for r in results.rows} == {"completed"}
    assert len({r["worker"] for r in results.rows}) == 2  # both workers ran some
    for run, row in zip(results.runs, results.rows):
        serial = quatrot.run(run.scene, threads=1)
        folder = tmp_path / row["outputs"]
        series = read_csv(folder / "energies.csv")
        assert series.keys() == serial["series"]["energies"].keys()
        for column, values in serial["series"]["energies"].items():
            np.testing.assert_array_equal(series[column], values, err_msg=f"{run.overrides} {column}")
        summary = json.loads((folder / "summary.json").read_text())
        assert {k: summary[k] for k in PHYSICS} == {k: serial["summary"][k] for k in PHYSICS}
        final = serial["summary"]["final_energies"]
        assert float(row["final_total_energy"]) == final["total"]
        assert float(row["final_energy_error"]) == final["error"]
        assert float(row["drift_per_time"]) == serial["summary"]["drift"]["relative_per_time"]
        assert row["integrator.kind"] == run.overrides["integrator.kind"]


def test_a_finished_sweep_started_again_runs_nothing(client, tmp_path: Path):
    """The second call submits no task: it is given the address of no
    scheduler at all, and would fail if it tried to reach one."""
    grid = {"initial.seed": [1, 2, 3]}
    first = quatrot.sweep.run(SCENE, grid, out=tmp_path, client=client)
    assert first.submitted == 3
    stamps = {p: p.stat().st_mtime_ns for p in tmp_path.glob("runs/*/*")}
    again = quatrot.sweep.run(SCENE, grid, out=tmp_path, client="tcp://127.0.0.1:9")
    assert again.submitted == 0
    assert again.rows == first.rows
    assert {p: p.stat().st_mtime_ns for p in tmp_path.glob("runs/*/*")} == stamps
    # More threads per run are another computation (other last bits): all run again.
    assert quatrot.sweep.run(SCENE, grid, out=tmp_path, client=client, threads_per_run=2).submitted == 3


def test_an_invalid_combination_is_reported_by_its_overrides(client, tmp_path: Path, capsys):
    """Through the command line: a negative time step is a scene error and a
    huge one blows up (energy-error guard); the other runs complete."""
    scene = tmp_path / "scene.toml"
    scene.write_text(quatrot.builtin_scenes()["dipole_in_field"])
    code = sweep_main(
        [str(scene), "--set", "integrator.kind=gear_b,dlm", "--set", "run.dt=0.005,-0.005",
         "--case", "run.dt=0.5;record.energy_error_threshold=1e-3;record.check_every=1",
         "--out", str(tmp_path / "sweep"), "--scheduler", client.scheduler.address]
    )  # fmt: skip
    out = capsys.readouterr().out
    assert code == 0, out
    assert "{integrator.kind=gear_b, run.dt=-0.005} scene_error: run.dt: must be > 0, got -0.005" in out
    assert "{integrator.kind=dlm, run.dt=-0.005} scene_error: run.dt: must be > 0, got -0.005" in out
    assert "{run.dt=0.5, record.energy_error_threshold=0.001, record.check_every=1} blew_up: blew up at step" in out
    with (tmp_path / "sweep" / "results.csv").open() as f:
        rows = {(r["integrator.kind"], r["run.dt"]): r for r in csv.DictReader(f)}
    assert [rows[k]["status"] for k in [("gear_b", "0.005"), ("gear_b", "-0.005"), ("dlm", "0.005"), ("dlm", "-0.005"), ("", "0.5")]] == [
        "completed", "scene_error", "completed", "scene_error", "blew_up"
    ]  # fmt: skip
    assert int(rows[("", "0.5")]["last_step"]) < 2000


class KillOnce(distributed.WorkerPlugin):
    """Makes the first worker that runs a sweep task exit abruptly once the
    task's run has begun writing its series (mid-run); the marker file,
    created exclusively, holds that worker's process id."""

    def __init__(self, marker: Path, runs: Path):
        self.marker, self.runs = str(marker), runs

    def transition(self, key, start, finish, **kwargs):
        if finish != "executing" or not str(key).startswith("quatrot-run-"):
            return
        try:
            fd = os.open(self.marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except FileExistsError:
            return
        os.write(fd, f"{os.getpid()} {key}".encode())
        os.close(fd)
        series = self.runs / str(key).split("-")[2] / "energies.csv"
        threading.Thread(target=self._exit_when_written, args=(series,), daemon=True).start()

    @staticmethod
    def _exit_when_written(series: Path):
        deadline = time.monotonic() + PATIENCE
        while time.monotonic() < deadline and not (series.exists() and series.stat().st_size > 0):
            time.sleep(0.002)
        os._exit(1)


def test_a_worker_killed_mid_run_loses_no_run(client, tmp_path: Path):
    """The scheduler gives the dead worker's task to a live one, which starts
    the run again from an emptied folder: every run is recorded once, and
    the killed one's outputs are those of a serial run."""
    scene = tomllib.loads(quatrot.builtin_scenes()["quadrupole_lattice_fcc"])
    scene["run"]["steps"] = 1000  # about 0.25 s
    scene["record"] = {"series": [{"name": "energies", "every": 1, "quantities": ["total_energy"]}]}
    marker = tmp_path / "killed"
    client.register_plugin(KillOnce(marker, tmp_path / "sweep" / "runs"), name="kill-once")
    try:
        results = quatrot.sweep.run(scene, {"initial.seed": [1, 2, 3, 4]}, out=tmp_path / "sweep", client=client)
    finally:
        client.unregister_worker_plugin("kill-once")
    pid, key = marker.read_text().split()
    victim = key.split("-")[2]
    assert [r["status"] for r in results.rows] == ["completed"] * 4
    row = next(r for r in results.rows if r["id"] == victim)
    assert row["worker"].split(":")[1] != pid  # finished by another process
    run = next(r for r in results.runs if r.id == victim)
    serial = quatrot.run(run.scene, threads=1)["series"]["energies"]["total_energy"]
    np.testing.assert_array_equal(read_csv(tmp_path / "sweep" / row["outputs"] / "energies.csv")["total_energy"], serial)


def test_a_killed_sweep_leaves_a_readable_table_and_resumes(client, tmp_path: Path):
    """`python -m quatrot.sweep` on its own local cluster, killed (with its
    workers) once two runs are in the table; the table reads whole, and the
    sweep started again runs exactly the runs not yet finished."""
    scene = tomllib.loads(quatrot.builtin_scenes()["quadrupole_lattice_fcc"])
    scene["run"]["steps"] = 1000  # about 0.25 s
    path = tmp_path / "scene.toml"
    path.write_text(quatrot.builtin_scenes()["quadrupole_lattice_fcc"].replace("steps = 500", "steps = 1000"))
    out = tmp_path / "sweep"
    table = out / "results.csv"
    seeds = list(range(1, 11))
    command = [sys.executable, "-m", "quatrot.sweep", str(path), "--set", f"initial.seed={','.join(map(str, seeds))}", "--out", str(out), "--workers", "1"]
    sweep = subprocess.Popen(command, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + PATIENCE
        while not (table.exists() and len(table.read_text().splitlines()) >= 3):
            assert time.monotonic() < deadline and sweep.poll() is None, "the sweep recorded no two runs"
            time.sleep(0.01)
    finally:
        os.killpg(sweep.pid, signal.SIGKILL)
        sweep.wait()
    with table.open() as f:
        rows = list(csv.DictReader(f))
    assert 2 <= len(rows) < len(seeds)
    assert all(r["status"] == "completed" and r["final_total_energy"] for r in rows)
    finished = {p.parent.name for p in out.glob("runs/*/result.json")}
    assert {r["id"] for r in rows} <= finished
    results = quatrot.sweep.run(path, {"initial.seed": seeds}, out=out, client=client)
    assert results.submitted == len(seeds) - len(finished)
    assert [r["status"] for r in results.rows] == ["completed"] * len(seeds)
    with table.open() as f:
        assert sorted(r["id"] for r in csv.DictReader(f)) == sorted(r.id for r in results.runs)


def test_ctrl_c_on_a_sweep_prints_one_line(tmp_path: Path):
    """Ctrl-C (SIGINT to the terminal's process group: the sweep and its
    local cluster's workers) stops the sweep with exit code 130 and one line
    on stderr; it used to print every worker's traceback and warnings."""
    out = tmp_path / "sweep"
    table = out / "results.csv"
    # 40 runs of about 2 s on two workers (20,000 steps; 1,000 took 0.1 s
    # by 2026-11-28, and Dask hands finished runs over in batches, so on a
    # loaded machine the first table written could already hold all 40):
    # far from finished when the first is recorded.
    command = [sys.executable, "-m", "quatrot.sweep", "quadrupole_lattice_fcc", "--set", "initial.seed=" + ",".join(map(str, range(1, 41))),
               "--set", "run.steps=20000", "--out", str(out), "--workers", "2"]  # fmt: skip
    # A terminal's foreground job takes SIGINT by default; a test run from a
    # background job (`cmd &` in a script, nohup) has it ignored, and an
    # ignored signal stays ignored across exec, so Python would not even
    # install its handler in the sweep: set the default back in the child.
    sweep = subprocess.Popen(command, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                             preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # fmt: skip
    try:
        deadline = time.monotonic() + PATIENCE
        while not (table.exists() and len(table.read_text().splitlines()) >= 2):
            assert time.monotonic() < deadline and sweep.poll() is None, "the sweep recorded no run"
            time.sleep(0.01)
        recorded = len(table.read_text().splitlines()) - 1
        os.killpg(sweep.pid, signal.SIGINT)
        _, err = sweep.communicate(timeout=PATIENCE)
    finally:
        if sweep.poll() is None:
            os.killpg(sweep.pid, signal.SIGKILL)
            sweep.wait()
    assert recorded < 40, "the sweep finished before the interrupt: the test needs longer runs"
    assert sweep.returncode == 130
    assert err.splitlines() == [f"interrupted: {table} holds the runs finished so far; the same command resumes"]


def test_only_distributeds_cancel_race_is_kept_out_of_the_log():
    """The filter drops the record of distributed's NameError in
    `sync.<locals>.cancel` on Ctrl-C, and lets every other record through
    (an error in another callback, the same message without the NameError)."""
    import logging

    from quatrot.sweep.execute import _sync_cancel_race

    def record(message: str, exc: BaseException | None) -> logging.LogRecord:
        info = (type(exc), exc, None) if exc else None
        return logging.LogRecord("tornado.application", logging.ERROR, __file__, 1, message, None, info)

    race = "Exception in callback functools.partial(<function sync.<locals>.cancel at 0x7f990c258360>)"
    assert not _sync_cancel_race(record(race, NameError("cannot access free variable 'future'")))
    assert _sync_cancel_race(record(race, ValueError("another error")))
    assert _sync_cancel_race(record("Exception in callback functools.partial(<function other>)", NameError("x")))
    assert _sync_cancel_race(record(race, None))
