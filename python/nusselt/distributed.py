"""Distributed runs on Dask: row blocks as tasks on a ``dask.distributed`` cluster.

``form_factors(scene, client=client)`` (CLI: ``nusselt matrix ... --dask SCHEDULER``) plans
row blocks of ``block_size`` work each (:func:`nusselt.blocks.plan_range`) over the rows the
checkpoint does not already hold and submits one task per block. The scene's geometry goes to every worker once
(``client.scatter(..., broadcast=True)``; a worker that joins later fetches it from a peer), and
each worker process builds its core scene once and keeps it for every block it computes. Blocks
come back to the client as they finish and are written to the checkpoint at once, so a killed
client resumes (``resume=True`` / ``--resume``) and a killed worker costs only the blocks it was
computing, which the scheduler runs again elsewhere (``retries``). Every method is deterministic
for its seed and the blocks are assembled exactly as locally: the matrix is identical.

Needs the optional extra ``nusselt[dask]`` (``dask[distributed]``) on the client and on every
worker, with the same nusselt version.
"""

from __future__ import annotations

import hashlib
import uuid
from collections.abc import Callable
from concurrent.futures import CancelledError
from typing import Any

import numpy as np

from . import blocks
from .blocks import Block

#: Times the scheduler reruns a block whose worker died (distributed's task retries).
RETRIES = 3

# Worker side: core scenes built in this process, by geometry digest (one per scene).
_SCENES: dict[str, Any] = {}
_BUILDS: dict[str, int] = {}


def scene_payload(scene: Any) -> dict:
    """What a worker needs to build the core scene: the polygons' vertex coordinates in
    order, the offset of each polygon, which polygons receive, and the planarity tolerance."""
    faces = scene.faces
    sizes = np.fromiter((len(f) for f in faces), dtype=np.int64, count=len(faces))
    offsets = np.zeros(len(faces) + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    coords = np.ascontiguousarray(np.asarray(scene.vertices, dtype=np.float64)[np.concatenate(faces)])
    receiver = ~np.asarray(scene.obstruction, dtype=bool)
    h = hashlib.sha256()
    for a in (coords, offsets, receiver):
        h.update(a.tobytes())
    h.update(repr(float(scene.planarity_tol)).encode())
    return {
        "digest": h.hexdigest(),
        "coords": coords,
        "offsets": offsets,
        "receiver": receiver,
        "planarity_tol": float(scene.planarity_tol),
    }


def _core_scene(payload: dict):
    core = _SCENES.get(payload["digest"])
    if core is None:
        from . import _core

        # arrays that came over the wire may be unaligned views of a message buffer: copy
        core = _core.SceneCore(
            np.array(payload["coords"], dtype=np.float64),
            np.array(payload["offsets"], dtype=np.int64),
            np.array(payload["receiver"], dtype=bool),
            payload["planarity_tol"],
        )
        _SCENES.clear()  # one scene at a time per worker process
        _SCENES[payload["digest"]] = core
        _BUILDS[payload["digest"]] = _BUILDS.get(payload["digest"], 0) + 1
    return core


def scene_builds() -> dict[str, int]:
    """(Run on a worker with ``client.run``) how often this process built each scene."""
    return dict(_BUILDS)


def compute_block(payload: dict, rows: np.ndarray, method: str, opts: dict, kind: str) -> tuple:
    """One row block on a worker: the arrays of a :class:`nusselt.blocks.Block` without rows."""
    core = _core_scene(payload)
    rows = np.array(rows, dtype=np.int64)  # aligned and contiguous, as the core needs
    if kind == "pairs":
        return tuple(core.pair_rows(rows, method, opts))
    from .assembly import compact_row_block

    b = compact_row_block(Block(rows, *core.full_rows(rows, method, opts)))
    return (b.indptr, b.indices, b.data, b.std, b.lost)


def run_blocks(
    client: Any,
    scene: Any,
    method: str,
    opts: dict,
    kind: str,
    recv: np.ndarray,
    block_size: int,
    *,
    checkpoint: Any = None,
    progress_bar: Any = None,
    keep: Callable[[Block], Block] | None = None,
) -> list[Block]:
    """Every block of ``recv`` computed on the cluster of ``client`` (those the checkpoint
    holds are loaded instead), each written to the checkpoint as it arrives; in row order."""
    from distributed import as_completed

    keep = keep or (lambda b: b)
    n = len(recv)
    finished = checkpoint.load_all(recv) if checkpoint is not None else []
    done: dict[int, Block] = {}
    todo: list[tuple[int, int]] = []
    pos = 0
    for start, stop, b in [*finished, (n, n, None)]:
        todo += blocks.plan_range(n, kind, block_size, pos, start)  # the rows no block holds
        if b is not None:
            done[start] = keep(b)
            if progress_bar is not None:
                progress_bar.update(stop - start)
        pos = stop
    plan = {start: np.ascontiguousarray(recv[start:stop], dtype=np.int64) for start, stop in todo}
    index = checkpoint.next_index() if checkpoint is not None else 0
    if todo:
        payload = scene_payload(scene)

        # one future under a fresh key: scattering the dict itself keys its arrays by their names
        # ("coords", ...), and a second run would reuse keys the first run is still releasing
        # (its blocks then failed with "lost dependencies")
        def ship():
            [f] = client.scatter([payload], broadcast=True, hash=False)
            return f

        shipped = ship()
        tag = hashlib.sha256((payload["digest"] + method + repr(sorted(opts.items())) + kind).encode()).hexdigest()[:16]
        # keys fresh per run: a key the scheduler still holds from an earlier, cancelled or
        # released run of the same blocks would hand its fate (cancelled) to this one
        run = uuid.uuid4().hex[:12]
        futures: dict = {}
        resubmits = dict.fromkeys(plan, 0)

        def submit(start: int, stop: int, attempt: int = 0):
            nonlocal shipped
            # the scene itself can be lost (every worker holding it gone before the nanny's
            # new ones got a copy): its blocks are then cancelled for "lost dependencies",
            # and again at every resubmission unless it is shipped again
            if attempt and shipped.status != "finished":
                client.cancel([shipped])
                shipped = ship()
            f = client.submit(
                compute_block,
                shipped,
                plan[start],
                method,
                opts,
                kind,
                key=f"nusselt-block-{tag}-{run}-{start}" + (f"-again{attempt}" if attempt else ""),
                retries=RETRIES,
                pure=False,
            )
            futures[f] = (start, stop)
            return f

        for start, stop in todo:
            submit(start, stop)
        try:
            pending = as_completed(list(futures))
            for f in pending:
                start, stop = futures.pop(f)
                try:
                    result = f.result()
                except CancelledError:
                    # the scheduler may forget a task whose worker died while its result was
                    # being handed over ("already forgotten"), or cancel it when the scene it
                    # needs was lost: compute that block again, under a new key (with the
                    # scene shipped again if lost), a bounded number of times
                    if resubmits[start] >= RETRIES:
                        raise
                    resubmits[start] += 1
                    pending.add(submit(start, stop, resubmits[start]))
                    continue
                # arrays off the wire may be unaligned views of the message: made aligned
                parts = [None if a is None else np.require(a, requirements=["C", "A"]) for a in result]
                b = Block(plan[start], *parts)  # type: ignore[arg-type]
                if checkpoint is not None:
                    checkpoint.save(index, start, stop, b)
                    index += 1
                done[start] = keep(b)
                f.release()
                if progress_bar is not None:
                    progress_bar.update(stop - start)
        finally:
            if futures:
                client.cancel(list(futures))
            client.cancel([shipped])
    return [done[start] for start in sorted(done)]


def connect(address: str | None = None, *, scheduler_file: str | None = None, local_workers: int | None = None):
    """A ``distributed.Client``: to a scheduler ``address``, through a ``scheduler_file``, or
    (neither given) to a new LocalCluster of ``local_workers`` processes, one thread each (the
    core is multithreaded itself), closed with the client."""
    try:
        from distributed import Client
    except ImportError:
        raise ImportError("distributed runs need dask.distributed: pip install 'nusselt[dask]'") from None
    if scheduler_file is not None:
        return Client(scheduler_file=scheduler_file)
    if address is not None:
        return Client(address)
    return Client(n_workers=local_workers, processes=True, threads_per_worker=1, dashboard_address=None)
