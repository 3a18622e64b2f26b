"""Mean radiant temperature in an office in winter, from a room file to a comfort map.

What it shows (for building / thermal-comfort engineers):

1. A 5 x 4 x 2.7 m office written as an OBJ file (one object per named surface), in a
   temporary directory: a cold window and a warm radiator panel in the south wall, two desks
   and a cabinet standing in the room (they block views and take part in the exchange).
2. The surface temperatures (K) and emissivities, and the grey-body exchange between the
   surfaces (``nusselt.exchange.solve`` on the surface-level form factors): the net radiant
   heat flow of every surface (W) and its radiosity J (W/m2).
3. The mean radiant temperature on a 0.25 m grid at 1.1 m (the head height of a seated
   person and the abdomen of a standing one, ISO 7726's reference height for both), obstructed
   by the furniture, in two forms: a small black sphere (exact angle factors: the visible
   solid angle of every surface over 4 pi) and ISO 7726's six plane radiant temperatures
   weighted for a seated person facing the window.

Grey surfaces reflect: a sensor receives the radiosity J_j of each surface, not sigma T_j^4, so
the radiant temperatures use each surface's effective temperature (J_j / sigma)^(1/4) (its
surface average). With every emissivity 1 these are the surface temperatures.

Run (a few seconds on two cores):

    python examples/room_mrt.py                    # outputs go to a new temporary directory
    python examples/room_mrt.py --outdir results   # or to a directory of your choice
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np

import nusselt
from nusselt import exchange, sensors

# name: (temperature K, emissivity)
SURFACES = {
    "floor": (294.0, 0.90),
    "ceiling": (294.5, 0.90),
    "wall_south": (290.0, 0.90),
    "wall_north": (293.0, 0.90),
    "wall_west": (293.0, 0.90),
    "wall_east": (293.0, 0.90),
    "window": (279.0, 0.84),
    "radiator": (323.0, 0.95),
    "desks": (294.0, 0.85),
    "cabinet": (293.5, 0.85),
}


def rect(p0, u, v):
    p0, u, v = (np.asarray(x, float) for x in (p0, u, v))
    return np.array([p0, p0 + u, p0 + u + v, p0 + v])


def box(lo, hi):
    """The five visible faces of a box standing on the floor (fronts outwards, no bottom)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    dx, dy, dz = x1 - x0, y1 - y0, z1 - z0
    return [
        rect([x0, y0, z1], [dx, 0, 0], [0, dy, 0]),
        rect([x0, y0, z0], [dx, 0, 0], [0, 0, dz]),
        rect([x0, y1, z0], [0, 0, dz], [dx, 0, 0]),
        rect([x0, y0, z0], [0, 0, dz], [0, dy, 0]),
        rect([x1, y0, z0], [0, dy, 0], [0, 0, dz]),
    ]


#: (x0, x1, y0, y1) of the desks and the cabinet: cut out of the floor, which they hide
FOOTPRINTS = [(0.8, 2.2, 1.2, 2.0), (2.8, 4.2, 1.2, 2.0), (3.6, 4.8, 3.4, 3.9)]


def floor_around(length: float, width: float, holes) -> list[np.ndarray]:
    """The floor (facing up) as the rectangles of the grid through the footprints' edges that
    lie outside every footprint: the room stays a closed enclosure."""
    xs = sorted({0.0, length, *[v for h in holes for v in h[:2]]})
    ys = sorted({0.0, width, *[v for h in holes for v in h[2:]]})
    cells = []
    for x0, x1 in zip(xs, xs[1:]):
        for y0, y1 in zip(ys, ys[1:]):
            cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
            if not any(a < cx < b and c < cy < d for a, b, c, d in holes):
                cells.append(rect([x0, y0, 0], [x1 - x0, 0, 0], [0, y1 - y0, 0]))
    return cells


def office() -> dict[str, list[np.ndarray]]:
    """Named surfaces of the office, every front facing into the room (x east, y north, z up)."""
    L, W, H = 5.0, 4.0, 2.7
    s = {
        "floor": floor_around(L, W, FOOTPRINTS),
        "ceiling": [rect([0, 0, H], [0, W, 0], [L, 0, 0])],
        "wall_north": [rect([0, W, 0], [L, 0, 0], [0, 0, H])],
        "wall_west": [rect([0, 0, 0], [0, W, 0], [0, 0, H])],
        "wall_east": [rect([L, 0, 0], [0, 0, H], [0, W, 0])],
        # the south wall (y = 0, facing +y) around a 3 x 1.5 m window and a 2 x 0.5 m radiator below it
        "window": [rect([1.0, 0, 0.9], [0, 0, 1.5], [3.0, 0, 0])],
        "radiator": [rect([1.5, 0, 0.15], [0, 0, 0.5], [2.0, 0, 0])],
        "wall_south": [
            rect([0, 0, 0], [0, 0, H], [1.0, 0, 0]),
            rect([4.0, 0, 0], [0, 0, H], [1.0, 0, 0]),
            rect([1.0, 0, 2.4], [0, 0, 0.3], [3.0, 0, 0]),
            rect([1.0, 0, 0], [0, 0, 0.9], [0.5, 0, 0]),
            rect([3.5, 0, 0], [0, 0, 0.9], [0.5, 0, 0]),
            rect([1.5, 0, 0.65], [0, 0, 0.25], [2.0, 0, 0]),
            rect([1.5, 0, 0], [0, 0, 0.15], [2.0, 0, 0]),
        ],
        # two desks as solid blocks 0.75 m high, and a cabinet by the north wall
        "desks": box((0.8, 1.2, 0), (2.2, 2.0, 0.75)) + box((2.8, 1.2, 0), (4.2, 2.0, 0.75)),
        "cabinet": box((3.6, 3.4, 0), (4.8, 3.9, 1.9)),  # keep FOOTPRINTS in step
    }
    return s


def write_obj(path: str, surfaces: dict[str, list[np.ndarray]]) -> None:
    lines, k = [], 1
    for name, polys in surfaces.items():
        lines.append(f"o {name}")
        for p in polys:
            lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in p]
            lines.append("f " + " ".join(str(k + i) for i in range(len(p))))
            k += len(p)
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--outdir", help="directory for the outputs (default: a new temporary directory)")
    ap.add_argument("--spacing", type=float, default=0.25, help="grid spacing of the MRT map, m (default 0.25)")
    a = ap.parse_args()
    outdir = a.outdir or tempfile.mkdtemp(prefix="nusselt-room-mrt-")
    os.makedirs(outdir, exist_ok=True)
    t0 = time.perf_counter()

    # 1. the room file, read back as a scene of named surfaces
    path = os.path.join(outdir, "office.obj")
    write_obj(path, office())
    scene = nusselt.Scene.from_file(path)
    print(f"{path}: {len(scene)} polygons, surfaces {', '.join(scene.surface_names)}")

    # 2. grey-body exchange between the surfaces
    ff = nusselt.form_factors(scene).by_surface()
    names = list(ff.names)
    temp = np.array([SURFACES[n][0] for n in names])
    eps = np.array([SURFACES[n][1] for n in names])
    ex = exchange.solve(ff, eps, temperature=temp)
    print(f"\nform factors: closure {ff.closure_error:.1e}, reciprocity {ff.reciprocity_error:.1e}")
    print(f"{'surface':12s} {'T (K)':>7s} {'eps':>5s} {'area m2':>8s} {'J W/m2':>8s} {'T_eff K':>8s} {'Q (W)':>9s}")
    t_eff = (ex.radiosity / exchange.SIGMA) ** 0.25
    for k, n in enumerate(names):
        print(
            f"{n:12s} {temp[k]:7.1f} {eps[k]:5.2f} {ff.areas[k]:8.2f} {ex.radiosity[k]:8.1f} {t_eff[k]:8.2f} {ex.heat[k]:9.1f}"
        )
    print(f"sum of Q: {ex.heat.sum():.2e} W (a closed room: 0 up to the rows' closure error)")

    # 3. the MRT map at 1.1 m, points inside the cabinet left out
    h = a.spacing
    xs, ys = np.arange(h / 2, 5.0, h), np.arange(h / 2, 4.0, h)
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    pts = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, 1.1)])
    x0, x1, y0, y1 = FOOTPRINTS[2]
    inside = (pts[:, 0] > x0) & (pts[:, 0] < x1) & (pts[:, 1] > y0) & (pts[:, 1] < y1)
    pts = pts[~inside]
    effective = dict(zip(names, t_eff))
    t1 = time.perf_counter()
    mrt_sphere = sensors.mean_radiant_temperature(pts, scene, effective)
    # a seated person facing the window (south, -y), ISO 7726 Annex B weights
    mrt_seated = sensors.mean_radiant_temperature(pts, scene, effective, form="seated", front=(0, -1, 0))
    tpr = sensors.plane_radiant_temperatures(pts, scene, effective, front=(0, -1, 0))
    t2 = time.perf_counter()
    asym = tpr["front"] - tpr["back"]
    out = os.path.join(outdir, "mrt_map.csv")
    np.savetxt(
        out,
        np.column_stack([pts, mrt_sphere, mrt_seated, tpr["front"], tpr["back"]]),
        delimiter=",",
        header="x,y,z,t_mrt_sphere,t_mrt_seated,t_pr_front,t_pr_back",
        comments="",
        fmt="%.6f",
    )
    print(
        f"\nMRT at 1.1 m on {len(pts)} points ({t2 - t1:.1f} s): sphere {mrt_sphere.min() - 273.15:.2f} .. "
        f"{mrt_sphere.max() - 273.15:.2f} C, seated (ISO 7726) {mrt_seated.min() - 273.15:.2f} .. {mrt_seated.max() - 273.15:.2f} C"
    )
    k = int(np.argmax(np.abs(asym)))
    print(
        f"largest radiant asymmetry front/back (towards the window): {asym[k]:.2f} K at x={pts[k, 0]:.2f}, y={pts[k, 1]:.2f}"
    )
    # a coarse text map of the sphere MRT (rows: north at the top)
    grid = np.full(gx.shape, np.nan)
    idx = np.flatnonzero(~inside)
    grid.ravel()[idx] = mrt_sphere - 273.15
    print("\nsphere MRT (C), north at the top, window at the bottom:")
    for j in range(len(ys) - 1, -1, -2):
        print(" ".join("  -- " if np.isnan(v) else f"{v:5.1f}" for v in grid[::2, j]))
    print(f"\nwrote {out} ({time.perf_counter() - t0:.1f} s in all)")


if __name__ == "__main__":
    main()
