"""Sensors: view factors from many points to a scene, and mean radiant temperature.

A sensor point is a differential plane element (a point with a unit normal: it sees the half
space in front of it) or a small sphere (it sees every direction). From each point the core
computes F to every receiving patch of a scene in one call, in parallel, with the scene's
polygons as obstacles (every polygon blocks from both sides; a receiver never blocks its own
view): Lambert's closed form where nothing is in between, the exact visible region where
something may block (method ``auto``/``clipping``).

Radiant temperatures treat the surfaces as black (ISO 7726 computes plane radiant and mean
radiant temperatures from surface temperatures and angle factors this way); temperatures in
kelvin.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Literal, TypeAlias, cast, overload

import numpy as np
import scipy.sparse as sp

from .methods import MethodName, resolve
from .scene import Scene

#: ISO 7726:1998 Annex B, projected-area weights of the six plane radiant temperatures
#: (up/down, left/right, front/back) for a standing and a seated person.
ISO7726_WEIGHTS: dict[str, tuple[float, float, float]] = {
    "standing": (0.08, 0.23, 0.35),
    "seated": (0.18, 0.22, 0.30),
}


def _rows(x, what: str, n: int | None = None) -> np.ndarray:
    a = np.asarray(x, dtype=np.float64)
    if a.ndim == 1:
        a = a[None, :]
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{what}: expected shape (P, 3) or (3,), got {np.shape(x)}")
    if n is not None and a.shape[0] == 1 and n != 1:
        a = np.repeat(a, n, axis=0)
    bad = np.flatnonzero(~np.isfinite(a).all(axis=1))
    if bad.size:
        raise ValueError(f"{what} row {bad[0]}: not finite: {a[bad[0]].tolist()}")
    return np.ascontiguousarray(a)


def _unit(normals: np.ndarray) -> np.ndarray:
    length = np.linalg.norm(normals, axis=1)
    bad = np.flatnonzero(~(length > 0))
    if bad.size:
        raise ValueError(f"normals row {bad[0]}: the normal is zero")
    return np.ascontiguousarray(normals / length[:, None])


def _receiver_columns(scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """Scene face index of each column, and each face's column (-1 for obstructions)."""
    faces = scene.receivers
    col_of = np.full(len(scene), -1, dtype=np.int64)
    col_of[faces] = np.arange(len(faces))
    return faces, col_of


def _assemble(scene: Scene, parts, n_points: int, dense: bool, by_surface: bool):
    indptr, idx, val, _ = parts
    faces, col_of = _receiver_columns(scene)
    m = sp.csr_array((np.asarray(val), col_of[np.asarray(idx)], np.asarray(indptr)), shape=(n_points, len(faces)))
    if by_surface:
        m = surface_sum(m, scene)
    return m.toarray() if dense else m


def surface_sum(patch_matrix, scene: Scene):
    """(P, n_receivers) patch columns summed into (P, n_surfaces) columns (additivity of F
    over receivers), columns in the order of ``scene.surface_names``."""
    faces = scene.receivers
    s = scene.surface[faces]
    agg = sp.csr_array((np.ones(len(faces)), (np.arange(len(faces)), s)), shape=(len(faces), len(scene.surface_names)))
    m = patch_matrix if sp.issparse(patch_matrix) else sp.csr_array(patch_matrix)
    return (m @ agg).tocsr()


#: What :func:`point_view_factors` returns: a sparse matrix, or an array with ``dense=True``.
Matrix: TypeAlias = "sp.csr_array | np.ndarray"


@overload
def point_view_factors(
    points,
    normals,
    scene: Scene,
    *,
    method: MethodName = ...,
    obstructed: bool = ...,
    by_surface: bool = ...,
    dense: bool = ...,
    return_std: Literal[False] = ...,
    **options: Any,
) -> Matrix: ...
@overload
def point_view_factors(
    points,
    normals,
    scene: Scene,
    *,
    method: MethodName = ...,
    obstructed: bool = ...,
    by_surface: bool = ...,
    dense: bool = ...,
    return_std: Literal[True],
    **options: Any,
) -> tuple[Matrix, Matrix]: ...
@overload
def point_view_factors(
    points,
    normals,
    scene: Scene,
    *,
    method: MethodName = ...,
    obstructed: bool = ...,
    by_surface: bool = ...,
    dense: bool = ...,
    return_std: bool,
    **options: Any,
) -> Matrix | tuple[Matrix, Matrix]: ...
def point_view_factors(
    points,
    normals,
    scene: Scene,
    *,
    method: MethodName = "auto",
    obstructed: bool = True,
    by_surface: bool = False,
    dense: bool = False,
    return_std: bool = False,
    **options: Any,
) -> Matrix | tuple[Matrix, Matrix]:
    """F from differential plane elements at ``points`` (unit ``normals``) to every receiving
    patch of ``scene``.

    Parameters
    ----------
    points : (P, 3) array
    normals : (P, 3) or (3,) array
        Each point's normal (normalised here); it sees the half-space in front of it.
    method : str
        ``auto``, ``clipping``, ``analytic`` or ``contour`` (Lambert's form on exact visible
        regions), or another pair method with visibility (``quadrature``, ``subdivision``,
        ``adaptive``, ``montecarlo``: its per-point estimator where something may block).
    obstructed : bool
        Every polygon of the scene (obstruction-only ones too) blocks; else Lambert's closed
        form to each receiver alone.
    by_surface : bool
        Return the (P, n_surfaces) sums over each named surface's patches instead.
    dense : bool
        Return a numpy array instead of a ``scipy.sparse.csr_array``.
    return_std : bool
        Also return the standard errors (patch level, zero for the deterministic methods).

    Returns
    -------
    (P, n_receivers) matrix, columns in the order of ``scene.receivers`` (or (P, n_surfaces)
    with ``by_surface``, columns in the order of ``scene.surface_names``).
    """
    p = _rows(points, "points")
    n = _unit(_rows(normals, "normals", len(p)))
    if len(n) != len(p):
        raise ValueError(f"{len(p)} points but {len(n)} normals")
    _, opts = resolve(method, options)
    parts = scene._core.point_rows(p, n, method, opts, bool(obstructed))
    f = _assemble(scene, parts, len(p), dense, by_surface)
    if not return_std:
        return f
    indptr, idx, _, std = parts
    err = np.zeros(len(idx)) if std is None else np.asarray(std)
    std_parts = (indptr, idx, err, None)
    return f, _assemble(scene, std_parts, len(p), dense, False)


def sphere_view_factors(
    points, scene: Scene, *, obstructed: bool = True, by_surface: bool = False, dense: bool = False
):
    """F from a small sphere at each point to every receiving patch: the solid angle of the
    patch's visible part over 4 pi (exact; equal to the mean of the plane element's F over
    all normal directions). Shapes and column order as :func:`point_view_factors`."""
    p = _rows(points, "points")
    parts = scene._core.point_sphere_rows(p, bool(obstructed))
    return _assemble(scene, parts, len(p), dense, by_surface)


def _surface_t4(scene: Scene, temperatures) -> tuple[np.ndarray, list[str]]:
    """T^4 per named surface from a mapping name -> kelvin or an array per surface."""
    names = scene.surface_names
    if isinstance(temperatures, Mapping):
        unknown = [k for k in temperatures if k not in names]
        if unknown:
            raise ValueError(f"unknown surface {unknown[0]!r} (surfaces: {', '.join(names)})")
        missing = [k for k in names if k not in temperatures]
        t = np.array([temperatures.get(k, np.nan) for k in names], dtype=np.float64)
    else:
        t = np.asarray(temperatures, dtype=np.float64)
        if t.shape != (len(names),):
            raise ValueError(f"temperatures: expected one per surface ({len(names)}), got shape {t.shape}")
        missing = [names[k] for k in np.flatnonzero(np.isnan(t))]
    if np.any(t[np.isfinite(t)] <= 0) or np.any(np.isinf(t)):
        raise ValueError("temperatures must be positive and finite (kelvin)")
    t4 = t**4
    t4[np.isnan(t)] = np.nan
    return t4, missing


def radiant_temperature(
    f_surface, scene: Scene, temperatures, *, rest: float | None = None, closure_tol: float = 1e-6
) -> np.ndarray:
    """Radiant temperature seen by each sensor: T = (sum_j F_j T_j^4 + (1 - sum_j F_j) T_rest^4)^(1/4).

    ``f_surface`` is a (P, n_surfaces) matrix (``by_surface=True``) of plane elements (the
    plane radiant temperature of ISO 7726) or spheres (the mean radiant temperature).
    ``temperatures``: kelvin per surface name (mapping) or per surface (array). Surfaces a
    sensor sees must have a temperature. ``rest``: the temperature of everything the scene
    does not cover (sky, ambient); without it, a sensor whose F sums to less than
    1 - closure_tol is an error (the scene is open for it).
    """
    f = f_surface.toarray() if sp.issparse(f_surface) else np.asarray(f_surface, dtype=np.float64)
    t4, missing = _surface_t4(scene, temperatures)
    seen = f > 0
    lacking: np.ndarray | list[int] = np.flatnonzero(seen[:, np.isnan(t4)].any(axis=0)) if np.isnan(t4).any() else []
    if len(lacking):
        name = [scene.surface_names[k] for k in np.flatnonzero(np.isnan(t4))][lacking[0]]
        raise ValueError(f"surface {name!r} is seen by a sensor but has no temperature")
    covered = f.sum(axis=1)
    e = np.where(seen, f * np.nan_to_num(t4), 0.0).sum(axis=1)
    if rest is None:
        open_ = np.flatnonzero(covered < 1 - closure_tol)
        if open_.size:
            raise ValueError(
                f"sensor {open_[0]} sees only {covered[open_[0]]:.9g} of its field of view covered by the scene: "
                "give the temperature of the rest (rest=..., the sky or ambient)"
            )
        e = e / covered  # rounding of the row sum only
    else:
        if not (rest > 0 and np.isfinite(rest)):
            raise ValueError("rest must be a positive temperature (kelvin)")
        e = e + np.clip(1.0 - covered, 0.0, None) * rest**4
    return e**0.25


#: Directions of the six plane radiant temperatures, in the person's frame.
_SIX = ("up", "down", "left", "right", "front", "back")


def six_directions(front=(1.0, 0.0, 0.0), up=(0.0, 0.0, 1.0)) -> dict[str, np.ndarray]:
    """The unit normals of ISO 7726's six plane radiant temperatures for a person facing
    ``front`` with ``up`` vertical: up, down, left, right, front, back."""
    u = np.asarray(up, float) / np.linalg.norm(up)
    f = np.asarray(front, float)
    f = f - f.dot(u) * u
    if not np.linalg.norm(f) > 1e-12:
        raise ValueError("front must not be parallel to up")
    f /= np.linalg.norm(f)
    left = np.cross(u, f)
    return {"up": u, "down": -u, "left": left, "right": -left, "front": f, "back": -f}


def mean_radiant_temperature(
    points,
    scene: Scene,
    temperatures,
    *,
    form: Literal["sphere", "standing", "seated"] = "sphere",
    front=(1.0, 0.0, 0.0),
    up=(0.0, 0.0, 1.0),
    rest: float | None = None,
    obstructed: bool = True,
    method: MethodName = "auto",
) -> np.ndarray:
    """Mean radiant temperature (kelvin) at each point.

    ``form="sphere"``: of a small sphere, T_mrt^4 = sum_j F_sphere,j T_j^4 (exact angle
    factors, :func:`sphere_view_factors`). ``"standing"``/``"seated"``: ISO 7726:1998 Annex
    B, the six plane radiant temperatures T_pr (up, down, left, right, front, back, see
    :func:`six_directions`) weighted by the person's projected areas (:data:`ISO7726_WEIGHTS`):
    T_mrt = sum_d w_d T_pr,d / sum_d w_d.
    """
    p = _rows(points, "points")
    if form == "sphere":
        f = sphere_view_factors(p, scene, obstructed=obstructed, by_surface=True)
        return radiant_temperature(f, scene, temperatures, rest=rest)
    if form not in ISO7726_WEIGHTS:
        raise ValueError(f"form must be 'sphere', 'standing' or 'seated', got {form!r}")
    t = plane_radiant_temperatures(
        p, scene, temperatures, front=front, up=up, rest=rest, obstructed=obstructed, method=method
    )
    w_ud, w_lr, w_fb = ISO7726_WEIGHTS[form]
    w = {"up": w_ud, "down": w_ud, "left": w_lr, "right": w_lr, "front": w_fb, "back": w_fb}
    return cast(np.ndarray, sum(w[d] * t[d] for d in _SIX) / sum(w.values()))


def plane_radiant_temperatures(
    points,
    scene: Scene,
    temperatures,
    *,
    front=(1.0, 0.0, 0.0),
    up=(0.0, 0.0, 1.0),
    rest: float | None = None,
    obstructed: bool = True,
    method: MethodName = "auto",
) -> dict[str, np.ndarray]:
    """The six plane radiant temperatures (kelvin) at each point, by direction name
    (:func:`six_directions`), all in one core call."""
    p = _rows(points, "points")
    dirs = six_directions(front, up)
    normals = np.concatenate([np.repeat(dirs[d][None, :], len(p), axis=0) for d in _SIX])
    f = point_view_factors(np.tile(p, (6, 1)), normals, scene, by_surface=True, obstructed=obstructed, method=method)
    t = radiant_temperature(f, scene, temperatures, rest=rest)
    return {d: t[k * len(p) : (k + 1) * len(p)] for k, d in enumerate(_SIX)}


def read_points_csv(path) -> tuple[np.ndarray, np.ndarray]:
    """Points and normals from a CSV file with a header naming the columns x, y, z, nx, ny,
    nz (in any order; other columns are ignored). Errors name the file and line."""
    from .io.scenedata import csv_rows

    rows = csv_rows(str(path), "CSV")
    first = next(rows, None)
    if first is None:
        raise ValueError(f"{path}: empty file, expected a header x,y,z,nx,ny,nz")
    header = [h.strip().lower() for h in first[1]]
    need = ["x", "y", "z", "nx", "ny", "nz"]
    missing = [c for c in need if c not in header]
    if missing:
        raise ValueError(f"{path}:{first[0]}: missing column(s) {', '.join(missing)} (header: {','.join(header)})")
    cols = [header.index(c) for c in need]
    out = []
    for line, row in rows:
        if not row or all(not c.strip() for c in row):
            continue
        if len(row) < len(header):
            raise ValueError(f"{path}:{line}: {len(row)} fields, the header has {len(header)}")
        try:
            v = [float(row[c]) for c in cols]
        except ValueError:
            raise ValueError(f"{path}:{line}: not a number in x,y,z,nx,ny,nz: {','.join(row)}") from None
        if not np.all(np.isfinite(v)):
            raise ValueError(f"{path}:{line}: not finite: {','.join(row)}")
        if not np.linalg.norm(v[3:]) > 0:
            raise ValueError(f"{path}:{line}: the normal (nx, ny, nz) is zero")
        out.append(v)
    if not out:
        raise ValueError(f"{path}: no points after the header")
    a = np.array(out)
    return a[:, :3], a[:, 3:]
