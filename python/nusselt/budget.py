"""Will a run fit? Memory and disk of a result, estimated and checked before any work.

A row of F holds at most n - 1 nonzero entries, so a run of n receivers has at most
n (n - 1) entries. With a sparse threshold t a pair is kept only if F_ij >= t or F_ji >= t;
as a row sums to at most 1 (plus the method's error, for which 10 % is allowed here), at most
1.1 / t entries of a row reach t, so at most 2.2 n / t entries are kept: the threshold bounds
the result whatever the geometry. Pair methods apply it to each block as it arrives
(:mod:`nusselt.assembly`), so it bounds their memory too; row methods threshold the whole
matrix, so their memory is bounded by n (n - 1).

Most scenes hold far fewer: two patches exchange radiation only if each lies, at least in
part, in front of the other (a roof above everything sees nothing; the ground sees only
walls: 8 % of the pairs of the urban grid). :func:`estimated_entries` counts, for a sample of
rows, the receivers whose centroid and its own lie strictly in front of each other, and
scales the sample's mean (plus three standard errors, plus 25 % for pairs that face only in
part) to all rows; the check uses that estimate, never more than the bound above.

Bytes per entry at the peak (index int32, value float64 = 12 bytes; +8 with standard errors):
pair methods hold the upper-triangle blocks (half the entries, float64) while the mirror
writes the full matrix in the stored type: 0.5 x 12 + 1 x 12 (float32: + 1 x 8); row methods
copy blocks into the final arrays one by one: about 1 x plus one block, and the threshold of
a whole matrix needs about 3 x more.
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


#: Rows sampled by :func:`estimated_entries` (evenly spaced over the receivers).
SAMPLE_ROWS = 256
#: Entries of the (receivers x sample rows) tables of one pass of the facing test.
_CHUNK = 1 << 22


def estimated_entries(scene, recv: np.ndarray | None = None, sample: int = SAMPLE_ROWS) -> int:
    """About how many nonzero entries the matrix of ``scene`` over receivers ``recv`` holds,
    from a facing test of a sample of rows (see the module docstring); an overestimate for
    scenes with obstructions, which remove pairs the test keeps. Scenes of at most
    ``sample`` rows count every row."""
    recv = np.arange(len(scene)) if recv is None else np.asarray(recv, dtype=np.int64)
    n = len(recv)
    if n < 2:
        return 0
    rows = recv if n <= sample else recv[np.unique(np.linspace(0, n - 1, sample).astype(np.int64))]
    c = np.asarray(scene.centroids, dtype=np.float64)
    c = c - c.mean(axis=0)  # small coordinates: the products below lose less to rounding
    nrm = np.asarray(scene.normals, dtype=np.float64)
    tol = 1e-9 * (float(np.linalg.norm(np.ptp(scene.vertices, axis=0))) or 1.0)
    cc, nc = c[recv], nrm[recv]
    own = np.einsum("kj,kj->k", cc, nc)  # c_k . n_k
    counts = np.zeros(len(rows), dtype=np.int64)
    step = max(1, _CHUNK // n)
    for s in range(0, len(rows), step):
        r = rows[s : s + step]
        # receiver k is ahead of row r: (c_k - c_r) . n_r > 0; r is ahead of k: (c_r - c_k) . n_k > 0
        ahead = cc @ nrm[r].T - np.einsum("rj,rj->r", c[r], nrm[r])[None, :] > tol
        ahead &= own[:, None] - nc @ c[r].T < -tol
        counts[s : s + step] = np.count_nonzero(ahead, axis=0)
    if len(rows) == n:
        return int(counts.sum())
    mean = float(counts.mean())
    se = float(counts.std(ddof=1)) / math.sqrt(len(rows))
    per_row = min(n - 1.0, 1.25 * (mean + 3.0 * se))
    return int(math.ceil(per_row * n))


def peak_bytes(
    n: int, *, kind: str, threshold: float = 0.0, dtype=np.float64, with_std: bool = False, entries: int | None = None
) -> int:
    """Bytes a run of n receivers holds at its peak (blocks plus result), for ``entries``
    nonzero entries (default: the most it can hold, :func:`max_entries`)."""
    e = max_entries(n, threshold, kind)
    if entries is not None:
        e = min(e, int(entries))
    per = entry_bytes(np.float64, with_std)  # the blocks hold float64
    if kind == "pairs":
        # the upper-triangle blocks (half the entries) and the result the mirror writes
        peak = e * per // 2 + e * entry_bytes(dtype, with_std)
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


def check_memory(
    n: int, *, kind: str, threshold: float, dtype, with_std: bool, dense: bool = False, scene=None, recv=None
) -> None:
    """Raises MemoryError, with the numbers and what to change, when the run does not fit:
    its most entries, or, given the ``scene``, the entries :func:`estimated_entries` expects."""
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
    sizes = {"kind": kind, "threshold": threshold, "dtype": dtype, "with_std": with_std}
    need = peak_bytes(n, **sizes)
    if need <= avail:
        return
    most = max_entries(n, threshold, kind)
    what = f"may hold {most:,} entries"
    if scene is not None:
        expect = estimated_entries(scene, recv)
        need = peak_bytes(n, entries=expect, **sizes)
        if need <= avail:
            return
        what = (
            f"is expected to hold about {min(expect, most):,} entries (facing pairs of sampled rows; at most {most:,})"
        )
    hint = (
        "a sparse threshold (threshold=/--threshold, e.g. 1e-4) bounds a pair method's result at "
        "2.2 n / threshold entries"
        if kind == "pairs"
        else "a row method keeps every entry it finds; use a pair method with a threshold, or fewer patches"
    )
    raise MemoryError(
        f"the result of {n} receivers {what}, about {_gib(need)} at the peak, but {_gib(avail)} are available: "
        f"{hint}; float32 values (dtype=float32/--float32) save a third; or call "
        "form_factors(..., check_memory=False) if you know most pairs cannot see each other"
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
