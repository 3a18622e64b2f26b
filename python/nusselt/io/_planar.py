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

import numpy as np


def newell_normal(p: np.ndarray) -> np.ndarray:
    """Area vector of a polygon (Newell): n = 1/2 sum_i p_i x p_{i+1}; |n| = area."""
    q = np.roll(p, -1, axis=0)
    return 0.5 * np.cross(p, q).sum(axis=0)


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
