"""Running a sweep's runs as Dask tasks and keeping its results table.

Nothing lost, nothing repeated:

* a run with a final status in the table (completed, blew up, scene error)
  is not run again when the sweep is started again (resumed) with the same
  threads per run; neither is one whose folder holds the `result.json` of a
  finished attempt that the table missed (the sweep was killed in between);
* a run that fails or blows up is a row with its status and error; the
  other runs go on;
* a worker that dies mid-run has its task retried on another worker by the
  scheduler (up to `distributed.scheduler.allowed-failures` deaths; the
  local cluster sets `ALLOWED_FAILURES`), from scratch in the run's folder;
  past that the run is recorded as `failed` and retried on the next resume;
* the table is rewritten atomically after each run (or after each batch of
  runs that finished while it was being written);
* one sweep per folder: the folder is locked while a sweep runs in it, and
  nothing is written through a symbolic link in it (`folder`).
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import signal
import threading
import uuid
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

try:
    import dask
    import distributed
except ImportError as e:  # the `sweep` extra is not installed
    raise ImportError(
        f"quatrot.sweep runs on Dask: install it with `pip install 'quatrot[sweep]'` ({e})"
    ) from e

import quatrot
from quatrot.sweep.folder import locked, real_folder, sweep_folder
from quatrot.sweep.plan import Run, expand
from quatrot.sweep.table import FINISHED, NAME, Table
from quatrot.sweep.task import RESULT_FILE, run_task

#: Deaths of workers running the same task before the local cluster's
#: scheduler gives up on it (Dask's default).
ALLOWED_FAILURES = 3

#: The folder, inside the sweep's, holding one folder per run.
RUNS = "runs"

#: The most threads a run may have (the limit of `quatrot.run`'s `threads`),
#: and the most worker processes of a local cluster.
MAX_THREADS = quatrot.MAX_THREADS


@dataclass
class Results:
    """What a sweep call did: the table's path, its runs and their rows (in
    the plan's order; cells as text, as in the file) and how many runs it
    submitted (the others were finished already).

    Examples
    --------
    See `quatrot.sweep.run`, which returns it:

    >>> results.submitted, results.unfinished()
    (2, [])
    """

    table: Path
    runs: list[Run]
    rows: list[dict[str, str]]
    submitted: int

    def unfinished(self) -> list[dict[str, str]]:
        """The rows without a final status (run again on the next call)."""
        return [r for r in self.rows if r["status"] not in FINISHED]


def run(
    scene: Any,
    grid: Mapping[str, Iterable[Any]] | None = None,
    cases: Iterable[Mapping[str, Any]] | None = None,
    *,
    out: str | os.PathLike,
    client: distributed.Client | str | None = None,
    workers: int | None = None,
    threads_per_run: int = 1,
    on_result: Callable[[Run, dict[str, str]], None] | None = None,
) -> Results:
    """Runs the sweep of `scene` over `grid` and `cases` (see
    `quatrot.sweep.expand`) into the folder `out`: `out/runs/<id>/` holds
    each run's outputs, `out/results.csv` the table. `client` is a
    `distributed.Client` or a scheduler address; without one, a local
    cluster of `workers` processes (default: cores / `threads_per_run`)
    starts and stops with the call. Each run uses `threads_per_run` threads.
    `on_result(run, row)` is called after each run is recorded. Runs already
    finished in `out` are not run again. (A script that starts the local
    cluster needs the `if __name__ == "__main__":` guard: its workers are
    new Python processes.) The folder is locked while the call runs: a
    second sweep on it raises `FolderInUse` (an `OSError`).

    Examples
    --------
    Two runs on an in-process cluster of threads, into a temporary folder:

    >>> import tempfile
    >>> from distributed import Client
    >>> out = tempfile.mkdtemp()
    >>> with Client(processes=False, n_workers=1, dashboard_address=None) as client:
    ...     results = quatrot.sweep.run("dipole_in_field", {"run.dt": [0.01, 0.005]}, out=out, client=client)
    >>> [row["status"] for row in results.rows]
    ['completed', 'completed']
    """
    _count("threads_per_run", threads_per_run)
    if workers is not None:
        _count("workers", workers)
        if client is not None:
            raise ValueError("workers: only for the local cluster (not with a client or scheduler address)")
    out = sweep_folder(out)
    runs = expand(scene, grid, cases)
    with locked(out):
        real_folder(out / RUNS)
        table = Table(out / NAME)
        order = [r.id for r in runs]
        for r in runs:
            _adopt_finished_attempt(table, r, out, threads_per_run)
        table.write(order)
        todo = [r for r in runs if not table.finished(r.id, threads_per_run)]
        if todo:
            n_workers = workers or max(1, (os.cpu_count() or 1) // threads_per_run)
            with _connect(client, n_workers) as c:
                _submit_and_record(c, todo, table, order, out, threads_per_run, on_result)
    return Results(out / NAME, runs, [table.rows[i] for i in order], len(todo))


def _count(name: str, value: int) -> None:
    """A thread or worker count: an integer from 1 to `MAX_THREADS` (the
    wording of `quatrot.run`'s `threads`)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"{name}: expected an integer, got {type(value).__name__}")
    if not 1 <= value <= MAX_THREADS:
        raise ValueError(f"{name}: must be between 1 and {MAX_THREADS}, got {value}")


def _outputs(run: Run) -> str:
    return f"{RUNS}/{run.id}"


def _adopt_finished_attempt(table: Table, run: Run, out: Path, threads: int) -> None:
    """Records a finished attempt that the table missed (the sweep was killed
    between the run's end and the table's next write)."""
    if table.finished(run.id, threads):
        return
    try:
        outcome = json.loads((out / _outputs(run) / RESULT_FILE).read_text())
    except (OSError, ValueError):
        return
    if outcome.get("status") in FINISHED and outcome.get("threads") == threads:
        table.record(run, {**outcome, "outputs": _outputs(run)})


def _sync_cancel_race(record: logging.LogRecord) -> bool:
    """False for the one record of distributed's race on Ctrl-C (2026.8.0):
    `distributed.utils.sync` declares its `future` without a value, and a
    KeyboardInterrupt that lands before the loop has created it schedules a
    `cancel` that fails with NameError, logged by tornado with its
    traceback (seen once in `test_ctrl_c_on_a_sweep_prints_one_line`,
    2026-12-03). Nothing was running to cancel; every other record passes."""
    exc = record.exc_info[1] if record.exc_info else None
    return not (isinstance(exc, NameError) and "sync.<locals>.cancel" in record.getMessage())


@contextlib.contextmanager
def _connect(client: distributed.Client | str | None, workers: int) -> Iterator[distributed.Client]:
    """The given client, a client of the scheduler at the given address, or
    one of a local cluster started (and stopped) here; meanwhile tornado
    logs no `_sync_cancel_race` record."""
    tornado = logging.getLogger("tornado.application")
    tornado.addFilter(_sync_cancel_race)
    try:
        with _connected(client, workers) as c:
            yield c
    finally:
        tornado.removeFilter(_sync_cancel_race)


@contextlib.contextmanager
def _connected(client: distributed.Client | str | None, workers: int) -> Iterator[distributed.Client]:
    if isinstance(client, distributed.Client):
        yield client
    elif isinstance(client, str):
        with distributed.Client(client) as c:
            yield c
    elif client is None:
        with dask.config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES}), _sigint_ignored():
            cluster = distributed.LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                dashboard_address=None,
                # No dashboard; the scheduler's HTTP routes (health, metrics)
                # on a free loopback port, not Dask's default 8787, which
                # another cluster may hold (a warning on stderr) or expose.
                scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
            )
        with cluster, distributed.Client(cluster) as c:
            try:
                yield c
            except KeyboardInterrupt:
                _quiet_workers(c)
                raise
    else:
        raise TypeError(f"client: expected a distributed.Client or a scheduler address, got {type(client).__name__}")


@contextlib.contextmanager
def _sigint_ignored() -> Iterator[None]:
    """SIGINT ignored while the local cluster starts its worker processes,
    which inherit that: Ctrl-C reaches the sweep alone, which stops them
    (instead of each worker printing its own traceback). Only from the main
    thread, where Python handles signals."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _quiet_workers(client: distributed.Client) -> None:
    """Before an interrupted sweep stops its own local cluster: its workers
    log no warning for the runs cancelled under them, nor do the cluster's
    nannies in this process when they kill a worker still in a run ("Worker
    process still alive after 4.0 seconds, killing"): the table says what
    finished; the interrupted line says the rest."""
    _log_errors_only()
    with contextlib.suppress(Exception):
        client.run(_log_errors_only)


def _log_errors_only() -> None:
    logging.getLogger("distributed").setLevel(logging.ERROR)


def _submit_and_record(
    client: distributed.Client,
    todo: list[Run],
    table: Table,
    order: list[str],
    out: Path,
    threads: int,
    on_result: Callable[[Run, dict[str, str]], None] | None,
) -> None:
    """Submits one task per run and records the outcomes as they arrive, the
    table rewritten once for the runs that finished since its last write
    (one run each time, unless they finish faster than it is written)."""
    call = uuid.uuid4().hex[:8]  # keys unique to this call on a shared scheduler
    futures = {
        client.submit(
            run_task, str(out / _outputs(r)), r.scene, threads, key=f"quatrot-run-{r.id}-{call}", pure=False
        ): r
        for r in todo
    }
    for batch in distributed.as_completed(futures).batches():
        recorded = [(futures[f], table.record(futures[f], _outcome(f, threads, futures[f]))) for f in batch]
        table.write(order)
        for r, row in recorded:
            if on_result:
                on_result(r, row)


def _outcome(future: distributed.Future, threads: int, run: Run) -> dict[str, Any]:
    """The row of a finished task (and the future released)."""
    try:
        outcome = future.result()
    except Exception as e:  # the task raised outside the run, or its workers kept dying
        outcome = {"status": "failed", "error": f"{type(e).__name__}: {e}", "threads": threads}
    future.release()
    return {**outcome, "outputs": _outputs(run)}
