"""Where the time of a lattice step goes: `perf record` of the CLI running
the built-in 1000-rotor dipole lattice on one thread with NO_SQUISH (the
scene's own recording: energies every 10 steps, a trajectory frame every
50), reported as the share of samples per function."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

BINARY = Path("target/release/quatrot")
STEPS = 3000
SHARE_FLOOR = 1.0  # percent: functions below this are left out


def hot_functions() -> dict | None:
    """``{"command": ..., "functions": [(percent, symbol), ...]}``, or None
    without perf or the release binary."""
    if shutil.which("perf") is None or not BINARY.exists():
        return None
    with tempfile.TemporaryDirectory() as tmp:
        data = Path(tmp) / "perf.data"
        command = [str(BINARY), "run", "dipole_lattice_sc_cutoff", "--integrator", "no_squish", "--steps", str(STEPS), "--out", tmp]
        env = {**os.environ, "RAYON_NUM_THREADS": "1"}
        record = subprocess.run(["perf", "record", "-q", "-o", str(data), "--", *command], env=env, capture_output=True, text=True)
        if record.returncode != 0:
            return None
        report = subprocess.run(
            ["perf", "report", "-i", str(data), "--no-children", "--sort", "symbol", "--stdio", "-q"],
            capture_output=True,
            text=True,
        )
    functions = []
    for line in report.stdout.splitlines():
        m = re.match(r"\s*([\d.]+)%\s+\[\.\]\s+(.*)", line)
        if m and float(m.group(1)) >= SHARE_FLOOR:
            functions.append((float(m.group(1)), re.split(r"\s{2,}", m.group(2).strip())[0]))
    return {"command": "RAYON_NUM_THREADS=1 perf record -- " + " ".join(command[:-2]), "functions": functions}
