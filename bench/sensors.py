"""Sensor throughput: view factors from a grid of points to every patch of a furnished room.

The room is 6 x 5 x 3 m in tiles of `--tile` metres (0.25 m: 2016 patches), furnished with
tables (boxes whose tops are at 0.75 m), cabinets and a partition, every face a receiver and an
obstacle. Points: an n x n grid at 1.1 m (seated head height; those inside furniture left out), one normal each (up, or each of
the six ISO 7726 directions with --six).

    python bench/sensors.py                # 10 000 points facing up
    python bench/sensors.py --six          # the same grid, six directions (60 000 rows)
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import nusselt
from nusselt import sensors


def box(lo, hi, inward: bool):
    """The six faces of an axis-aligned box, fronts facing out (or in)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    faces = [
        [[x0, y0, z0], [x0, y1, z0], [x1, y1, z0], [x1, y0, z0]],  # -z
        [[x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]],  # +z
        [[x0, y0, z0], [x1, y0, z0], [x1, y0, z1], [x0, y0, z1]],  # -y
        [[x0, y1, z0], [x0, y1, z1], [x1, y1, z1], [x1, y1, z0]],  # +y
        [[x0, y0, z0], [x0, y0, z1], [x0, y1, z1], [x0, y1, z0]],  # -x
        [[x1, y0, z0], [x1, y1, z0], [x1, y1, z1], [x1, y0, z1]],  # +x
    ]
    faces = [np.array(f, float) for f in faces]
    return [f[::-1].copy() for f in faces] if inward else faces


def tiles(face: np.ndarray, size: float):
    """A rectangle (4 vertices) split into tiles of at most `size`, same orientation."""
    a, b, d = face[0], face[1], face[3]
    nu = max(1, int(np.ceil(np.linalg.norm(b - a) / size - 1e-9)))
    nv = max(1, int(np.ceil(np.linalg.norm(d - a) / size - 1e-9)))
    u, v = (b - a) / nu, (d - a) / nv
    return [
        np.array([a + i * u + j * v, a + (i + 1) * u + j * v, a + (i + 1) * u + (j + 1) * v, a + i * u + (j + 1) * v])
        for i in range(nu)
        for j in range(nv)
    ]


NAMES = ["floor", "ceiling", "wall_south", "wall_north", "wall_west", "wall_east"]


FURNITURE = [
    ("table", (0.8, 0.8, 0.70), (2.0, 1.6, 0.75)),
    ("table", (3.0, 0.8, 0.70), (4.2, 1.6, 0.75)),
    ("table", (0.8, 3.0, 0.70), (2.0, 3.8, 0.75)),
    ("table", (3.0, 3.0, 0.70), (4.2, 3.8, 0.75)),
    ("cabinet", (5.4, 0.2, 0.0), (5.9, 1.4, 1.9)),
    ("cabinet", (5.4, 3.4, 0.0), (5.9, 4.6, 1.9)),
    ("partition", (2.7, 2.0, 0.0), (2.75, 3.0, 1.6)),
]


def outside_furniture(pts: np.ndarray) -> np.ndarray:
    """Mask of the points not inside a piece of furniture."""
    inside = np.zeros(len(pts), bool)
    for _, lo, hi in FURNITURE:
        inside |= np.all((pts > lo) & (pts < hi), axis=1)
    return ~inside


def furnished_room(tile: float = 0.25) -> nusselt.Scene:
    polys, surf = [], []
    for name, f in zip(NAMES, box((0, 0, 0), (6, 5, 3), inward=True)):
        for t in tiles(f, tile):
            polys.append(t)
            surf.append(name)
    for name, lo, hi in FURNITURE:
        for f in box(lo, hi, inward=False):
            polys.append(f)
            surf.append(name)
    return nusselt.Scene.from_polygons(polys, surface=surf)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--grid", type=int, default=100, help="points per side (default 100: 10 000 points)")
    ap.add_argument("--tile", type=float, default=0.25)
    ap.add_argument("--six", action="store_true", help="six ISO 7726 directions per point")
    ap.add_argument("--sphere", action="store_true", help="sphere sensors instead of plane elements")
    a = ap.parse_args()
    scene = furnished_room(a.tile)
    g = (np.arange(a.grid) + 0.5) / a.grid
    x, y = np.meshgrid(0.05 + 5.9 * g, 0.05 + 4.9 * g, indexing="ij")
    pts = np.column_stack([x.ravel(), y.ravel(), np.full(x.size, 1.1)])
    pts = pts[outside_furniture(pts)]
    if a.six:
        d = sensors.six_directions()
        normals = np.concatenate([np.repeat(d[k][None], len(pts), 0) for k in d])
        pts = np.tile(pts, (6, 1))
    else:
        normals = np.repeat([[0.0, 0.0, 1.0]], len(pts), 0)
    t0, c0 = time.perf_counter(), os.times()
    if a.sphere:
        f = sensors.sphere_view_factors(pts, scene)
    else:
        f = sensors.point_view_factors(pts, normals, scene)
    t1, c1 = time.perf_counter(), os.times()
    cpu = (c1.user - c0.user) + (c1.system - c0.system)
    rs = np.asarray(f.sum(axis=1)).ravel()
    print(
        f"{len(pts)} points x {len(scene)} patches ({'sphere' if a.sphere else 'plane'}): wall {t1 - t0:.2f} s, "
        f"CPU {cpu:.2f} s, nnz {f.nnz}, row sums {rs.min():.12f} .. {rs.max():.12f}"
    )


if __name__ == "__main__":
    main()
