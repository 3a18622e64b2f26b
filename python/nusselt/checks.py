"""Checks of a computed result against what the geometry allows (warnings, not errors)."""

from __future__ import annotations

import warnings

import numpy as np

from ._sparse import Csr, as_scipy, issparse
from .scene import NusseltWarning, Scene


class ZeroRowWarning(NusseltWarning):
    """Rows of F are 0 although another face lies in front of them (a face turned the
    wrong way, most often)."""


class ToleranceWarning(NusseltWarning):
    """Pairs whose adaptive integral (``auto``, ``clipping``, and the obstructed pairs of
    ``analytic`` and ``contour``) ran out of point evaluations before it met the tolerance
    asked for: their error estimates are in the result's ``std_err``."""


#: At most this many (zero row, receiver) pairs are tested; beyond it zero rows are sampled.
_BUDGET = 20_000_000


def facing_partner(scene: Scene, rows: np.ndarray, cols: np.ndarray, backs: bool = False) -> np.ndarray:
    """For each face in ``rows``: whether some face in ``cols`` and it lie in front of each
    other (centroid of each strictly on the front side of the other's plane, by 1e-9 of the
    scene's size). Without obstacles such a pair has F > 0 both ways: near the centroids
    there are points that see each other's front. ``backs=True``: the same for the backs
    (the pair would see each other if both were turned around)."""
    c, n = scene.centroids, (-scene.normals if backs else scene.normals)
    size = float(np.linalg.norm(np.ptp(scene.vertices, axis=0))) or 1.0
    tol = 1e-9 * size
    out = np.zeros(len(rows), dtype=bool)
    step = max(1, _BUDGET // max(len(cols), 1) // 8)
    cc, nc = c[cols], n[cols]
    for s in range(0, len(rows), step):
        r = rows[s : s + step]
        d = cc[None, :, :] - c[r][:, None, :]  # (r, cols, 3): from row to column
        ahead = np.einsum("rkj,rj->rk", d, n[r]) > tol
        behind = np.einsum("rkj,kj->rk", d, nc) < -tol
        out[s : s + step] = (ahead & behind).any(axis=1)
    return out


def warn_zero_rows(scene: Scene, matrix, faces: np.ndarray, *, stacklevel: int = 3) -> None:
    """Warn (:class:`ZeroRowWarning`) when rows of ``matrix`` (rows = ``faces`` of the
    scene) are 0 while another receiver lies in front of them, or the whole result is 0."""
    nr = matrix.shape[0]
    if nr < 2:
        return
    # the plain row sums need no copy of the entries (abs(m) would copy them all: 210 MB on
    # a 6 144-patch cube); a sum of 0 from entries of both signs is told apart on those rows
    if isinstance(matrix, Csr):  # the assembly's matrix: no scipy needed
        nnz = matrix.nnz
        zero = np.flatnonzero(matrix.row_sums() == 0)
        if len(zero):
            zero = zero[matrix.abs_row_sums(zero) == 0]
    else:
        import scipy.sparse as sp

        m = matrix if issparse(matrix) else sp.csr_array(np.asarray(matrix))
        nnz = m.nnz
        zero = np.flatnonzero(np.asarray(m.sum(axis=1)).ravel() == 0)
        if len(zero):
            zero = zero[np.asarray(abs(sp.csr_array(m[zero])).sum(axis=1)).ravel() == 0]
    if not len(zero):
        return
    checked = zero
    if len(zero) * nr > _BUDGET:
        checked = zero[np.unique(np.linspace(0, len(zero) - 1, max(1, _BUDGET // nr)).astype(np.int64))]
    faces = np.asarray(faces)
    bad = checked[facing_partner(scene, faces[checked], faces)]
    # A face turned the wrong way empties its whole surface; patches of a surface whose other
    # patches see something are hidden, not reversed (floor tiles under a block that stands
    # on them), so only surfaces with every row 0 are suspicious.
    surface = np.asarray(scene.surface)[faces]
    seen = np.zeros(int(surface.max()) + 1, dtype=bool)
    seen[surface[np.setdiff1d(np.arange(nr), zero, assume_unique=True)]] = True
    bad = bad[~seen[surface[bad]]]
    backs = nnz == 0 and not len(bad)
    if backs:
        bad = checked[facing_partner(scene, faces[checked], faces, backs=True)]
    if not len(bad):
        return
    first = scene._face_label(int(faces[bad[0]]))
    sampled = f" (of {len(checked)} zero rows checked)" if len(checked) < len(zero) else ""
    if nnz == 0:
        how = "behind" if backs else "in front of"
        msg = (
            f"the whole result is 0, although faces lie {how} each other ({first} and others): "
            "the faces probably face the wrong way (fronts must face each other: counter-clockwise "
            "seen from the front); try orient='inward' (a room) or 'outward' (solids), or "
            "two_sided for plates (nusselt matrix --orient ...)"
        )
    else:
        msg = (
            f"{len(bad)} of {nr} rows are 0{sampled} although another face lies in front of each "
            f"({first} first): every row of their surfaces is 0: those faces probably face the "
            "wrong way (or are hidden entirely behind other faces); see orient and two_sided in the guide"
        )
    warnings.warn(f"{scene.source + ': ' if scene.source else ''}{msg}", ZeroRowWarning, stacklevel=stacklevel)


def warn_unmet_tolerance(
    scene: Scene, std, matrix, faces: np.ndarray, method: str, name: str, tol: float, *, stacklevel: int = 4
) -> None:
    """Warn (:class:`ToleranceWarning`) when a deterministic pair method's result carries
    error estimates (``std``: sparse, of F, rows and columns = ``faces``): the pairs whose
    integral ended short of its target ``tol`` (option ``name``, relative to each pair's
    unobstructed F)."""
    s = as_scipy(std).tocoo()
    keep = s.data > 0
    if not keep.any():
        return
    r, c, e = s.row[keep], s.col[keep], s.data[keep]
    k = int(np.argmax(e))
    f = float(as_scipy(matrix).tocsr()[int(r[k]), int(c[k])])
    where = f"{scene._face_label(int(faces[r[k]]))} -> {scene._face_label(int(faces[c[k]]))}"
    msg = (
        f"method {method!r}: {len(e)} entries of F did not reach {name}={tol:g} within "
        f"the evaluation limit of their integral; their error estimates are in std_err (the "
        f"largest {e[k]:.3g} for F = {f:.6g}, {where}). The estimate is the integral's own: "
        "where blockers come within a tiny fraction of a face's size it may itself fall short"
    )
    prefix = f"{scene.source}: " if scene.source else ""
    warnings.warn(prefix + msg, ToleranceWarning, stacklevel=stacklevel)
