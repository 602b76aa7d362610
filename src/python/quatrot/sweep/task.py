"""The task a worker runs for one run of a sweep.

Idempotent: each attempt empties the run's own folder first (a symbolic
link there, or at `runs/`, is refused, never followed) and writes only
there, so an attempt cut short (its worker died) leaves nothing the next one
could mix with. It runs on a rayon pool of a fixed size, so its numbers do
not depend on the worker's cores. A scene error or a blow-up is an outcome,
returned like a completed run; `result.json`, written last, marks an attempt
that finished.
"""

from __future__ import annotations

import os
import shutil
import socket
import time
from pathlib import Path
from typing import Any

import quatrot
from quatrot.sweep.folder import real_folder, refuse_link
from quatrot.sweep.table import summary_row, write_json

#: The file, in a run's folder, holding the row of an attempt that finished.
RESULT_FILE = "result.json"


def run_task(run_dir: str, scene: dict[str, Any], threads: int) -> dict[str, Any]:
    """Runs `scene` with its outputs in `run_dir` (emptied first) on
    `threads` threads; returns the row of its outcome (`status`, `error` and
    the summary's numbers, see `table.TAIL`)."""
    folder = Path(run_dir)
    refuse_link(folder.parent)
    refuse_link(folder)
    if folder.exists():
        shutil.rmtree(folder)
    real_folder(folder)
    start, cpu_start = time.perf_counter(), time.process_time()
    try:
        row = summary_row(quatrot.run(scene, out_dir=folder, threads=threads)["summary"])
    except quatrot.BlowUpError as e:
        row = summary_row(e.result["summary"])
    except quatrot.SceneError as e:
        row = {"status": "scene_error", "error": str(e)}
    row["task_seconds"] = time.perf_counter() - start
    row["cpu_seconds"] = time.process_time() - cpu_start
    row["threads"] = threads
    row["worker"] = f"{socket.gethostname()}:{os.getpid()}"
    write_json(folder / RESULT_FILE, row)
    return row
