"""Writers for form-factor results: .npz, .csv, View3D text, EnergyPlus IDF, VTU.

All low-level writers take plain data: ``matrix`` is a scipy.sparse array or a dense
ndarray with F[i, j] = fraction leaving row i that reaches column j (row = source).
Files are written to a temporary name and renamed, so a killed run never leaves a
half-written output under the final name.
"""

from __future__ import annotations

import csv
import json
import os
from collections.abc import Callable
from typing import Any

import numpy as np
import scipy.sparse as sp

from .atomic import atomic_open, atomic_path

#: Largest matrix written as a dense text table (CSV, View3D text) unless asked otherwise.
MAX_DENSE_ROWS = 20000

NPZ_FORMAT = "nusselt-form-factors"
NPZ_VERSION = 1


def _atomic(path: str, mode: str = "w"):
    """A temporary file next to ``path``, renamed to ``path`` durably on success (see
    :mod:`nusselt.io.atomic`)."""
    return atomic_open(path, mode)


def _square(matrix, what: str = "matrix"):
    shape = matrix.shape
    if len(shape) != 2 or shape[0] != shape[1]:
        raise ValueError(f"{what} must be square, got shape {shape}")
    return shape[0]


def _csr(matrix) -> sp.csr_array:
    if sp.issparse(matrix):
        return sp.csr_array(matrix)
    return sp.csr_array(np.asarray(matrix, dtype=np.float64))


def _names(names, n: int) -> list[str]:
    names = [str(s) for s in names]
    if len(names) != n:
        raise ValueError(f"{len(names)} names for {n} rows")
    return names


def _areas(areas, n: int) -> np.ndarray:
    a = np.asarray(areas, dtype=np.float64).ravel()
    if a.shape != (n,):
        raise ValueError(f"{a.size} areas for {n} rows")
    return a


def _dense_rows(matrix, n: int, block: int = 256):
    """Rows of the matrix as dense float arrays, a block at a time (bounded memory)."""
    if sp.issparse(matrix):
        m = sp.csr_array(matrix)
        for s in range(0, n, block):
            for r in m[s : s + block].toarray():
                yield r
    else:
        m = np.asarray(matrix, dtype=np.float64)
        for r in m:
            yield r


def _check_size(path: str, n: int, max_rows: int | None, kind: str) -> None:
    if max_rows is not None and n > max_rows:
        gb = n * n * 10 / 1e9
        raise ValueError(
            f"{path}: a dense {kind} of {n} x {n} values (about {gb:.3g} GB of text) is too large "
            f"(limit {max_rows} rows); write .npz instead (sparse, read back with "
            "nusselt.io.load_npz), or aggregate to surfaces"
        )


# --- npz ----------------------------------------------------------------------------------


def write_npz(path, matrix, areas, names, *, compress: bool = False, **extra_arrays) -> None:
    """Store the form factors as a ``.npz`` (zip-deflated with ``compress=True``).

    Keys: ``format``, ``version``, ``shape``, ``indptr``, ``indices``, ``data`` (the CSR
    parts of F), ``areas``, ``names`` and every extra array under its own name. A sparse
    extra (e.g. ``std_err``) is stored as ``<name>.indptr`` / ``.indices`` / ``.data`` /
    ``.shape``; a dict or string extra as JSON text. Read it back with :func:`load_npz`.
    Index arrays are stored as int32 when they fit (else int64) and values as float32 or
    float64 as given, so the file is no larger than the matrix in memory.
    """
    path = os.fspath(path)
    n = _square(matrix)
    m = _csr(matrix)
    m.sum_duplicates()
    m.sort_indices()
    arrays = {
        "format": np.array(NPZ_FORMAT),
        "version": np.array(NPZ_VERSION),
        "shape": np.array(m.shape, dtype=np.int64),
        "indptr": _index_array(m.indptr, m.nnz),
        "indices": _index_array(m.indices, n),
        "data": _value_array(m.data),
        "areas": _areas(areas, n),
        "names": np.array(_names(names, n), dtype=str),
    }
    for key, val in extra_arrays.items():
        if key in arrays or "." in key:
            raise ValueError(f"extra array name {key!r} is reserved or contains '.'")
        if val is None:
            continue
        if sp.issparse(val):
            e = sp.csr_array(val)
            arrays[f"{key}.shape"] = np.array(e.shape, dtype=np.int64)
            arrays[f"{key}.indptr"] = _index_array(e.indptr, e.nnz)
            arrays[f"{key}.indices"] = _index_array(e.indices, max(e.shape))
            arrays[f"{key}.data"] = _value_array(e.data)
        elif isinstance(val, dict):
            arrays[f"{key}.json"] = np.array(json.dumps(val, default=str))
        else:
            a = np.asarray(val)
            if a.dtype == object:
                a = np.array([str(x) for x in a.ravel()], dtype=str).reshape(a.shape)
            arrays[key] = a
    # Callable[..., None]: numpy's stubs reject ``**arrays`` as it could hold ``allow_pickle``.
    save: Callable[..., None] = np.savez_compressed if compress else np.savez
    with _atomic(path, "wb") as fh:
        save(fh, **arrays)


def _index_array(a: np.ndarray, largest: int) -> np.ndarray:
    """int32 when every index (at most ``largest``) fits, else int64; no copy if already so."""
    dtype = np.int32 if largest <= np.iinfo(np.int32).max else np.int64
    return np.asarray(a, dtype=dtype)


def _value_array(a: np.ndarray) -> np.ndarray:
    return a if a.dtype in (np.float32, np.float64) else np.asarray(a, dtype=np.float64)


def load_npz(path) -> dict:
    """Load a result written by :func:`write_npz` (``nusselt matrix ... -o out.npz``).

    >>> r = nusselt.io.load_npz("out.npz")
    >>> F = r["matrix"]            # scipy.sparse.csr_array, F[i, j], row = source
    >>> r["areas"], r["names"]     # ndarray, list of str

    Extra arrays come back under their names (sparse ones as csr_array, JSON ones as dicts).
    """
    path = os.fspath(path)
    from .scenedata import check_readable, parse_error

    check_readable(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            files = {k: z[k] for k in z.files}
    except Exception as e:
        raise parse_error(path, None, f"not a readable .npz file ({type(e).__name__}: {e})") from None
    if "format" not in files or str(files["format"]) != NPZ_FORMAT:
        raise parse_error(path, None, "not a nusselt form-factor file (no 'format' marker)")
    try:
        shape = tuple(int(x) for x in files.pop("shape"))
        matrix = sp.csr_array((files.pop("data"), files.pop("indices"), files.pop("indptr")), shape=shape)
    except Exception as e:
        raise parse_error(path, None, f"damaged matrix ({type(e).__name__}: {e})") from None
    out = {"matrix": matrix, "areas": files.pop("areas"), "names": [str(s) for s in files.pop("names")]}
    files.pop("format")
    out["version"] = int(files.pop("version"))
    groups: dict[str, dict] = {}
    for key, val in files.items():
        if "." in key:
            base, part = key.rsplit(".", 1)
            groups.setdefault(base, {})[part] = val
        else:
            out[key] = val
    for base, parts in groups.items():
        if "json" in parts:
            out[base] = json.loads(str(parts["json"]))
        else:
            out[base] = sp.csr_array(
                (parts["data"], parts["indices"], parts["indptr"]), shape=tuple(int(x) for x in parts["shape"])
            )
    return out


# --- csv ----------------------------------------------------------------------------------


def write_csv(path, matrix, names, *, precision: int | None = None, max_rows: int | None = MAX_DENSE_ROWS) -> None:
    """Dense table: a header row ``from \\ to, name1, name2, ...`` and one row per source
    starting with its name. Values are written exactly (shortest round-trip form) unless
    ``precision`` (significant digits) is given. Refuses more than ``max_rows`` rows."""
    path = os.fspath(path)
    n = _square(matrix)
    names = _names(names, n)
    _check_size(path, n, max_rows, "CSV table")
    fmt = repr if precision is None else (lambda x, p=int(precision): f"{x:.{p}g}")
    with _atomic(path, "w") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(["from \\ to"] + names)
        for name, row in zip(names, _dense_rows(matrix, n)):
            w.writerow([name] + list(map(fmt, row.tolist())))


# --- View3D -------------------------------------------------------------------------------


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


# --- EnergyPlus ---------------------------------------------------------------------------


def write_energyplus(path, matrix, names, zone_name: str, *, all_pairs: bool = False) -> None:
    """EnergyPlus ``ZoneProperty:UserViewFactors:BySurfaceName`` object (IDF text).

    Fields (EnergyPlus Input Output Reference / Energy+.idd, 22.1 and later):
    ``Zone or ZoneList or Space or SpaceList Name``, then repeated triplets
    ``From Surface <i>``, ``To Surface <i>``, ``View Factor <i>`` (the view factor from the
    "from" surface to the "to" surface, at most 1.0). Omitted pairs count as zero, so only
    nonzero entries are written unless ``all_pairs``. ``names`` must be the EnergyPlus
    surface names of the zone.
    """
    from .energyplus import write_user_view_factors

    n = _square(matrix)
    write_user_view_factors(path, [(zone_name, matrix, _names(names, n))], format="idf", all_pairs=all_pairs)


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


# --- dispatch -----------------------------------------------------------------------------

_EXT_FORMAT = {
    ".npz": "npz",
    ".csv": "csv",
    ".txt": "view3d",
    ".view3d": "view3d",
    ".vf": "view3d",
    ".idf": "energyplus",
    ".epjson": "epjson",
    ".vtu": "vtu",
}
FORMATS = ("npz", "csv", "view3d", "energyplus", "epjson", "vtu")


def result_format(path, format: str | None = None) -> str:
    """The output format for a path (by extension) or an explicit ``format`` name."""
    if format is not None:
        f = format.lower()
        f = {"txt": "view3d", "idf": "energyplus", "eplus": "energyplus"}.get(f, f)
        if f not in FORMATS:
            raise ValueError(f"unknown output format {format!r}; choose one of {', '.join(FORMATS)}")
        return f
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in _EXT_FORMAT:
        raise ValueError(
            f"{path}: cannot tell the output format from the extension {ext or '(none)'}; "
            "use .npz, .csv, .txt (View3D), .idf or .epJSON (EnergyPlus) or .vtu"
        )
    return _EXT_FORMAT[ext]


def _get(result, key, default=None):
    if isinstance(result, dict):
        return result.get(key, default)
    return getattr(result, key, default)


def write_result(
    path,
    result,
    *,
    format: str | None = None,
    scene=None,
    to_surface: str | None = None,
    zone_name: str | None = None,
    precision: int | None = None,
    compress: bool = False,
) -> None:
    """Write a form-factor result in the format given by ``format`` or the extension:
    ``.npz`` (sparse, everything), ``.csv``, ``.txt`` (View3D text output), ``.idf``
    (EnergyPlus), ``.vtu`` (the scene's polygons with per-cell data; needs ``scene``).

    ``result`` is a :class:`nusselt.FormFactors` (or any object/dict with ``matrix``,
    ``areas``, ``names`` and optionally ``faces``, ``surface``, ``surface_names``,
    ``std_err``, ``lost``, ``method``, ``info``, ``by_surface()``).

    * ``.idf`` / ``.epJSON`` are always per named surface (patch results are aggregated
      with the form-factor algebra), all N^2 pairs of every zone, zeros included. A scene
      from a building model (EnergyPlus) gives one object per zone of the result (compute
      it with :func:`nusselt.zones.zone_form_factors`); ``zone_name`` then picks one zone
      (or renames the only one). Other scenes are one zone, named ``zone_name`` (default:
      the scene file's stem).
    * ``.txt`` is per surface when the scene came from a View3D file (View3D's own output
      is per surface), else as given; emissivities and ``encl`` come from the scene. When
      the ``.vs3`` file says ``emit=1`` the matrix is Hottel's script-F of those
      emissivities (clamped to [0.001, 0.999] as View3D does), as View3D then writes.
    * ``.vtu``: cell data ``area``, ``surface``, ``obstruction``, ``row`` (row of the
      result, -1 for none), ``row_sum``, and ``F_to_<name>`` when ``to_surface`` is given.
    * ``precision``: CSV significant digits / View3D decimals (default: exact for CSV,
      6 decimals for View3D as View3D writes).
    * ``compress``: ``.npz`` only, zip-deflated (smaller file, slower to write and read).
    """
    path = os.fspath(path)
    fmt = result_format(path, format)
    matrix, areas, names = _get(result, "matrix"), _get(result, "areas"), _get(result, "names")
    if matrix is None or areas is None or names is None:
        raise ValueError("result needs matrix, areas and names")
    meta = getattr(scene, "meta", None) or {}
    patch_level = _get(result, "surface") is not None

    if fmt == "npz":
        extra: dict[str, Any] = {}
        m = _get(result, "matrix")
        extra["row_sums"] = np.asarray(m.sum(axis=1)).ravel()
        for key in ("faces", "surface", "lost", "std_err"):
            v = _get(result, key)
            if v is not None:
                extra[key] = v
        sn = _get(result, "surface_names")
        if sn is not None:
            extra["surface_names"] = np.array([str(s) for s in sn], dtype=str)
        if _get(result, "method") is not None:
            extra["method"] = np.array(str(_get(result, "method")))
        info = _get(result, "info")
        if info:
            extra["info"] = dict(info)
        if scene is not None and getattr(scene, "source", None):
            extra["scene"] = np.array(str(scene.source))
        write_npz(path, matrix, areas, names, compress=compress, **extra)
    elif fmt == "csv":
        write_csv(path, matrix, names, precision=precision)
    elif fmt == "view3d":
        if patch_level and meta.get("format") == "view3d" and hasattr(result, "by_surface"):
            result = result.by_surface()
            matrix, areas, names, patch_level = result.matrix, result.areas, result.names, False
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
    elif fmt in ("energyplus", "epjson"):
        _write_result_energyplus(path, result, scene, zone_name, "epjson" if fmt == "epjson" else "idf", patch_level)
    else:
        if scene is None:
            raise ValueError(f"{path}: VTU output needs the scene geometry (pass scene=)")
        _write_result_vtu(path, result, scene, to_surface, patch_level)


def _view3d_script_f(path, matrix, emissivity):
    """View3D's ``emit=1`` output: script-F of the surface emissivities, which View3D clamps
    to [0.001, 0.999] when it reads them (getdat.c); returns (emissivities, script-F)."""
    if emissivity is None or not np.all(np.isfinite(emissivity)):
        raise ValueError(
            f"{path}: the .vs3 file says emit=1 (write script-F), which needs the emissivity "
            "of every surface with a row"
        )
    from ..exchange import script_f

    e = np.clip(np.asarray(emissivity, dtype=np.float64), 0.001, 0.999)
    f = matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix, dtype=np.float64)
    return e, np.asarray(script_f(f, e))


def _write_result_energyplus(path, result, scene, zone_name, fmt, patch_level):
    """One ZoneProperty:UserViewFactors:BySurfaceName object per zone of the result."""
    from .energyplus import write_user_view_factors

    if patch_level:
        if not hasattr(result, "by_surface"):
            raise ValueError(f"{path}: EnergyPlus needs surface names; aggregate the result to surfaces first")
        result = result.by_surface()
    matrix, names = _get(result, "matrix"), list(_get(result, "names"))
    f = matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix, dtype=np.float64)
    meta = getattr(scene, "meta", None) or {}
    surface_zone = meta.get("surface_zone")
    faces = _get(result, "faces")
    if not surface_zone or faces is None:
        if zone_name is None:
            src = getattr(scene, "source", None)
            zone_name = os.path.splitext(os.path.basename(src))[0] if src else "Zone 1"
        write_user_view_factors(path, [(zone_name, f, names)], format=fmt)
        return
    row_zone = np.array([surface_zone[int(k)] for k in faces], dtype=object)
    zones = [z for z in meta.get("zones", []) if (row_zone == z).any()]
    groups = {z: np.flatnonzero(row_zone == z) for z in zones}
    for z, rows in groups.items():
        outside = np.abs(f[np.ix_(rows, np.setdiff1d(np.arange(len(names)), rows))]).max(initial=0.0)
        if outside > 0:
            raise ValueError(
                f"{path}: zone {z!r} has view factors to surfaces of other zones (up to {outside:.3g}); "
                "every zone is its own enclosure: compute zone by zone "
                "(nusselt.zones.zone_form_factors, as `nusselt matrix` does for building models)"
            )
    if zone_name is not None:
        want = str(zone_name).strip()
        match = [z for z in zones if z.lower() == want.lower()]
        if match:
            groups = {match[0]: groups[match[0]]}
        elif len(zones) == 1:
            groups = {want: groups[zones[0]]}  # rename the only zone
        else:
            raise ValueError(f"{path}: no zone named {want!r} in the result (zones: {', '.join(zones)})")
    write_user_view_factors(path, [(z, f[np.ix_(r, r)], [names[i] for i in r]) for z, r in groups.items()], format=fmt)


def _row_emissivity(result, scene, patch_level):
    em = getattr(scene, "emissivity", None) if scene is not None else None
    faces = _get(result, "faces")
    if em is None or faces is None:
        return None
    em = np.asarray(em, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    sidx = np.asarray(scene.surface)[faces] if patch_level else faces
    return em[sidx]


def _write_result_vtu(path, result, scene, to_surface, patch_level):
    matrix = _get(result, "matrix")
    n = _square(matrix)
    m = _csr(matrix)
    faces_of_rows = np.asarray(_get(result, "faces"), dtype=np.int64)
    nface = len(scene.faces)
    surf = np.asarray(scene.surface, dtype=np.int64)
    if patch_level:
        row_of_face = np.full(nface, -1, dtype=np.int64)
        row_of_face[faces_of_rows] = np.arange(n)
        col_surface = np.asarray(_get(result, "surface"), dtype=np.int64)
        col_names = list(_get(result, "surface_names") or scene.surface_names)
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
