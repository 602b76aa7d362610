"""A sweep's folder and its limits (issue 37): one sweep per folder, nothing
written through a symbolic link planted in it, the table with the runs'
permissions, errors of the scene (those found while building the potential
too) as final `scene_error` rows, and every size that comes from the command
line bounded before anything starts. None of these needs a cluster: each is
refused, or done by the task itself, before one would start."""

import itertools
import os
import re
import stat
import subprocess
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest
import quatrot
import quatrot.sweep
from quatrot.sweep.cli import main as sweep_main
from quatrot.sweep.plan import MAX_RUNS
from quatrot.sweep.task import RESULT_FILE, run_task

#: One dipole in a field, 20 steps: a run of milliseconds.
SCENE = tomllib.loads(quatrot.builtin_scenes()["dipole_in_field"])
SCENE["run"]["steps"] = 20

#: Seconds a test waits for a helper process before giving up.
PATIENCE = 60


def hold_lock(out: Path) -> subprocess.Popen:
    """Another process holding the sweep folder's lock (until killed)."""
    code = (
        "import sys, time; from pathlib import Path; from quatrot.sweep.folder import locked\n"
        "with locked(Path(sys.argv[1])):\n    print('held', flush=True); time.sleep(600)"
    )
    holder = subprocess.Popen([sys.executable, "-c", code, str(out)], stdout=subprocess.PIPE, text=True)
    assert holder.stdout.readline().strip() == "held"
    return holder


def test_a_second_sweep_on_a_folder_in_use_is_refused_with_the_holder(tmp_path: Path, capsys):
    out = tmp_path / "sweep"
    holder = hold_lock(out)
    try:
        code = sweep_main(["dipole_in_field", "--set", "run.steps=10,20", "--out", str(out)])
        err = capsys.readouterr().err
        assert code == 2
        assert f"the sweep folder is in use by process {holder.pid}" in err
        with pytest.raises(quatrot.sweep.FolderInUse, match=f"process {holder.pid}"):
            quatrot.sweep.run(SCENE, {"run.steps": [10, 20]}, out=out)
    finally:
        holder.kill()
        holder.wait()
    assert not (out / "results.csv").exists() and not (out / "runs").exists()


def test_a_runs_folder_that_is_a_link_is_refused_and_its_target_untouched(tmp_path: Path):
    victim = tmp_path / "victim"
    victim.mkdir()
    (victim / "keep.txt").write_text("a user's file")
    out = tmp_path / "sweep"
    out.mkdir()
    (out / "runs").symlink_to(victim)
    with pytest.raises(OSError, match="runs: is a symbolic link"):
        quatrot.sweep.run(SCENE, {"run.steps": [10, 20]}, out=out)
    assert [p.name for p in victim.iterdir()] == ["keep.txt"]
    assert (victim / "keep.txt").read_text() == "a user's file"


def test_a_run_folder_that_is_a_link_is_neither_emptied_nor_written(tmp_path: Path):
    victim = tmp_path / "victim"
    victim.mkdir()
    (victim / "keep.txt").write_text("a user's file")
    runs = tmp_path / "sweep" / "runs"
    runs.mkdir(parents=True)
    (runs / "0123456789abcdef").symlink_to(victim)
    with pytest.raises(OSError, match="0123456789abcdef: is a symbolic link"):
        run_task(str(runs / "0123456789abcdef"), SCENE, 1)
    assert [p.name for p in victim.iterdir()] == ["keep.txt"]


def test_a_lock_file_that_is_a_link_is_not_followed(tmp_path: Path):
    victim = tmp_path / "victim.txt"
    victim.write_text("a user's file")
    out = tmp_path / "sweep"
    out.mkdir()
    (out / ".quatrot.lock").symlink_to(victim)
    with pytest.raises(OSError, match="quatrot.lock: is a symbolic link"):
        quatrot.sweep.run(SCENE, {"run.steps": [10, 20]}, out=out)
    assert victim.read_text() == "a user's file"


def test_the_table_and_results_have_the_permissions_of_the_runs_files(tmp_path: Path):
    """`results.csv` and `result.json` get `0666` less the umask, as the
    run's own files do (the temporary file they are renamed from is 0600)."""
    out = tmp_path / "sweep"
    run_dir = out / "runs" / "0123456789abcdef"
    row = run_task(str(run_dir), SCENE | {"record": {"series": [{"name": "energies", "every": 5, "quantities": ["total_energy"]}]}}, 1)
    assert row["status"] == "completed"
    from quatrot.sweep.table import Table

    table = Table(out / "results.csv")
    table.write([])
    mode = lambda p: stat.S_IMODE(p.stat().st_mode)  # noqa: E731
    assert mode(run_dir / "energies.csv") == 0o666 & ~current_umask()
    assert mode(out / "results.csv") == mode(run_dir / "energies.csv")
    assert mode(run_dir / RESULT_FILE) == mode(run_dir / "energies.csv")


def current_umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def test_an_error_found_while_building_the_potential_is_a_final_scene_error(tmp_path: Path):
    """Coincident sites are found when the potential is built, after the
    scene is read: still the scene's error, `quatrot.SceneError`, and a
    sweep's final `scene_error` (not `failed`, which every resume retries)."""
    site = {"position": [0.0, 0.0, 0.0], "inertia": 1.0, "dipole": [0.0, 0.0, 1.0]}
    scene = {
        "version": 1,
        "rotors": {"kind": "sites", "sites": [site, site]},
        "interactions": {"terms": ["dipole_dipole"], "boundary": {"kind": "open"}},
        "initial": {"kind": "random", "seed": 1, "temperature": 1.0},
        "integrator": {"kind": "dlm"},
        "run": {"dt": 0.01, "steps": 3},
    }
    with pytest.raises(quatrot.SceneError, match=r"^potential: rotors\[0\]\.site and rotors\[1\]\.site: coincide"):
        quatrot.run(scene)
    row = run_task(str(tmp_path / "run"), scene, 1)
    assert row["status"] == "scene_error" and "coincide" in row["error"]


def test_a_grid_past_the_limit_is_refused_before_anything_is_made(tmp_path: Path, capsys):
    """A dry run of a 10^6-run grid: refused at once (it used to expand the
    whole grid: past 60 s and 3.2 GB), naming the count and the limit."""
    seeds = ",".join(str(k) for k in range(1, 1001))
    steps = ",".join(str(k) for k in range(1, 1001))
    start = time.monotonic()
    code = sweep_main(["dipole_in_field", "--set", f"initial.seed={seeds}", "--set", f"run.steps={steps}", "--out", str(tmp_path), "--dry-run"])
    assert time.monotonic() - start < PATIENCE
    assert code == 2
    assert f"grid: 1000000 runs, more than the {MAX_RUNS} a sweep may have" in capsys.readouterr().err
    with pytest.raises(ValueError, match=f"grid: `initial.seed`: more than the {MAX_RUNS} runs"):
        quatrot.sweep.expand(SCENE, {"initial.seed": itertools.count(1)})
    with pytest.raises(ValueError, match=f"cases: more than the {MAX_RUNS} runs"):
        quatrot.sweep.expand(SCENE, cases=({"initial.seed": k} for k in itertools.count(1)))


def test_a_dry_run_lists_the_runs_as_it_makes_them(tmp_path: Path, capsys):
    code = sweep_main(["dipole_in_field", "--set", "run.steps=10,20,10", "--out", str(tmp_path), "--dry-run"])
    lines = capsys.readouterr().out.splitlines()
    assert code == 0
    assert [line.split(" ", 1)[1] for line in lines] == ["to do {run.steps=10}", "to do {run.steps=20}"]


@pytest.mark.parametrize(
    "threads, error, message",
    [
        (10**9, ValueError, "threads: must be between 1 and 1024, got 1000000000"),
        (1025, ValueError, "threads: must be between 1 and 1024, got 1025"),
        (0, ValueError, "threads: must be between 1 and 1024, got 0"),
        (-(2**70), ValueError, "threads: must be between 1 and 1024, got -1180591620717411303424"),
        (1.5, TypeError, "threads: expected an integer, got float"),
        (True, TypeError, "threads: expected an integer, got bool"),
        ("2", TypeError, "threads: expected an integer, got str"),
    ],
)
def test_thread_counts_are_integers_within_the_limit(threads, error, message):
    """A run's thread count is refused past `quatrot.MAX_THREADS` before any
    thread starts (10^9 used to spawn threads until the system refused)."""
    assert quatrot.MAX_THREADS == 1024
    with pytest.raises(error, match="^" + message):
        quatrot.run(SCENE, threads=threads)


def test_numpy_thread_counts_are_integers():
    assert quatrot.run(SCENE, threads=np.int64(1))["summary"]["status"] == "completed"


def test_a_sweep_refuses_more_threads_or_workers_than_a_run_may_have(tmp_path: Path, capsys):
    code = sweep_main(["dipole_in_field", "--out", str(tmp_path), "--threads-per-run", "1000000000"])
    assert code == 2
    assert "threads_per_run: must be between 1 and 1024, got 1000000000" in capsys.readouterr().err
    with pytest.raises(TypeError, match="threads_per_run: expected an integer, got bool"):
        quatrot.sweep.run(SCENE, out=tmp_path, threads_per_run=True)
    code = sweep_main(["dipole_in_field", "--out", str(tmp_path), "--workers", "1000000000"])
    assert code == 2
    assert "workers: must be between 1 and 1024, got 1000000000" in capsys.readouterr().err


def test_an_empty_sweep_folder_path_is_refused(tmp_path: Path, capsys, monkeypatch):
    """Found by the sweep fuzz (issue 37): `--out ''` swept into the current
    directory (a run's empty output path is refused)."""
    monkeypatch.chdir(tmp_path)
    message = "out: a sweep folder's path must not be empty (\".\" is the current directory)"
    assert sweep_main(["dipole_in_field", "--out", "", "--dry-run"]) == 2
    assert capsys.readouterr().err == f"error: {message}\n"
    with pytest.raises(ValueError, match="^" + re.escape(message) + "$"):
        quatrot.sweep.run(SCENE, {"run.steps": [10, 20]}, out="")
    assert list(tmp_path.iterdir()) == []
