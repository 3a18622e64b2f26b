"""Assembly of finished row blocks into the result's CSR matrix, with bounded memory.

Pair methods return the upper triangle of the symmetric G_ij = A_i F_ij; the core's
``mirror_pairs`` mirrors it and divides each row by its area in one pass (F_ij = G_ij / A_i,
F_ji = G_ij / A_j), once per run. Row methods return whole rows of F, copied block by block
into the final arrays (each block is released as soon as it is copied). A sparse threshold is
applied to each pair block as it arrives, so what is dropped never reaches the result.
"""

from __future__ import annotations

import numpy as np

from . import _core
from ._sparse import Csr, as_scipy
from .blocks import Block


def compact_row_block(b: Block) -> Block:
    """A row-method block as it is kept: int32 columns when they fit, and no standard-error
    array when the method has none (the core marks those NaN)."""
    idx = b.indices
    if idx.dtype != np.int32 and (idx.size == 0 or int(idx.max()) <= np.iinfo(np.int32).max):
        idx = idx.astype(np.int32)
    std = b.std
    if std is not None and (std.size == 0 or np.isnan(std).all()):
        std = None
    return Block(b.rows, b.indptr, idx, b.data, std, b.lost)


def threshold_pair_block(b: Block, areas: np.ndarray, threshold: float, dropped: np.ndarray) -> Block:
    """Drops the pairs of an upper-triangle block whose F_ij = G_ij / A_i and F_ji = G_ij / A_j
    are both below ``threshold`` (the same divisions as the mirror, so the decision is the one
    the full matrix would give); adds the dropped F to ``dropped`` (per scene face, both rows)."""
    if threshold <= 0.0 or b.data.size == 0:
        return b
    row_of = np.repeat(b.rows, np.diff(b.indptr))
    cols = b.indices.astype(np.int64)
    fi, fj = b.data / areas[row_of], b.data / areas[cols]
    keep = (fi >= threshold) | (fj >= threshold)
    if keep.all():
        return b
    gone = ~keep
    dropped += np.bincount(row_of[gone], weights=fi[gone], minlength=len(dropped))
    dropped += np.bincount(cols[gone], weights=fj[gone], minlength=len(dropped))
    kept_before = np.zeros(keep.size + 1, dtype=np.int64)
    np.cumsum(keep, out=kept_before[1:])
    indptr = kept_before[b.indptr]
    std = b.std[keep] if b.std is not None else None
    return Block(b.rows, indptr, b.indices[keep], b.data[keep], std, b.lost)


def canonical_csr(data: np.ndarray, idx: np.ndarray, indptr: np.ndarray, nr: int) -> Csr:
    """The result's matrix over the given parts, without copies and without scipy (sorted,
    no duplicates: the caller's promise); :meth:`Csr.to_scipy` wraps it for scipy."""
    return Csr(data, idx, indptr, nr)


def pair_reciprocity(done: list[Block], scene_areas: np.ndarray, dtype=np.float64) -> float:
    """The reciprocity error max |A_i F_ij - A_j F_ji| / max(|A_i F_ij|, |A_j F_ji|) of the
    matrix the mirror will build from these upper-triangle blocks, from the blocks themselves
    in the core (the same divisions, F_ij = G_ij / A_i and F_ji = G_ij / A_j, and the same
    rounding to ``dtype``), so it needs no transpose of the result; :mod:`nusselt.trust`
    computes the same measure from any matrix, and a test checks they agree."""
    blocks = [(b.rows, b.indptr, np.asarray(b.indices, dtype=np.int32), b.data) for b in done if b.data.size]
    areas = np.ascontiguousarray(scene_areas, dtype=np.float64)
    return _core.pair_reciprocity(areas, blocks, np.dtype(dtype) == np.float32)


#: Arrays from this many bytes on get their pages mapped at once (see :func:`mapped_zeros`).
MAPPED_BYTES = 1 << 24


def mapped_zeros(count: int, dtype) -> np.ndarray:
    """The mirror's output arrays, ``count`` zeros. A big one is an anonymous mapping whose
    pages are all mapped when it is made (``MAP_POPULATE``): one by one, first touches cost
    the most system time of the mirror, and numpy's own arrays (huge pages asked of the
    kernel) vary most with the host's state. The mirror phase of the 6 144-patch cube
    (377 MB), user+sys, 4 runs each alternating: populated 0.41-0.47 s, 4 KiB pages touched
    one by one 0.48-0.74, np.zeros 0.48-1.22. Where the system lacks it: np.zeros."""
    import mmap

    dt = np.dtype(dtype)
    nbytes = int(count) * dt.itemsize
    populate = getattr(mmap, "MAP_POPULATE", 0)
    if nbytes < MAPPED_BYTES or not populate or not hasattr(mmap, "MAP_ANONYMOUS"):
        return np.zeros(count, dtype=dt)
    try:
        buf = mmap.mmap(-1, nbytes, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS | populate)
    except OSError as e:  # the mapping refused: out of memory, as np.zeros would say
        raise MemoryError(f"cannot map {nbytes / 2**20:.0f} MiB for the result ({e})") from None
    return np.frombuffer(buf, dtype=dt)  # the array keeps the mapping alive


def assemble_pairs(done: list[Block], col_of: np.ndarray, areas: np.ndarray, dtype=np.float64):
    """(F, std of F or None) from upper-triangle blocks of G; ``done`` is emptied as the
    blocks are handed over (so their memory goes once the mirror has copied them)."""
    nr = len(areas)
    # column indices are int32 (blocks of older checkpoints may hold int64: converted)
    blocks = [(b.rows, b.indptr, np.asarray(b.indices, dtype=np.int32), b.data, b.std) for b in done]
    done.clear()
    float32 = np.dtype(dtype) == np.float32  # divided in float64, written as float32 at once
    areas = np.ascontiguousarray(areas, dtype=np.float64)
    indptr, idx, f, sd = _core.mirror_pairs(areas, col_of, blocks, float32, mapped_zeros)
    del blocks
    matrix = canonical_csr(f, idx, indptr, nr)
    std = canonical_csr(sd, idx, indptr, nr).to_scipy() if sd is not None else None
    return matrix, std


def assemble_rows(done: list[Block], col_of: np.ndarray, nr: int, dtype=np.float64):
    """(F, std or None, lost or None) from whole-row blocks over receiver indices; ``done`` is
    emptied block by block as each is copied into the final arrays. F is a :class:`Csr`
    (a scipy array where the rows needed sorting), std a scipy array."""
    counts = np.zeros(nr, dtype=np.int64)
    with_std = any(b.std is not None for b in done)
    with_lost = bool(done) and done[0].lost is not None
    for b in done:
        counts[col_of[b.rows]] = np.diff(b.indptr)
    indptr = np.zeros(nr + 1, dtype=np.int64)
    np.cumsum(counts, out=indptr[1:])
    nnz = int(indptr[-1])
    idx = np.empty(nnz, dtype=np.int32 if nr <= np.iinfo(np.int32).max else np.int64)
    val = np.empty(nnz, dtype=dtype)
    sd = np.zeros(nnz, dtype=dtype) if with_std else None
    lost = np.zeros(nr) if with_lost else None
    while done:
        b = done.pop(0)
        r = col_of[b.rows]
        if len(r) and np.all(np.diff(r) == 1):  # the usual case: one contiguous run of rows
            s, e = indptr[r[0]], indptr[r[-1] + 1]
            idx[s:e], val[s:e] = col_of[b.indices], b.data
            if sd is not None and b.std is not None:
                sd[s:e] = np.nan_to_num(b.std)
        else:
            for k, row in enumerate(r):
                s, e, bs, be = indptr[row], indptr[row + 1], b.indptr[k], b.indptr[k + 1]
                idx[s:e], val[s:e] = col_of[b.indices[bs:be]], b.data[bs:be]
                if sd is not None and b.std is not None:
                    sd[s:e] = np.nan_to_num(b.std[bs:be])
        if lost is not None and b.lost is not None:
            lost[r] = b.lost
        del b
    if _rows_ascend(idx, indptr):  # row methods return rows sorted; this checks
        std = canonical_csr(sd, idx, indptr, nr).to_scipy() if sd is not None else None
        return canonical_csr(val, idx, indptr, nr), std, lost
    import scipy.sparse as sp

    matrix = sp.csr_array((val, idx, indptr), shape=(nr, nr))
    matrix.sum_duplicates()
    std = None
    if sd is not None:
        std = sp.csr_array((sd, idx, indptr), shape=(nr, nr))
        std.sum_duplicates()
    return matrix, std, lost


def _rows_ascend(idx: np.ndarray, indptr: np.ndarray, chunk: int = 1 << 22) -> bool:
    """Whether the columns of every row ascend strictly (checked by chunks: bounded memory)."""
    starts = np.zeros(len(idx) + 1, dtype=bool)
    starts[indptr] = True  # positions where a row begins (its first entry has no predecessor)
    for s in range(1, len(idx), chunk):
        e = min(s + chunk, len(idx))
        if np.any((idx[s:e] <= idx[s - 1 : e - 1]) & ~starts[s:e]):
            return False
    return True


def threshold_matrix(matrix, std, threshold: float):
    """Row-method results: drop a pair when both F_ij and F_ji are below ``threshold`` (needs
    both rows, so it is applied to the whole matrix). Returns (matrix, std, largest row mass
    dropped)."""
    import scipy.sparse as sp

    matrix = as_scipy(matrix)

    big = (matrix >= threshold).astype(np.int8)
    keep = (big + big.T).tocsr()
    kept = sp.csr_array(matrix.multiply(keep > 0).tocsr())
    kept.sort_indices()
    nr = matrix.shape[0]
    dropped = float(np.max(matrix.sum(axis=1) - kept.sum(axis=1))) if nr else 0.0
    if std is not None:
        std = sp.csr_array(std.multiply(keep > 0).tocsr())
    return kept, std, dropped
