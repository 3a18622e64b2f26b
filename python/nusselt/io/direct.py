"""Writing a big file past the page cache (``O_DIRECT``), where the system allows it.

Why: a big result written the usual way is first copied into the kernel's page cache, and
that copy, into freshly allocated memory, was most of the system time of a whole
``nusselt matrix`` run: 0.25 to 0.95 s for the 378 MB result of the 6 144-patch cube, where
writing the same bytes with ``O_DIRECT`` from one reused, page-aligned buffer took 0.05 to
0.1 s. The bytes go through the buffer in chunks of :data:`CHUNK` (every write then has the
alignment ``O_DIRECT`` needs), the last chunk padded with zeros and the file cut back to its
length. Where ``O_DIRECT`` is missing (macOS, Windows) or refused (a file system without it),
the same chunks are written the usual way: the bytes on disk are the same either way.

The file is written sequentially and cannot seek (``zipfile`` then writes a data descriptor
after each entry instead of going back to its header). Durability (fsync, rename) is the
caller's: :func:`nusselt.io.atomic.atomic_path`.
"""

from __future__ import annotations

import contextlib
import errno
import io
import mmap
import os

import numpy as np

#: Bytes per write: a multiple of every block size O_DIRECT asks alignment to.
CHUNK = 1 << 23
#: Smaller files are written the usual way: nothing to gain, and they stay in the cache.
MIN_BYTES = 1 << 25
_ALIGN = 1 << 12


class DirectWriter(io.RawIOBase):
    """A write-only, sequential binary file over an existing ``path`` (truncated), written
    with ``O_DIRECT`` where the system takes it (``direct`` says whether it did)."""

    def __init__(self, path: str | os.PathLike):
        super().__init__()
        flags = os.O_WRONLY | os.O_TRUNC | getattr(os, "O_BINARY", 0)
        direct = getattr(os, "O_DIRECT", 0)
        self.direct = bool(direct)
        self._fd = -1
        if direct:
            try:
                self._fd = os.open(path, flags | direct)
            except OSError as e:
                if e.errno != errno.EINVAL:
                    raise
                self.direct = False  # a file system without O_DIRECT
        if self._fd < 0:
            self._fd = os.open(path, flags)
        self._map = mmap.mmap(-1, CHUNK)  # page-aligned
        self._buf = np.frombuffer(self._map, dtype=np.uint8)
        self._fill = 0  # bytes waiting in the buffer
        self._written = 0  # bytes written to the file

    def writable(self) -> bool:
        return True

    def tell(self) -> int:
        return self._written + self._fill

    def write(self, b) -> int:
        src = np.frombuffer(b, dtype=np.uint8) if not isinstance(b, np.ndarray) else b.reshape(-1).view(np.uint8)
        n, at = src.size, 0
        while at < n:
            k = min(CHUNK - self._fill, n - at)
            self._buf[self._fill : self._fill + k] = src[at : at + k]
            self._fill += k
            at += k
            if self._fill == CHUNK:
                self._write_out(CHUNK)
        return n

    def _write_out(self, length: int) -> None:
        view = memoryview(self._map)[:length]
        try:
            done = 0
            while done < length:
                try:
                    done += os.write(self._fd, view[done:])
                except OSError as e:
                    if not (self.direct and e.errno == errno.EINVAL):
                        raise
                    self._buffered()  # refused at write time (alignment): the usual way
        finally:
            view.release()
        self._written += self._fill
        self._fill = 0

    def _buffered(self) -> None:
        import fcntl

        fcntl.fcntl(self._fd, fcntl.F_SETFL, fcntl.fcntl(self._fd, fcntl.F_GETFL) & ~os.O_DIRECT)
        self.direct = False

    def close(self) -> None:
        if self.closed:
            return
        try:
            if self._fd >= 0 and self._fill:
                size = self._written + self._fill
                if self.direct:  # whole aligned blocks, then cut to the length
                    padded = -(-self._fill // _ALIGN) * _ALIGN
                    self._buf[self._fill : padded] = 0
                    self._write_out(padded)
                    os.ftruncate(self._fd, size)
                else:
                    self._write_out(self._fill)
                self._written = size
        finally:
            with contextlib.suppress(OSError):
                os.close(self._fd)
            self._fd = -1
            self._buf = np.empty(0, dtype=np.uint8)
            self._map.close()
            super().close()
