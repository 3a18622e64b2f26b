"""Will a run fit? Worst-case memory and disk of a result, checked before any work.

A row of F holds at most n - 1 nonzero entries, so a run of n receivers has at most
n (n - 1) entries. With a sparse threshold t a pair is kept only if F_ij >= t or F_ji >= t;
as a row sums to at most 1 (plus the method's error, for which 10 % is allowed here), at most
1.1 / t entries of a row reach t, so at most 2.2 n / t entries are kept: the threshold bounds
the result whatever the geometry. Pair methods apply it to each block as it arrives
(:mod:`nusselt.assembly`), so it bounds their memory too; row methods threshold the whole
matrix, so their memory is bounded by n (n - 1).

Bytes per entry at the peak (index int32, value float64 = 12 bytes; +8 with standard errors):
pair methods hold the upper-triangle blocks (half the entries) while the mirror writes the
full matrix: 1.5 x; row methods copy blocks into the final arrays one by one: about 1 x plus
one block, and the threshold of a whole matrix needs about 3 x more.
"""

from __future__ import annotations

import math
import os

import numpy as np


def max_entries(n: int, threshold: float = 0.0, kind: str = "pairs") -> int:
    """Most nonzero entries an n-receiver result can hold (see the module docstring)."""
    full = n * max(n - 1, 0)
    if threshold > 0.0 and kind == "pairs":
        return min(full, math.ceil(2.2 * n / threshold))
    return full


def entry_bytes(dtype=np.float64, with_std: bool = False) -> int:
    v = np.dtype(dtype).itemsize
    return 4 + v + (v if with_std else 0)


def peak_bytes(n: int, *, kind: str, threshold: float = 0.0, dtype=np.float64, with_std: bool = False) -> int:
    """Worst-case bytes a run of n receivers holds at its peak (blocks plus result)."""
    e = max_entries(n, threshold, kind)
    per = entry_bytes(np.float64, with_std)  # blocks and the mirror work in float64
    if kind == "pairs":
        # full-n upper blocks (before the threshold of a block: one block's worth extra)
        peak = e * per * 3 // 2 + (e * entry_bytes(dtype, with_std) if np.dtype(dtype) != np.float64 else 0)
    else:
        peak = e * (per + entry_bytes(dtype, with_std)) if threshold <= 0 else 4 * e * per
    return int(peak + 16 * n)


def file_bytes(n: int, *, kind: str, threshold: float = 0.0, dtype=np.float64, with_std: bool = False) -> int:
    """Worst-case size of the result's uncompressed ``.npz`` (matrix, std, areas, names)."""
    return int(max_entries(n, threshold, kind) * entry_bytes(dtype, with_std) + 64 * n)


def available_memory() -> int | None:
    """Bytes this process may still allocate: the least of the system's available memory
    (MemAvailable), a cgroup limit, and an address-space limit (RLIMIT_AS); None if unknown."""
    limits = []
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    limits.append(int(line.split()[1]) * 1024)
                    break
    except OSError:
        try:
            limits.append(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (ValueError, OSError, AttributeError):
            pass
    try:
        with open("/sys/fs/cgroup/memory.max") as fh:
            cap = fh.read().strip()
        if cap != "max":
            with open("/sys/fs/cgroup/memory.current") as fh:
                limits.append(int(cap) - int(fh.read().strip()))
    except (OSError, ValueError):
        pass
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft not in (resource.RLIM_INFINITY, -1):
            with open("/proc/self/statm") as fh:
                used = int(fh.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
            limits.append(soft - used)
    except (ImportError, OSError, ValueError, AttributeError):
        pass
    return max(0, min(limits)) if limits else None


def _gib(b: float) -> str:
    return f"{b / 2**30:.2f} GiB" if b >= 2**28 else f"{b / 2**20:.1f} MiB"


def check_memory(n: int, *, kind: str, threshold: float, dtype, with_std: bool, dense: bool = False) -> None:
    """Raises MemoryError, with the numbers and what to change, when the worst case does not fit."""
    avail = available_memory()
    if avail is None:
        return
    if dense:
        need = 2 * n * n * np.dtype(dtype).itemsize
        if need > avail:
            raise MemoryError(
                f"a dense {n} x {n} matrix needs about {_gib(need)} but {_gib(avail)} are available; "
                "use the sparse result (dense=False)"
            )
    need = peak_bytes(n, kind=kind, threshold=threshold, dtype=dtype, with_std=with_std)
    if need > avail:
        hint = (
            "a sparse threshold (threshold=/--threshold, e.g. 1e-4) bounds a pair method's result at "
            "2.2 n / threshold entries"
            if kind == "pairs"
            else "a row method keeps every entry it finds; use a pair method with a threshold, or fewer patches"
        )
        raise MemoryError(
            f"the result of {n} receivers may hold {max_entries(n, threshold, kind):,} entries, about {_gib(need)} "
            f"at the peak, but {_gib(avail)} are available: {hint}; float32 values (dtype=float32/--float32) save "
            "a third; or call form_factors(..., check_memory=False) if you know most pairs cannot see each other"
        )


def check_disk(
    path: str, n: int, *, kind: str, threshold: float, dtype, with_std: bool, checkpoint: bool = True
) -> None:
    """Raises OSError when the worst-case output (plus its checkpoint) does not fit on disk."""
    d = os.path.dirname(os.path.abspath(path))
    try:
        import shutil

        free = shutil.disk_usage(d).free
    except OSError:
        return
    result = file_bytes(n, kind=kind, threshold=threshold, dtype=dtype, with_std=with_std)
    held = 0
    if checkpoint:
        # the checkpoint keeps every block as computed, before any threshold (a resume may
        # choose another one): the upper triangle for pair methods, whole rows otherwise
        e = max_entries(n, 0.0, kind)
        held = (e // 2 if kind == "pairs" else e) * entry_bytes(np.float64, with_std)
    if result + held > free:
        raise OSError(
            f"{path}: the run may need {_gib(result + held)} on disk ({_gib(result)} for the result, "
            f"{_gib(held)} for its checkpoint of finished blocks) but {_gib(free)} are free in {d}; "
            "--threshold and --float32 make the result smaller (--compress smaller still); the checkpoint "
            "needs a disk with room for every pair"
        )
