"""Work trees of the mutation runs: copies of the project's tracked files."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def sync_tree(tree: Path) -> Path:
    """Makes ``tree`` hold the tracked files of the source tree as they are
    in the working tree, rewriting only those that differ, so that a build
    there stays warm: cargo's fingerprints of the others hold, and a
    rewritten file is newer than the last build (a file left mutated by an
    interrupted run, restored, is rebuilt rather than taken for unchanged)."""
    listed = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, check=True, capture_output=True, text=True).stdout
    for name in filter(None, listed.split("\0")):
        source, copy = ROOT / name, tree / name
        if not source.is_file():
            continue
        if copy.is_file() and copy.read_bytes() == source.read_bytes():
            continue
        copy.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, copy)
        shutil.copymode(source, copy)
    return tree
