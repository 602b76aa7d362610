"""The sweep's folder: locked for the sweep's lifetime, written only inside.

* The lock is an advisory `flock` on `LOCK_FILE` in the folder (the file a
  run locks its folder with, recording the holder's process id). The kernel
  releases it when the process ends, however it ends, so a stale lock cannot
  outlive its sweep; a second sweep on the folder is refused naming the
  holder. (`flock` may not be honoured across machines on network file
  systems.)
* Nothing is created or written through a symbolic link inside the folder:
  the lock file, `runs/` and each run's folder must be what they seem (a
  link there is refused, never followed or emptied); the table and the
  runs' `result.json` are replaced by rename, which replaces a link rather
  than writing through it.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import stat
from collections.abc import Iterator
from pathlib import Path

#: The lock file in the sweep's folder (the name a run's folder uses too).
LOCK_FILE = ".quatrot.lock"


class FolderInUse(OSError):
    """Another process holds the sweep folder's lock.

    Examples
    --------
    >>> issubclass(quatrot.sweep.FolderInUse, OSError)
    True
    """


def sweep_folder(out: str | os.PathLike) -> Path:
    """The sweep's folder `out` as an absolute path; an empty path is
    refused (as a run's is: it would be the current directory unsaid)."""
    if not os.fspath(out):
        raise ValueError("out: a sweep folder's path must not be empty (\".\" is the current directory)")
    return Path(out).resolve()


def refuse_link(path: Path) -> None:
    """An `OSError` naming `path` if it is a symbolic link."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return
    if stat.S_ISLNK(mode):
        raise OSError(f"{path}: is a symbolic link; a sweep writes only inside its folder, never through a link")


def real_folder(path: Path) -> Path:
    """`path` as a folder, created if missing, refused if it is a symbolic
    link (or anything but a folder)."""
    refuse_link(path)
    path.mkdir(parents=True, exist_ok=True)
    refuse_link(path)  # created by another process meanwhile
    return path


@contextlib.contextmanager
def locked(out: Path) -> Iterator[Path]:
    """Creates the folder `out` if missing and holds its lock while the
    context lasts, or raises `FolderInUse` naming the holder's process."""
    out.mkdir(parents=True, exist_ok=True)
    path = out / LOCK_FILE
    refuse_link(path)
    fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC, 0o666)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 32).decode(errors="replace").strip()
            who = f"process {holder}" if holder.isdigit() else "another process"
            raise FolderInUse(
                f"{out}: the sweep folder is in use by {who} (one sweep per folder: "
                "start it again once that one has stopped, and it resumes; or choose another --out)"
            ) from None
        os.ftruncate(fd, 0)
        os.pwrite(fd, str(os.getpid()).encode(), 0)
        yield out
    finally:
        os.close(fd)
