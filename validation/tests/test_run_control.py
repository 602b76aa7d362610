"""`quatrot.run` as a library call (issue 17 item 4, issue 19 item 6):
progress reported to a callback and a bar, and Ctrl-C (SIGINT sent to a
subprocess running a long run) stopping the run promptly with its files
flushed, the summary saying "interrupted" and the partial result on the
`KeyboardInterrupt`."""

import csv
import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

import quatrot

# The run polls Ctrl-C every 20 ms; a loaded machine may add scheduling delays.
STOP_WITHIN_SECONDS = 5.0


def test_on_progress_sees_the_steps_up_to_the_total():
    calls = []
    result = quatrot.run("dipole_in_field", steps=3000, on_progress=lambda step, total: calls.append((step, total)))
    assert calls, "on_progress was never called"
    assert all(total == 3000 for _, total in calls)
    steps = [s for s, _ in calls]
    assert steps == sorted(steps) and steps[-1] == 3000
    assert result["summary"]["status"] == "completed"


def test_an_exception_in_on_progress_stops_the_run_and_is_raised_with_the_result():
    class Enough(Exception):
        pass

    def stop(step, total):
        if step > 0:
            raise Enough

    with pytest.raises(Enough) as e:
        quatrot.run("dipole_in_field", steps=10**9, on_progress=stop)
    summary = e.value.result["summary"]
    assert summary["status"] == "interrupted"
    assert 0 < summary["last_step"] < 10**9


def test_progress_true_draws_a_bar_on_stderr(capfd):
    """tqdm's bar (tqdm is in the validation requirements)."""
    quatrot.run("dipole_in_field", steps=2000, progress=True)
    err = capfd.readouterr().err
    assert "2000/2000" in err and "step/s" in err


def test_progress_true_without_tqdm_writes_a_line(capfd, monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)  # import tqdm raises ImportError
    quatrot.run("dipole_in_field", steps=2000, progress=True)
    err = capfd.readouterr().err
    assert err.endswith("\r2000/2000 steps\n") and "step/s" not in err


CHILD = textwrap.dedent(
    """
    import json, signal, sys
    import quatrot

    # Ctrl-C as a terminal delivers it, also when this suite runs as a
    # shell's background job (which starts its children with SIGINT ignored).
    signal.signal(signal.SIGINT, signal.default_int_handler)
    started = False

    def on_progress(step, total):
        global started
        if step > 0 and not started:
            started = True
            print("started", flush=True)

    try:
        quatrot.run("dipole_in_field", steps=10**9, out_dir=sys.argv[1], on_progress=on_progress)
    except KeyboardInterrupt as e:
        r = e.result
        print(json.dumps({"summary": r["summary"], "rows": len(r["series"]["energies"]["step"])}), flush=True)
        sys.exit(0)
    print("finished without an interrupt", flush=True)
    sys.exit(1)
    """
)


def test_ctrl_c_stops_a_run_promptly_with_outputs_flushed_and_the_partial_result(tmp_path):
    out = tmp_path / "out"
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        assert child.stdout.readline().strip() == "started"
        time.sleep(0.3)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        stdout, stderr = child.communicate(timeout=60)
        elapsed = time.monotonic() - sent
    finally:
        child.kill()
    assert child.returncode == 0, (stdout, stderr)
    assert elapsed < STOP_WITHIN_SECONDS
    reported = json.loads(stdout.strip().splitlines()[-1])
    summary = reported["summary"]
    assert summary["status"] == "interrupted"
    last = summary["last_step"]
    assert 0 < last < 10**9
    assert summary["message"] == f"interrupted at step {last}"
    # The files: the summary as returned, the CSV whole lines, every sample up to the stop.
    assert json.loads((out / "summary.json").read_text())["status"] == "interrupted"
    text = (out / "energies.csv").read_text()
    assert text.endswith("\n")
    rows = list(csv.DictReader(text.splitlines()))
    assert len(rows) == reported["rows"] == last // 10 + 1
    assert int(rows[-1]["step"]) == last // 10 * 10
