"""Scenes: planar polygons with named surfaces, some of them obstruction-only."""

from __future__ import annotations

import dataclasses
import os
import types
import warnings
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from . import _core, ranges
from .io.scenedata import NusseltWarning, first_bad_face
from .io.topology import ORIENTS, orient_faces, sorted_unique
from .overlaps import coplanar_overlaps

#: Default relative planarity tolerance (fraction of a polygon's size).
PLANARITY_TOL = 1e-6


def geometry_error(err: _core.GeometryError, label: Callable[[int], str], where: str = "") -> ValueError:
    """The core's error about one polygon as the ValueError a user sees, naming the polygon
    as the input named it: ``label(index)`` for the index the core reports (the polygon's
    position in the list the core was given). The one place where core geometry errors get
    face labels."""
    _, index, _, reason, _ = err.args
    return ValueError(f"{where}{label(int(index))} {reason}")


def _degenerate(err: _core.GeometryError | None) -> bool:
    """No area to speak of (the core's judgement): ``repair`` drops such faces."""
    return err is not None and bool(err.args[4])


class RepairWarning(NusseltWarning):
    """``repair=True`` dropped faces (zero area, or duplicates of another face)."""


class OrientationWarning(NusseltWarning):
    """Faces probably face the wrong way (their fronts would see nothing)."""


class _FrozenList(list):
    """A list that refuses changes (a Scene's names and faces)."""

    def _refuse(self, *args, **kwargs):
        raise TypeError("a Scene is immutable: build a new one with its with_* methods")

    __setitem__ = __delitem__ = __iadd__ = __imul__ = _refuse
    append = extend = insert = pop = remove = clear = sort = reverse = _refuse


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a)  # a copy: the caller's array stays writeable and cannot change ours
    a.flags.writeable = False
    return a


def _frozen_faces(faces: list[np.ndarray]) -> list[np.ndarray]:
    """Read-only copies of the faces: views into one copy of them all (a copy per face cost
    more than the rest of a 6 144-face scene's checks)."""
    flat = _frozen(np.concatenate(faces))
    return np.split(flat, np.cumsum(np.fromiter(map(len, faces), dtype=np.int64, count=len(faces)))[:-1])


def _face_indices(faces, where: str) -> list[np.ndarray]:
    """Faces as int64 index arrays; non-integer indices (1.5, True) are refused, not truncated."""
    rows = list(faces) if not (isinstance(faces, np.ndarray) and faces.ndim == 2) else list(faces)
    out = []
    for k, f in enumerate(rows):
        a = np.asarray(f).ravel()
        if a.dtype.kind == "b" or a.dtype.kind not in "iuf" and a.size:
            raise TypeError(f"{where}face {k}: vertex indices must be integers, got {a.dtype} values")
        if a.dtype.kind == "f":
            bad = ~(np.isfinite(a) & (a == np.round(a)))
            if bad.any():
                raise ValueError(f"{where}face {k}: vertex index {float(a[bad][0])!r} is not an integer")
        out.append(a.astype(np.int64))
    return out


def _face_mask(sel, nf: int, what: str) -> np.ndarray:
    """A per-face bool mask from a bool sequence of length nf or a sequence of face indices."""
    a = np.asarray(sel).ravel()
    if a.dtype.kind == "b":
        if a.shape != (nf,):
            raise ValueError(f"{what} has {a.size} entries for {nf} faces")
        return a.copy()
    if a.size == 0:
        return np.zeros(nf, dtype=bool)
    if a.dtype.kind not in "iu":
        raise TypeError(f"{what}: give a bool per face or integer face indices, got {a.dtype} values")
    if a.min() < -nf or a.max() >= nf:
        raise ValueError(
            f"{what}: face index {int(a.max() if a.max() >= nf else a.min())} out of range (the scene has {nf} faces)"
        )
    m = np.zeros(nf, dtype=bool)
    m[a] = True
    return m


def _stack(polygons) -> tuple[np.ndarray, list[np.ndarray]]:
    """(vertices, faces) of a list of (n, 3) polygons, each face its own run of vertices."""
    polys = [np.asarray(p, dtype=np.float64) for p in polygons]
    for k, p in enumerate(polys):
        if p.ndim != 2 or p.shape[1] != 3:
            raise ValueError(f"polygon {k}: expected an (n, 3) array, got shape {p.shape}")
    starts = np.concatenate([[0], np.cumsum([len(p) for p in polys])]).astype(np.int64)
    faces = [np.arange(starts[k], starts[k + 1]) for k in range(len(polys))]
    return (np.concatenate(polys) if polys else np.zeros((0, 3))), faces


class Scene:
    """A set of planar polygons (patches) grouped into named surfaces.

    A Scene is immutable: its arrays are read-only (``flags.writeable`` is False) and its
    attributes cannot be reassigned, since the compiled core keeps its own copy of the
    geometry. Build changed scenes with :meth:`with_obstruction`, :meth:`with_surfaces`,
    :meth:`with_emissivity`, :meth:`with_two_sided`, :meth:`with_vertices`,
    :meth:`scaled` and :meth:`refined`.

    Parameters
    ----------
    vertices : (V, 3) array of float
        Vertex coordinates, in any length unit (F does not depend on it).
    faces : sequence of index sequences, or (F, k) int array
        Each face lists its vertex indices counter-clockwise seen from its front side
        (only the front emits and receives). Faces may have any number >= 3 of vertices and
        may be concave, but must be planar and simple. Indices must be integers.
    surface : sequence of str or int, optional
        The named surface of each face (default: every face is its own surface ``"face<k>"``).
        Integers index into ``names``.
    names : sequence of str, optional
        Surface names when ``surface`` holds integers.
    obstruction : sequence of bool, optional
        Faces that block radiation but get no row or column in the result.
    emissivity : sequence of float, optional
        Per named surface (kept for the writers; F does not use it).
    two_sided : sequence of bool, or of face indices, optional
        Faces that emit and receive on both sides (a thin plate, a fin). ``form_factors``
        computes their front and back as two patches and joins them into one row and
        column: the row is the area-weighted mean of the two sides' rows, the column the
        sum of what reaches either side, and the area reported is both sides' (2 A), so
        reciprocity and closure hold as for any patch. Obstruction-only faces block from
        both sides anyway and cannot be two-sided.
    orient : ``"auto"`` (default), ``"inward"``, ``"outward"`` or ``"as-is"``
        How closed shells of faces are turned (see :func:`nusselt.io.topology.orient_faces`):
        ``"auto"`` turns inward a closed shell whose fronts face outward while it holds
        everything else (a room exported as a solid, whose fronts would see nothing) and
        leaves every other face as given; ``"inward"`` / ``"outward"`` turn every closed
        shell to face into / out of its volume; ``"as-is"`` keeps the given order and warns
        (:class:`OrientationWarning`) about such a room. What was turned is in
        ``meta["orient"]``.
    repair : bool
        Drop faces of zero area and faces that duplicate (cover) another coplanar face
        facing the same way, with a :class:`RepairWarning` giving the count. Without it
        such faces are an error naming them.
    planarity_tol : float
        Allowed distance of a vertex from its face's plane, relative to the face's size.
    """

    _frozen_now = False

    def __setattr__(self, name, value):
        if self._frozen_now:
            raise AttributeError(
                f"a Scene is immutable (cannot set {name!r}): build a new one with "
                "with_obstruction, with_surfaces, with_emissivity, with_two_sided, ..."
            )
        object.__setattr__(self, name, value)

    def __init__(
        self,
        vertices,
        faces,
        *,
        surface=None,
        names: Sequence[str] | None = None,
        obstruction=None,
        emissivity=None,
        two_sided=None,
        orient: str = "auto",
        repair: bool = False,
        planarity_tol: float = PLANARITY_TOL,
        source: str | None = None,
        origin: Sequence[str] | None = None,
        meta: Mapping[str, Any] | None = None,
    ):
        where = f"{source}: " if source else ""
        v = np.asarray(vertices, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 3:
            raise ValueError(f"{where}vertices must be an (V, 3) array, got shape {v.shape}")
        bad = np.flatnonzero(~np.isfinite(v).all(axis=1))
        if bad.size:
            raise ValueError(f"{where}vertex {bad[0]} has a NaN or infinite coordinate: {v[bad[0]].tolist()}")
        ranges.check_coordinates(v, f"{where}the scene".strip())
        ranges.check_extent(v, f"{where}the scene".strip())
        face_list = _face_indices(faces, where)
        if not face_list:
            raise ValueError(f"{where}the scene has no faces")
        self._origin = list(origin) if origin is not None else None
        k = first_bad_face(face_list, len(v))
        if k is not None:
            f = face_list[k]
            if f.size < 3:
                raise ValueError(f"{where}{self._face_label(k)} has {f.size} vertices; a polygon needs at least 3")
            raise ValueError(
                f"{where}{self._face_label(k)} refers to vertex {int(f.max() if f.max() >= len(v) else f.min())},"
                f" but there are {len(v)} vertices"
            )
        if not (np.isfinite(planarity_tol) and 0 < planarity_tol < 1):
            raise ValueError(f"planarity_tol must be in (0, 1), got {planarity_tol}")
        if orient not in ORIENTS:
            raise ValueError(f"orient must be one of {', '.join(map(repr, ORIENTS))}, got {orient!r}")

        nf = len(face_list)
        if surface is None:
            surface_names = [f"face{k}" for k in range(nf)]
            surf = np.arange(nf, dtype=np.int64)
        else:
            surface = list(surface)
            if len(surface) != nf:
                raise ValueError(f"{where}surface has {len(surface)} entries for {nf} faces")
            if names is not None:
                surface_names = [str(s) for s in names]
                surf = np.asarray(surface, dtype=np.int64)
                if surf.min() < 0 or surf.max() >= len(surface_names):
                    raise ValueError(f"{where}surface index out of range of names")
            else:
                surface_names, surf = _unique_in_order([str(s) for s in surface])
        obst = np.zeros(nf, dtype=bool) if obstruction is None else np.asarray(obstruction, dtype=bool).ravel()
        if obst.shape != (nf,):
            raise ValueError(f"{where}obstruction has {obst.size} entries for {nf} faces")
        two = np.zeros(nf, dtype=bool) if two_sided is None else _face_mask(two_sided, nf, f"{where}two_sided")
        if (two & obst).any():
            k = int(np.flatnonzero(two & obst)[0])
            raise ValueError(
                f"{where}{self._face_label(k)} is obstruction-only and two-sided: obstructions "
                "block from both sides already and get no row; make it one or the other"
            )
        emis = None if emissivity is None else np.asarray(emissivity, dtype=np.float64)
        if not (isinstance(planarity_tol, (int, float, np.floating, np.integer))):
            raise TypeError(f"planarity_tol must be a number, got {planarity_tol!r}")

        # Zero-area faces: the core finds them; repair drops them, else the first is an error.
        core = self._build_core(v, face_list, obst, float(planarity_tol))
        errors = core.errors()
        degenerate = np.array([_degenerate(e) for e in errors])
        keep = np.ones(nf, dtype=bool)
        dropped: dict[str, list[int]] = {}
        if degenerate.any():
            if not repair:
                k = int(np.flatnonzero(degenerate)[0])
                err = geometry_error(errors[k], self._face_label, where)
                raise ValueError(
                    f"{err}"
                    + (f" ({int(degenerate.sum())} faces have no area)" if degenerate.sum() > 1 else "")
                    + "; repair=True (nusselt matrix --repair) drops faces without area"
                )
            keep &= ~degenerate
            dropped["zero area"] = np.flatnonzero(degenerate).tolist()
        for k, e in enumerate(errors):
            if e is not None and not degenerate[k]:
                raise geometry_error(e, self._face_label, where)
        if not keep.any():
            raise ValueError(f"{where}every face has zero area")

        # Orientation of closed shells (on the faces that stay).
        kept = np.flatnonzero(keep)
        sub = [face_list[k] for k in kept]
        oriented, report = orient_faces(v, sub, orient)
        flipped = kept[report["flipped"]]
        for kept_k, f in zip(kept, oriented):
            face_list[kept_k] = f
        orient_info = {
            "orient": orient,
            "flipped": flipped.tolist(),
            "open_faces": int(len(report["open"])),
            "shells": int(report.get("shells", 0)),
        }
        if orient == "as-is" and len(report.get("outward_enclosure", ())):
            enc = kept[report["outward_enclosure"]]
            warnings.warn(
                f"{where}{len(enc)} faces ({self._face_label(int(enc[0]))}, ...) form a closed shell whose "
                "fronts face outward while it holds every other face: seen from outside it sees nothing, so "
                "its rows will be 0. Rooms must face inward: use orient='auto' or 'inward' (nusselt matrix "
                "--orient inward)",
                OrientationWarning,
                stacklevel=2,
            )

        if orient == "as-is" and len(report.get("inconsistent", ())):
            bad = kept[report["inconsistent"]]
            warnings.warn(
                f"{where}{len(bad)} faces ({self._face_label(int(bad[0]))}, ...) of a closed mesh face against "
                "their neighbours (each of their edges is run the same way by the next face): they are "
                "probably reversed; orient='auto', 'inward' or 'outward' makes the mesh consistent",
                OrientationWarning,
                stacklevel=2,
            )
        if len(flipped) or not keep.all():
            core = None
        if not keep.all():
            face_list, surf, obst, two = ([face_list[k] for k in kept], surf[kept], obst[kept], two[kept])
            self._origin = [self._origin[k] for k in kept] if self._origin is not None else None
        if core is None:
            core = self._build_core(v, face_list, obst, float(planarity_tol))

        # Coplanar same-facing faces covering each other are counted twice: refuse, or drop.
        areas = np.asarray(core.areas())
        normals = np.asarray(core.normals())
        centroids = np.asarray(core.centroids())
        recv = np.flatnonzero(~obst)
        pairs = coplanar_overlaps(v, face_list, normals, centroids, core.triangulate, recv)
        if pairs:
            covered = [
                j if ov >= (1 - 1e-6) * areas[j] else i
                for i, j, ov in pairs
                if ov >= (1 - 1e-6) * min(areas[i], areas[j])
            ]
            partial = [(i, j, ov) for i, j, ov in pairs if ov < (1 - 1e-6) * min(areas[i], areas[j])]
            if not repair or partial:
                i, j, ov = (partial or pairs)[0]
                hint = (
                    "; repair=True (nusselt matrix --repair) drops faces that duplicate another"
                    if not partial
                    else "; repair drops only faces covered whole by another: fix the mesh"
                )
                raise ValueError(
                    f"{where}{self._face_label(i)} and {self._face_label(j)} lie in one plane, face the same way "
                    f"and overlap ({ov / min(areas[i], areas[j]):.3g} of the smaller one): each would be counted, "
                    f"so rows would sum to more than 1 ({len(pairs)} such pairs){hint}"
                )
            drop = sorted_unique(np.asarray(covered, dtype=np.int64))
            back = kept if not keep.all() else np.arange(nf)
            dropped["duplicate"] = back[drop].tolist()
            stay = np.setdiff1d(np.arange(len(face_list)), drop)
            face_list, surf, obst, two = [face_list[k] for k in stay], surf[stay], obst[stay], two[stay]
            self._origin = [self._origin[k] for k in stay] if self._origin is not None else None
            core = self._build_core(v, face_list, obst, float(planarity_tol))
            areas = np.asarray(core.areas())
            normals = np.asarray(core.normals())
            centroids = np.asarray(core.centroids())
        if dropped:
            what = ", ".join(
                f"{len(ks)} with {w}" if w == "zero area" else f"{len(ks)} duplicates of another face"
                for w, ks in dropped.items()
            )
            warnings.warn(
                f"{where}repair dropped {sum(map(len, dropped.values()))} of {nf} faces ({what}); "
                "face numbers now count the faces kept (meta['repair'] lists the dropped ones)",
                RepairWarning,
                stacklevel=2,
            )

        self.vertices = _frozen(v)
        self.faces = _FrozenList(_frozen_faces(face_list))
        self.surface = _frozen(surf)
        self.surface_names = _FrozenList(surface_names)
        self.obstruction = _frozen(obst)
        self.two_sided = _frozen(two)
        self.emissivity = None if emis is None else _frozen(emis)
        self.source = source
        info = dict(meta or {})
        if orient != "as-is" or "orient" not in info:  # a changed copy keeps what its origin turned
            info["orient"] = orient_info
        if dropped:
            info["repair"] = dropped
        self.meta: Mapping[str, Any] = types.MappingProxyType(info)  # read-only view (what the reader kept)
        self.planarity_tol = float(planarity_tol)
        self._core = core
        self.areas = _frozen(areas)
        self.normals = _frozen(normals)
        self.centroids = _frozen(centroids)
        self._frozen_now = True

    @staticmethod
    def _build_core(v, face_list, obst, planarity_tol):
        nf = len(face_list)
        offsets = np.zeros(nf + 1, dtype=np.int64)
        offsets[1:] = np.cumsum([f.size for f in face_list])
        coords = v[np.concatenate(face_list)]
        return _core.SceneCore(coords, offsets, ~obst, planarity_tol)

    # --- constructors -------------------------------------------------------------------
    @classmethod
    def from_polygons(cls, polygons, *, surface=None, names=None, obstruction=None, **kw) -> Scene:
        """A scene from a list of (n, 3) vertex arrays."""
        verts, faces = _stack(polygons)
        return cls(verts, faces, surface=surface, names=names, obstruction=obstruction, **kw)

    @classmethod
    def from_file(
        cls, path: str | os.PathLike, *, format: str | None = None, orient: str = "auto", repair: bool = False, **kw
    ) -> Scene:
        """Reads OBJ (objects/groups become surfaces), View3D ``.vs3`` and every mesh format
        meshio reads. Parse errors are ``ValueError`` naming the file and line or element.
        ``orient`` and ``repair`` are as for :class:`Scene`."""
        from .io import read_scene

        data = read_scene(os.fspath(path), format=format)
        # a SceneData's fields are the constructor's arguments of the same names
        return cls(
            **{f.name: getattr(data, f.name) for f in dataclasses.fields(data)}, orient=orient, repair=repair, **kw
        )

    # --- changed copies -------------------------------------------------------------------
    def _replace(self, **changes) -> Scene:
        """A new Scene with some constructor arguments changed (orientation as it is now)."""
        args: dict[str, Any] = dict(
            surface=self.surface,
            names=self.surface_names,
            obstruction=self.obstruction,
            emissivity=self.emissivity,
            two_sided=self.two_sided,
            planarity_tol=self.planarity_tol,
            source=self.source,
            origin=self._origin,
            meta=self.meta,
            orient="as-is",
        )
        vertices = changes.pop("vertices", self.vertices)
        faces = changes.pop("faces", self.faces)
        args.update(changes)
        return Scene(vertices, faces, **args)

    def with_obstruction(self, obstruction) -> Scene:
        """The same scene with other obstruction-only faces: a bool per face, or face indices."""
        return self._replace(obstruction=_face_mask(obstruction, len(self), "obstruction"))

    def with_two_sided(self, two_sided) -> Scene:
        """The same scene with other two-sided faces: a bool per face, or face indices."""
        return self._replace(two_sided=_face_mask(two_sided, len(self), "two_sided"))

    def with_surfaces(self, surface, names: Sequence[str] | None = None) -> Scene:
        """The same polygons grouped into other named surfaces (``surface`` as for the
        constructor). Emissivities are per named surface and are dropped."""
        return self._replace(surface=surface, names=names, emissivity=None)

    def with_emissivity(self, emissivity) -> Scene:
        """The same scene with an emissivity per named surface (None for none)."""
        if emissivity is not None:
            e = np.asarray(emissivity, dtype=np.float64).ravel()
            if e.shape != (len(self.surface_names),):
                raise ValueError(f"emissivity has {e.size} entries for {len(self.surface_names)} named surfaces")
            emissivity = e
        return self._replace(emissivity=emissivity)

    def with_vertices(self, vertices) -> Scene:
        """The same faces on moved vertices (same count); orientation is kept as given."""
        v = np.asarray(vertices, dtype=np.float64)
        if v.shape != self.vertices.shape:
            raise ValueError(f"vertices must have shape {self.vertices.shape}, got {v.shape}")
        return self._replace(vertices=v)

    # --- views ----------------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.faces)

    def __repr__(self) -> str:
        two = int(self.two_sided.sum())
        return (
            f"Scene({len(self)} polygons, {len(self.surface_names)} surfaces, "
            f"{int(self.obstruction.sum())} obstruction-only" + (f", {two} two-sided" if two else "") + ")"
        )

    @property
    def polygons(self) -> list[np.ndarray]:
        return [self.vertices[f] for f in self.faces]

    @property
    def receivers(self) -> np.ndarray:
        """Indices of the faces that get rows and columns (all but obstruction-only)."""
        return np.flatnonzero(~self.obstruction)

    def scaled(self, factor: float) -> Scene:
        """The same scene with every length multiplied by ``factor`` (F is unchanged).

        ``factor`` must be positive: a negative factor mirrors the scene through the origin,
        which turns every face's front to its back (all F would be 0); it is refused rather
        than silently re-oriented."""
        if isinstance(factor, (bool, np.bool_)) or not isinstance(factor, (int, float, np.integer, np.floating)):
            raise TypeError(f"factor must be a number, got {factor!r}")
        if not (np.isfinite(factor) and factor > 0):
            raise ValueError(
                f"factor must be positive and finite, got {factor!r} (a negative factor would "
                "mirror the scene and turn every face around)"
            )
        return self._replace(vertices=self.vertices * float(factor))

    def refined(self, max_edge: float) -> Scene:
        """A finer mesh of the same surfaces: every quadrilateral split bilinearly into k x m
        quads and every other polygon fan-triangulated and each triangle split into k^2, so
        that no edge is longer than ``max_edge``. Surface names and obstruction flags carry over.
        Obstruction-only polygons are kept whole: they get no row or column, so tiles would
        only add work (a large ground plane would become millions of them) and block the same."""
        if isinstance(max_edge, (bool, np.bool_)) or not isinstance(max_edge, (int, float, np.integer, np.floating)):
            raise TypeError(f"max_edge must be a number, got {max_edge!r}")
        if not (np.isfinite(max_edge) and max_edge > 0):
            raise ValueError(f"max_edge must be positive, got {max_edge}")
        polys, surf, obst, two = [], [], [], []

        def emit(p, k):
            polys.append(p)
            surf.append(self.surface[k])
            obst.append(self.obstruction[k])
            two.append(self.two_sided[k])

        for k, f in enumerate(self.faces):
            v = self.vertices[f]
            if self.obstruction[k]:
                emit(v, k)
                continue
            if len(v) == 4 and self._core.strictly_convex(k):
                nu = max(1, int(np.ceil(max(np.linalg.norm(v[1] - v[0]), np.linalg.norm(v[2] - v[3])) / max_edge)))
                nv = max(1, int(np.ceil(max(np.linalg.norm(v[3] - v[0]), np.linalg.norm(v[2] - v[1])) / max_edge)))
                s, t = np.linspace(0, 1, nu + 1), np.linspace(0, 1, nv + 1)
                bil = lambda a, b: (1 - a) * (1 - b) * v[0] + a * (1 - b) * v[1] + a * b * v[2] + (1 - a) * b * v[3]
                for i in range(nu):
                    for j in range(nv):
                        emit(
                            np.array(
                                [bil(s[i], t[j]), bil(s[i + 1], t[j]), bil(s[i + 1], t[j + 1]), bil(s[i], t[j + 1])]
                            ),
                            k,
                        )
                continue
            for tri in self._core.triangulate(k):
                a, b, c = v[tri[0]], v[tri[1]], v[tri[2]]
                n = max(
                    1, int(np.ceil(max(np.linalg.norm(b - a), np.linalg.norm(c - b), np.linalg.norm(a - c)) / max_edge))
                )
                at = lambda i, j: a + (b - a) * (i / n) + (c - a) * (j / n)
                for i in range(n):
                    for j in range(n - i):
                        emit(np.array([at(i, j), at(i + 1, j), at(i, j + 1)]), k)
                        if i + j + 1 < n:
                            emit(np.array([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]), k)
        verts, faces = _stack(polys)
        return self._replace(
            vertices=verts,
            faces=faces,
            surface=surf,
            obstruction=obst,
            two_sided=np.array(two, dtype=bool),
            origin=None,
        )

    def _face_label(self, k: int) -> str:
        if self._origin is not None and k < len(self._origin):
            return f"face {k} ({self._origin[k]})"
        return f"face {k}"


def _unique_in_order(items: list[str]) -> tuple[list[str], np.ndarray]:
    index: dict[str, int] = {}
    inv = np.empty(len(items), dtype=np.int64)
    for k, s in enumerate(items):
        inv[k] = index.setdefault(s, len(index))
    return list(index), inv
