"""Accuracy versus time of every method with visibility, on two obstructed problems with exact
answers, plus full-scene throughput on a box room with an inner box.

Problems (unit squares at z = 0 facing up and z = 1 facing down, one opaque axis-aligned
rectangle parallel to them at height h): from a point (x, y, 0) the blocker's shadow on the
receiver plane is again a rectangle, so the visible F is exact by superposition of Howell's
corner formula; integrating that over the emitter with scipy's adaptive dblquad (to 1e-12)
gives the exact answer independently of nusselt.

    python bench/obstructed.py            # the table; --room N for the room (default 8 per wall)
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np
from scipy.integrate import dblquad

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tests"))
from conftest import parallel_rect, rect  # noqa: E402  (Howell's corner formula, shared with the tests)

import nusselt  # noqa: E402


def exact(blocker, h):
    bx0, bx1, by0, by1 = blocker

    def f(y, x):
        sx0, sx1 = max(0.0, x + (bx0 - x) / h), min(1.0, x + (bx1 - x) / h)
        sy0, sy1 = max(0.0, y + (by0 - y) / h), min(1.0, y + (by1 - y) / h)
        sh = parallel_rect(x, y, sx0, sx1, sy0, sy1, 1.0) if sx1 > sx0 and sy1 > sy0 else 0.0
        return parallel_rect(x, y, 0, 1, 0, 1, 1.0) - sh

    return dblquad(f, 0, 1, 0, 1, epsabs=1e-13, epsrel=1e-12)[0]


PROBLEMS = {
    "centred square h=0.5": ((0.25, 0.75, 0.25, 0.75), 0.5),
    "half-plane slab h=0.3": ((0.5, 3.0, -2.0, 3.0), 0.3),
}

SETTINGS = {
    "clipping": [{"tol": t} for t in (1e-4, 1e-6, 1e-8, 1e-10)],
    "auto": [{}],
    "quadrature": [{"order": k} for k in (2, 4, 8, 16, 24)],
    "montecarlo": [{"samples": n} for n in (256, 1024, 4096, 16384, 65536)],
    "subdivision": [{"divisions": d} for d in (4, 8, 16, 32)],
    "adaptive": [{"tol": t} for t in (1e-3, 1e-4, 1e-5, 1e-6)],
}


def table() -> None:
    print(f"{'problem':24s} {'method':12s} {'setting':18s} {'F':>14s} {'abs error':>10s} {'ms/pair':>9s}")
    for name, (blk, h) in PROBLEMS.items():
        ref = exact(blk, h)
        a, b = rect(0, 1, 0, 1, 0), rect(0, 1, 0, 1, 1, flip=True)
        obs = [rect(blk[0], blk[1], blk[2], blk[3], h)]
        print(f"{name:24s} {'exact':12s} {'dblquad':18s} {ref:14.10f}")
        for method, settings in SETTINGS.items():
            for s in settings:
                reps, t0 = 0, time.perf_counter()
                while True:
                    f = nusselt.view_factor(a, b, obstacles=obs, method=method, **s)
                    reps += 1
                    if time.perf_counter() - t0 > 0.2:
                        break
                ms = (time.perf_counter() - t0) / reps * 1e3
                label = ",".join(f"{k}={v}" for k, v in s.items()) or "default"
                print(f"{'':24s} {method:12s} {label:18s} {f:14.10f} {abs(f - ref):10.2e} {ms:9.3f}", flush=True)


def room(n: int, method: str, tol: float | None = None, source: str | None = None) -> None:
    from nusselt.scene import Scene

    polys = []
    for size, offset, inward in ((3.0, np.zeros(3), True), (1.0, np.array([0.8, 0.7, 1.1]), False)):
        t = np.linspace(0.0, size, (n if inward else max(2, n // 3)) + 1)
        for axis in range(3):
            for side in (0.0, size):
                u, w = [k for k in range(3) if k != axis]
                normal = np.zeros(3)
                normal[axis] = (1.0 if side == 0.0 else -1.0) * (1 if inward else -1)
                for i in range(len(t) - 1):
                    for j in range(len(t) - 1):
                        q = np.zeros((4, 3))
                        for k, (di, dj) in enumerate([(0, 0), (1, 0), (1, 1), (0, 1)]):
                            q[k, axis], q[k, u], q[k, w] = side, t[i + di], t[j + dj]
                        if np.cross(q[1] - q[0], q[2] - q[0]) @ normal < 0:
                            q = q[::-1].copy()
                        polys.append(q + offset)
    scene = Scene.from_polygons(polys)
    t0 = time.perf_counter()
    kw = {} if tol is None else {"obstructed_tol" if method == "auto" else "tol": tol}
    if source is not None:
        kw["source"] = source if source in ("centre", "adaptive") else int(source)
    res = nusselt.form_factors(scene, method=method, **kw)
    dt = time.perf_counter() - t0
    print(
        f"room with inner box: {len(scene)} patches, method {method} {kw or 'default'}: {dt:.2f} s wall, "
        f"{len(scene) / dt:.0f} rows/s, max |row sum - 1| = {res.closure_error:.2e}, "
        f"reciprocity error = {res.reciprocity_error:.2e}"
    )


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--room", type=int, default=8, help="quads per room wall edge (0: skip)")
    p.add_argument("--room-method", default="auto")
    p.add_argument(
        "--room-tol",
        type=float,
        default=None,
        help="obstructed accuracy target of the room (auto: obstructed_tol, clipping: tol)",
    )
    p.add_argument(
        "--room-source",
        default=None,
        help="clipping only: source rule of obstructed pairs ('centre' or k for k x k Gauss points)",
    )
    p.add_argument("--no-table", action="store_true")
    a = p.parse_args()
    if not a.no_table:
        table()
    if a.room:
        room(a.room, a.room_method, a.room_tol, a.room_source)
