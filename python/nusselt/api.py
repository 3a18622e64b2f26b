"""The public functions: form factors of a pair, of a point, and of a whole scene."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from . import _core
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


def view_factor(pi, pj, *, obstacles=None, method: str = "auto", **options) -> float:
    """F_ij: the fraction of the radiation leaving polygon ``pi`` that reaches polygon ``pj``.

    Polygons are (n, 3) arrays, counter-clockwise seen from their front (emitting and
    receiving) side. ``obstacles`` is a list of polygons (opaque from both sides) or a Scene.
    ``method`` is one of :data:`nusselt.METHODS`; its options are keyword arguments.
    """
    a, b = _polygon(pi, "pi"), _polygon(pj, "pj")
    obs = _obstacles(obstacles)
    _, opts = resolve(method, options, obstructed=bool(obs))
    return float(_core.view_factor(a, b, obs, method, opts, PLANARITY_TOL))


def point_view_factor(point, normal, pj, *, obstacles=None, method: str = "auto", **options) -> float:
    """F from a differential area at ``point`` with unit ``normal`` to polygon ``pj``."""
    p = _vector(point, "point")
    n = _vector(normal, "normal")
    length = np.linalg.norm(n)
    if not length > 0:
        raise ValueError("normal must be a nonzero vector")
    b = _polygon(pj, "pj")
    obs = _obstacles(obstacles)
    _, opts = resolve(method, options, obstructed=bool(obs))
    return float(_core.point_view_factor(p, n / length, b, obs, method, opts, PLANARITY_TOL))


def form_factors(
    scene: Scene,
    *,
    method: str = "auto",
    dense: bool = False,
    progress: bool = False,
    block_pairs: int = 2_000_000,
    **options,
) -> FormFactors:
    """The form-factor matrix of a scene: F[i, j] for every pair of receiving polygons.

    Rows are computed in parallel, block by block (Ctrl-C stops between blocks). For pair
    methods every unordered pair is computed once, so reciprocity A_i F_ij = A_j F_ji holds
    to rounding. Obstruction-only polygons block but get no row or column.
    Returns a :class:`FormFactors` whose ``matrix`` is a ``scipy.sparse.csr_array`` (or a
    dense array with ``dense=True``).
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"form_factors expects a nusselt.Scene, got {type(scene).__name__}")
    m, opts = resolve(method, options)
    recv = scene.receivers
    n_faces = len(scene)
    col_of = np.full(n_faces, -1, dtype=np.int64)
    col_of[recv] = np.arange(len(recv))
    nr = len(recv)

    blocks = _pair_blocks(recv, block_pairs)
    bar = _progress(progress, total=len(recv), desc=f"nusselt {method}")
    rows_g, cols_g, vals_g = [], [], []
    try:
        for block in blocks:
            indptr, indices, data = scene._core.pair_rows(block, method, opts)
            counts = np.diff(indptr)
            rows_g.append(np.repeat(col_of[block], counts))
            cols_g.append(col_of[indices])
            vals_g.append(data)
            if bar is not None:
                bar.update(len(block))
    finally:
        if bar is not None:
            bar.close()
    r = np.concatenate(rows_g) if rows_g else np.zeros(0, np.int64)
    c = np.concatenate(cols_g) if cols_g else np.zeros(0, np.int64)
    g = np.concatenate(vals_g) if vals_g else np.zeros(0)
    areas = scene.areas[recv]
    # G is symmetric: mirror the upper triangle, then F = G / A_row.
    rr = np.concatenate([r, c])
    cc = np.concatenate([c, r])
    f = np.concatenate([g / areas[r], g / areas[c]])
    matrix = sp.csr_array((f, (rr, cc)), shape=(nr, nr))
    matrix.sum_duplicates()
    matrix.sort_indices()
    names = [f"{scene.surface_names[scene.surface[k]]}[{k}]" for k in recv]
    return FormFactors(
        matrix.toarray() if dense else matrix,
        areas,
        names,
        recv,
        method,
        surface=scene.surface[recv],
        surface_names=scene.surface_names,
        info={"options": opts},
    )


def _pair_blocks(recv: np.ndarray, block_pairs: int) -> list[np.ndarray]:
    """Splits the receiving rows into blocks of about ``block_pairs`` upper-triangle pairs."""
    n = len(recv)
    blocks, start, pairs = [], 0, 0
    for k in range(n):
        pairs += n - k - 1
        if pairs >= block_pairs or k == n - 1:
            blocks.append(np.ascontiguousarray(recv[start : k + 1], dtype=np.int64))
            start, pairs = k + 1, 0
    return blocks


def _progress(enabled: bool, total: int, desc: str):
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="rows")
