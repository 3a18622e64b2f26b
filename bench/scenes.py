"""Scene builders shared by the benchmarks: obstructed scenes with many blockers.

Every builder returns a :class:`Spec` (polygons, surface names, which polygons only block,
and what identity or reference checks it). Lengths are in metres; polygons are (n, 3)
float64 arrays, counter-clockwise seen from their front side, as the rest of nusselt.

- :func:`building`: a closed two-storey building (~400 surfaces): rooms, full and partial
  partitions, a hanging partition, window reveals with fins, a floor slab with a stair
  opening and a stair. Closed, so every row must sum to 1.
- :func:`office`: a closed furnished office (~2 000 patches): desks, shelves, cabinets and
  chairs as boxes. Closed.
- :func:`blocked_cylinder`: an open outer prism around an inner prism inside a faceted
  sphere (544 polygons); F(inner -> sphere) = 1 - F(inner -> outer) exactly.
- :func:`blocker_plates`: two parallel unit plates 1 apart, each meshed, and a centred
  opaque square at mid-height (OpenViewFactor's "blocking" family); the plate-to-plate F is
  known to 1e-12 by an independent dblquad (:func:`blocker_plates_exact`).
- :func:`room_with_crate`: a closed 3 m cube room, walls meshed n x n, with a unit crate
  floating inside, faces meshed m x m (n, m = 6, 3: 270 patches). Closed.
- :func:`urban`: ground plus a 4 x 4 grid of buildings, 160 k^2 patches (k = 4, 6, 12 give
  2 560, 5 760 and 23 040). Open.

The closed scenes are built as the boundary of the empty cells of a rectilinear cell grid
(:func:`cell_enclosure`): every face between an empty cell and a solid one (or the outside)
becomes one quad facing into the empty cell, so the enclosure is exactly closed whatever the
furniture, and objects standing on the floor need no special meshing.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

# the prism, the faceted sphere and Howell's corner formula are the tests' (tests/conftest.py)
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
from conftest import parallel_rect, prism, uv_sphere  # noqa: E402


@dataclass
class Spec:
    """A benchmark scene.

    polygons : the faces, (n, 3) arrays.
    surface : a surface name per face.
    obstruction : faces that only block (no row/column), or None.
    closed : True if the receivers form an enclosure (every row sums to 1).
    """

    name: str
    polygons: list[np.ndarray]
    surface: list[str]
    obstruction: np.ndarray | None = None
    closed: bool = False
    meta: dict = field(default_factory=dict)

    def scene(self):
        import nusselt

        return nusselt.Scene.from_polygons(self.polygons, surface=self.surface, obstruction=self.obstruction)


def quad(corners: Sequence[Sequence[float]], normal: Sequence[float]) -> np.ndarray:
    """A quad with the given corners (in order around it), turned to face along `normal`."""
    q = np.asarray(corners, dtype=np.float64)
    if np.cross(q[1] - q[0], q[2] - q[0]) @ np.asarray(normal, float) < 0:
        q = q[::-1].copy()
    return q


def rect_grid(origin, u, v, nu: int, nv: int, normal) -> list[np.ndarray]:
    """The parallelogram origin + s u + t v (s, t in [0, 1]) meshed nu x nv, facing `normal`."""
    o, u, v = (np.asarray(x, float) for x in (origin, u, v))
    out = []
    for i in range(nu):
        for j in range(nv):
            p = lambda a, b: o + u * (a / nu) + v * (b / nv)
            out.append(quad([p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)], normal))
    return out


def cell_enclosure(xs, ys, zs, solid: Callable[[float, float, float], bool], max_edge: float = np.inf):
    """The boundary of the empty cells of the grid xs x ys x zs (cell centres tested by
    `solid`; outside the grid counts as solid), facing into the empty cells. The cell faces
    of one plane are merged greedily into rectangles, each then split evenly into pieces no
    longer than `max_edge`. Surfaces are named by the direction a face looks. Returns
    (polygons, surface names)."""
    g = [np.asarray(xs, float), np.asarray(ys, float), np.asarray(zs, float)]
    shape = tuple(len(a) - 1 for a in g)
    centres = [0.5 * (a[1:] + a[:-1]) for a in g]
    full = np.ones(tuple(s + 2 for s in shape), dtype=bool)  # padded: outside is solid
    for i, cx in enumerate(centres[0]):
        for j, cy in enumerate(centres[1]):
            for k, cz in enumerate(centres[2]):
                full[i + 1, j + 1, k + 1] = bool(solid(cx, cy, cz))
    names = {(0, 1): "x-", (0, -1): "x+", (1, 1): "y-", (1, -1): "y+", (2, 1): "floor", (2, -1): "ceiling"}
    polys, surf = [], []
    empty = ~full[1:-1, 1:-1, 1:-1]
    for axis in range(3):
        u, w = [a for a in range(3) if a != axis]
        for step in (-1, 1):
            # empty cell c with a solid neighbour c + step e_axis: a face on their shared
            # plane, normal -step e_axis (into c)
            sl = [slice(1, -1)] * 3
            sl[axis] = slice(1 + step, full.shape[axis] - 1 + step)
            faces = empty & full[tuple(sl)]
            n = np.zeros(3)
            n[axis] = -step
            for layer in range(shape[axis]):
                mask = np.moveaxis(faces, axis, 0)[layer].copy()  # indexed [u, w]
                plane = g[axis][layer + 1] if step == 1 else g[axis][layer]
                for a0, b0 in zip(*np.nonzero(mask)):
                    if not mask[a0, b0]:
                        continue
                    a1 = a0
                    while a1 + 1 < mask.shape[0] and mask[a1 + 1, b0]:
                        a1 += 1
                    b1 = b0
                    while b1 + 1 < mask.shape[1] and mask[a0 : a1 + 1, b1 + 1].all():
                        b1 += 1
                    mask[a0 : a1 + 1, b0 : b1 + 1] = False
                    lo_u, hi_u, lo_w, hi_w = g[u][a0], g[u][a1 + 1], g[w][b0], g[w][b1 + 1]
                    nu = max(1, int(np.ceil((hi_u - lo_u) / max_edge - 1e-9)))
                    nw = max(1, int(np.ceil((hi_w - lo_w) / max_edge - 1e-9)))
                    o, du, dw = np.zeros(3), np.zeros(3), np.zeros(3)
                    o[axis], o[u], o[w] = plane, lo_u, lo_w
                    du[u], dw[w] = hi_u - lo_u, hi_w - lo_w
                    pieces = rect_grid(o, du, dw, nu, nw, n)
                    polys += pieces
                    surf += [names[(axis, -step)]] * len(pieces)
    return polys, surf


def _in(p, lo, hi) -> bool:
    return all(l < x < h for x, l, h in zip(p, lo, hi))


def building(max_edge: float = 2.5) -> Spec:
    """A closed two-storey building, 12 x 8 x 6.2 m (~400 surfaces at the default max_edge).

    Ground floor: three rooms split by a full partition with a door and a partition 1.2 m
    high; upper floor: a hanging partition (from 1.2 m below the ceiling up) and a partition
    2.1 m high. A 0.2 m slab between storeys with a stair opening and a 10-step stair under
    it; window reveals 0.3 m deep in the south and north walls, with a vertical fin in each.
    """
    W, D, H, slab = 12.0, 8.0, 6.2, (3.0, 3.2)
    wall = 0.3  # exterior wall thickness: windows are recesses into it
    windows_x = [(1.0, 2.6), (4.6, 6.2), (8.2, 9.8)]
    win_z = [(0.9, 2.3), (4.1, 5.5)]
    fin = 0.1  # fin thickness, centred in each window
    stair = (9.4, 11.7, 0.3, 1.5)  # x0, x1, y0, y1 of the stair and opening
    steps = 10
    part = [  # (x0, x1, y0, y1, z0, z1) partitions
        (4.0, 4.12, wall, D - wall, 0.0, slab[0]),  # full, door cut below
        (7.5, 7.62, wall, D - wall, 0.0, 1.2),  # low partition
        (wall, 6.0, 4.0, 4.12, slab[1] + 1.8, H),  # hanging partition, upper floor
        (8.0, 8.12, 3.0, D - wall, slab[1], slab[1] + 2.1),  # 2.1 m partition, upper floor
    ]
    door = (4.0, 4.12, 5.0, 6.0, 0.0, 2.1)

    def solid(x, y, z):
        p = (x, y, z)
        in_wall = x < wall or x > W - wall or y < wall or y > D - wall
        if in_wall:
            # window recesses in the south (y < wall) and north walls, fins left standing
            if y < wall or y > D - wall:
                for x0, x1 in windows_x:
                    for z0, z1 in win_z:
                        if x0 < x < x1 and z0 < z < z1:
                            xm = 0.5 * (x0 + x1)
                            return abs(x - xm) < fin / 2
            return True
        if slab[0] < z < slab[1]:
            return not (stair[0] < x < stair[1] and stair[2] < y < stair[3])
        if stair[0] < x < stair[1] and stair[2] < y < stair[3] and z < slab[0]:
            k = int((x - stair[0]) / (stair[1] - stair[0]) * steps)
            return z < (k + 1) * slab[0] / steps
        if _in(p, door[0::2], door[1::2]):
            return False
        return any(_in(p, b[0::2], b[1::2]) for b in part)

    feats_x = [0, wall, W - wall, W, stair[0], stair[1], door[0], door[1]]
    for x0, x1 in windows_x:
        xm = 0.5 * (x0 + x1)
        feats_x += [x0, x1, xm - fin / 2, xm + fin / 2]
    feats_x += [v for b in part for v in b[:2]]
    feats_x += list(np.linspace(stair[0], stair[1], steps + 1))
    feats_y = [0, wall, D - wall, D, stair[2], stair[3], door[2], door[3]] + [v for b in part for v in b[2:4]]
    feats_z = [0, H, *slab, door[5]] + [v for b in part for v in b[4:]] + [z for w in win_z for z in w]
    feats_z += list(np.linspace(0, slab[0], steps + 1))
    xs, ys, zs = (np.unique(np.round(f, 12)) for f in (feats_x, feats_y, feats_z))
    polys, surf = cell_enclosure(xs, ys, zs, solid, max_edge)
    return Spec("building", polys, surf, closed=True, meta={"grid": (len(xs), len(ys), len(zs))})


def office(max_edge: float = 0.36) -> Spec:
    """A closed office 8 x 6 x 3 m furnished with boxes (~2 000 patches at the default max_edge):
    six desks (tops on legs-free pedestals), four chairs, two shelves and a cabinet."""
    W, D, H = 8.0, 6.0, 3.0
    boxes = []
    for i in range(3):
        for j in range(2):
            x0, y0 = 1.0 + 2.3 * i, 1.0 + 2.4 * j
            boxes.append((x0, x0 + 1.6, y0, y0 + 0.8, 0.7, 0.75))  # desk top
            boxes.append((x0, x0 + 0.4, y0, y0 + 0.8, 0.0, 0.7))  # pedestal
            if (i + j) % 2 == 0:
                boxes.append((x0 + 0.6, x0 + 1.1, y0 + 1.0, y0 + 1.5, 0.0, 0.45))  # chair seat
                boxes.append((x0 + 0.6, x0 + 1.1, y0 + 1.45, y0 + 1.5, 0.45, 1.0))  # chair back
    boxes.append((0.1, 2.1, D - 0.45, D - 0.05, 0.0, 2.0))  # shelf
    boxes.append((4.0, 6.0, D - 0.45, D - 0.05, 0.0, 1.2))  # low shelf
    boxes.append((W - 0.65, W - 0.05, 0.5, 1.7, 0.0, 1.0))  # cabinet

    def solid(x, y, z):
        return any(_in((x, y, z), b[0::2], b[1::2]) for b in boxes)

    xs = np.unique([0, W] + [v for b in boxes for v in b[:2]])
    ys = np.unique([0, D] + [v for b in boxes for v in b[2:4]])
    zs = np.unique([0, H] + [v for b in boxes for v in b[4:]])
    polys, surf = cell_enclosure(xs, ys, zs, solid, max_edge)
    return Spec("office", polys, surf, closed=True, meta={"grid": (len(xs), len(ys), len(zs))})


def blocked_cylinder(sides: int = 16, rings: int = 4, nu: int = 32, nv: int = 13) -> Spec:
    """Inner prism (radius 0.125, outward) inside an open outer prism (0.25, inward) inside a
    sphere of radius 3 (inward): 2 * 16 * 4 + 32 * 13 = 544 polygons. What leaves the inner
    walls reaches the outer walls or escapes through the open ends to the sphere, so
    F(inner -> sphere) = 1 - F(inner -> outer), and every inner row sums to 1."""
    inner = prism(0.125, sides, inward=False, rings=rings)
    outer = prism(0.25, sides, inward=True, rings=rings)
    sphere = uv_sphere(3.0, nu, nv, (0.0, 0.0, 0.5))
    surf = ["inner"] * len(inner) + ["outer"] * len(outer) + ["sphere"] * len(sphere)
    return Spec("blocked cylinder", inner + outer + sphere, surf)


BLOCKER = (0.25, 0.75, 0.25, 0.75, 0.5)  # x0, x1, y0, y1, height of the centred blocker


def blocker_plates(n_lower: tuple[int, int], n_upper: tuple[int, int] | None = None, triangles: bool = False) -> Spec:
    """Unit plates at z = 0 (facing up) and z = 1 (facing down) meshed nx x ny quads each (or
    twice as many triangles), and the opaque square BLOCKER (obstruction only) between."""
    n_upper = n_upper or n_lower

    def plate(n, z, up):
        qs = rect_grid((0, 0, z), (1, 0, 0), (0, 1, 0), n[0], n[1], (0, 0, 1 if up else -1))
        if not triangles:
            return qs
        return [t for q in qs for t in (q[[0, 1, 2]], q[[0, 2, 3]])]

    lo, hi = plate(n_lower, 0.0, True), plate(n_upper, 1.0, False)
    x0, x1, y0, y1, h = BLOCKER
    blk = quad([(x0, y0, h), (x1, y0, h), (x1, y1, h), (x0, y1, h)], (0, 0, -1))
    polys = lo + hi + [blk]
    obstruction = np.zeros(len(polys), bool)
    obstruction[-1] = True
    surf = ["lower"] * len(lo) + ["upper"] * len(hi) + ["blocker"]
    return Spec("blocker plates", polys, surf, obstruction=obstruction, meta={"pairs": len(lo) * len(hi)})


def blocker_plates_point(x: float, y: float) -> float:
    """The visible F from (x, y, 0) to the upper plate: the blocker's shadow on z = 1 is a
    rectangle, so it is the unobstructed F minus the shadow's (superposition)."""
    bx0, bx1, by0, by1, h = BLOCKER
    sx0, sx1 = max(0.0, x + (bx0 - x) / h), min(1.0, x + (bx1 - x) / h)
    sy0, sy1 = max(0.0, y + (by0 - y) / h), min(1.0, y + (by1 - y) / h)
    sh = parallel_rect(x, y, sx0, sx1, sy0, sy1, 1.0) if sx1 > sx0 and sy1 > sy0 else 0.0
    return parallel_rect(x, y, 0, 1, 0, 1, 1.0) - sh


def blocker_plates_exact() -> float:
    """F(lower plate -> upper plate) with the blocker, by scipy's dblquad to 1e-12."""
    from scipy.integrate import dblquad

    return dblquad(lambda y, x: blocker_plates_point(x, y), 0, 1, 0, 1, epsabs=1e-13, epsrel=1e-12)[0]


def room_with_crate(n: int = 6, m: int = 3) -> Spec:
    """The cube room [0, 3]^3 with walls of n x n quads facing in and the crate
    [0.8, 1.8] x [0.7, 1.7] x [1.1, 2.1] floating inside, faces of m x m quads facing out:
    6 (n^2 + m^2) patches (270 at the default). Every crate face sees the room and hides part
    of the walls from each other. Surfaces: the six walls and the six crate faces."""
    polys: list[np.ndarray] = []
    surf: list[str] = []

    def box(lo, size, k, inward, prefix):
        lo = np.asarray(lo, float)
        for axis in range(3):
            u, v = (np.eye(3)[a] * size for a in range(3) if a != axis)
            for side in (0, 1):
                origin = lo + np.eye(3)[axis] * size * side
                out = np.eye(3)[axis] * (1 if side else -1)
                faces = rect_grid(origin, u, v, k, k, -out if inward else out)
                polys.extend(faces)
                surf.extend([f"{prefix}{'xyz'[axis]}{'+' if side else '-'}"] * len(faces))

    box((0, 0, 0), 3.0, n, True, "wall ")
    box((0.8, 0.7, 1.1), 1.0, m, False, "crate ")
    return Spec("room with crate", polys, surf, closed=True, meta={"n": n, "m": m})


def urban(k: int = 6) -> Spec:
    """Ground [0, 8]^2 meshed 4k x 4k, and 16 buildings 1 x 1 x 2 m at (2i + 0.5, 2j + 0.5), roofs meshed
    k x k and walls k x 2k: 16 k^2 + 16 (k^2 + 8 k^2) = 160 k^2 patches (k = 4, 6, 12: 2 560, 5 760,
    23 040). The ground is one grid under everything (a site slab with buildings put on it; for
    k = 4m the walls stand on ground cell edges): the parts under a footprint see nothing, and
    the roofs, all in one plane above everything else, see nothing either. Open: rows sum to
    less than 1."""
    polys, surf = [], []
    g = rect_grid((0, 0, 0), (8, 0, 0), (0, 8, 0), 4 * k, 4 * k, (0, 0, 1))
    polys += g
    surf += ["ground"] * len(g)
    for i in range(4):
        for j in range(4):
            x, y, h = 2.0 * i + 0.5, 2.0 * j + 0.5, 2.0
            name = f"b{i}{j}"
            faces = rect_grid((x, y, h), (1, 0, 0), (0, 1, 0), k, k, (0, 0, 1))
            faces += rect_grid((x, y, 0), (1, 0, 0), (0, 0, h), k, 2 * k, (0, -1, 0))
            faces += rect_grid((x, y + 1, 0), (1, 0, 0), (0, 0, h), k, 2 * k, (0, 1, 0))
            faces += rect_grid((x, y, 0), (0, 1, 0), (0, 0, h), k, 2 * k, (-1, 0, 0))
            faces += rect_grid((x + 1, y, 0), (0, 1, 0), (0, 0, h), k, 2 * k, (1, 0, 0))
            polys += faces
            surf += [name] * len(faces)
    return Spec(f"urban k={k}", polys, surf, meta={"k": k})


if __name__ == "__main__":
    for s in (
        room_with_crate(),
        building(),
        office(),
        blocked_cylinder(),
        blocker_plates((20, 20)),
        urban(4),
        urban(6),
        urban(12),
    ):
        print(f"{s.name:18s} {len(s.polygons):6d} polygons {s.meta}")
