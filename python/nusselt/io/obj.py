"""Wavefront OBJ reader that keeps objects and groups as named surfaces.

meshio's OBJ reader drops ``o``/``g`` names, which are exactly what a renderer's scene uses
to say "this is the floor", so this small reader is our own. Polygons are kept as written
(quads stay quads); the core checks planarity later.
"""

from __future__ import annotations

import numpy as np

from .scenedata import MAX_LINE_BYTES, SceneData, check_readable, parse_error, text_lines

#: Statements that carry nothing a form-factor computation needs.
_IGNORED = {
    "vt",
    "vn",
    "vp",
    "usemtl",
    "mtllib",
    "s",
    "l",
    "p",
    "maplib",
    "usemap",
    "lod",
    "bevel",
    "c_interp",
    "d_interp",
    "shadow_obj",
    "trace_obj",
    "mg",
    "call",
    "csh",
}
#: Free-form geometry: curves and surfaces we cannot turn into polygons.
_FREEFORM = {
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
}

DEFAULT_SURFACE = "default"


def _logical_lines(path: str, lines):
    """(line number, content) from (number, physical line) pairs, with comments removed and
    ``\\`` continuations joined; the number is that of the first physical line."""
    pending, start = "", 0
    for no, raw in lines:
        line = raw.split("#", 1)[0] if "#" in raw else raw
        line = line.rstrip()
        if not pending:
            start = no
        if line.endswith("\\"):
            pending += line[:-1] + " "
            if len(pending) > MAX_LINE_BYTES:
                raise parse_error(path, f"line {start}", f"continued past {MAX_LINE_BYTES >> 20} MiB: damaged")
            continue
        yield start, pending + line
        pending = ""
    if pending.strip():
        yield start, pending


def read_obj(path: str) -> SceneData:
    """Read a Wavefront OBJ file.

    Supports ``v`` (extra components such as w or vertex colours are ignored), ``f`` with
    ``v``, ``v/vt``, ``v//vn``, ``v/vt/vn`` and negative (relative) indices, ``o`` and
    ``g`` names as surfaces (the most recent ``o`` or ``g`` statement names the faces that
    follow; faces before any name belong to ``"default"``), comments, ``\\`` line
    continuations and CRLF line ends. ``usemtl``, texture and normal data, lines and points
    are ignored; free-form curves/surfaces are refused.
    """
    path = str(path)
    check_readable(path)

    coords: list[tuple[float, float, float]] = []
    vline: list[int] = []
    faces: list[list[int]] = []
    origin: list[str] = []
    face_surface: list[int] = []
    names: dict[str, int] = {}
    current: str | None = None

    for no, line in _logical_lines(path, text_lines(path, "text OBJ")):
        parts = line.split()
        if not parts:
            continue
        key = parts[0]
        where = f"line {no}"
        if key == "v":
            if len(parts) < 4:
                raise parse_error(path, where, f"a vertex needs x y z, got {line.strip()!r}")
            try:
                xyz = (float(parts[1]), float(parts[2]), float(parts[3]))
            except ValueError:
                raise parse_error(path, where, f"bad number in vertex {line.strip()!r}") from None
            if not all(np.isfinite(xyz)):
                raise parse_error(path, where, f"vertex has a NaN or infinite coordinate: {line.strip()!r}")
            coords.append(xyz)
            vline.append(no)
        elif key == "f" or key == "fo":
            if len(parts) < 4:
                raise parse_error(path, where, f"a face needs at least 3 vertices, got {len(parts) - 1}")
            idx = []
            nv = len(coords)
            for tok in parts[1:]:
                head = tok.split("/", 1)[0]
                try:
                    i = int(head)
                except ValueError:
                    raise parse_error(path, where, f"bad vertex index {tok!r} in face") from None
                if i == 0:
                    raise parse_error(path, where, "vertex index 0 in face (OBJ indices start at 1)")
                if i < 0:
                    # Relative index: -1 is the most recently defined vertex.
                    if -i > nv:
                        raise parse_error(
                            path,
                            where,
                            f"face refers to vertex {i} (relative), but only {nv} vertices are defined so far",
                        )
                    i = nv + i
                else:
                    i -= 1
                idx.append(i)
            if current is None:
                current = DEFAULT_SURFACE
                names.setdefault(current, len(names))
            faces.append(idx)
            origin.append(where)
            face_surface.append(names[current])
        elif key in ("o", "g"):
            name = " ".join(parts[1:]) or DEFAULT_SURFACE
            current = name
            names.setdefault(name, len(names))
        elif key in _IGNORED:
            continue
        elif key in _FREEFORM:
            raise parse_error(
                path,
                where,
                f"free-form geometry ({key!r}) is not supported; export polygons (triangles, quads or n-gons)",
            )
        else:
            raise parse_error(path, where, f"unknown OBJ statement {key!r}")

    if not faces:
        raise parse_error(path, None, "no faces ('f' statements) found")
    nv = len(coords)
    for k, f in enumerate(faces):
        m = max(f)
        if m >= nv:
            raise parse_error(path, origin[k], f"face refers to vertex {m + 1}, but only {nv} vertices are defined")
    # Names that only appear before other names and own no faces are dropped.
    used = sorted(set(face_surface))
    remap = {old: new for new, old in enumerate(used)}
    all_names = list(names)
    return SceneData(
        vertices=np.array(coords, dtype=np.float64).reshape(-1, 3),
        faces=[np.array(f, dtype=np.int64) for f in faces],
        surface=np.array([remap[s] for s in face_surface], dtype=np.int64),
        names=[all_names[old] for old in used],
        origin=origin,
        source=path,
        meta={"format": "obj"},
    )
