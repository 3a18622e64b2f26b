"""Wavefront OBJ reader that keeps objects and groups as named surfaces.

meshio's OBJ reader drops ``o``/``g`` names, which are exactly what a renderer's scene uses
to say "this is the floor", so this small reader is our own. Polygons are kept as written
(quads stay quads); the core checks planarity later.
"""

from __future__ import annotations

import numpy as np

from .scenedata import MAX_LINE_BYTES, SceneData, check_readable, parse_error, text_lines
from .topology import sorted_unique

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

    The lines are only sorted by statement as they are read; the numbers of all ``v`` and
    ``f`` statements are then converted and checked at once, with numpy. The error raised is
    the one for the first bad line, as a reader that checks line by line would find it.
    """
    path = str(path)
    check_readable(path)

    vtext: list[str] = []  # each vertex's line, split in vparts, its number in vline
    vparts: list[list[str]] = []
    vline: list[int] = []
    ftext: list[list[str]] = []  # each face's statement, split; its line in fline
    fline: list[int] = []
    fseen: list[int] = []  # vertices defined before each face (relative indices count back from there)
    face_surface: list[int] = []
    names: dict[str, int] = {}
    current: str | None = None
    stop: ValueError | None = None  # the loop's own refusal: raised unless an earlier line is bad

    try:
        for no, line in _logical_lines(path, text_lines(path, "text OBJ")):
            parts = line.split()
            if not parts:
                continue
            key = parts[0]
            if key == "v":
                vtext.append(line)
                vparts.append(parts)
                vline.append(no)
            elif key == "f" or key == "fo":
                if current is None:
                    current = DEFAULT_SURFACE
                    names.setdefault(current, len(names))
                ftext.append(parts)
                fline.append(no)
                fseen.append(len(vline))
                face_surface.append(names[current])
            elif key in ("o", "g"):
                name = " ".join(parts[1:]) or DEFAULT_SURFACE
                current = name
                names.setdefault(name, len(names))
            elif key in _IGNORED:
                continue
            elif key in _FREEFORM:
                stop = parse_error(
                    path,
                    f"line {no}",
                    f"free-form geometry ({key!r}) is not supported; export polygons (triangles, quads or n-gons)",
                )
                break
            else:
                stop = parse_error(path, f"line {no}", f"unknown OBJ statement {key!r}")
                break
    except ValueError as e:  # from the line reader (NUL byte, overlong line), after every line read
        stop = e

    vertices, vbad = _vertices(path, vtext, vparts, vline)
    index, starts, fbad = _faces(path, ftext, fline, fseen)
    first = min((e for e in (vbad, fbad) if e is not None), key=lambda e: e[0], default=None)
    if first is not None:
        raise first[1]
    if stop is not None:
        raise stop
    if not ftext:
        raise parse_error(path, None, "no faces ('f' statements) found")
    nv = len(vertices)
    top = np.maximum.reduceat(index, starts[:-1])
    if top.size and top.max() >= nv:
        k = int(np.argmax(top >= nv))
        raise parse_error(
            path, f"line {fline[k]}", f"face refers to vertex {top[k] + 1}, but only {nv} vertices are defined"
        )
    # Names that only appear before other names and own no faces are dropped.
    surface = np.array(face_surface, dtype=np.int64)
    used = sorted_unique(surface)
    remap = np.zeros(len(names), dtype=np.int64)
    remap[used] = np.arange(len(used))
    all_names = list(names)
    return SceneData(
        vertices=vertices,
        faces=np.split(index, starts[1:-1]),
        surface=remap[surface],
        names=[all_names[old] for old in used],
        origin=[f"line {no}" for no in fline],
        source=path,
        meta={"format": "obj"},
    )


def _vertices(path: str, text: list[str], parts: list[list[str]], line: list[int]):
    """(V, 3) coordinates of the ``v`` lines (split in ``parts``), and (line, error) of the first
    bad one or None."""
    ok = np.fromiter(map(len, parts), dtype=np.int64, count=len(parts)) >= 4
    flat = [x for p in parts for x in p[1:4]] if ok.all() else []
    xyz = np.zeros((0, 3))
    try:
        xyz = np.fromiter(map(float, flat), dtype=np.float64, count=len(flat)).reshape(-1, 3)
        if len(xyz) == len(text) and np.isfinite(xyz).all():
            return xyz, None
    except ValueError:
        pass
    for k, p in enumerate(parts):  # a bad line (error path only): the first, checked as it reads
        where, stated = f"line {line[k]}", text[k].strip()
        if len(p) < 4:
            return xyz, (line[k], parse_error(path, where, f"a vertex needs x y z, got {stated!r}"))
        try:
            row = [float(x) for x in p[1:4]]
        except ValueError:
            return xyz, (line[k], parse_error(path, where, f"bad number in vertex {stated!r}"))
        if not np.isfinite(row).all():
            return xyz, (line[k], parse_error(path, where, f"vertex has a NaN or infinite coordinate: {stated!r}"))
    raise AssertionError("unreachable: a vertex line was bad")


def _faces(path: str, parts: list[list[str]], line: list[int], seen: list[int]):
    """(vertex indices of every face, one after another; where each face starts, with the
    end last; (line, error) of the first bad face or None). Relative indices count back from
    the vertices ``seen`` before the face."""
    nf = len(parts)
    counts = np.fromiter(map(len, parts), dtype=np.int64, count=nf) - 1
    starts = np.zeros(nf + 1, dtype=np.int64)
    np.cumsum(counts, out=starts[1:])
    tokens = [t for p in parts for t in p[1:]]
    heads = [t.split("/", 1)[0] for t in tokens]
    try:
        raw = np.array(list(map(int, heads)), dtype=np.int64)
        unreadable = np.zeros(raw.size, dtype=bool)
    except (ValueError, OverflowError):  # error path only: which ones
        raw, unreadable = _ints(heads)
    before = np.repeat(np.asarray(seen, dtype=np.int64), counts)
    index = np.where(raw < 0, before + raw, raw - 1)
    # per token, in the order a line-by-line reader checks: unreadable, 0, relative too far back
    problem = unreadable | (raw == 0) | (-raw > before)
    short = counts < 3
    if not (problem.any() or short.any()):
        return index, starts, None
    token_face = np.repeat(np.arange(nf), counts)
    problem &= ~short[token_face]  # a face with too few vertices says so first
    faces_bad = short.copy()
    faces_bad[token_face[problem]] = True
    k = int(np.argmax(faces_bad))
    where = f"line {line[k]}"
    if short[k]:
        return index, starts, (line[k], parse_error(path, where, f"a face needs at least 3 vertices, got {counts[k]}"))
    t = int(starts[k] + np.argmax(problem[starts[k] : starts[k + 1]]))
    if unreadable[t]:
        why = f"bad vertex index {tokens[t]!r} in face"
    elif raw[t] == 0:
        why = "vertex index 0 in face (OBJ indices start at 1)"
    else:
        why = f"face refers to vertex {raw[t]} (relative), but only {before[t]} vertices are defined so far"
    return index, starts, (line[k], parse_error(path, where, why))


def _ints(texts: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """Integers of ``texts`` (1 where unreadable) and which were unreadable."""
    out = np.ones(len(texts), dtype=np.int64)
    bad = np.zeros(len(texts), dtype=bool)
    for k, t in enumerate(texts):
        try:
            out[k] = int(t)
        except (ValueError, OverflowError):
            bad[k] = True
    return out, bad
