"""Row blocks: how a scene-wide run is cut into pieces, and the loop that computes them.

The core computes one block of rows per call with the GIL released and all cores busy. Between
blocks this loop updates the progress bar, lets Python raise KeyboardInterrupt, and (with a
checkpoint, :mod:`nusselt.checkpoint`) writes the finished block to disk, so that a run killed
at any moment resumes without losing or changing finished work: the block boundaries depend
only on the scene and the block size, and every method is deterministic for a given seed.
The same blocks are the tasks of a distributed run (:mod:`nusselt.distributed`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from .checkpoint import Checkpoint


@dataclass
class Block:
    """One finished block: CSR parts over its rows (scene face ids as rows and columns).

    Pair methods: the upper triangle of G_ij = A_i F_ij (columns j > i); row methods: whole
    rows of F. ``std`` holds standard errors of the values (None for exact methods), ``lost``
    the hemisphere fraction each row of a row method left unassigned."""

    rows: np.ndarray
    indptr: np.ndarray
    indices: np.ndarray
    data: np.ndarray
    std: np.ndarray | None = None
    lost: np.ndarray | None = None

    @property
    def nbytes(self) -> int:
        return sum(
            a.nbytes for a in (self.rows, self.indptr, self.indices, self.data, self.std, self.lost) if a is not None
        )


def plan_blocks(recv: np.ndarray, kind: str, block_size: int) -> list[np.ndarray]:
    """Row blocks. Pair methods: about ``block_size`` upper-triangle pairs per block (row k
    has n-k-1 pairs); row methods: about ``block_size`` / n rows per block."""
    n = len(recv)
    if n == 0:
        return []
    if kind == "rows":
        per = max(1, block_size // max(n, 1))
        return [np.ascontiguousarray(recv[s : s + per]) for s in range(0, n, per)]
    blocks, start, pairs = [], 0, 0
    for k in range(n):
        pairs += n - k - 1
        if pairs >= block_size or k == n - 1:
            blocks.append(np.ascontiguousarray(recv[start : k + 1], dtype=np.int64))
            start, pairs = k + 1, 0
    return blocks


def run_blocks(
    compute: Callable[[np.ndarray], Block],
    blocks: Sequence[np.ndarray],
    *,
    checkpoint: Checkpoint | None,
    progress_bar: Any = None,
    keep: Callable[[Block], Block] | None = None,
) -> list[Block]:
    """Computes (or loads from the checkpoint) every block in order; returns the Blocks, each
    passed through ``keep`` first if given (e.g. a sparse threshold: only what is kept stays in
    memory; the checkpoint holds the block as computed)."""
    done = []
    for k, rows in enumerate(blocks):
        b = checkpoint.load(k, rows) if checkpoint is not None else None
        if b is None:
            b = compute(rows)
            if checkpoint is not None:
                checkpoint.save(k, b)
        done.append(keep(b) if keep is not None else b)
        if progress_bar is not None:
            progress_bar.update(len(rows))
    return done
