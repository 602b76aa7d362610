"""The tutorial (docs/examples/tutorial_rotor_lattice.py) runs as a new user runs it,
from the command line in its quick mode, and its own assertions pass (the
``tutorial`` check runs the same code in full in ``make validate``)."""

import os
import subprocess
import sys
from pathlib import Path

TUTORIAL = Path(__file__).resolve().parents[2] / "docs" / "examples" / "tutorial_rotor_lattice.py"


def test_tutorial_runs_in_quick_mode(tmp_path):
    env = os.environ | {"QUATROT_TUTORIAL_QUICK": "1", "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, str(TUTORIAL), "--out", str(tmp_path)], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "C1 of the weakly coupled lattice vs the free top" in done.stdout
    assert (tmp_path / "tutorial_rotor_lattice.png").stat().st_size > 0
