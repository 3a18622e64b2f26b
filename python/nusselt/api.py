"""The public functions: form factors of a pair, of a point, and of a whole scene."""

from __future__ import annotations

import os

import numpy as np
import scipy.sparse as sp

from . import _core, engine
from .checks import warn_zero_rows
from .methods import resolve
from .result import FormFactors
from .scene import PLANARITY_TOL, Scene


def _polygon(p, what: str) -> np.ndarray:
    a = np.asarray(p, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{what}: expected an (n, 3) array of vertices, got shape {a.shape}")
    return np.ascontiguousarray(a)


def _vector(x, what: str) -> np.ndarray:
    a = np.asarray(x, dtype=np.float64).ravel()
    if a.shape != (3,) or not np.isfinite(a).all():
        raise ValueError(f"{what} must be 3 finite numbers, got {np.asarray(x).tolist()}")
    return a


def _obstacles(obstacles) -> list[np.ndarray]:
    if obstacles is None:
        return []
    if isinstance(obstacles, Scene):
        return obstacles.polygons
    return [_polygon(o, f"obstacle {k}") for k, o in enumerate(obstacles)]


def view_factor(pi, pj, *, obstacles=None, method: str = "auto", return_std: bool = False, **options):
    """F_ij: the fraction of the radiation leaving polygon ``pi`` that reaches polygon ``pj``.

    Polygons are (n, 3) arrays, counter-clockwise seen from their front (emitting and
    receiving) side. ``obstacles`` is a list of polygons (opaque from both sides) or a Scene.
    ``method`` is one of :data:`nusselt.METHODS`; its options are keyword arguments.
    With ``return_std=True`` returns ``(F, standard error)`` (0 for deterministic methods).
    """
    a, b = _polygon(pi, "pi"), _polygon(pj, "pj")
    obs = _obstacles(obstacles)
    _, opts = resolve(method, options, obstructed=bool(obs))
    f, s = _core.view_factor(a, b, obs, method, opts, PLANARITY_TOL)
    return (float(f), float(s)) if return_std else float(f)


def point_view_factor(point, normal, pj, *, obstacles=None, method: str = "auto", return_std: bool = False, **options):
    """F from a differential area at ``point`` with unit ``normal`` to polygon ``pj``
    (``return_std=True``: ``(F, standard error)``)."""
    p = _vector(point, "point")
    n = _vector(normal, "normal")
    length = np.linalg.norm(n)
    if not length > 0:
        raise ValueError("normal must be a nonzero vector")
    b = _polygon(pj, "pj")
    obs = _obstacles(obstacles)
    _, opts = resolve(method, options, obstructed=bool(obs))
    f, s = _core.point_view_factor(p, n / length, b, obs, method, opts, PLANARITY_TOL)
    return (float(f), float(s)) if return_std else float(f)


def form_factors(
    scene: Scene,
    *,
    method: str = "auto",
    dense: bool = False,
    progress: bool = False,
    checkpoint: str | os.PathLike | None = None,
    resume: bool = False,
    block_size: int = 2_000_000,
    threshold: float = 0.0,
    **options,
) -> FormFactors:
    """The form-factor matrix of a scene: F[i, j] for every pair of receiving polygons.

    Rows are computed in parallel, block by block; Ctrl-C stops between blocks. Pair methods
    compute every unordered pair once, so reciprocity A_i F_ij = A_j F_ji holds to rounding.
    Obstruction-only polygons block but get no row or column.

    Parameters
    ----------
    method : str
        One of :data:`nusselt.METHODS`; its options are keyword arguments.
    dense : bool
        Return ``matrix`` as a dense ndarray (refused if it would not fit in memory).
    progress : bool
        Show a progress bar with rows/s and ETA.
    checkpoint : path, optional
        Directory where finished row blocks are written as they complete; with ``resume=True``
        an interrupted run continues from there and gives the identical matrix.
    block_size : int
        Work per block: upper-triangle pairs (pair methods) or row entries (row methods).
    threshold : float
        Sparse threshold: a pair is dropped from the result when both F_ij and F_ji are below
        ``threshold`` (default 0: every nonzero entry is kept), so reciprocity still holds.
        Rows then sum to less by what they dropped; ``info["dropped"]`` reports the largest
        row mass dropped.

    Returns a :class:`FormFactors`; ``matrix`` is a ``scipy.sparse.csr_array`` unless dense.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"form_factors expects a nusselt.Scene, got {type(scene).__name__}")
    if isinstance(block_size, np.integer):
        block_size = int(block_size)  # numpy integers are integers
    if not (isinstance(block_size, int) and not isinstance(block_size, bool) and block_size >= 1):
        raise ValueError(f"block_size must be a positive integer, got {block_size!r}")
    if scene.two_sided.any():
        from .two_sided import two_sided_form_factors

        return two_sided_form_factors(form_factors, scene, method=method, dense=dense, progress=progress,
                                      checkpoint=checkpoint, resume=resume, block_size=block_size,
                                      threshold=threshold, **options)
    if not (isinstance(threshold, (int, float)) and 0.0 <= threshold < 1.0):
        raise ValueError(f"threshold must be a number in [0, 1), got {threshold!r}")
    m, opts = resolve(method, options)
    recv = scene.receivers
    nr = len(recv)
    if dense:
        _check_dense_fits(nr)
    col_of = np.full(len(scene), -1, dtype=np.int64)
    col_of[recv] = np.arange(nr)

    kind = m.kind
    blocks = engine.plan_blocks(recv, kind, block_size)
    ckpt = None
    if checkpoint is not None:
        digest = engine.scene_digest(scene, method, opts, kind, block_size)
        ckpt = engine.Checkpoint(checkpoint, digest, len(blocks), resume)

    def compute(rows):
        if kind == "pairs":
            return engine.Block(rows, *scene._core.pair_rows(rows, method, opts))
        return engine.Block(rows, *scene._core.full_rows(rows, method, opts))

    bar = _progress(progress, total=nr, desc=f"nusselt {method}")
    try:
        done = engine.run_blocks(compute, blocks, checkpoint=ckpt, progress_bar=bar)
    finally:
        if bar is not None:
            bar.close()

    areas = scene.areas[recv]
    std = lost = None
    if kind == "pairs":
        matrix, std = _assemble_pairs(done, col_of, areas)
    else:
        matrix, std, lost = _assemble_rows(done, col_of, nr)
    dropped = 0.0
    if threshold > 0.0:
        # Drop a pair only when both directions are small, so reciprocity still holds.
        big = (matrix >= threshold).astype(np.int8)
        keep = (big + big.T).tocsr()
        kept = matrix.multiply(keep > 0).tocsr()
        kept.sort_indices()
        dropped = float(np.max(matrix.sum(axis=1) - kept.sum(axis=1))) if nr else 0.0
        matrix = sp.csr_array(kept)
        if std is not None:
            std = sp.csr_array(std.multiply(keep > 0).tocsr())
    warn_zero_rows(scene, matrix, recv)
    names = [f"{scene.surface_names[scene.surface[k]]}[{k}]" for k in recv]
    return FormFactors(
        matrix.toarray() if dense else matrix,
        areas,
        names,
        recv,
        method,
        surface=scene.surface[recv],
        surface_names=scene.surface_names,
        std_err=std,
        lost=lost,
        info={"options": opts, "threshold": threshold, "dropped": dropped},
    )


def _stack_blocks(done: list, col_of: np.ndarray, nr: int):
    """The blocks' CSR parts as one CSR over receiver indices (rows given once each)."""
    counts = np.zeros(nr, dtype=np.int64)
    if done:
        counts[col_of[np.concatenate([b.rows for b in done])]] = np.concatenate([np.diff(b.indptr) for b in done])
    indptr = np.zeros(nr + 1, dtype=np.int64)
    np.cumsum(counts, out=indptr[1:])
    idx = col_of[np.concatenate([b.indices for b in done])] if done else np.zeros(0, np.int64)
    data = np.concatenate([b.data for b in done]) if done else np.zeros(0)
    sd = np.concatenate([b.std for b in done]) if done else np.zeros(0)
    return indptr, idx, data, sd


def _canonical_csr(data, idx, indptr, nr):
    # scipy keeps index arrays as given only when both have one dtype: int32 (idx's dtype)
    # while the entries fit, so the big idx array is not copied
    if idx.dtype == np.int32 and indptr[-1] <= np.iinfo(np.int32).max:
        indptr = indptr.astype(np.int32)
    m = sp.csr_array((data, idx, indptr), shape=(nr, nr))
    m.has_sorted_indices = True
    m.has_canonical_format = True
    return m


def _assemble_pairs(done, col_of, areas):
    """Pair methods return the upper triangle of the symmetric G = A_i F_ij: the core mirrors
    it and divides each row by its area in one pass (F_ij = G_ij / A_i, F_ji = G_ij / A_j)."""
    nr = len(areas)
    # column indices are int32 (checkpoints of older versions may hold int64: converted)
    blocks = [(b.rows, b.indptr, np.asarray(b.indices, dtype=np.int32), b.data, b.std) for b in done]
    indptr, idx, f, sd = _core.mirror_pairs(np.ascontiguousarray(areas, dtype=np.float64), col_of, blocks)
    matrix = _canonical_csr(f, idx, indptr, nr)
    std = _canonical_csr(sd, idx.copy(), indptr.copy(), nr) if sd is not None else None
    return matrix, std


def _assemble_rows(done, col_of, nr):
    """Row methods return whole rows F_i. (with standard errors and lost fractions)."""
    indptr, idx, v, sd = _stack_blocks(done, col_of, nr)
    matrix = sp.csr_array((v, idx, indptr), shape=(nr, nr))
    matrix.sort_indices()  # row methods return rows sorted; this only checks
    std = lost = None
    if sd.size and not np.all(np.isnan(sd)):
        std = sp.csr_array((np.nan_to_num(sd), idx, indptr), shape=(nr, nr))
        std.sort_indices()
    if done and done[0].lost is not None:
        lost = np.zeros(nr)
        lost[col_of[np.concatenate([b.rows for b in done])]] = np.concatenate([b.lost for b in done])
    return matrix, std, lost


def memory_estimate(n: int, dense: bool = False) -> tuple[int, int | None]:
    """(bytes the result of an n-row run may need, bytes of memory available or None).

    Sparse: the worst case, every pair nonzero, about 60 bytes per entry while the result is
    assembled (row/column/value triplets for both halves of the symmetric G, then CSR).
    Dense: the matrix plus one temporary."""
    need = (8 * 2 if dense else 60) * n * n
    try:
        avail = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        avail = None
    return need, avail


def _check_dense_fits(n: int) -> None:
    need, avail = memory_estimate(n, dense=True)
    if avail is not None and need > avail:
        raise MemoryError(
            f"a dense {n} x {n} matrix needs about {need / 2**30:.1f} GiB but {avail / 2**30:.1f} GiB are free; "
            "use the sparse result (dense=False)"
        )


def _progress(enabled: bool, total: int, desc: str):
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="rows", dynamic_ncols=True)
