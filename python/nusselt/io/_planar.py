"""Planar helpers for cutting sub-surfaces, masks and null surfaces out of their base.

View3D surfaces are convex (triangles or convex quadrilaterals) and a sub-surface lies
inside its base. The base minus its holes is written as a union of disjoint convex pieces:
for a convex hole H with counter-clockwise edges e_1..e_m and a convex piece P,

    P \\ H = U_k  P  n  right(e_k)  n  left(e_1) n ... n left(e_{k-1})

(each point of P outside H lies right of a first edge e_k, and left of all earlier ones),
so the pieces are disjoint, convex, and found by half-plane clipping alone (Sutherland-
Hodgman with one edge). Several holes are removed one after the other. Vertices are exact
edge intersections; slivers from holes touching the base boundary are dropped by a
relative area test.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np


def newell_normal(p: np.ndarray) -> np.ndarray:
    """Area vector of a polygon (Newell): n = 1/2 sum_i p_i x p_{i+1}; |n| = area."""
    q = np.roll(p, -1, axis=0)
    return 0.5 * np.cross(p, q).sum(axis=0)


def cos_sin_deg(deg: float) -> tuple[float, float]:
    """cos and sin of an angle in degrees, exact at multiples of 90 degrees."""
    q = deg / 90.0
    if q == round(q):
        return [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][int(round(q)) % 4]
    r = math.radians(deg)
    return math.cos(r), math.sin(r)


def polygon_area_3d(p: np.ndarray) -> float:
    return float(np.linalg.norm(newell_normal(p)))


def signed_area_2d(p: np.ndarray) -> float:
    """Shoelace formula, positive for counter-clockwise."""
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


class PlaneFrame:
    """Orthonormal frame (origin c, axes u, v, normal n = u x v) of a planar polygon."""

    def __init__(self, p: np.ndarray):
        a = newell_normal(p)
        area = np.linalg.norm(a)
        if not area > 0:
            raise ValueError("degenerate polygon (zero area)")
        self.n = a / area
        self.c = p.mean(axis=0)
        e = p[1] - p[0]
        e = e - (e @ self.n) * self.n
        if not np.linalg.norm(e) > 0:
            e = p[2] - p[0]
            e = e - (e @ self.n) * self.n
        self.u = e / np.linalg.norm(e)
        self.v = np.cross(self.n, self.u)
        self.size = float(np.max(np.linalg.norm(p - self.c, axis=1)))

    def to2d(self, p: np.ndarray) -> np.ndarray:
        d = p - self.c
        return np.column_stack([d @ self.u, d @ self.v])

    def to3d(self, q: np.ndarray) -> np.ndarray:
        return self.c + q[:, :1] * self.u + q[:, 1:2] * self.v

    def height(self, p: np.ndarray) -> np.ndarray:
        return (p - self.c) @ self.n


def is_convex_2d(q: np.ndarray, tol: float) -> bool:
    """True when the counter-clockwise 2-D outline ``q`` turns left (or straight, within the
    cross-product tolerance ``tol``, an area) at every vertex."""
    n = len(q)
    for k in range(n):
        a, b, c = q[k - 1], q[k], q[(k + 1) % n]
        if (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) < -tol:
            return False
    return True


def _clip(poly: np.ndarray, a: np.ndarray, b: np.ndarray, keep_left: bool) -> np.ndarray:
    """Sutherland-Hodgman clip of a convex polygon to one side of the line a->b
    (points on the line are kept on both sides)."""
    if len(poly) == 0:
        return poly
    d = b - a
    s = d[0] * (poly[:, 1] - a[1]) - d[1] * (poly[:, 0] - a[0])  # > 0: left of a->b
    if not keep_left:
        s = -s
    out = []
    n = len(poly)
    for i in range(n):
        j = (i + 1) % n
        pi, pj, si, sj = poly[i], poly[j], s[i], s[j]
        if si >= 0:
            out.append(pi)
        if (si > 0 and sj < 0) or (si < 0 and sj > 0):
            t = si / (si - sj)
            out.append(pi + t * (pj - pi))
    return np.array(out).reshape(-1, 2)


def _clean(poly: np.ndarray, tol: float) -> np.ndarray:
    """Drop repeated and collinear vertices (tolerances relative to the base size)."""
    pts = list(poly)
    changed = True
    while changed and len(pts) >= 3:
        changed = False
        n = len(pts)
        for i in range(n):
            a, b, c = pts[i - 1], pts[i], pts[(i + 1) % n]
            if np.linalg.norm(b - a) <= tol or abs(
                (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
            ) <= tol * np.linalg.norm(c - a):
                del pts[i]
                changed = True
                break
    return np.array(pts).reshape(-1, 2)


def convex_intersection_area(p: np.ndarray, q: np.ndarray) -> float:
    """Area of the intersection of two convex CCW polygons (2-D)."""
    r = p
    for i in range(len(q)):
        r = _clip(r, q[i], q[(i + 1) % len(q)], keep_left=True)
        if len(r) < 3:
            return 0.0
    return max(signed_area_2d(r), 0.0)


def subtract_convex_holes(base: np.ndarray, holes: list[np.ndarray], size: float) -> list[np.ndarray]:
    """Convex CCW 2-D ``base`` minus disjoint convex CCW ``holes`` as a list of disjoint
    convex CCW pieces. ``size`` sets the relative tolerances."""
    tol = 1e-12 * size
    min_area = 1e-12 * size * size
    pieces = [base]
    for h in holes:
        m = len(h)
        out = []
        for p in pieces:
            if convex_intersection_area(p, h) <= min_area:
                out.append(p)  # untouched by this hole: keep it whole
                continue
            rest = p
            for k in range(m):
                a, b = h[k], h[(k + 1) % m]
                piece = _clip(rest, a, b, keep_left=False)
                piece = _clean(piece, tol) if len(piece) >= 3 else piece
                if len(piece) >= 3 and signed_area_2d(piece) > min_area:
                    out.append(piece)
                rest = _clip(rest, a, b, keep_left=True)
                if len(rest) < 3:
                    break
        pieces = out
    return pieces


def triangulate_2d(p: np.ndarray) -> list[np.ndarray]:
    """Ear clipping of a simple counter-clockwise 2-D polygon; ValueError when it is not simple."""
    idx = list(range(len(p)))
    tris = []
    scale = float(np.max(np.ptp(p, axis=0))) or 1.0
    eps = 1e-14 * scale * scale

    def cross(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

    guard = 0
    while len(idx) > 3 and guard < 10 * len(p) ** 2:
        guard += 1
        m = len(idx)
        for k in range(m):
            i0, i1, i2 = idx[k - 1], idx[k], idx[(k + 1) % m]
            a, b, c = p[i0], p[i1], p[i2]
            if cross(a, b, c) <= eps:
                continue
            inside = False
            for j in idx:
                if j in (i0, i1, i2):
                    continue
                q = p[j]
                if cross(a, b, q) >= -eps and cross(b, c, q) >= -eps and cross(c, a, q) >= -eps:
                    inside = True
                    break
            if not inside:
                tris.append(np.array([a, b, c]))
                del idx[k]
                break
        else:
            raise ValueError("polygon is not simple (no ear found)")
    if len(idx) == 3:
        tris.append(p[idx])
    return tris


@dataclass(frozen=True)
class Hole:
    """A polygon to cut out of its base: its 3-D vertices, where the file gives it (handed to
    the reader's error function), ``what`` names it in its own messages and ``name`` in
    another hole's, and ``reversed`` says it is listed in the opposite sense to its base (as
    View3D lists masks and null surfaces)."""

    poly: np.ndarray
    where: Any
    what: str
    name: str
    reversed: bool = False


@dataclass(frozen=True)
class CutRules:
    """How a file format's holes must sit in their base.

    ``plane_tol``: the largest distance of a hole's vertex from the base's plane, relative to
    the base's size. ``concave_base``: a concave base is split into triangles (else refused).
    ``messages``: the format's wording of each refusal, as ``str.format`` templates over
    ``base`` (the base's label), ``number`` (its number in the file, where it has one),
    ``what``, ``other`` (the hole met), ``dist`` and ``pct``; keys ``zero_base``,
    ``concave_base`` (refused) or ``not_simple`` (not triangulated), ``off_plane``,
    ``zero_area``, ``wrong_way`` and ``wrong_way_reversed`` (facing against the rule),
    ``not_convex``, ``outside``, ``overlap``."""

    plane_tol: float
    concave_base: bool
    messages: Mapping[str, str]


def cut_holes(
    base: np.ndarray,
    holes: Sequence[Hole],
    rules: CutRules,
    *,
    where: Any,
    label: str,
    number: Any = "",
    fail: Callable[[Any, str], Exception],
) -> list[np.ndarray]:
    """The 3-D polygon ``base`` minus its convex ``holes`` as convex 3-D pieces, after checking
    each hole against ``rules`` (in its base's plane, facing as the rule says, convex, inside
    the base, overlapping no earlier hole). A refusal raises ``fail(where, message)``."""
    if not holes:
        return [base]
    msg = rules.messages

    def refuse(at: Any, key: str, **values) -> Exception:
        return fail(at, msg[key].format(base=label, number=number, **values))

    try:
        frame = PlaneFrame(base)
    except ValueError:
        raise refuse(where, "zero_base") from None
    size = frame.size
    b2 = frame.to2d(base)
    if is_convex_2d(b2, 1e-9 * size * size):
        parts = [b2]
    elif not rules.concave_base:
        raise refuse(where, "concave_base")
    else:
        try:
            parts = triangulate_2d(b2)
        except ValueError:
            raise refuse(where, "not_simple") from None
    kept: list[tuple[Hole, np.ndarray]] = []
    for h in holes:
        dist = float(np.max(np.abs(frame.height(h.poly))))
        if dist > rules.plane_tol * size:
            raise refuse(h.where, "off_plane", what=h.what, dist=dist)
        q = frame.to2d(h.poly)
        a = signed_area_2d(q)
        if a == 0:
            raise refuse(h.where, "zero_area", what=h.what)
        if (a < 0) != h.reversed:
            raise refuse(h.where, "wrong_way_reversed" if h.reversed else "wrong_way", what=h.what)
        if a < 0:
            q, a = q[::-1].copy(), -a
        if not is_convex_2d(q, 1e-9 * size * size):
            raise refuse(h.where, "not_convex", what=h.what)
        inside = sum(convex_intersection_area(q, t) for t in parts)
        if inside < (1 - 1e-6) * a:
            raise refuse(h.where, "outside", what=h.what, pct=100 * (1 - inside / a))
        for g, q2 in kept:
            if convex_intersection_area(q, q2) > 1e-9 * min(a, signed_area_2d(q2)):
                raise refuse(h.where, "overlap", what=h.what, other=g.name)
        kept.append((h, q))
    pieces = []
    for t in parts:
        pieces.extend(subtract_convex_holes(t, [q for _, q in kept], size))
    return [frame.to3d(p) for p in pieces]
