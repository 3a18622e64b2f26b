"""The ``.vtu`` output: the scene's polygons with per-cell data, for ParaView
(docs/formats/vtu.md)."""

from __future__ import annotations

import os

import numpy as np

from ..._sparse import as_scipy
from ..atomic import atomic_path
from ._common import _csr, _square, field


def write_vtu(path, polygons_vertices, faces, cell_data: dict | None = None) -> None:
    """Polygons with per-cell data as a VTK XML unstructured grid (opens in ParaView).

    Consecutive faces with the same vertex count form one cell block (``triangle``,
    ``quad`` or ``polygon``), so cells keep their order: cell k of the file is ``faces[k]``.
    ``cell_data`` maps a name to an (F,) or (F, k) array.
    """
    import meshio

    path = os.fspath(path)
    pts = np.asarray(polygons_vertices, dtype=np.float64).reshape(-1, 3)
    faces = [np.asarray(f, dtype=np.int64).ravel() for f in faces]
    nf = len(faces)
    if nf == 0:
        raise ValueError("no faces to write")
    for k, f in enumerate(faces):
        if f.size < 3 or f.min() < 0 or f.max() >= len(pts):
            raise ValueError(f"face {k} is not a polygon over the {len(pts)} vertices")
    data: dict[str, np.ndarray] = {}
    for name, arr in (cell_data or {}).items():
        a = np.asarray(arr)
        if a.shape[:1] != (nf,):
            raise ValueError(f"cell data {name!r} has {a.shape[0] if a.ndim else 0} entries for {nf} faces")
        if a.dtype == bool:
            a = a.astype(np.int8)
        data[str(name)] = a
    sizes = np.array([f.size for f in faces])
    starts = np.flatnonzero(np.r_[True, sizes[1:] != sizes[:-1]])
    ends = np.r_[starts[1:], nf]
    cells = []
    block_data: dict[str, list[np.ndarray]] = {k: [] for k in data}
    for s, e in zip(starts, ends):
        m = sizes[s]
        ctype = {3: "triangle", 4: "quad"}.get(int(m), "polygon")
        cells.append(meshio.CellBlock(ctype, np.array(faces[s:e])))
        for key, a in data.items():
            block_data[key].append(a[s:e])
    mesh = meshio.Mesh(pts, cells, cell_data=block_data)
    with atomic_path(path) as tmp:
        meshio.write(tmp, mesh, file_format="vtu")


def write_result_vtu(path: str, result, scene, to_surface: str | None, patch_level: bool) -> None:
    """A result on the scene's polygons (see :func:`nusselt.io.write_result`)."""
    matrix = field(result, "matrix")
    n = _square(matrix)
    m = as_scipy(_csr(matrix))
    faces_of_rows = np.asarray(field(result, "faces"), dtype=np.int64)
    nface = len(scene.faces)
    surf = np.asarray(scene.surface, dtype=np.int64)
    if patch_level:
        row_of_face = np.full(nface, -1, dtype=np.int64)
        row_of_face[faces_of_rows] = np.arange(n)
        col_surface = np.asarray(field(result, "surface"), dtype=np.int64)
        col_names = list(field(result, "surface_names") or scene.surface_names)
    else:
        row_of_surface = {int(s): r for r, s in enumerate(faces_of_rows)}
        row_of_face = np.array([row_of_surface.get(int(s), -1) for s in surf], dtype=np.int64)
        col_surface = faces_of_rows
        col_names = list(scene.surface_names)
    has_row = row_of_face >= 0
    sums = np.asarray(m.sum(axis=1)).ravel()
    row_sum = np.full(nface, np.nan)
    row_sum[has_row] = sums[row_of_face[has_row]]
    data = {
        "area": np.asarray(scene.areas, dtype=np.float64),
        "surface": surf,
        "obstruction": np.asarray(scene.obstruction, dtype=np.int8),
        "row": row_of_face,
        "row_sum": row_sum,
    }
    if to_surface is not None:
        if to_surface not in col_names:
            shown = ", ".join(col_names[:10]) + (" ..." if len(col_names) > 10 else "")
            raise ValueError(f"{path}: no surface named {to_surface!r} (surfaces: {shown})")
        t = col_names.index(to_surface)
        indicator = (col_surface == t).astype(np.float64)
        f_to = m @ indicator
        col = np.full(nface, np.nan)
        col[has_row] = f_to[row_of_face[has_row]]
        data[f"F_to_{to_surface}"] = col
    write_vtu(path, scene.vertices, scene.faces, data)
