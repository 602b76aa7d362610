"""The results table of a sweep, `<sweep>/results.csv`: one row per run with
its identifier, status and error, its overrides (one column per path,
`set:` before a path that names one of the table's own columns), the
numbers of its summary and the folder of its outputs.

CSV rather than Parquet: the table is small (one row per run: 10^4 runs
make 2.7 MB, written in 0.2 s), is rewritten whole either way, and is read
by people and by any tool without a dependency (pyarrow 26 is a 55 MB wheel);
floats are written in Python's shortest round-trip form, so `float(cell)`
gives back the run's number bit for bit.

The file is replaced atomically (written to a temporary file in the same
folder, flushed to disk, renamed over the old one): a sweep killed at any
moment leaves the previous complete table. It gets the permissions of every
other output (`0666` less the process's umask, as the runs' files).
"""

from __future__ import annotations

import csv
import json
import os
import tempfile
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from quatrot.sweep.plan import Run, format_value

#: Statuses that are a run's final answer: running it again gives the same
#: one. A `failed` run (its worker died too often, or an error outside the
#: physics such as a full disk) is run again when the sweep is resumed.
FINISHED = frozenset({"completed", "blew_up", "scene_error"})

HEAD = ("id", "status", "error")

#: The columns after the overrides: what the run's summary says, then how
#: and where it ran (`wall_seconds`: the run's loop; `task_seconds`: the
#: whole task; `cpu_seconds`: the worker process's CPU time during the task,
#: below `task_seconds x threads` when the cores are shared).
TAIL = (
    "integrator",
    "rotors",
    "dt",
    "last_step",
    "seed",
    "initial_total_energy",
    "final_kinetic_energy",
    "final_potential_energy",
    "final_total_energy",
    "final_energy_error",
    "drift_per_time",
    "wall_seconds",
    "task_seconds",
    "cpu_seconds",
    "threads",
    "worker",
    "quatrot_version",
    "outputs",
)

NAME = "results.csv"

#: The prefix of an override's column when its path is also the name of one
#: of the table's own columns (the path `integrator`, a whole table, against
#: the summary's `integrator`).
OVERRIDE_PREFIX = "set:"


def override_column(path: str) -> str:
    """The column of the override `path`: the path itself, or with
    `OVERRIDE_PREFIX` when that is one of the table's own columns."""
    return OVERRIDE_PREFIX + path if path in HEAD or path in TAIL else path


def summary_row(summary: Mapping[str, Any]) -> dict[str, Any]:
    """The table's numbers from a run's summary (`quatrot.run`'s `summary`);
    energies and drift are absent when the scene records no energies."""
    final = summary.get("final_energies") or {}
    initial = summary.get("initial_energy") or {}
    drift = summary.get("drift") or {}
    return {
        "status": summary["status"],
        "error": summary.get("message"),
        "integrator": summary.get("integrator"),
        "rotors": summary.get("rotors"),
        "dt": summary.get("dt"),
        "last_step": summary.get("last_step"),
        "seed": summary.get("seed"),
        "initial_total_energy": initial.get("total"),
        "final_kinetic_energy": final.get("kinetic"),
        "final_potential_energy": final.get("potential"),
        "final_total_energy": final.get("total"),
        "final_energy_error": final.get("error"),
        "drift_per_time": drift.get("relative_per_time"),
        "wall_seconds": summary.get("wall_seconds"),
        "quatrot_version": (summary.get("versions") or {}).get("quatrot"),
    }


def _cell(value: Any) -> str:
    return "" if value is None else format_value(value)


class Table:
    """The rows of a sweep's table by run identifier (cells as text), read
    from `path` if it exists, and written back whole."""

    def __init__(self, path: Path):
        self.path = Path(path)
        self.rows: dict[str, dict[str, str]] = {}
        self.override_columns: list[str] = []
        if self.path.exists():
            self._read()

    def _read(self) -> None:
        with self.path.open(newline="") as f:
            reader = csv.DictReader(f)
            columns = reader.fieldnames or []
            if not set(HEAD) <= set(columns):
                raise ValueError(f"{self.path}: not a sweep's results table (no `id` and `status` columns)")
            self.override_columns = [c for c in columns if c not in HEAD and c not in TAIL]
            for row in reader:
                self.rows[row["id"]] = row

    def finished(self, run_id: str, threads: int) -> bool:
        """Whether the run has a final status from a run on `threads` threads
        (the periodic pair loop's last bits depend on the thread count)."""
        row = self.rows.get(run_id)
        return row is not None and row["status"] in FINISHED and row.get("threads") == str(threads)

    def record(self, run: Run, outcome: Mapping[str, Any]) -> dict[str, str]:
        """Sets the row of `run` from its `outcome` (status, error and the
        `TAIL` values) and returns it as text."""
        for path in run.overrides:
            if override_column(path) not in self.override_columns:
                self.override_columns.append(override_column(path))
        row = {"id": run.id, **{override_column(p): _cell(v) for p, v in run.overrides.items()}}
        row.update({c: _cell(outcome.get(c)) for c in ("status", "error", *TAIL)})
        self.rows[run.id] = row
        return row

    def write(self, order: Iterable[str]) -> None:
        """Replaces the file atomically with the rows, those of `order` (run
        identifiers) first and in that order."""
        rank = {run_id: k for k, run_id in enumerate(order)}
        rows = sorted(self.rows.values(), key=lambda r: rank.get(r["id"], len(rank)))
        columns = [*HEAD, *self.override_columns, *TAIL]
        write_atomically(self.path, lambda f: _write_csv(f, columns, rows))


def _write_csv(f, columns: list[str], rows: list[dict[str, str]]) -> None:
    writer = csv.DictWriter(f, fieldnames=columns, restval="")
    writer.writeheader()
    writer.writerows(rows)


def _umask() -> int:
    """The process's umask: `/proc/self/status` where Linux gives it, else
    set and restored (at import, before any thread of this package)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    except (OSError, ValueError, IndexError):
        pass
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


#: The mode of the files a sweep writes: that of a file the runs create.
_FILE_MODE = 0o666 & ~_umask()


def write_atomically(path: Path, write) -> None:
    """Calls `write(file)` on a temporary text file beside `path`, flushes it
    to disk and renames it to `path` (then flushes the folder, so the rename
    survives a power cut); on any error the temporary file is removed and
    `path` is untouched."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        os.fchmod(fd, _FILE_MODE)
        with os.fdopen(fd, "w", newline="") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    folder = os.open(path.parent, os.O_RDONLY)
    try:
        os.fsync(folder)
    finally:
        os.close(folder)


def write_json(path: Path, value: Any) -> None:
    """`value` as JSON in `path`, atomically."""
    write_atomically(path, lambda f: json.dump(value, f, indent=1))
