"""View3D ``.vs3`` input files (what EnergyPlus and building-physics users have).

Dialect (View3D 3.2, G. Walton, NISTIR 6925, and its reader ``getdat.c``):

* one record per line, the first character of the first word decides the record
  (case-insensitive); ``!`` anywhere, or a word starting with ``/``, starts a comment;
* ``T`` title, ``C`` controls (``name=value`` separated by blanks, ``=`` or ``,``),
  ``F 3`` / ``F 3a`` geometry form, ``V n x y z`` vertices (``F 3``), surfaces
  ``S``/``M``/``N``/``O``, ``X`` (ignored), ``E...`` or ``*`` end of data (the rest of the
  file is not read);
* surfaces are numbered 1, 2, 3 ... across S, M, N and O records; obstruction-only ``O``
  surfaces come after all others; vertices are numbered 1, 2, 3 ... in order.

How the records map to polygons and named surfaces:

* ``S`` with ``base = 0``: a surface (own name, row and column).
* ``S`` with ``base > 0``: a sub-surface (window in a wall), coplanar with and inside its base,
  facing the same way; its area is removed from the base.
* ``M`` mask: coplanar with its base, facing the opposite way; the base loses that part and
  the mask is a surface of its own (View3D reports it), which blocks the masked part.
* ``N`` null surface: a hole in its base; no polygon, no row or column.
* ``O``: obstruction only (blocks, no row or column).
* ``cmb > 0``: the surface is combined into surface ``cmb`` in the output; its polygons are
  put in the named surface of ``cmb`` (the form-factor algebra of the per-surface result then
  does what View3D's combine step does).

A base with holes becomes several convex polygons, all in the base's named surface (see
``_planar.subtract_convex_holes``).
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np

from . import _planar
from .scenedata import SceneData, check_readable, parse_error, text_lines

_INT_CONTROLS = {"maxu", "maxo", "mino", "row", "col", "encl", "emit", "out", "list", "prjd", "maxv"}
# View3D 3.2's control words (getdat.c GetCtrl) and what nusselt does with them: honoured,
# accepted silently (``list``, the detail of View3D's log, bears on no result and is in most
# files EnergyPlus's tools write), or ignored with a warning saying what View3D would do.
_HONOURED = {"encl", "emit"}
_SILENT = {"list"}
_ALGORITHM_CONTROLS = {
    "eps": "View3D's adaptive-integration convergence limit; nusselt's methods are exact or take their own "
    "tolerances (e.g. --option obstructed_tol=...)",
    "maxu": "View3D's recursion limit for unobstructed pairs; not used by nusselt",
    "maxo": "View3D's recursion limit for obstructed pairs; not used by nusselt",
    "mino": "View3D's minimum recursions for obstructed pairs; not used by nusselt",
    "prjd": "View3D's projection-direction switch; not used by nusselt",
    "row": "View3D then computes only that row (and prints it to its log); nusselt computes the whole matrix",
    "col": "View3D then computes only that entry; nusselt computes the whole matrix",
    "out": "View3D's output format; nusselt's output format follows the output file's extension",
}
_SHAPE_NUMBERS = {"R": 2, "T": 6, "Q": 8}
_KIND_WORD = {"S": "surface", "M": "mask surface", "N": "null surface", "O": "obstruction surface"}


def _strip_comment(line: str) -> str:
    """Remove ``!`` comments (anywhere) and ``/`` comments (a word starting with ``/``)."""
    if "!" in line:
        line = line.split("!", 1)[0]
    m = re.search(r"(^|\s)/", line)
    if m:
        line = line[: m.start()]
    return line.strip()


def local_plane_axes(azimuth: float, tilt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local axes of a View3D ``F 3a`` surface plane.

    With azimuth a measured clockwise from +y (north) and tilt t from +z (0 = facing up,
    90 = vertical, 180 = facing down), the outward normal is

        n = (sin t sin a,  sin t cos a,  cos t),

    the local x axis is horizontal, to the right of a viewer facing the surface,

        e_x = (-cos a,  sin a,  0),

    and the local y axis goes "up" the surface, e_y = n x e_x
        = (-cos t sin a,  -cos t cos a,  sin t),
    so that e_x x e_y = n and a counter-clockwise local polygon faces along n.
    Local point (x, y) maps to origin + x e_x + y e_y (View3D's GetVS3Da transformation).
    """
    ca, sa = _planar.cos_sin_deg(azimuth)
    ct, st = _planar.cos_sin_deg(tilt)
    ex = np.array([-ca, sa, 0.0])
    ey = np.array([-ct * sa, -ct * ca, st])
    n = np.array([st * sa, st * ca, ct])
    return ex, ey, n


class _Surface:
    __slots__ = ("number", "kind", "line", "verts", "coords", "base", "cmb", "emit", "name", "shape")

    def __init__(self, number, kind, line):
        self.number, self.kind, self.line = number, kind, line
        self.verts = None  # F 3: 1-based vertex numbers
        self.coords = None  # (n, 3) coordinates once resolved
        self.base, self.cmb, self.emit, self.name, self.shape = 0, 0, None, None, None


def read_view3d(path: str) -> SceneData:
    """Read a View3D ``.vs3`` file (``F 3`` and ``F 3a`` forms).

    Returns a :class:`SceneData` whose ``meta`` holds ``format="view3d"``, ``geometry``
    (``"3"`` or ``"3a"``), ``title``, ``controls`` (also copied as top-level keys, e.g.
    ``meta["encl"]``), and ``surfaces``: one dict per View3D surface number with
    ``number, kind, name, base, cmb, emit, line``. ``meta["surface_numbers"]`` gives the
    View3D number of each named surface (same order as ``names``).
    """
    path = str(path)
    check_readable(path)

    def err(no, msg):
        return parse_error(path, f"line {no}" if no else None, msg)

    def as_int(tok, no, what):
        try:
            return int(tok)
        except ValueError:
            raise err(no, f"{what} must be an integer, got {tok!r}") from None

    def as_float(tok, no, what):
        try:
            x = float(tok)
        except ValueError:
            raise err(no, f"{what} must be a number, got {tok!r}") from None
        if not math.isfinite(x):
            raise err(no, f"{what} is {tok!r}; coordinates and values must be finite")
        return x

    # Records up to the end-of-data mark, with their line numbers.
    records: list[tuple[int, str, list[str]]] = []
    ended = False  # an end-of-data record was seen
    for no, line in text_lines(path, "View3D text input"):
        text = _strip_comment(line)
        if not text:
            continue
        c = text[0].upper()
        if c in ("E", "*"):
            ended = True
            break
        records.append((no, text, text.split()))
    if not records:
        raise err(None, "no View3D records found (the file holds only comments or an end-of-data mark)")

    # The geometry form first (View3D reads it in a counting pass, so it may come anywhere).
    geometry, f_line = None, None
    for no, text, toks in records:
        if text[0].upper() == "F":
            if len(toks) < 2:
                raise err(no, "F record without a geometry form: expected 'F 3' or 'F 3a'")
            g = toks[1].lower()
            if g not in ("3", "3a"):
                raise err(
                    no,
                    f"unsupported geometry form 'F {toks[1]}': nusselt reads 'F 3' and 'F 3a' "
                    "(3-D View3D files); 2-D View2D files are not supported",
                )
            if geometry is not None and g != geometry:
                raise err(no, f"second F record 'F {toks[1]}' contradicts 'F {geometry}' on line {f_line}")
            geometry, f_line = g, no
    if geometry is None:
        raise err(
            None,
            "missing F record: the geometry form ('F 3' with V and S records, "
            "or 'F 3a' with local shapes) must be given",
        )

    title = ""
    controls: dict[str, float | int | str] = {}  # unknown controls keep their text
    vertices: list[tuple[float, float, float]] = []
    vertex_line: list[int] = []
    surfaces: list[_Surface] = []
    surface_line: list[int] = []
    first_obstruction: _Surface | None = None

    def check_next(no: int, n: int, word: str, lines: list[int], series: str) -> None:
        """Vertices and surfaces are numbered 1, 2, 3 ... in order; ``lines`` holds where each so far is."""
        if 1 <= n <= len(lines):
            raise err(no, f"{word} {n} is defined twice (first on line {lines[n - 1]})")
        if n != len(lines) + 1:
            raise err(
                no,
                f"{word} {n} out of sequence: expected {word} {len(lines) + 1} "
                f"(View3D numbers {series} 1, 2, 3 ... in order)",
            )

    i = 0
    while i < len(records):
        no, text, toks = records[i]
        i += 1
        c = text[0].upper()
        if c == "T":
            title = text[len(toks[0]) :].strip()
        elif c == "C":
            words = [w for w in re.split(r"[\s=,]+", text[len(toks[0]) :].strip()) if w]
            if len(words) % 2:
                raise err(no, f"control {words[-1]!r} has no value (write name=value)")
            for name, value in zip(words[::2], words[1::2]):
                key = name.lower()
                if key not in _HONOURED and key not in _SILENT and key not in _ALGORITHM_CONTROLS:
                    # View3D warns "Invalid control word" and goes on (getdat.c GetCtrl)
                    warnings.warn(
                        f"{path}, line {no}: control {name}={value} is not a View3D 3.2 control "
                        "(obsolete or misspelt); ignored, as View3D does",
                        stacklevel=2,
                    )
                    controls[name] = value
                    continue
                if key in _INT_CONTROLS:
                    controls[name] = as_int(value, no, f"control {name}")
                else:
                    controls[name] = as_float(value, no, f"control {name}")
                if key in _ALGORITHM_CONTROLS and not (key in ("row", "col", "out", "prjd") and controls[name] == 0):
                    warnings.warn(
                        f"{path}, line {no}: control {name}={value} ignored: {_ALGORITHM_CONTROLS[key]}", stacklevel=2
                    )
        elif c == "F" or c == "X":
            continue
        elif c == "V":
            if geometry == "3a":
                raise err(no, "V records are not used with 'F 3a' (each surface carries its own geometry)")
            if len(toks) < 5:
                raise err(no, f"a vertex record needs 'V n x y z', got {text!r}")
            n = as_int(toks[1], no, "vertex number")
            check_next(no, n, "vertex", vertex_line, "vertices")
            vertices.append(tuple(as_float(t, no, f"coordinate of vertex {n}") for t in toks[2:5]))
            vertex_line.append(no)
        elif c in "SMNO":
            if len(toks) < 2:
                raise err(no, f"{_KIND_WORD[c]} record without a surface number")
            n = as_int(toks[1], no, "surface number")
            check_next(no, n, "surface", surface_line, "S, M, N and O surfaces")
            if c != "O" and first_obstruction is not None:
                raise err(
                    no,
                    f"{_KIND_WORD[c]} {n} comes after obstruction surface {first_obstruction.number} "
                    f"(line {first_obstruction.line}); O records must come after all S, M and N records",
                )
            s = _Surface(n, c, no)
            if geometry == "3":
                need = 6 if c == "O" else 9
                if len(toks) < need:
                    form = "O n v1 v2 v3 v4" if c == "O" else f"{c} n v1 v2 v3 v4 base cmb emit name"
                    raise err(no, f"{_KIND_WORD[c]} {n}: expected '{form}', got {text!r}")
                s.verts = [as_int(t, no, f"vertex number of surface {n}") for t in toks[2:6]]
                rest = toks[6:]
            else:
                if len(toks) < 3:
                    raise err(
                        no, f"{_KIND_WORD[c]} {n}: expected '{c} n shape base cmb emit name' with shape R, Q or T"
                    )
                s.shape = toks[2].upper()
                if s.shape not in _SHAPE_NUMBERS:
                    raise err(
                        no,
                        f"surface {n}: unknown shape {toks[2]!r}; 'F 3a' shapes are "
                        "R (rectangle), Q (quadrilateral) and T (triangle)",
                    )
                rest = toks[3:]
                if c != "O" and len(rest) < 3:
                    raise err(no, f"{_KIND_WORD[c]} {n}: expected '{c} n shape base cmb emit name', got {text!r}")
            if c != "O":
                s.base = as_int(rest[0], no, f"base of surface {n}")
                s.cmb = as_int(rest[1], no, f"cmb of surface {n}")
                s.emit = as_float(rest[2], no, f"emissivity of surface {n}")
                if not 0.0 <= s.emit <= 1.0:
                    raise err(no, f"surface {n}: emissivity {rest[2]} is outside [0, 1]")
                s.name = rest[3] if len(rest) > 3 else None
            else:
                # View3D ignores anything after the vertices of an O record; a name is kept.
                s.name = rest[3] if len(rest) > 3 else None
            if geometry == "3a":
                # x0 y0 z0 azimuth tilt and the shape data, on the following line(s).
                want = 5 + _SHAPE_NUMBERS[s.shape]
                nums: list[float] = []
                while len(nums) < want:
                    if i >= len(records):
                        raise err(
                            no,
                            f"surface {n} (shape {s.shape}) needs {want} numbers after its record "
                            "(x0 y0 z0 azimuth tilt and the shape data); the file ends first",
                        )
                    gno, _, gtoks = records[i]
                    i += 1
                    for t in gtoks:
                        if len(nums) == want:
                            break
                        try:
                            x = float(t)
                        except ValueError:
                            raise err(
                                gno,
                                f"surface {n} (shape {s.shape}, line {no}) needs {want} numbers "
                                f"(x0 y0 z0 azimuth tilt and the shape data), found {t!r}",
                            ) from None
                        if not math.isfinite(x):
                            raise err(gno, f"surface {n}: geometry value {t!r} is not finite")
                        nums.append(x)
                s.coords = _shape_coords(s.shape, nums)
            if c == "O" and first_obstruction is None:
                first_obstruction = s
            surfaces.append(s)
            surface_line.append(s.line)
        else:
            raise err(no, f"unknown record {toks[0]!r} (View3D records: T C F V S M N O X E)")

    if not surfaces:
        raise err(None, "no surfaces (S records) found")

    # Resolve vertex references (F 3).
    nv = len(vertices)
    if geometry == "3":
        xyz = np.array(vertices, dtype=np.float64).reshape(-1, 3)
        for s in surfaces:
            v = s.verts
            for k, j in enumerate(v):
                if j > nv:
                    raise err(
                        s.line,
                        f"{_KIND_WORD[s.kind]} {s.number} refers to vertex {j}, but only {nv} vertices are defined",
                    )
                if j < 0 or (j == 0 and k < 3):
                    raise err(
                        s.line,
                        f"{_KIND_WORD[s.kind]} {s.number} has vertex number {j}; "
                        "vertices are numbered from 1 (only v4 = 0 is allowed: a triangle)",
                    )
            s.verts = [j for j in v if j != 0] if v[3] == 0 else v
            s.coords = xyz[np.array(s.verts) - 1]

    _check_references(surfaces, err)
    data = _build(path, geometry, title, controls, surfaces, err)
    if not ended:
        # View3D input ends with an end-of-data record; without it the file was cut short
        # (a file cut at a record boundary otherwise loads silently with surfaces missing)
        last = records[-1][0]
        raise err(
            None,
            f"the file ends without its end-of-data record ('E' or 'End of data') after "
            f"{len(surfaces)} surfaces (last record on line {last}): it looks truncated; "
            "if it is complete, add a last line 'End of data'",
        )
    return data


def _shape_coords(shape: str, nums: list[float]) -> np.ndarray:
    """3-D vertices of an ``F 3a`` shape; see :func:`local_plane_axes`."""
    x0, y0, z0, azm, tilt = nums[:5]
    ex, ey, _ = local_plane_axes(azm, tilt)
    if shape == "R":
        w, h = nums[5], nums[6]
        local = [(0.0, h), (0.0, 0.0), (w, 0.0), (w, h)]  # View3D's vertex order, CCW
    else:
        d = nums[5:]
        local = list(zip(d[0::2], d[1::2]))
    o = np.array([x0, y0, z0])
    return np.array([o + x * ex + y * ey for x, y in local])


def _check_references(surfaces: list[_Surface], err) -> None:
    nall = len(surfaces)
    for s in surfaces:
        what = f"{_KIND_WORD[s.kind]} {s.number}"
        if s.kind == "O":
            s.base = s.cmb = 0
            continue
        if s.base < 0 or s.base > nall:
            raise err(s.line, f"{what}: base surface {s.base} does not exist (there are {nall} surfaces)")
        if s.base == s.number:
            raise err(s.line, f"{what} names itself as its base")
        if s.kind in "MN" and s.base == 0:
            raise err(s.line, f"{what} needs a base surface (the surface it lies on)")
        if s.base:
            b = surfaces[s.base - 1]
            if b.kind in "MN":
                raise err(s.line, f"{what}: its base {s.base} is a {_KIND_WORD[b.kind]}, which cannot be a base")
            if b.kind != "O" and s.base > s.number:
                raise err(s.line, f"{what} must come after its base surface {s.base}")
        if s.cmb:
            if s.kind != "S":
                raise err(s.line, f"{what} cannot be combined with another surface (only S surfaces can)")
            if s.cmb < 0 or s.cmb >= s.number:
                raise err(s.line, f"{what}: must combine with a previous surface, not {s.cmb}")
            t = surfaces[s.cmb - 1]
            if t.kind != "S":
                raise err(s.line, f"{what}: cannot combine with {_KIND_WORD[t.kind]} {t.number}")
            if t.cmb:
                raise err(
                    s.line,
                    f"{what}: cannot combine with surface {t.number}, which is itself combined "
                    f"into surface {t.cmb} (View3D does not chain combinations)",
                )


#: View3D's rules for sub-surfaces, masks and null surfaces (all convex, base convex too).
_CUT_RULES = _planar.CutRules(
    plane_tol=1e-5,
    concave_base=False,
    messages={
        "zero_base": "{base} has zero area but has sub-surfaces",
        "concave_base": "{base} has sub-surfaces but is not convex (View3D surfaces must be convex)",
        "off_plane": "{what} is not in the plane of its base surface {number} (a vertex is {dist:.3g} from that plane)",
        "zero_area": "{what} has zero area",
        "wrong_way": "{what} must face the same way as its base {number}",
        "wrong_way_reversed": "{what} must face the opposite way to its base surface {number} "
        "(View3D convention: list its vertices in the reverse order)",
        "not_convex": "{what} is not convex (View3D surfaces must be convex)",
        "outside": "{what} is not inside its base surface {number} ({pct:.3g}% of it lies outside)",
        "overlap": "{what} overlaps {other} on the same base {number}",
    },
)


def _cut_holes(base: _Surface, holes: list[_Surface], err) -> list[np.ndarray]:
    """The base's polygon minus its sub-surfaces, masks and null surfaces, as convex pieces."""
    cut = []
    for h in holes:
        what = f"sub-surface {h.number}" if h.kind == "S" else f"{_KIND_WORD[h.kind]} {h.number}"
        cut.append(_planar.Hole(h.coords, h.line, what, what, reversed=h.kind in "MN"))
    return _planar.cut_holes(
        base.coords,
        cut,
        _CUT_RULES,
        where=base.line,
        label=f"{_KIND_WORD[base.kind]} {base.number}",
        number=base.number,
        fail=err,
    )


def _build(path, geometry, title, controls, surfaces, err) -> SceneData:
    holes: dict[int, list[_Surface]] = {}
    for s in surfaces:
        if s.base:
            holes.setdefault(s.base, []).append(s)

    # Named surfaces: uncombined S, M and O records, in View3D order (= View3D output order).
    names: list[str] = []
    numbers: list[int] = []
    emissivity: list[float] = []
    name_of: dict[int, int] = {}
    taken: set[str] = set()
    for s in surfaces:
        if s.kind == "N" or (s.kind == "S" and s.cmb):
            continue
        label = s.name or (f"obstruction{s.number}" if s.kind == "O" else f"surface{s.number}")
        if label in taken:
            label = f"{label}#{s.number}"
        taken.add(label)
        name_of[s.number] = len(names)
        names.append(label)
        numbers.append(s.number)
        emissivity.append(np.nan if s.kind == "O" else s.emit)
    for s in surfaces:
        if s.kind == "S" and s.cmb:
            name_of[s.number] = name_of[s.cmb]

    verts: list[np.ndarray] = []
    faces, surface, obstruction, origin = [], [], [], []
    nverts = 0
    for s in surfaces:
        if s.kind == "N":
            continue
        polys = _cut_holes(s, holes[s.number], err) if s.number in holes else [s.coords]
        for k, p in enumerate(polys):
            verts.append(p)
            faces.append(np.arange(nverts, nverts + len(p)))
            nverts += len(p)
            surface.append(name_of[s.number])
            obstruction.append(s.kind == "O")
            tag = f"{_KIND_WORD[s.kind]} {s.number}" + (f", part {k + 1} of {len(polys)}" if len(polys) > 1 else "")
            origin.append(f"line {s.line} ({tag})")

    meta = {
        "format": "view3d",
        "geometry": geometry,
        "title": title,
        "controls": dict(controls),
        "surfaces": [
            {
                "number": s.number,
                "kind": s.kind,
                "name": s.name,
                "base": s.base,
                "cmb": s.cmb,
                "emit": s.emit,
                "line": s.line,
            }
            for s in surfaces
        ],
        "surface_numbers": numbers,
    }
    for k, v in controls.items():
        meta.setdefault(k, v)
    return SceneData(
        vertices=np.concatenate(verts) if verts else np.zeros((0, 3)),
        faces=faces,
        surface=np.array(surface, dtype=np.int64),
        names=names,
        obstruction=np.array(obstruction, dtype=bool),
        emissivity=np.array(emissivity, dtype=np.float64),
        origin=origin,
        source=path,
        meta=meta,
    )


def read_view3d_output(path: str) -> dict:
    """Read a View3D 3.2 text output file (``out=0``), as View3D or :func:`write_view3d` writes it.

    Returns ``{"version", "out", "encl", "emit", "matrix" (N, N) ndarray, "areas", "emissivity"}``."""
    path = str(path)
    check_readable(path)
    # (line number, text) of the non-blank lines, read one at a time: rows are parsed as they come
    lines = ((no, ln) for no, ln in text_lines(path, "View3D output") if ln.strip())
    first = next(lines, None)
    if first is None:
        raise parse_error(path, None, "not a View3D output file: only blank lines")
    head_no, head_text = first
    head = head_text.split()
    if len(head) < 6 or head[0] != "View3D":
        raise parse_error(path, f"line {head_no}", "not a View3D output file (expected 'View3D 3.2 out encl emit N')")
    try:
        out, encl, emit, n = (int(t) for t in head[2:6])
    except ValueError:
        raise parse_error(path, f"line {head_no}", f"bad header {head_text.strip()!r}") from None
    if out != 0:
        raise parse_error(path, f"line {head_no}", f"out={out}: only the text form (out=0) is read")
    if n < 0:
        raise parse_error(path, f"line {head_no}", f"bad header: {n} surfaces")

    def row(k):
        got = next(lines, None)
        if got is None:
            raise parse_error(path, None, f"{n} surfaces need {n + 3} lines, the file has {k}")
        no, text = got
        try:
            r = np.array([float(t) for t in text.split()])
        except ValueError:
            raise parse_error(path, f"line {no}", "bad number") from None
        if r.size != n:
            raise parse_error(path, f"line {no}", f"expected {n} values, found {r.size}")
        return r

    areas = row(1)
    matrix = np.array([row(2 + i) for i in range(n)]).reshape(n, n)  # grows only as rows are found
    emissivity = row(2 + n)
    return {
        "version": head[1],
        "out": out,
        "encl": encl,
        "emit": emit,
        "areas": areas,
        "matrix": matrix,
        "emissivity": emissivity,
    }
