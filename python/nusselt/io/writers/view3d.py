"""The View3D text output (``.txt``), in View3D 3.2's layout (docs/formats/view3d-output.md)."""

from __future__ import annotations

import os

import numpy as np
import scipy.sparse as sp

from ._common import MAX_DENSE_ROWS, _areas, _atomic, _check_size, _dense_rows, _square, field


def write_view3d(
    path,
    matrix,
    areas,
    emissivity=None,
    encl: int = 0,
    precision: int | None = 6,
    *,
    emit: int = 0,
    max_rows: int | None = MAX_DENSE_ROWS,
) -> None:
    """View3D 3.2 text output (``out=0``) layout::

        View3D 3.2 0 <encl> <emit> <N>      (padded to 30 characters, as View3D does)
        <N areas, %g>
        <N rows of F, %.6f>
        <N emissivities, %.3f>

    ``precision=6`` reproduces View3D's digits; ``precision=None`` writes every number in
    its shortest exact (round-trip) form; another integer sets the decimals of F.
    ``emissivity=None`` writes 1.000 (unknown: black). ``emit`` is the header flag saying
    the matrix is Hottel's script-F (0: plain F, which is what nusselt computes).
    """
    path = os.fspath(path)
    n = _square(matrix)
    a = _areas(areas, n)
    _check_size(path, n, max_rows, "View3D table")
    e = np.ones(n) if emissivity is None else np.asarray(emissivity, dtype=np.float64).ravel()
    if e.shape != (n,):
        raise ValueError(f"{e.size} emissivities for {n} rows")
    e = np.where(np.isfinite(e), e, 1.0)
    if precision is None:
        fa = ff = fe = repr
    else:
        p = int(precision)
        fa, ff, fe = (lambda x: f"{x:g}"), (lambda x: f"{x:.{p}f}"), (lambda x: f"{x:.3f}")
    header = f"View3D 3.2 0 {int(bool(encl))} {int(bool(emit))} {n}".ljust(30)
    with _atomic(path, "w") as fh:
        fh.write(header + "\n")
        fh.write(" ".join(map(fa, a.tolist())) + "\n")
        for row in _dense_rows(matrix, n):
            fh.write(" ".join(map(ff, row.tolist())) + "\n")
        fh.write(" ".join(map(fe, e.tolist())) + "\n")


def write_result_view3d(path: str, result, scene, *, precision: int | None, patch_level: bool) -> None:
    """A result as View3D writes it (see :func:`nusselt.io.write_result`): per surface when the
    scene came from a View3D file, emissivities and ``encl`` from the scene, script-F when
    the ``.vs3`` file says ``emit=1``."""
    meta = getattr(scene, "meta", None) or {}
    matrix, areas = field(result, "matrix"), field(result, "areas")
    if patch_level and meta.get("format") == "view3d" and hasattr(result, "by_surface"):
        result = result.by_surface()
        matrix, areas, patch_level = result.matrix, result.areas, False
    em = _row_emissivity(result, scene, patch_level)
    emit = int(bool(meta.get("emit", 0))) if meta.get("format") == "view3d" else 0
    if emit:
        em, matrix = _view3d_script_f(path, matrix, em)
    write_view3d(
        path,
        matrix,
        areas,
        emissivity=em,
        encl=int(meta.get("encl", 0) or 0),
        precision=6 if precision is None else precision,
        emit=emit,
    )


def _view3d_script_f(path, matrix, emissivity):
    """View3D's ``emit=1`` output: script-F of the surface emissivities, which View3D clamps
    to [0.001, 0.999] when it reads them (getdat.c); returns (emissivities, script-F)."""
    if emissivity is None or not np.all(np.isfinite(emissivity)):
        raise ValueError(
            f"{path}: the .vs3 file says emit=1 (write script-F), which needs the emissivity "
            "of every surface with a row"
        )
    from ...exchange import script_f

    e = np.clip(np.asarray(emissivity, dtype=np.float64), 0.001, 0.999)
    f = matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix, dtype=np.float64)
    return e, np.asarray(script_f(f, e))


def _row_emissivity(result, scene, patch_level):
    em = getattr(scene, "emissivity", None) if scene is not None else None
    faces = field(result, "faces")
    if em is None or faces is None:
        return None
    em = np.asarray(em, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    sidx = np.asarray(scene.surface)[faces] if patch_level else faces
    return em[sidx]
