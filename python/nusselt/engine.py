"""Orchestration of a scene-wide run: row blocks, progress, Ctrl-C, checkpoints and resume.

The core computes one block of rows per call with the GIL released and all cores busy. Between
blocks this layer updates the progress bar, lets Python raise KeyboardInterrupt, and (with a
checkpoint directory) writes the finished block to disk atomically, so that a run killed at any
moment resumes without losing or changing finished work: the block boundaries depend only on the
scene and the block size, and every method is deterministic for a given seed.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from dataclasses import dataclass

import numpy as np

CHECKPOINT_VERSION = 1


@dataclass
class Block:
    """One finished block: CSR parts over its rows (global face ids as columns)."""

    rows: np.ndarray
    indptr: np.ndarray
    indices: np.ndarray
    data: np.ndarray
    std: np.ndarray | None = None
    lost: np.ndarray | None = None


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


def scene_digest(scene, method: str, options: dict, kind: str, block_size: int) -> str:
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(scene.vertices).tobytes())
    for f in scene.faces:
        h.update(np.asarray(f, dtype=np.int64).tobytes())
        h.update(b"|")
    h.update(scene.obstruction.tobytes())
    h.update(json.dumps([method, sorted(options.items()), kind, block_size], default=str).encode())
    return h.hexdigest()


class Checkpoint:
    """A directory of finished blocks plus a manifest naming what they belong to."""

    def __init__(self, path: str, digest: str, n_blocks: int, resume: bool):
        self.path = os.fspath(path)
        manifest = os.path.join(self.path, "manifest.json")
        if os.path.exists(manifest):
            with open(manifest) as fh:
                old = json.load(fh)
            same = old.get("digest") == digest and old.get("version") == CHECKPOINT_VERSION
            if not resume:
                raise ValueError(
                    f"checkpoint directory {self.path} already holds a run; resume it (--resume) or remove it"
                )
            if not same:
                raise ValueError(
                    f"checkpoint {self.path} belongs to a different scene, method, options or block size; "
                    "remove it to start afresh"
                )
        else:
            os.makedirs(self.path, exist_ok=True)
            _atomic_write_json(manifest, {"version": CHECKPOINT_VERSION, "digest": digest, "blocks": n_blocks})

    def _file(self, k: int) -> str:
        return os.path.join(self.path, f"block_{k:06d}.npz")

    def load(self, k: int) -> Block | None:
        f = self._file(k)
        if not os.path.exists(f):
            return None
        with np.load(f) as z:
            return Block(
                z["rows"], z["indptr"], z["indices"], z["data"],
                z["std"] if "std" in z else None, z["lost"] if "lost" in z else None,
            )

    def save(self, k: int, b: Block) -> None:
        arrays = {"rows": b.rows, "indptr": b.indptr, "indices": b.indices, "data": b.data}
        if b.std is not None:
            arrays["std"] = b.std
        if b.lost is not None:
            arrays["lost"] = b.lost
        tmp = self._file(k) + ".tmp.npz"
        np.savez(tmp, **arrays)
        os.replace(tmp, self._file(k))  # atomic: a killed run leaves whole blocks or none

    def remove(self) -> None:
        shutil.rmtree(self.path, ignore_errors=True)


def _atomic_write_json(path: str, obj) -> None:
    tmp = path + ".tmp"
    with open(tmp, "w") as fh:
        json.dump(obj, fh)
    os.replace(tmp, path)


def run_blocks(compute, blocks, *, checkpoint: Checkpoint | None, progress_bar=None):
    """Computes (or loads) every block in order; yields nothing, returns the list of Blocks."""
    done = []
    for k, rows in enumerate(blocks):
        b = checkpoint.load(k) if checkpoint is not None else None
        if b is None:
            b = compute(rows)
            if checkpoint is not None:
                checkpoint.save(k, b)
        done.append(b)
        if progress_bar is not None:
            progress_bar.update(len(rows))
    return done
