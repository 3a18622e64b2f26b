"""Checkpoints: a directory of finished row blocks and a manifest saying which run they belong to.

Layout of a checkpoint directory::

    manifest.json        {"format": "nusselt-checkpoint", "version": 3, "digest": <sha256>,
                          "run": {scene, polygons, receivers, method, options, kind}}
    block_000000.npz     rows, indptr, indices, data[, std][, lost] and "meta": JSON text
    block_000001.npz     {"digest": <the manifest's digest>, "index": k, "start": s, "stop": e,
    ...                   "sha256": <content>}

``digest`` is the SHA-256 of the ``run`` description (the scene's geometry hash, the method,
its resolved options and the kind of blocks): every value depends on nothing else, and where
block boundaries fall changes none (:mod:`nusselt.blocks`). Block k holds the receivers
``recv[start:stop]``; it carries the digest, its index, its range and a SHA-256 of its arrays,
so a resumed run uses a block only if it is whole, belongs to this run, holds the rows of its
range and overlaps no other block; the rows no block holds are computed (in blocks of any
size). Anything else is refused with a ValueError naming the directory and the block (the CLI
exits with status 2); nothing is ever trusted without a manifest.

Every file is written to a temporary name, fsynced, renamed and its directory fsynced
(:mod:`nusselt.io.atomic`): a killed run leaves whole blocks or none.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import shutil
from typing import Any

import numpy as np

from .blocks import Block
from .io.atomic import atomic_open

FORMAT = "nusselt-checkpoint"
VERSION = 3
MANIFEST = "manifest.json"
_ARRAYS = ("rows", "indptr", "indices", "data", "std", "lost")


def scene_hash(scene: Any) -> str:
    """SHA-256 of what the core sees of a scene: vertices, faces and which faces receive."""
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(scene.vertices, dtype=np.float64).tobytes())
    sizes = np.fromiter((len(f) for f in scene.faces), dtype=np.int64, count=len(scene.faces))
    h.update(sizes.tobytes())
    h.update(np.concatenate(scene.faces).astype(np.int64).tobytes() if len(scene.faces) else b"")
    h.update(np.ascontiguousarray(scene.obstruction, dtype=bool).tobytes())
    return h.hexdigest()


def describe_run(scene: Any, method: str, options: dict, kind: str) -> dict:
    """What a checkpoint's blocks depend on, as JSON-able data (stored in the manifest and
    compared item by item on ``resume``, so a refusal can say what changed)."""
    return {
        "scene": scene_hash(scene),
        "polygons": len(scene.faces),
        "receivers": int(np.count_nonzero(~np.asarray(scene.obstruction))),
        "method": str(method),
        "options": json.loads(json.dumps({str(k): options[k] for k in sorted(options)}, default=str)),
        "kind": str(kind),
    }


def run_digest(run: dict) -> str:
    return hashlib.sha256(json.dumps(run, sort_keys=True).encode()).hexdigest()


def content_hash(arrays: dict[str, np.ndarray]) -> str:
    """SHA-256 over each array's name, dtype, shape and bytes."""
    h = hashlib.sha256()
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.view(np.uint8).data if a.size else b"")
    return h.hexdigest()


def what_changed(old: dict, new: dict) -> str:
    """A readable list of the differences between two run descriptions."""
    out = []
    if old.get("scene") != new.get("scene"):
        po, pn = old.get("polygons"), new.get("polygons")
        out.append(
            "the scene geometry"
            + (
                f" ({po} polygons then, {pn} now)"
                if po != pn
                else " (same number of polygons, different vertices or faces)"
            )
        )
    for key, label in (("method", "the method"), ("kind", "the kind of blocks")):
        if old.get(key) != new.get(key):
            out.append(f"{label} ({old.get(key)!r} then, {new.get(key)!r} now)")
    oo, no = old.get("options") or {}, new.get("options") or {}
    if oo != no:
        diffs = [
            f"{k}={oo.get(k, '(unset)')!r} then, {no.get(k, '(unset)')!r} now"
            for k in sorted(set(oo) | set(no))
            if oo.get(k) != no.get(k)
        ]
        out.append("the options (" + "; ".join(diffs) + ")")
    return ", ".join(out) or "nothing visible (the manifest's digest does not match its description)"


def holds_run(path: str | os.PathLike) -> bool:
    """Whether ``path`` holds anything of a run (a manifest or block files, or a directory
    that does, as a zone's of :mod:`nusselt.zones`): such a directory is opened, checked or
    refused, before any work; otherwise it may be created later."""
    path = os.fspath(path)
    if not os.path.isdir(path):
        return os.path.exists(path)  # a file there: Checkpoint refuses it at once
    return any(
        f == MANIFEST
        or (f.startswith("block_") and f.endswith(".npz"))
        or (os.path.isdir(os.path.join(path, f)) and holds_run(os.path.join(path, f)))
        for f in os.listdir(path)
    )


class Checkpoint:
    """A directory of finished blocks plus a manifest naming the run they belong to.

    ``resume=False`` refuses a directory that already holds a run; ``resume=True`` refuses one
    that holds a different run (saying what changed) and validates each block as it is
    loaded. A directory with block files but no manifest is always refused."""

    def __init__(self, path: str | os.PathLike, run: dict, resume: bool):
        self.path = os.fspath(path)
        self.run = dict(run)
        self.digest = run_digest(self.run)
        self._lock_fd: int | None = None
        manifest = os.path.join(self.path, MANIFEST)
        if os.path.isdir(self.path) and not os.path.exists(manifest):
            strays = sorted(f for f in os.listdir(self.path) if f.startswith("block_") and f.endswith(".npz"))
            if strays:
                raise ValueError(
                    f"checkpoint {self.path} holds {len(strays)} block file(s) ({strays[0]} ...) but no {MANIFEST}: "
                    "they cannot be checked against this run and are not used; remove the directory to start afresh"
                )
        if os.path.exists(manifest):
            old = self._read_manifest(manifest)
            if not resume:
                raise ValueError(
                    f"checkpoint directory {self.path} already holds a run; resume it (--resume) or remove it"
                )
            if old.get("version") != VERSION:
                raise ValueError(
                    f"checkpoint {self.path} was written by another version of nusselt (format version "
                    f"{old.get('version')!r}, this one writes {VERSION}); remove it to start afresh"
                )
            if old.get("digest") != self.digest:
                raise ValueError(
                    f"checkpoint {self.path} belongs to a different run: "
                    f"{what_changed(old.get('run') or {}, self.run)} "
                    "changed; run again with what it was made with, or remove it to start afresh"
                )
        else:
            os.makedirs(self.path, exist_ok=True)
            with atomic_open(manifest, "w") as fh:
                json.dump(
                    {
                        "format": FORMAT,
                        "version": VERSION,
                        "digest": self.digest,
                        "run": self.run,
                    },
                    fh,
                    indent=1,
                )
        self._lock()

    def _read_manifest(self, manifest: str) -> dict:
        try:
            with open(manifest, encoding="utf-8") as fh:
                old = json.load(fh)
            if not isinstance(old, dict) or old.get("format") != FORMAT:
                raise ValueError("not a nusselt checkpoint manifest")
            if not isinstance(old.get("digest"), str) or not isinstance(old.get("run"), dict):
                raise ValueError("no digest or run description")  # noqa: TRY004 - reported as damaged
        except (OSError, ValueError, UnicodeDecodeError) as e:
            raise ValueError(
                f"checkpoint {self.path}: {MANIFEST} is damaged or not nusselt's ({type(e).__name__}: {e}); "
                "remove the directory to start afresh"
            ) from None
        return old

    def _lock(self) -> None:
        """An advisory lock, so that two runs never write one checkpoint (POSIX only)."""
        try:
            import fcntl
        except ImportError:
            return
        fd = os.open(os.path.join(self.path, "lock"), os.O_RDWR | os.O_CREAT, 0o666)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise ValueError(f"checkpoint {self.path} is in use by another running nusselt") from None
        except OSError:  # a file system without locks (some NFS): go on unlocked
            os.close(fd)
            return
        self._lock_fd = fd

    def close(self) -> None:
        if self._lock_fd is not None:
            with contextlib.suppress(OSError):
                os.close(self._lock_fd)
            self._lock_fd = None

    def file(self, k: int) -> str:
        return os.path.join(self.path, f"block_{k:06d}.npz")

    def finished(self) -> list[int]:
        """Indices of the block files present (not yet validated)."""
        out = []
        for f in os.listdir(self.path):
            if f.startswith("block_") and f.endswith(".npz") and f[6:-4].isdigit():
                out.append(int(f[6:-4]))
        return sorted(out)

    def _refuse(self, k: int, why: str) -> ValueError:
        return ValueError(
            f"checkpoint {self.path}: block {k} ({os.path.basename(self.file(k))}) {why}; delete that file "
            f"and resume to recompute it, or remove {self.path} to start afresh"
        )

    def next_index(self) -> int:
        """The index for the next block written (after every block present)."""
        return max(self.finished(), default=-1) + 1

    def load_all(self, recv: np.ndarray) -> list[tuple[int, int, Block]]:
        """Every finished block as (start, stop, Block), validated, in row order; refused if
        one is damaged, of another run, holds other rows than ``recv[start:stop]`` or
        overlaps another."""
        out = sorted((self.load(k, recv) + (k,) for k in self.finished()), key=lambda t: t[0])
        for (_, stop, _, a), (start, _, _, b) in zip(out, out[1:]):
            if start < stop:
                raise self._refuse(b, f"overlaps block {a} (rows {start} to {stop - 1} in both)")
        return [(start, stop, b) for start, stop, b, _ in out]

    def load(self, k: int, recv: np.ndarray) -> tuple[int, int, Block]:
        """Finished block ``k`` as (start, stop, Block), validated against ``recv``."""
        f = self.file(k)
        try:
            with np.load(f, allow_pickle=False) as z:
                arrays = {name: z[name] for name in z.files}
        except Exception as e:  # noqa: BLE001 - BadZipFile, EOFError, zlib.error, ValueError, OSError ...
            raise self._refuse(k, f"is damaged ({type(e).__name__}: {e})") from None
        try:
            meta = json.loads(str(arrays.pop("meta")))
            stored = {name: arrays[name] for name in arrays if name in _ARRAYS}
            if set(stored) != set(arrays):
                raise ValueError(f"unexpected arrays {sorted(set(arrays) - set(stored))}")
            if not isinstance(meta, dict):
                raise ValueError("meta is not a JSON object")  # noqa: TRY004 - reported as damaged
        except (KeyError, ValueError) as e:
            raise self._refuse(k, f"is damaged or not nusselt's ({type(e).__name__}: {e})") from None
        if meta.get("digest") != self.digest:
            raise self._refuse(k, "belongs to another run (its digest is not the manifest's)")
        if meta.get("index") != k:
            raise self._refuse(k, f"holds block {meta.get('index')!r}, not {k}")
        if meta.get("sha256") != content_hash(stored):
            raise self._refuse(k, "is damaged (its content does not match its SHA-256)")
        start, stop = meta.get("start"), meta.get("stop")
        if not (isinstance(start, int) and isinstance(stop, int) and 0 <= start < stop <= len(recv)):
            raise self._refuse(k, f"has no valid row range ({start!r} to {stop!r} of {len(recv)} receivers)")
        try:
            b = Block(*(stored.get(name) for name in _ARRAYS))  # type: ignore[arg-type]
            _check_block(b)
        except (TypeError, ValueError) as e:
            raise self._refuse(k, f"is malformed ({e})") from None
        if not np.array_equal(b.rows, recv[start:stop]):
            raise self._refuse(k, "holds other rows than this run has at its place")
        return start, stop, b

    def save(self, k: int, start: int, stop: int, b: Block) -> None:
        """Writes block ``k`` (receivers ``start:stop``) durably (temporary file, fsync,
        rename, fsync of the directory)."""
        arrays = {name: getattr(b, name) for name in _ARRAYS if getattr(b, name) is not None}
        meta = {"digest": self.digest, "index": int(k), "start": int(start), "stop": int(stop)}
        meta["sha256"] = content_hash(arrays)
        with atomic_open(self.file(k), "wb") as fh:
            np.savez(fh, meta=np.array(json.dumps(meta)), **arrays)

    def remove(self) -> None:
        self.close()
        remove_dir(self.path)


def remove_dir(path: str | os.PathLike) -> None:
    """Removes a checkpoint directory, its manifest last: removal stopped half-way (Ctrl-C,
    kill) leaves a manifest with some of its blocks, which resumes, never blocks without one."""
    path = os.fspath(path)
    if not os.path.isdir(path):
        return
    for f in sorted(os.listdir(path), key=lambda f: f == MANIFEST):
        p = os.path.join(path, f)
        with contextlib.suppress(OSError):
            if os.path.isdir(p) and not os.path.islink(p):
                remove_dir(p)  # a zone's checkpoint inside (nusselt.zones)
            else:
                os.unlink(p)
    shutil.rmtree(path, ignore_errors=True)


def _check_block(b: Block) -> None:
    if b.rows is None or b.indptr is None or b.indices is None or b.data is None:
        raise ValueError("missing arrays")
    if b.rows.ndim != 1 or b.indptr.shape != (len(b.rows) + 1,):
        raise ValueError("indptr does not match rows")
    if (
        b.indptr[0] != 0
        or np.any(np.diff(b.indptr) < 0)
        or b.indptr[-1] != len(b.indices)
        or len(b.indices) != len(b.data)
    ):
        raise ValueError("inconsistent CSR parts")
    if b.std is not None and b.std.shape != b.data.shape:
        raise ValueError("std does not match data")
    if b.lost is not None and b.lost.shape != b.rows.shape:
        raise ValueError("lost does not match rows")
