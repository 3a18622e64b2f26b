"""Coplanar same-facing faces that overlap (duplicated or overlapping faces of a scene).

Two faces that cover the same piece of a plane and face the same way are each counted as a
receiver, so rows sum to more than 1 (a doubled mesh gives row sums of 2). Finding them
without comparing every pair:

1. faces are grouped by plane: unit normal rounded to 1e-6, then sorted by the plane's
   offset n . c and split where the offset jumps by more than 1e-8 of the scene's size;
2. within a plane group, faces are triangulated and their triangles' 2-D bounding boxes,
   shrunk by 1e-9 of the scene's size so that neighbours sharing an edge do not count,
   are put in a uniform grid; boxes sharing a cell are candidates;
3. candidate triangle pairs are tested for an interior overlap by the separating-axis
   theorem (two convex polygons overlap with positive area iff no edge normal of either
   separates them by more than the tolerance), all in numpy.

Faces facing opposite ways (a two-sided wall modelled as two faces, a View3D mask) are in
different groups and never reported.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .io import _planar
from .io.topology import sorted_unique


def _pairs_in_sweep(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Index pairs (a, b), a < b, of boxes whose [lo, hi] intervals overlap in x and y.

    Boxes go into a uniform grid of cells the size of the median box; pairs are taken
    within a cell (a grid of n patches costs O(n), where a sweep along one axis would
    cost O(n^1.5)). Boxes spanning more than 16 cells are tested against all boxes."""
    n = len(lo)
    ext = (hi - lo).max(axis=1)
    srt = np.sort(ext)  # the median; np.median first imports numpy.ma
    h = float(0.5 * (srt[(n - 1) // 2] + srt[n // 2])) if n else 0.0
    if not h > 0:
        h = float(np.max(ext)) or 1.0
    origin = lo.min(axis=0)
    i0 = np.floor((lo - origin) / h).astype(np.int64)
    i1 = np.floor((np.maximum(hi, lo) - origin) / h).astype(np.int64)
    span = i1 - i0 + 1
    cells = span[:, 0] * span[:, 1]
    big = np.flatnonzero(cells > 16)
    small = np.flatnonzero(cells <= 16)
    pa, pb = [], []
    for k in big:  # few: each against every box
        hit = np.flatnonzero(
            (lo[:, 0] < hi[k, 0]) & (lo[k, 0] < hi[:, 0]) & (lo[:, 1] < hi[k, 1]) & (lo[k, 1] < hi[:, 1])
        )
        hit = hit[hit != k]
        pa.append(np.minimum(hit, k))
        pb.append(np.maximum(hit, k))
    # every small box in each cell it covers
    c = cells[small]
    box = np.repeat(small, c)
    local = np.arange(c.sum()) - np.repeat(np.cumsum(c) - c, c)
    w = np.repeat(span[small, 0], c)
    cx = np.repeat(i0[small, 0], c) + local % w
    cy = np.repeat(i0[small, 1], c) + local // w
    key = cx * (int(cy.max() if len(cy) else 0) + 1) + cy
    order = np.argsort(key, kind="stable")
    key, box = key[order], box[order]
    end = np.searchsorted(key, key, side="right")
    start = np.arange(len(key)) + 1
    cnt = np.maximum(end - start, 0)
    a = np.repeat(np.arange(len(key)), cnt)
    offs = np.repeat(np.cumsum(cnt) - cnt, cnt)
    b = np.repeat(start, cnt) + (np.arange(cnt.sum()) - offs)
    a, b = box[a], box[b]
    pa.append(np.minimum(a, b))
    pb.append(np.maximum(a, b))
    a, b = np.concatenate(pa), np.concatenate(pb)
    keep = (a != b) & (lo[a, 0] < hi[b, 0]) & (lo[b, 0] < hi[a, 0]) & (lo[a, 1] < hi[b, 1]) & (lo[b, 1] < hi[a, 1])
    uniq = sorted_unique(a[keep] * n + b[keep])
    return uniq // n, uniq % n


def _sat_overlap(ta: np.ndarray, tb: np.ndarray, eps: float) -> np.ndarray:
    """For (P, 3, 2) triangle pairs: whether they overlap with positive area (by more than
    ``eps`` along every edge normal)."""
    ok = np.ones(len(ta), dtype=bool)
    for tri in (ta, tb):
        for k in range(3):
            e = tri[:, (k + 1) % 3] - tri[:, k]
            ax = np.stack([-e[:, 1], e[:, 0]], axis=1)
            ax /= np.maximum(np.linalg.norm(ax, axis=1, keepdims=True), 1e-300)
            pa = np.einsum("pvi,pi->pv", ta, ax)
            pb = np.einsum("pvi,pi->pv", tb, ax)
            depth = np.minimum(pa.max(1), pb.max(1)) - np.maximum(pa.min(1), pb.min(1))
            ok &= depth > eps
    return ok


def coplanar_overlaps(
    vertices: np.ndarray,
    faces: list[np.ndarray],
    normals: np.ndarray,
    centroids: np.ndarray,
    triangulate: Callable[[int], list],
    among: np.ndarray,
) -> list[tuple[int, int, float]]:
    """Pairs ``(i, j, overlap area)``, i < j, of faces in ``among`` (indices) that lie in
    one plane, face the same way and overlap with positive area."""
    among = np.asarray(among, dtype=np.int64)
    if len(among) < 2:
        return []
    size = float(np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0))) or 1.0
    n = normals[among]
    key = np.round(n * 1e6).astype(np.int64)
    # plane offsets from the scene's corner, not the origin: two planes 5e-8 apart in tilt
    # differ in offset by that times the distance from where it is measured (moved by 7, faces
    # 1e-8 .. 6e-8 apart fell into one group and were refused; tests/test_properties.py)
    d = np.einsum("ij,ij->i", n, centroids[among] - vertices.min(axis=0))
    order = np.lexsort((d, key[:, 2], key[:, 1], key[:, 0]))
    ks, ds = key[order], d[order]
    new = np.ones(len(order), dtype=bool)
    new[1:] = (ks[1:] != ks[:-1]).any(axis=1) | (np.diff(ds) > 1e-8 * size)
    group = np.cumsum(new) - 1
    sizes = np.bincount(group)
    eps = 1e-9 * size
    found: dict[tuple[int, int], list] = {}
    for g in np.flatnonzero(sizes >= 2):
        members = among[order[group == g]]
        nrm = normals[members[0]]
        frame_u = np.cross(nrm, [1.0, 0.0, 0.0] if abs(nrm[0]) < 0.9 else [0.0, 1.0, 0.0])
        frame_u /= np.linalg.norm(frame_u)
        frame_v = np.cross(nrm, frame_u)
        # convex faces are fanned here, by face size at once; the core triangulates the rest
        sizes_m = np.array([len(faces[k]) for k in members])
        tris, owner, rest = [], [], []
        for m in sorted_unique(sizes_m):
            ks = members[sizes_m == m]
            p = vertices[np.array([faces[k] for k in ks], dtype=np.int64)]  # (g, m, 3)
            e = np.roll(p, -1, axis=1) - p
            turn = np.einsum("gij,gj->gi", np.cross(e, np.roll(e, -1, axis=1)), normals[ks])
            convex = (turn > 0).all(axis=1) if m > 3 else np.ones(len(ks), dtype=bool)
            fan = np.stack([np.zeros(m - 2, np.int64), np.arange(1, m - 1), np.arange(2, m)], axis=1)
            tris.append(p[convex][:, fan].reshape(-1, 3, 3))
            owner.append(np.repeat(ks[convex], m - 2))
            rest.extend(ks[~convex].tolist())
        for k in rest:
            t = np.asarray(triangulate(int(k)), dtype=np.int64).reshape(-1, 3)
            tris.append(vertices[faces[k]][t])
            owner.append(np.full(len(t), k))
        t3 = np.concatenate(tris)
        own = np.concatenate(owner)
        t2 = np.stack([t3 @ frame_u, t3 @ frame_v], axis=2)
        lo, hi = t2.min(axis=1) + eps, t2.max(axis=1) - eps
        a, b = _pairs_in_sweep(lo, hi)
        diff = own[a] != own[b]
        a, b = a[diff], b[diff]
        hit = _sat_overlap(t2[a], t2[b], eps)
        for x, y in zip(a[hit].tolist(), b[hit].tolist()):
            i, j = int(own[x]), int(own[y])
            found.setdefault((min(i, j), max(i, j)), []).append((t2[x], t2[y]))
    out = []
    for (i, j), parts in sorted(found.items()):
        # in one plane: every vertex of each within eps of the other's plane (the groups above
        # are coarser, 1e-8 of the scene's size in offset)
        if any(np.abs((vertices[faces[q]] - centroids[p]) @ normals[p]).max() > eps for p, q in ((i, j), (j, i))):
            continue
        area = 0.0
        for p, q in parts:
            p = p if _planar.signed_area_2d(p) > 0 else p[::-1]
            q = q if _planar.signed_area_2d(q) > 0 else q[::-1]
            area += _planar.convex_intersection_area(p, q)
        out.append((i, j, area))
    return out
