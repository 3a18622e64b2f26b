"""Durable, atomic file replacement: a file is whole under its final name or not there at all.

A file is written under a temporary name in the target's own directory (a rename is atomic
only within one file system), flushed to disk (``fsync``), renamed over the target, and the
directory entry is flushed too, so neither a kill nor a power cut leaves a half-written file
under the final name. The temporary name says what it is and who wrote it::

    .<target name>.nusselt-<pid>-<random>.tmp

so a temporary left by a killed run is recognisable: the next write of the same target
removes those whose writing process is gone, and an exception removes its own at once.
The file is created with mode ``0o666`` less the umask, as ``open()`` would create it
(``tempfile.mkstemp`` would make it 0600 whatever the umask).
"""

from __future__ import annotations

import contextlib
import os
import re
from collections.abc import Iterator
from typing import IO

_TMP_TAG = ".nusselt-"


def _tmp_pattern(target: str) -> re.Pattern:
    return re.compile(re.escape("." + os.path.basename(target) + _TMP_TAG) + r"(\d+)-[0-9a-f]+\.tmp$")


def temp_name(target: str) -> str:
    """A fresh temporary path next to ``target`` (see the module docstring)."""
    d, base = os.path.split(os.path.abspath(target))
    return os.path.join(d, f".{base}{_TMP_TAG}{os.getpid()}-{os.urandom(4).hex()}.tmp")


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True  # exists (another user's), or cannot tell: leave its file alone
    return True


def remove_stale_temps(target: str) -> list[str]:
    """Removes the temporaries of ``target`` left by processes that no longer run; returns
    their paths. Temporaries of running processes (another writer) are left alone."""
    d = os.path.dirname(os.path.abspath(target))
    pat = _tmp_pattern(target)
    removed: list[str] = []
    try:
        names = os.listdir(d)
    except OSError:
        return removed
    for name in names:
        m = pat.match(name)
        if m and not _alive(int(m.group(1))):
            p = os.path.join(d, name)
            with contextlib.suppress(OSError):
                os.unlink(p)
                removed.append(p)
    return removed


def fsync_dir(path: str) -> None:
    """Flushes a directory's entries (a rename inside it) to disk, where the OS allows it."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:
        return  # e.g. Windows: directories cannot be opened; the rename is still atomic
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _create(tmp: str) -> int:
    # O_EXCL: never write through a name someone else made; 0o666: the umask applies
    return os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)


def commit(tmp: str, target: str) -> None:
    """fsync ``tmp``, rename it over ``target`` and fsync the directory."""
    fd = os.open(tmp, os.O_RDONLY | getattr(os, "O_BINARY", 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
    os.replace(tmp, target)
    fsync_dir(os.path.dirname(os.path.abspath(target)))


@contextlib.contextmanager
def atomic_path(target: str | os.PathLike) -> Iterator[str]:
    """Yields a temporary path for a writer that wants a file name (e.g. meshio); on success
    the file written there replaces ``target`` durably, on an exception it is removed."""
    target = os.fspath(target)
    remove_stale_temps(target)
    tmp = temp_name(target)
    os.close(_create(tmp))
    try:
        yield tmp
        commit(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


@contextlib.contextmanager
def atomic_open(target: str | os.PathLike, mode: str = "w") -> Iterator[IO]:
    """Opens a temporary file for writing (``"w"`` text as UTF-8 with untranslated newlines,
    or ``"wb"``); on success it replaces ``target`` durably, on an exception it is removed."""
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_open writes only ('w' or 'wb'), got mode {mode!r}")
    target = os.fspath(target)
    remove_stale_temps(target)
    tmp = temp_name(target)
    fd = _create(tmp)
    try:
        fh: IO = os.fdopen(fd, "wb") if mode == "wb" else os.fdopen(fd, "w", encoding="utf-8", newline="")
        with fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, target)
        fsync_dir(os.path.dirname(os.path.abspath(target)))
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
