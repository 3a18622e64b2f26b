"""Scenes: planar polygons with named surfaces, some of them obstruction-only."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np

from . import _core

#: Default relative planarity tolerance (fraction of a polygon's size).
PLANARITY_TOL = 1e-6


class Scene:
    """A set of planar polygons (patches) grouped into named surfaces.

    Parameters
    ----------
    vertices : (V, 3) array of float
        Vertex coordinates, in any length unit (F does not depend on it).
    faces : sequence of index sequences, or (F, k) int array
        Each face lists its vertex indices counter-clockwise seen from its front side
        (only the front emits and receives). Faces may have any number >= 3 of vertices and
        may be concave, but must be planar and simple.
    surface : sequence of str or int, optional
        The named surface of each face (default: every face is its own surface ``"face<k>"``).
        Integers index into ``names``.
    names : sequence of str, optional
        Surface names when ``surface`` holds integers.
    obstruction : sequence of bool, optional
        Faces that block radiation but get no row or column in the result.
    planarity_tol : float
        Allowed distance of a vertex from its face's plane, relative to the face's size.
    """

    def __init__(
        self,
        vertices,
        faces,
        *,
        surface=None,
        names: Sequence[str] | None = None,
        obstruction=None,
        emissivity=None,
        planarity_tol: float = PLANARITY_TOL,
        source: str | None = None,
        origin: Sequence[str] | None = None,
        meta: dict | None = None,
    ):
        where = f"{source}: " if source else ""
        v = np.asarray(vertices, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 3:
            raise ValueError(f"{where}vertices must be an (V, 3) array, got shape {v.shape}")
        bad = np.flatnonzero(~np.isfinite(v).all(axis=1))
        if bad.size:
            raise ValueError(f"{where}vertex {bad[0]} has a NaN or infinite coordinate: {v[bad[0]].tolist()}")
        if isinstance(faces, np.ndarray) and faces.ndim == 2:
            face_list = [np.asarray(f, dtype=np.int64) for f in faces]
        else:
            face_list = [np.asarray(f, dtype=np.int64).ravel() for f in faces]
        if not face_list:
            raise ValueError(f"{where}the scene has no faces")
        self._origin = list(origin) if origin is not None else None
        for k, f in enumerate(face_list):
            if f.size < 3:
                raise ValueError(f"{where}{self._face_label(k)} has {f.size} vertices; a polygon needs at least 3")
            if f.min() < 0 or f.max() >= len(v):
                raise ValueError(
                    f"{where}{self._face_label(k)} refers to vertex {int(f.max() if f.max() >= len(v) else f.min())},"
                    f" but there are {len(v)} vertices"
                )
        if not (np.isfinite(planarity_tol) and 0 < planarity_tol < 1):
            raise ValueError(f"planarity_tol must be in (0, 1), got {planarity_tol}")

        nf = len(face_list)
        if surface is None:
            self.surface_names = [f"face{k}" for k in range(nf)]
            self.surface = np.arange(nf, dtype=np.int64)
        else:
            surface = list(surface)
            if len(surface) != nf:
                raise ValueError(f"{where}surface has {len(surface)} entries for {nf} faces")
            if names is not None:
                self.surface_names = [str(s) for s in names]
                self.surface = np.asarray(surface, dtype=np.int64)
                if self.surface.min() < 0 or self.surface.max() >= len(self.surface_names):
                    raise ValueError(f"{where}surface index out of range of names")
            else:
                self.surface_names, inv = _unique_in_order([str(s) for s in surface])
                self.surface = inv
        self.obstruction = (
            np.zeros(nf, dtype=bool) if obstruction is None else np.asarray(obstruction, dtype=bool).ravel()
        )
        if self.obstruction.shape != (nf,):
            raise ValueError(f"{where}obstruction has {self.obstruction.size} entries for {nf} faces")
        self.emissivity = None if emissivity is None else np.asarray(emissivity, dtype=np.float64)
        self.vertices = v
        self.faces = face_list
        self.source = source
        self.meta = dict(meta or {})
        self.planarity_tol = float(planarity_tol)

        offsets = np.zeros(nf + 1, dtype=np.int64)
        offsets[1:] = np.cumsum([f.size for f in face_list])
        coords = v[np.concatenate(face_list)]
        self._core = _core.SceneCore(coords, offsets, ~self.obstruction, self.planarity_tol)
        errors = self._core.errors()
        for k, msg in enumerate(errors):
            if msg is not None:
                raise ValueError(f"{where}{self._face_label(k)} {msg}")
        self.areas = np.asarray(self._core.areas())
        self.normals = np.asarray(self._core.normals())
        self.centroids = np.asarray(self._core.centroids())

    # --- constructors -------------------------------------------------------------------
    @classmethod
    def from_polygons(cls, polygons, *, surface=None, names=None, obstruction=None, **kw) -> "Scene":
        """A scene from a list of (n, 3) vertex arrays."""
        polys = [np.asarray(p, dtype=np.float64) for p in polygons]
        for k, p in enumerate(polys):
            if p.ndim != 2 or p.shape[1] != 3:
                raise ValueError(f"polygon {k}: expected an (n, 3) array, got shape {p.shape}")
        sizes = [len(p) for p in polys]
        starts = np.concatenate([[0], np.cumsum(sizes)])
        faces = [np.arange(starts[k], starts[k + 1]) for k in range(len(polys))]
        verts = np.concatenate(polys) if polys else np.zeros((0, 3))
        return cls(verts, faces, surface=surface, names=names, obstruction=obstruction, **kw)

    @classmethod
    def from_file(cls, path: str | os.PathLike, *, format: str | None = None, **kw) -> "Scene":
        """Reads OBJ (objects/groups become surfaces), View3D ``.vs3`` and every mesh format
        meshio reads. Parse errors are ``ValueError`` naming the file and line or element."""
        from .io import read_scene

        data = read_scene(os.fspath(path), format=format)
        return cls(
            data.vertices,
            data.faces,
            surface=data.surface,
            names=data.names,
            obstruction=data.obstruction,
            emissivity=data.emissivity,
            source=data.source,
            origin=data.origin,
            meta=data.meta,
            **kw,
        )

    # --- views ----------------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.faces)

    def __repr__(self) -> str:
        return (
            f"Scene({len(self)} polygons, {len(self.surface_names)} surfaces, "
            f"{int(self.obstruction.sum())} obstruction-only)"
        )

    @property
    def polygons(self) -> list[np.ndarray]:
        return [self.vertices[f] for f in self.faces]

    @property
    def receivers(self) -> np.ndarray:
        """Indices of the faces that get rows and columns (all but obstruction-only)."""
        return np.flatnonzero(~self.obstruction)

    def scaled(self, factor: float) -> "Scene":
        """The same scene with every length multiplied by ``factor`` (F is unchanged)."""
        return Scene(
            self.vertices * factor,
            self.faces,
            surface=self.surface,
            names=self.surface_names,
            obstruction=self.obstruction,
            emissivity=self.emissivity,
            planarity_tol=self.planarity_tol,
            source=self.source,
            origin=self._origin,
            meta=self.meta,
        )

    def refined(self, max_edge: float) -> "Scene":
        """A finer mesh of the same surfaces: every quadrilateral split bilinearly into k x m
        quads and every other polygon fan-triangulated and each triangle split into k^2, so
        that no edge is longer than ``max_edge``. Surface names and obstruction flags carry over."""
        if not (np.isfinite(max_edge) and max_edge > 0):
            raise ValueError(f"max_edge must be positive, got {max_edge}")
        polys, surf, obst = [], [], []

        def emit(p, k):
            polys.append(p)
            surf.append(self.surface[k])
            obst.append(self.obstruction[k])

        for k, f in enumerate(self.faces):
            v = self.vertices[f]
            if len(v) == 4 and _is_convex(v, self.normals[k]):
                nu = max(1, int(np.ceil(max(np.linalg.norm(v[1] - v[0]), np.linalg.norm(v[2] - v[3])) / max_edge)))
                nv = max(1, int(np.ceil(max(np.linalg.norm(v[3] - v[0]), np.linalg.norm(v[2] - v[1])) / max_edge)))
                s, t = np.linspace(0, 1, nu + 1), np.linspace(0, 1, nv + 1)
                bil = lambda a, b: (1 - a) * (1 - b) * v[0] + a * (1 - b) * v[1] + a * b * v[2] + (1 - a) * b * v[3]
                for i in range(nu):
                    for j in range(nv):
                        emit(np.array([bil(s[i], t[j]), bil(s[i + 1], t[j]), bil(s[i + 1], t[j + 1]), bil(s[i], t[j + 1])]), k)
                continue
            for tri in self._core.triangulate(k):
                a, b, c = v[tri[0]], v[tri[1]], v[tri[2]]
                n = max(1, int(np.ceil(max(np.linalg.norm(b - a), np.linalg.norm(c - b), np.linalg.norm(a - c)) / max_edge)))
                at = lambda i, j: a + (b - a) * (i / n) + (c - a) * (j / n)
                for i in range(n):
                    for j in range(n - i):
                        emit(np.array([at(i, j), at(i + 1, j), at(i, j + 1)]), k)
                        if i + j + 1 < n:
                            emit(np.array([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]), k)
        return Scene.from_polygons(
            polys, surface=surf, names=self.surface_names, obstruction=obst, emissivity=self.emissivity,
            planarity_tol=self.planarity_tol, source=self.source, meta=self.meta,
        )

    def _face_label(self, k: int) -> str:
        if self._origin is not None and k < len(self._origin):
            return f"face {k} ({self._origin[k]})"
        return f"face {k}"


def _is_convex(v: np.ndarray, n: np.ndarray) -> bool:
    m = len(v)
    return all(np.cross(v[(i + 1) % m] - v[i], v[(i + 2) % m] - v[(i + 1) % m]) @ n > 0 for i in range(m))


def _unique_in_order(items: list[str]) -> tuple[list[str], np.ndarray]:
    index: dict[str, int] = {}
    inv = np.empty(len(items), dtype=np.int64)
    for k, s in enumerate(items):
        inv[k] = index.setdefault(s, len(index))
    return list(index), inv
