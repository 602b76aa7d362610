"""Packaging (issue 17 item 5): the wheel maturin builds from this tree
installs into a fresh plain virtual environment (not the suite's, no
system site-packages) with its declared dependencies, carries no debug
info, and `python -m quatrot` (and the `quatrot` script) run the command
line: `scenes` and one short run. About 20 s when the extension is built
(maturin reuses `make develop`'s build) and pip's cache holds numpy."""

import json
import os
import shutil
import struct
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
# Local wheels pip may use besides its index and cache.
WHEELS = Path("/opt/wheels")


def section_names(elf: bytes) -> list[str]:
    """The section names of a 64-bit little-endian ELF file (its header table)."""
    assert elf[:4] == b"\x7fELF" and elf[4] == 2 and elf[5] == 1
    shoff, = struct.unpack_from("<Q", elf, 0x28)
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", elf, 0x3A)
    headers = [elf[shoff + k * shentsize: shoff + (k + 1) * shentsize] for k in range(shnum)]
    strings_offset, = struct.unpack_from("<Q", headers[shstrndx], 0x18)
    names = []
    for h in headers:
        name, = struct.unpack_from("<I", h, 0)
        start = strings_offset + name
        names.append(elf[start: elf.index(b"\0", start)].decode())
    return names


def run(*args, **kwargs):
    return subprocess.run(args, check=True, capture_output=True, text=True, timeout=900, **kwargs)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(wheel, python of a fresh venv with the wheel installed)."""
    maturin = shutil.which("maturin", path=str(Path(sys.executable).parent))
    if maturin is None:
        pytest.skip("maturin is not installed beside this Python")
    tmp = tmp_path_factory.mktemp("packaging")
    env = os.environ | {"VIRTUAL_ENV": str(Path(sys.executable).parent.parent)}
    run(maturin, "build", "--release", "--quiet", "-o", str(tmp / "dist"), cwd=ROOT, env=env)
    (wheel,) = (tmp / "dist").glob("quatrot-*.whl")
    run(sys.executable, "-m", "venv", str(tmp / "venv"))
    python = tmp / "venv" / "bin" / "python"
    links = ["--find-links", str(WHEELS)] if WHEELS.is_dir() else []
    clean = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "PYTHONPATH")}
    run(str(python), "-m", "pip", "install", "--quiet", *links, str(wheel), env=clean)
    return wheel, python, clean


def test_the_wheel_has_no_debug_info_and_declares_numpy(installed):
    wheel, _, _ = installed
    with zipfile.ZipFile(wheel) as z:
        (native,) = [n for n in z.namelist() if n.startswith("quatrot/_native.") and not n.endswith(".pyi")]
        library = z.read(native)
        metadata = z.read(next(n for n in z.namelist() if n.endswith("METADATA"))).decode()
        # The type stubs ship with the module, so editors see the signatures.
        assert {"quatrot/_native.pyi", "quatrot/quaternion.pyi", "quatrot/py.typed"} <= set(z.namelist())
    sections = section_names(library)
    assert ".text" in sections and ".dynsym" in sections  # the table was read
    assert not [n for n in sections if n.startswith((".debug", ".zdebug"))], sections
    assert "Requires-Dist: numpy" in metadata


def test_python_m_quatrot_runs_the_command_line(installed, tmp_path):
    _, python, env = installed
    # Outside the source tree, so that only the installed package can be imported.
    scenes = run(str(python), "-m", "quatrot", "scenes", cwd=tmp_path, env=env).stdout
    assert "dipole_in_field" in scenes
    out = tmp_path / "out"
    run(str(python), "-m", "quatrot", "run", "dipole_in_field", "--steps", "100", "--out", str(out), cwd=tmp_path, env=env)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "completed" and summary["last_step"] == 100
    script = python.parent / "quatrot"
    assert "dipole_in_field" in run(str(script), "scenes", cwd=tmp_path, env=env).stdout
    origin = run(str(python), "-c", "import quatrot; print(quatrot.__file__)", cwd=tmp_path, env=env).stdout
    assert str(python.parent.parent) in origin
    usage = subprocess.run([str(python), "-m", "quatrot", "--bogus"], capture_output=True, text=True, cwd=tmp_path, env=env)
    assert usage.returncode == 2 and "unexpected argument '--bogus'" in usage.stderr
