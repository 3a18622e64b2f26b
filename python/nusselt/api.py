"""The public functions: form factors of a pair, of a point, and of a whole scene."""

from __future__ import annotations

import functools
import os
from collections.abc import Callable
from typing import Any, Literal, overload

import numpy as np

from . import _core, assembly, blocks, budget, ranges
from .checks import ToleranceWarning, warn_unmet_tolerance, warn_zero_rows
from .methods import MethodName, resolve
from .result import FormFactors
from .scene import PLANARITY_TOL, Scene, geometry_error


def _polygon(p, what: str) -> np.ndarray:
    a = np.asarray(p, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{what}: expected an (n, 3) array of vertices, got shape {a.shape}")
    if np.isfinite(a).all():  # NaN and infinity get the core's message
        ranges.check_coordinates(a, what)
        ranges.check_extent(a, what)
    return np.ascontiguousarray(a)


def _vector(x, what: str) -> np.ndarray:
    a = np.asarray(x, dtype=np.float64).ravel()
    if a.shape != (3,) or not np.isfinite(a).all():
        raise ValueError(f"{what} must be 3 finite numbers, got {np.asarray(x).tolist()}")
    ranges.check_coordinates(a[None, :], what)
    return a


def _obstacles(obstacles) -> list[np.ndarray]:
    if obstacles is None:
        return []
    if isinstance(obstacles, Scene):
        return obstacles.polygons
    return [_polygon(o, f"obstacle {k}") for k, o in enumerate(obstacles)]


def _labels(named: tuple[str, ...], obstacles) -> Callable[[int], str]:
    """Names of the polygons of one call, by their index in the core's list: ``named``
    first, then the obstacles (a Scene's faces by its own labels)."""

    def label(k: int) -> str:
        if k < len(named):
            return named[k]
        k -= len(named)
        return f"obstacle {obstacles._face_label(k) if isinstance(obstacles, Scene) else k}"

    return label


@overload
def view_factor(
    pi, pj, *, obstacles=None, method: MethodName = ..., return_std: Literal[False] = ..., **options: Any
) -> float: ...
@overload
def view_factor(
    pi, pj, *, obstacles=None, method: MethodName = ..., return_std: Literal[True], **options: Any
) -> tuple[float, float]: ...
@overload
def view_factor(
    pi, pj, *, obstacles=None, method: MethodName = ..., return_std: bool, **options: Any
) -> float | tuple[float, float]: ...
def view_factor(
    pi, pj, *, obstacles=None, method: MethodName = "auto", return_std: bool = False, **options: Any
) -> float | tuple[float, float]:
    """F_ij: the fraction of the radiation leaving polygon ``pi`` that reaches polygon ``pj``.

    Polygons are (n, 3) arrays, counter-clockwise seen from their front (emitting and
    receiving) side. ``obstacles`` is a list of polygons (opaque from both sides) or a Scene.
    ``method`` is one of :data:`nusselt.METHODS`; its options are keyword arguments.
    With ``return_std=True`` returns ``(F, standard error)``: 0 for deterministic methods,
    except where an obstructed pair's adaptive integral ran out of evaluations before it met
    ``obstructed_tol`` (``clipping``: ``tol``); then the integral's error estimate, and a
    :class:`ToleranceWarning`.
    """
    a, b = _polygon(pi, "pi"), _polygon(pj, "pj")
    obs = _obstacles(obstacles)
    _, opts = resolve(method, options)
    try:
        f, s = _core.view_factor(a, b, obs, method, opts, PLANARITY_TOL)
    except _core.GeometryError as err:
        raise geometry_error(err, _labels(("pi", "pj"), obstacles)) from None
    if s > 0.0 and not _sampled(method):
        import warnings

        name = _tol_name(opts)
        warnings.warn(
            f"method {method!r}: F = {f:.6g} did not reach {name}={opts[name]:g} within "
            f"the evaluation limit of its integral; its error estimate is {s:.3g}",
            ToleranceWarning,
            stacklevel=2,
        )
    return (float(f), float(s)) if return_std else float(f)


def _sampled(method: str) -> bool:
    """True for the methods whose standard error is statistical (they take a seed)."""
    from .methods import METHODS

    return "seed" in METHODS[method].options


def _tol_name(opts: dict[str, Any]) -> str:
    """The option that sets the relative target of a method's obstructed pairs (`clipping`'s
    own `tol`; the exact methods' `tol` is that of their unobstructed kernel)."""
    return "obstructed_tol" if "obstructed_tol" in opts else "tol"


@overload
def point_view_factor(
    point, normal, pj, *, obstacles=None, method: MethodName = ..., return_std: Literal[False] = ..., **options: Any
) -> float: ...
@overload
def point_view_factor(
    point, normal, pj, *, obstacles=None, method: MethodName = ..., return_std: Literal[True], **options: Any
) -> tuple[float, float]: ...
@overload
def point_view_factor(
    point, normal, pj, *, obstacles=None, method: MethodName = ..., return_std: bool, **options: Any
) -> float | tuple[float, float]: ...
def point_view_factor(
    point, normal, pj, *, obstacles=None, method: MethodName = "auto", return_std: bool = False, **options: Any
) -> float | tuple[float, float]:
    """F from a differential area at ``point`` with unit ``normal`` to polygon ``pj``
    (``return_std=True``: ``(F, standard error)``)."""
    p = _vector(point, "point")
    n = _vector(normal, "normal")
    length = np.linalg.norm(n)
    if not length > 0:
        raise ValueError("normal must be a nonzero vector")
    b = _polygon(pj, "pj")
    obs = _obstacles(obstacles)
    _, opts = resolve(method, options)
    try:
        f, s = _core.point_view_factor(p, n / length, b, obs, method, opts, PLANARITY_TOL)
    except _core.GeometryError as err:
        raise geometry_error(err, _labels(("pj",), obstacles)) from None
    return (float(f), float(s)) if return_std else float(f)


def form_factors(
    scene: Scene,
    *,
    method: MethodName = "auto",
    dense: bool = False,
    progress: bool = False,
    checkpoint: str | os.PathLike | None = None,
    resume: bool = False,
    checkpoint_after: float = 0.0,
    block_size: int = 2_000_000,
    threshold: float = 0.0,
    dtype: type | np.dtype | str = np.float64,
    client=None,
    check_memory: bool = True,
    **options,
) -> FormFactors:
    """The form-factor matrix of a scene: F[i, j] for every pair of receiving polygons.

    Rows are computed in parallel, block by block; Ctrl-C stops within a fraction of a second
    and keeps every finished block: in ``checkpoint``, or (without one) in a new checkpoint
    directory that the KeyboardInterrupt's message names, from which ``resume=True`` continues.
    Pair methods compute every unordered pair once, so reciprocity A_i F_ij = A_j F_ji holds
    to rounding.
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
    checkpoint_after : float
        Seconds (wall clock) of computing before ``checkpoint`` is first written (default 0:
        from the first block). Until then finished blocks are only held in memory, so a run
        that ends sooner writes no checkpoint at all; after it the held blocks and each later
        one are written as they finish. A kill in that time loses at most those seconds of
        work; Ctrl-C loses nothing (the finished blocks are written to ``checkpoint``). A
        checkpoint directory that already holds a run is opened at once, and so is one for a
        ``client`` run or a sparse ``threshold`` that drops pairs (blocks are not held whole).
    block_size : int
        The most work per block: upper-triangle pairs (pair methods) or row entries (row
        methods); it bounds a block's memory. Blocks are sized from the measured speed, small
        at first, to take about half a second each (:mod:`nusselt.blocks`); where they are
        cut changes no value, so a checkpoint resumes whatever the block size.
    threshold : float
        Sparse threshold: a pair is dropped from the result when both F_ij and F_ji are below
        ``threshold`` (default 0: every nonzero entry is kept), so reciprocity still holds.
        Rows then sum to less by what they dropped; ``info["dropped"]`` reports the largest
        row mass dropped.

    dtype : numpy.float64 or numpy.float32
        Type of the stored values (float32: a third less memory; F to about 6e-8 relative).
        The core always computes in float64.
    client : dask.distributed.Client, optional
        Run the row blocks as tasks on this Dask cluster (:mod:`nusselt.distributed`): the
        scene is shipped once per worker, finished blocks go to ``checkpoint`` as they
        arrive, and the matrix is identical to a local run.
    check_memory : bool
        Refuse (MemoryError, before any work) a run whose worst-case result does not fit in
        the available memory (:mod:`nusselt.budget`).

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

        return two_sided_form_factors(
            form_factors,
            scene,
            method=method,
            dense=dense,
            progress=progress,
            checkpoint=checkpoint,
            resume=resume,
            checkpoint_after=checkpoint_after,
            block_size=block_size,
            threshold=threshold,
            dtype=dtype,
            client=client,
            check_memory=check_memory,
            **options,
        )
    if not (isinstance(threshold, (int, float)) and 0.0 <= threshold < 1.0):
        raise ValueError(f"threshold must be a number in [0, 1), got {threshold!r}")
    value_type = np.dtype(dtype)
    if value_type not in (np.float64, np.float32):
        raise ValueError(f"dtype must be float64 or float32, got {dtype!r}")
    m, opts = resolve(method, options)
    recv = scene.receivers
    nr = len(recv)
    kind = m.kind
    if check_memory:
        budget.check_memory(
            nr,
            kind=kind,
            threshold=float(threshold),
            dtype=value_type,
            with_std=_sampled(method),
            dense=dense,
            scene=scene,
            recv=recv,
        )
    col_of = np.full(len(scene), -1, dtype=np.int64)
    col_of[recv] = np.arange(nr)

    if not (isinstance(checkpoint_after, (int, float)) and checkpoint_after >= 0.0):
        raise ValueError(f"checkpoint_after must be a number of seconds >= 0, got {checkpoint_after!r}")
    from . import checkpoint as _checkpoint  # hashlib, json, shutil: loaded by a run only

    run = _checkpoint.describe_run(scene, method, opts, kind)
    ckpt: _checkpoint.Checkpoint | None = None
    write_after: float | None = None
    later: Callable[[], _checkpoint.Checkpoint]
    if checkpoint is not None and checkpoint_after > 0 and client is None and not _checkpoint.holds_run(checkpoint):
        # deferred: opened when first written (a run that ends sooner leaves nothing on disk)
        later = functools.partial(_checkpoint.Checkpoint, checkpoint, run, False)
        write_after = float(checkpoint_after)
    else:
        if checkpoint is not None:
            ckpt = _checkpoint.Checkpoint(checkpoint, run, resume)

        def later() -> _checkpoint.Checkpoint:
            # Ctrl-C without a checkpoint: the finished blocks go to a fresh one (named in the message)
            import tempfile

            return _checkpoint.Checkpoint(tempfile.mkdtemp(prefix="nusselt-interrupted-"), run, resume=False)

    # pair blocks lose their below-threshold pairs as they arrive (stored whole in the checkpoint)
    dropped_mass = np.zeros(len(scene))
    scene_areas = np.asarray(scene.areas, dtype=np.float64)

    def keep(b: blocks.Block) -> blocks.Block:
        if kind == "pairs":
            return assembly.threshold_pair_block(b, scene_areas, float(threshold), dropped_mass)
        return b

    def compute(rows):
        if kind == "pairs":
            return blocks.Block(rows, *scene._core.pair_rows(rows, method, opts))
        return assembly.compact_row_block(blocks.Block(rows, *scene._core.full_rows(rows, method, opts)))

    bar = _progress(progress, total=nr, desc=f"nusselt {method}")
    held: list[tuple[int, int, blocks.Block]] = []  # finished, in memory only (deferred checkpoint)

    def run_all() -> list[blocks.Block]:
        try:
            if client is not None:
                from . import distributed

                return distributed.run_blocks(
                    client, scene, method, opts, kind, recv, block_size, checkpoint=ckpt, progress_bar=bar, keep=keep
                )
            return blocks.run_blocks(
                compute,
                recv,
                kind,
                block_size,
                checkpoint=ckpt,
                progress_bar=bar,
                keep=keep,
                threads=_threads(),
                later=later,
                write_after=write_after,
                held=held,
            )
        finally:
            if bar is not None:
                bar.close()
            if ckpt is not None:
                ckpt.close()

    try:
        return _assemble(scene, run_all(), kind, recv, col_of, value_type, dense, threshold, dropped_mass, method, opts)
    except KeyboardInterrupt:
        if not held:
            raise  # run_blocks said where the finished blocks are, or none were finished
        # every row was computed but held in memory only, and the Ctrl-C came while they were
        # assembled: they are written now, so nothing computed is lost
        saved = blocks.save_held(later, held)
        raise KeyboardInterrupt(
            f"interrupted after all {nr} rows were computed: they were saved to checkpoint {saved.path}; "
            f"the same call with checkpoint={saved.path!r}, resume=True assembles them (CLI: --resume)"
        ) from None


def _assemble(
    scene: Scene,
    done: list[blocks.Block],
    kind: str,
    recv: np.ndarray,
    col_of: np.ndarray,
    value_type: Any,
    dense: bool,
    threshold: float,
    dropped_mass: np.ndarray,
    method: str,
    opts: dict[str, Any],
) -> FormFactors:
    """The finished blocks of :func:`form_factors` as its result: the matrix over the
    receivers `recv` (pairs mirrored and divided by the areas, or rows), its trust measures
    and the mass a `threshold` dropped (`dropped_mass`, per polygon, for pair blocks)."""
    scene_areas = np.asarray(scene.areas, dtype=np.float64)
    areas = scene.areas[recv]
    std = lost = reciprocity = None
    dropped = 0.0
    nr = len(recv)
    if kind == "pairs":
        reciprocity = assembly.pair_reciprocity(done, scene_areas, value_type)
        matrix, std = assembly.assemble_pairs(done, col_of, areas, value_type)
        dropped = float(dropped_mass[recv].max()) if nr and threshold > 0.0 else 0.0
    else:
        matrix, std, lost = assembly.assemble_rows(done, col_of, nr, value_type)
        if threshold > 0.0:
            matrix, std, dropped = assembly.threshold_matrix(matrix, std, threshold)
    if threshold == 0.0:  # a threshold may empty a row legitimately
        warn_zero_rows(scene, matrix, recv)
    if std is not None and kind == "pairs" and not _sampled(method):
        name = _tol_name(opts)
        warn_unmet_tolerance(scene, std, matrix, recv, method, name, float(opts[name]))
    names = [f"{scene.surface_names[scene.surface[k]]}[{k}]" for k in recv]
    result = FormFactors(
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
    if reciprocity is not None and not dense:
        result._seed_measures(reciprocity_error=reciprocity)
    return result


def memory_estimate(n: int, dense: bool = False) -> tuple[int, int | None]:
    """(bytes the result of an n-row run may need at its peak, bytes of memory available or
    None): the worst case of :mod:`nusselt.budget` for a pair method without threshold."""
    need = 2 * 8 * n * n if dense else budget.peak_bytes(n, kind="pairs")
    return need, budget.available_memory()


def _threads() -> int:
    """How many threads the core's pool runs (NUSSELT_NUM_THREADS, else RAYON_NUM_THREADS,
    else the CPUs)."""
    return int(_core.num_threads())


def _progress(enabled: bool, total: int, desc: str):
    if not enabled:
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="rows", dynamic_ncols=True)
