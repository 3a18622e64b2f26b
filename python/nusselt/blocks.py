"""Row blocks: how a scene-wide run is cut into pieces, and the loop that computes them.

The core computes one block of rows per call with the GIL released and all cores busy. Between
blocks this loop updates the progress bar, lets Python raise KeyboardInterrupt, and (with a
checkpoint, :mod:`nusselt.checkpoint`) writes the finished block to disk, so that a run killed
at any moment resumes without losing or changing finished work.

A block is a contiguous run ``recv[start:stop]`` of the receivers. Local runs size blocks
from the measured throughput (:class:`Sizer`): the first is small, so the progress bar moves
within a fraction of a second, and later ones aim at :data:`TARGET_SECONDS` each, never above
``block_size`` units of work (the memory bound). Every pair and row is computed on its own
(sampled methods seed by row and sample, not by block), so where the boundaries fall changes
no value; a checkpoint stores each block's ``start`` and ``stop`` and a resumed run plans only
the rows its blocks do not hold. The blocks of a distributed run (:mod:`nusselt.distributed`)
have the fixed size ``block_size`` (:func:`plan_blocks`).
"""

from __future__ import annotations

import time
from collections.abc import Callable
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


#: What an adaptively sized block aims at, in wall-clock seconds: the progress bar moves, Ctrl-C
#: and a kill lose at most this much, and a block's fixed costs (a call into the core, writing
#: it to the checkpoint) stay small beside its work.
TARGET_SECONDS = 0.5
#: The first block's work (pairs; row methods: one row per core), before any throughput is known.
FIRST_PAIRS = 1024
#: A block is at most this many times larger than the one before (one fast block is no proof).
GROWTH = 4.0


def row_work(n: int, kind: str) -> np.ndarray:
    """Units of work of each receiver position: its upper-triangle pairs (pair methods; row k
    of n has n-k-1) or its n row entries (row methods), as ``block_size`` counts them."""
    if kind == "rows":
        return np.full(n, n, dtype=np.int64)
    return np.arange(n - 1, -1, -1, dtype=np.int64)


def plan_blocks(recv: np.ndarray, kind: str, block_size: int) -> list[np.ndarray]:
    """Fixed row blocks over all of ``recv`` (see :func:`plan_range`)."""
    return [np.ascontiguousarray(recv[s:e], dtype=np.int64) for s, e in plan_range(len(recv), kind, block_size)]


def plan_range(n: int, kind: str, block_size: int, start: int = 0, stop: int | None = None) -> list[tuple[int, int]]:
    """(start, stop) of fixed blocks over positions ``start:stop`` of n receivers. Pair methods:
    about ``block_size`` upper-triangle pairs per block; row methods: about ``block_size`` / n
    rows per block."""
    stop = n if stop is None else stop
    if kind == "rows":
        per = max(1, block_size // max(n, 1))
        return [(s, min(s + per, stop)) for s in range(start, stop, per)]
    out, s, pairs = [], start, 0
    for k in range(start, stop):
        pairs += n - k - 1
        if pairs >= block_size or k == stop - 1:
            out.append((s, k + 1))
            s, pairs = k + 1, 0
    return out


class Sizer:
    """Sizes the next block from the throughput measured so far: aims at ``target`` seconds,
    grows at most ``GROWTH``-fold per block and never exceeds ``block_size`` units of work."""

    def __init__(self, n: int, kind: str, block_size: int, threads: int = 1, target: float = TARGET_SECONDS):
        self.cum = np.concatenate([[0], np.cumsum(row_work(n, kind))])
        self.cap = max(1, int(block_size))
        self.target = target
        first = FIRST_PAIRS if kind == "pairs" else max(1, threads) * max(n, 1)
        self.work = float(min(self.cap, first))

    def stop(self, start: int, limit: int) -> int:
        """The end of the block that starts at ``start`` (at least one row, at most ``limit``)."""
        goal = self.cum[start] + self.work
        end = int(np.searchsorted(self.cum, goal, side="left"))
        return int(min(limit, max(start + 1, end)))

    def observe(self, start: int, stop: int, seconds: float) -> None:
        """Records a computed block: its work and the wall-clock seconds it took."""
        done = float(self.cum[stop] - self.cum[start])
        if done <= 0.0:
            return  # rows without pairs (the last row): says nothing about the rate
        aim = done * self.target / max(seconds, 1e-6)
        self.work = float(min(self.cap, max(1.0, min(aim, GROWTH * max(self.work, done)))))


def run_blocks(
    compute: Callable[[np.ndarray], Block],
    recv: np.ndarray,
    kind: str,
    block_size: int,
    *,
    checkpoint: Checkpoint | None,
    progress_bar: Any = None,
    keep: Callable[[Block], Block] | None = None,
    threads: int = 1,
    later: Callable[[], Checkpoint] | None = None,
    write_after: float | None = None,
    held: list[tuple[int, int, Block]] | None = None,
) -> list[Block]:
    """Computes every block (those the checkpoint holds are loaded instead), sized by
    :class:`Sizer`, each saved to the checkpoint as it finishes; returns the Blocks in row
    order, each passed through ``keep`` first if given (e.g. a sparse threshold: only what is
    kept stays in memory; the checkpoint holds the block as computed).

    Without an open ``checkpoint``, ``later`` opens one when it is needed, and the finished
    blocks are held until then:

    * ``write_after`` seconds (wall clock) into the computing, if given (a deferred
      checkpoint: a run that ends sooner writes none). From then on every block is written
      as it finishes, the held ones first; the deferral also ends as soon as ``keep`` drops
      part of a block (holding blocks whole beside what is kept would double their memory).
    * On KeyboardInterrupt: the finished blocks are written there and the KeyboardInterrupt
      raised names the directory. Without ``write_after`` (a rescue only), this stops as soon
      as ``keep`` drops part of a block: nothing whole is held any more.

    A checkpoint this function opens it also closes. ``held``, if given, is the list of the
    finished blocks not written (start, stop, block as computed): on return it holds those
    that are still only in memory, for :func:`save_held` to rescue if the caller is
    interrupted while it assembles them."""
    n = len(recv)
    finished = checkpoint.load_all(recv) if checkpoint is not None else []
    sizer = Sizer(n, kind, block_size, threads)
    done: list[Block] = []
    if held is None:
        held = []  # finished blocks as computed, not yet written
    opened: Checkpoint | None = None
    pos, nxt = 0, 0
    index = checkpoint.next_index() if checkpoint is not None else 0
    began = time.perf_counter()

    def open_later() -> Checkpoint:
        nonlocal checkpoint, opened, later, index
        assert later is not None
        checkpoint = opened = save_held(later, held, close=False)
        later = None
        index = checkpoint.next_index()
        return checkpoint

    try:
        while pos < n:
            if nxt < len(finished) and finished[nxt][0] == pos:
                start, stop, b = finished[nxt]
                nxt += 1
            else:
                limit = finished[nxt][0] if nxt < len(finished) else n
                start, stop = pos, sizer.stop(pos, limit)
                t0 = time.perf_counter()
                b = compute(np.ascontiguousarray(recv[start:stop], dtype=np.int64))
                t1 = time.perf_counter()
                sizer.observe(start, stop, t1 - t0)
                if checkpoint is None and later is not None and write_after is not None and t1 - began >= write_after:
                    open_later()
                if checkpoint is not None:
                    checkpoint.save(index, start, stop, b)
                    index += 1
                elif later is not None:
                    held.append((start, stop, b))
            kept = keep(b) if keep is not None else b
            if held and kept is not b:  # what keep dropped would be held whole
                if write_after is not None:
                    open_later()
                else:
                    held.clear()  # a rescue only: nothing whole to rescue
                    later = None
            done.append(kept)
            pos = stop
            if progress_bar is not None:
                progress_bar.update(stop - start)
    except KeyboardInterrupt:
        if later is not None and held:
            deferred = write_after is not None
            saved = open_later()
            if not deferred:
                raise KeyboardInterrupt(
                    f"interrupted: the {pos} of {n} rows finished were saved to checkpoint {saved.path}; "
                    f"the same call with checkpoint={saved.path!r}, resume=True continues from there"
                ) from None
        if checkpoint is not None and pos > 0:
            raise KeyboardInterrupt(
                f"interrupted: {pos} of {n} rows finished are kept in checkpoint {checkpoint.path}; "
                "resume=True (CLI: --resume) continues from there"
            ) from None
        raise
    finally:
        if opened is not None:
            opened.close()
    return done


def save_held(later: Callable[[], Checkpoint], held: list[tuple[int, int, Block]], close: bool = True) -> Checkpoint:
    """Opens the checkpoint ``later`` gives and writes the ``held`` blocks to it in order,
    emptying the list; closes it if ``close``."""
    checkpoint = later()
    index = checkpoint.next_index()
    while held:
        checkpoint.save(index, *held.pop(0))
        index += 1
    if close:
        checkpoint.close()
    return checkpoint
