"""Mesh formats through meshio (STL, PLY, VTK/VTU, Gmsh, Nastran, Abaqus, OFF, Medit, ...).

Triangles, quads and polygon cells are kept as they are. Named surfaces, first match wins:

1. Gmsh physical groups: ``gmsh:physical`` cell data, named by ``field_data``
   (``$PhysicalNames``); unnamed tags become ``physical<tag>``.
2. meshio cell sets (Abaqus ``*Elset``, MED groups ...): each cell goes to the smallest
   set that holds it (so a catch-all set such as ``ALL`` does not swallow the others);
   cells in no set become ``unassigned``.
3. Integer cell data: ``cell_tags``, ``CellEntityIds``, ``MaterialIds``, ``material``,
   ``medit:ref``, ``nastran:ref`` (property id), ``gmsh:geometrical`` ...; named
   ``<label><tag>`` (``material3``, ``property5``, ``entity2``).
4. ASCII STL solid names (``solid floor`` ... ``endsolid``), which meshio skips.
5. Otherwise one surface per cell block: ``block0``, ``block1`` ...
"""

from __future__ import annotations

import contextlib
import io
import os
import warnings

import numpy as np

from .scenedata import SceneData, SkippedCellsWarning, check_readable, parse_error

_SURFACE_TYPES = {
    "triangle": 3,
    "quad": 4,
    "polygon": None,
    # Second-order cells: their first 3 or 4 nodes are the corners.
    "triangle6": 3,
    "triangle7": 3,
    "quad8": 4,
    "quad9": 4,
}
_SKIPPED_TYPES = {"vertex", "line", "line3", "line4", "line5", "line6", "polyline"}
_VOLUME_PREFIXES = ("tetra", "hexahedron", "wedge", "pyramid", "polyhedron", "penta", "hexa")

# (cell-data key, name prefix), tried in this order after gmsh:physical and cell sets.
_TAG_KEYS = [
    ("cell_tags", "tag"),
    ("CellEntityIds", "entity"),
    ("MaterialIds", "material"),
    ("MaterialId", "material"),
    ("material", "material"),
    ("materials", "material"),
    ("mat", "material"),
    ("medit:ref", "ref"),
    ("nastran:ref", "property"),
    ("flac3d:zone", "zone"),
    ("PartId", "part"),
    ("region", "region"),
    ("gmsh:geometrical", "entity"),
]


def _one_line(e: BaseException) -> str:
    msg = " ".join(str(e).split())
    return msg or type(e).__name__


def _stl_solid_names(path: str, ntri: int) -> list[str] | None:
    """Per-triangle solid names of an ASCII STL file, or None (binary STL, or one unnamed solid)."""
    size = os.path.getsize(path)
    with open(path, "rb") as fh:
        head = fh.read(84)
        if not head.lstrip().lower().startswith(b"solid"):
            return None
        if size >= 84 and 84 + 50 * int.from_bytes(head[80:84], "little") == size:
            return None  # binary file whose header happens to start with "solid"
        fh.seek(0)
        names: list[str] = []
        current: str | None = None
        solids: list[str] = []
        for raw in fh:
            line = raw.decode("utf-8", errors="replace").strip()
            low = line.lower()
            if low.startswith("endsolid"):
                current = None
            elif low.startswith("solid"):
                current = line[5:].strip() or f"solid{len(solids)}"
                solids.append(current)
            elif low.startswith("facet"):
                names.append(current if current is not None else "default")
    if len(names) != ntri or not solids or (len(solids) == 1 and solids[0] == "solid0"):
        return None
    return names


def _check_stl(path: str) -> None:
    """Refuse an STL file that was cut short: a binary one shorter than its header's
    triangle count says (84 + 50 n bytes), an ASCII one whose last line is not ``endsolid``
    (meshio reads the complete facets before the cut and says nothing)."""
    size = os.path.getsize(path)
    with open(path, "rb") as fh:
        head = fh.read(84)
        n = int.from_bytes(head[80:84], "little") if len(head) >= 84 else -1
        if n >= 0 and 84 + 50 * n == size:
            return  # a complete binary file (its header may start with "solid")
        if not head.lstrip().lower().startswith(b"solid"):
            if n < 0:
                raise parse_error(
                    path, None, f"not an STL file: a binary STL needs an 84-byte header, the file has {size} bytes"
                )
            if size < 84 + 50 * n:
                raise parse_error(
                    path,
                    None,
                    f"truncated: the binary STL header declares {n} triangles "
                    f"({84 + 50 * n} bytes), the file has {size} bytes "
                    f"({(size - 84) // 50} whole triangles)",
                )
            return
        fh.seek(max(0, size - 4096))
        tail = fh.read().splitlines()
    last = next((t.strip() for t in reversed(tail) if t.strip()), b"")
    if not last.lower().startswith(b"endsolid"):
        raise parse_error(
            path,
            None,
            "truncated: the ASCII STL file does not end with 'endsolid' (its last line "
            f"is {last[:40].decode('utf-8', 'replace')!r}); the facets after the cut "
            "are missing",
        )


def read_mesh(path: str, format: str | None = None) -> SceneData:
    """Read any surface-mesh format meshio reads. ``format`` is a meshio format name
    (``"gmsh"``, ``"stl"``, ``"vtu"`` ...) when the extension does not tell."""
    path = str(path)
    check_readable(path)
    if (format or "").lower() == "stl" or (format is None and path.lower().endswith(".stl")):
        _check_stl(path)
    import meshio

    try:
        # meshio prints and warns on some inputs (e.g. ASCII STL); keep our output clean.
        with (
            warnings.catch_warnings(),
            np.errstate(all="ignore"),
            contextlib.redirect_stdout(io.StringIO()),
            contextlib.redirect_stderr(io.StringIO()),
        ):
            warnings.simplefilter("ignore")
            mesh = meshio.read(path, file_format=format)
    except (OSError, MemoryError):
        raise
    except SystemExit:
        # meshio's STL reader, having failed both ASCII and binary, prints "Couldn't read" and
        # calls sys.exit: there is no more detail to pass on
        kind = format or os.path.splitext(path)[1].lstrip(".").upper()
        raise parse_error(path, None, f"not a valid {kind} file") from None
    except meshio.ReadError as e:
        msg = _one_line(e)
        if "Unknown file format" in msg or "Could not deduce" in msg:
            ext = os.path.splitext(path)[1] or "(none)"
            raise parse_error(
                path,
                None,
                f"unknown file extension {ext}: give the format "
                "(obj, vs3, or a meshio format such as stl, ply, vtu, gmsh)",
            ) from None
        raise parse_error(path, None, f"cannot read the mesh: {msg}") from None
    except Exception as e:  # meshio's parsers raise many kinds of errors on bad input
        raise parse_error(path, None, f"cannot read the mesh ({type(e).__name__}: {_one_line(e)})") from None

    pts = np.asarray(mesh.points, dtype=np.float64)
    if pts.size == 0:
        raise parse_error(path, None, "the mesh has no points (no triangles, quads or polygons)")
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise parse_error(path, None, f"points have shape {pts.shape}, expected (n, 3)")
    if pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(len(pts))])
    bad = np.flatnonzero(~np.isfinite(pts).all(axis=1))
    if bad.size:
        raise parse_error(path, f"point {bad[0]}", f"NaN or infinite coordinate {pts[bad[0]].tolist()}")

    # Surface cells: (block index, index in block, global cell id, vertex indices).
    faces, block_of, index_in_block, origin = [], [], [], []
    volume_types: dict[str, int] = {}
    skipped: dict[str, int] = {}
    gid = 0
    for b, block in enumerate(mesh.cells):
        ctype = block.type
        data = block.data
        count = len(data)
        if ctype in _SURFACE_TYPES:
            corners = _SURFACE_TYPES[ctype]
            for k in range(count):
                f = np.asarray(data[k], dtype=np.int64).ravel()
                if corners is not None:
                    f = f[:corners]
                faces.append(f)
                block_of.append(b)
                index_in_block.append(k)
                origin.append(f"cell {gid + k}")
        elif ctype in _SKIPPED_TYPES:
            skipped[ctype] = skipped.get(ctype, 0) + count
        elif ctype.startswith(_VOLUME_PREFIXES):
            volume_types[ctype] = volume_types.get(ctype, 0) + count
        else:
            skipped[ctype] = skipped.get(ctype, 0) + count
        gid += count

    if not faces:
        if volume_types:
            kinds = ", ".join(f"{n} {t}" for t, n in volume_types.items())
            raise parse_error(
                path,
                None,
                f"the mesh holds only 3-D cells ({kinds}); form factors need the "
                "boundary surface: export the surface mesh (triangles/quads), e.g. "
                "a Gmsh 'Physical Surface' or ParaView's Extract Surface",
            )
        raise parse_error(path, None, "the mesh has no triangles, quads or polygons")
    npts = len(pts)
    for k, f in enumerate(faces):
        if f.size < 3:
            raise parse_error(path, origin[k], f"a polygon needs at least 3 vertices, this one has {f.size}")
        if f.min() < 0 or f.max() >= npts:
            j = int(f.max() if f.max() >= npts else f.min())
            raise parse_error(path, origin[k], f"refers to point {j}, but only {npts} points are defined")

    if skipped or volume_types:
        kinds = ", ".join(f"{n} {t}" for t, n in {**skipped, **volume_types}.items())
        warnings.warn(
            f"{path}: skipped {sum(skipped.values()) + sum(volume_types.values())} cells that are not "
            f"surfaces ({kinds}); read {len(faces)} surface cells (triangles, quads, polygons)",
            SkippedCellsWarning,
            stacklevel=3,
        )
    names, surface, how = _surface_names(path, mesh, np.array(block_of), np.array(index_in_block), len(faces))
    meta = {"format": "meshio", "meshio_format": format, "names_from": how}
    if volume_types:
        meta["skipped_volume_cells"] = volume_types
    if skipped:
        meta["skipped_cells"] = skipped
    return SceneData(
        vertices=pts,
        faces=faces,
        surface=surface,
        names=names,
        origin=origin,
        source=path,
        meta=meta,
    )


def _int_tags(arrays, block_of, index_in_block) -> np.ndarray | None:
    """Per-face integer tag gathered from per-block cell data, or None if not integer-valued."""
    out = np.empty(len(block_of), dtype=np.int64)
    for b in np.unique(block_of):
        if b >= len(arrays):
            return None
        a = np.asarray(arrays[b])
        if a.ndim != 1:
            a = a.reshape(len(a), -1)
            if a.shape[1] != 1:
                return None
            a = a[:, 0]
        sel = block_of == b
        vals = a[index_in_block[sel]] if a.size else np.zeros(0)
        if vals.size != sel.sum():
            return None
        if vals.dtype.kind == "f":
            if not (np.isfinite(vals).all() and np.all(vals == np.round(vals))):
                return None
        elif vals.dtype.kind not in "iub":
            return None
        out[sel] = vals.astype(np.int64)
    return out


def _names_from_tags(tags: np.ndarray, label: dict[int, str], prefix: str) -> tuple[list[str], np.ndarray]:
    uniq = list(dict.fromkeys(tags.tolist()))  # first-appearance order
    names, seen = [], set()
    for t in uniq:
        n = label.get(t, f"{prefix}{t}")
        if n in seen:
            n = f"{n}#{t}"
        seen.add(n)
        names.append(n)
    index = {t: k for k, t in enumerate(uniq)}
    return names, np.array([index[t] for t in tags.tolist()], dtype=np.int64)


def _surface_names(path, mesh, block_of, index_in_block, nf):
    cd = mesh.cell_data or {}
    # 1. Gmsh physical groups, named by $PhysicalNames (field_data: name -> [tag, dim]).
    if "gmsh:physical" in cd:
        tags = _int_tags(cd["gmsh:physical"], block_of, index_in_block)
        if tags is not None:
            label = {}
            for name, val in (mesh.field_data or {}).items():
                v = np.asarray(val).ravel()
                if v.size >= 2 and int(v[1]) == 2:
                    label[int(v[0])] = str(name)
            for name, val in (mesh.field_data or {}).items():  # other dimensions, if no 2-D name
                v = np.asarray(val).ravel()
                if v.size >= 1:
                    label.setdefault(int(v[0]), str(name))
            names, surface = _names_from_tags(tags, label, "physical")
            return names, surface, "gmsh:physical"
    # 2. Cell sets.
    sets = {k: v for k, v in (getattr(mesh, "cell_sets", None) or {}).items() if not str(k).startswith("gmsh:")}
    if sets:
        members = []
        lookup = {(int(b), int(k)): f for f, (b, k) in enumerate(zip(block_of, index_in_block))}
        for name, per_block in sets.items():
            cells = set()
            for b, idx in enumerate(per_block):
                if idx is None:
                    continue
                for k in np.asarray(idx).ravel().tolist():
                    f = lookup.get((b, int(k)))
                    if f is not None:
                        cells.add(f)
            if cells:
                members.append((len(cells), str(name), cells))
        if members:
            assign = np.full(nf, -1, dtype=np.int64)
            names = []
            for _, name, cells in sorted(members, key=lambda m: m[0]):  # stable: file order on ties
                idx = np.fromiter(cells, dtype=np.int64)
                free = idx[assign[idx] < 0]
                if free.size:
                    assign[free] = len(names)
                    names.append(name)
            if (assign < 0).any():
                assign[assign < 0] = len(names)
                names.append("unassigned" if "unassigned" not in names else "unassigned#")
            return _reorder(names, assign) + ("cell_sets",)
    # 3. Integer cell data.
    for key, prefix in _TAG_KEYS:
        if key in cd:
            tags = _int_tags(cd[key], block_of, index_in_block)
            if tags is not None:
                names, surface = _names_from_tags(tags, {}, prefix)
                return names, surface, key
    # 4. ASCII STL solid names.
    if path.lower().endswith(".stl"):
        solid = _stl_solid_names(path, nf)
        if solid is not None:
            uniq = list(dict.fromkeys(solid))
            index = {n: k for k, n in enumerate(uniq)}
            return uniq, np.array([index[n] for n in solid], dtype=np.int64), "stl solids"
    # 5. One surface per cell block.
    used = list(dict.fromkeys(block_of.tolist()))
    index = {b: k for k, b in enumerate(used)}
    return [f"block{b}" for b in used], np.array([index[b] for b in block_of.tolist()], dtype=np.int64), "cell blocks"


def _reorder(names: list[str], assign: np.ndarray) -> tuple[list[str], np.ndarray]:
    """Renumber surfaces in order of first appearance in the file."""
    first = list(dict.fromkeys(assign.tolist()))
    index = {s: k for k, s in enumerate(first)}
    return [names[s] for s in first], np.array([index[s] for s in assign.tolist()], dtype=np.int64)
