"""Accuracy versus CPU time of the obstructed path on the scenes of bench/scenes.py.

Each run prints the scene, the options, CPU time of the computation (user + sys of this
process, so run with RAYON_NUM_THREADS=1 for one core's CPU), wall time, the work units spent
(point evaluations times the blockers they cast, ray tests, ...: the same on a busy machine as
on an idle one, so two builds compare by them when CPU times are noisy), and the accuracy
against the scene's reference:
- building, office (closed): max |row sum - 1| (and reciprocity);
- blocked cylinder: |F(inner -> sphere) - (1 - F(inner -> outer))| and inner row sums;
- blocker plates: |F(lower -> upper) - exact| (dblquad) and the largest element-pair error
  against `clipping` at tol 1e-11 on a sample of pairs;
- urban: the largest error of a sample of pairs against `clipping` at tol 1e-10 with every
  other polygon an obstacle.

    RAYON_NUM_THREADS=1 python bench/obstructed_scenes.py building --obstructed-tol 1e-3
    RAYON_NUM_THREADS=1 python bench/obstructed_scenes.py plates --mesh 10x8 --triangles
    RAYON_NUM_THREADS=2 python bench/obstructed_scenes.py urban --k 6 --obstructed-tol 1e-3
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import scenes  # noqa: E402

import nusselt  # noqa: E402


def run(spec: scenes.Spec, method: str, opts: dict):
    scene = spec.scene()
    c0, t0, u0 = time.process_time(), time.perf_counter(), nusselt._core.work_units()
    res = nusselt.form_factors(scene, method=method, **opts)
    return scene, res, time.process_time() - c0, time.perf_counter() - t0, nusselt._core.work_units() - u0


def dense(res):
    m = res.matrix
    return m.toarray() if hasattr(m, "toarray") else np.asarray(m)


def sample_pair_error(spec: scenes.Spec, F: np.ndarray, recv: np.ndarray, pairs: list[tuple[int, int]], tol: float):
    """Largest |F_ij - reference| over `pairs` (scene polygon ids), the reference by
    `clipping` at `tol` with every other polygon as obstacle."""
    col = {int(k): c for c, k in enumerate(recv)}
    worst = 0.0
    for i, j in pairs:
        obs = [p for k, p in enumerate(spec.polygons) if k not in (i, j)]
        ref = nusselt.view_factor(spec.polygons[i], spec.polygons[j], obstacles=obs, method="clipping", tol=tol)
        worst = max(worst, abs(F[col[i], col[j]] - ref))
    return worst


def obstructed_sample(F: np.ndarray, free_fn, recv, n: int, rng) -> list[tuple[int, int]]:
    nz = np.argwhere(F > 1e-6)
    pick = nz[rng.choice(len(nz), size=min(n, len(nz)), replace=False)]
    return [(int(recv[a]), int(recv[b])) for a, b in pick]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene", choices=["building", "office", "cylinder", "plates", "urban"])
    p.add_argument("--method", default="auto")
    p.add_argument("--obstructed-tol", type=float, default=None)
    p.add_argument("--tol", type=float, default=None, help="clipping's tol")
    p.add_argument("--source", default=None)
    p.add_argument("--mesh", default="10x8", help="plates: nx x ny per plate")
    p.add_argument("--triangles", action="store_true", help="plates: triangles instead of quads")
    p.add_argument("--k", type=int, default=6, help="urban: 144 k^2 patches")
    p.add_argument("--sample", type=int, default=60, help="pairs checked against a tight reference")
    a = p.parse_args()
    opts = {}
    if a.obstructed_tol is not None:
        opts["obstructed_tol"] = a.obstructed_tol
    if a.tol is not None:
        opts["tol"] = a.tol
    if a.source is not None:
        opts["source"] = a.source if a.source in ("centre", "adaptive", "auto") else int(a.source)
    if a.scene == "building":
        spec = scenes.building()
    elif a.scene == "office":
        spec = scenes.office()
    elif a.scene == "cylinder":
        spec = scenes.blocked_cylinder()
    elif a.scene == "plates":
        n = tuple(int(x) for x in a.mesh.split("x"))
        spec = scenes.blocker_plates(n, triangles=a.triangles)
    else:
        spec = scenes.urban(a.k)
    scene, res, c, w, units = run(spec, a.method, opts)
    F = dense(res)
    recv = np.asarray(res.receivers) if hasattr(res, "receivers") else scene.receivers
    threads = os.environ.get("RAYON_NUM_THREADS", "all")
    head = f"{spec.name} ({len(scene)} polygons) {a.method} {opts or 'default'} threads={threads}: cpu {c:.2f} s, wall {w:.2f} s, {units / 1e6:.2f} M work units"
    rows = F.sum(axis=1)
    if spec.closed:
        print(f"{head}; max |row sum - 1| = {np.abs(rows - 1).max():.2e}, reciprocity {res.reciprocity_error:.1e}")
    elif a.scene == "cylinder":
        s = res.by_surface()
        f = s.dense() if hasattr(s, "dense") else s.matrix
        i, o, k = (list(s.names).index(x) for x in ("inner", "outer", "sphere"))
        inner = np.array([sf == "inner" for sf in np.asarray(spec.surface)[recv]])
        print(
            f"{head}; identity error {abs(f[i, k] - (1 - f[i, o])):.2e}, "
            f"inner max |row sum - 1| = {np.abs(rows[inner] - 1).max():.2e}"
        )
    elif a.scene == "plates":
        surf = np.asarray(spec.surface)[recv]
        lo, hi = surf == "lower", surf == "upper"
        area = scene.areas[recv]
        g = (area[lo, None] * F[np.ix_(lo, hi)]).sum()
        err = abs(g - scenes.blocker_plates_exact())
        rng = np.random.default_rng(1)
        pairs = [
            (int(recv[i]), int(recv[j]))
            for i, j in zip(rng.choice(np.flatnonzero(lo), a.sample), rng.choice(np.flatnonzero(hi), a.sample))
        ]
        pe = sample_pair_error(spec, F, recv, pairs, 1e-11)
        print(
            f"{head}; {spec.meta['pairs'] * 2} element pairs (ordered); plate F error {err:.2e}, "
            f"largest element-pair error of {len(pairs)} {pe:.2e}"
        )
    else:
        rng = np.random.default_rng(1)
        pairs = obstructed_sample(F, None, recv, a.sample, rng)
        pe = sample_pair_error(spec, F, recv, pairs, 1e-10)
        print(f"{head}; largest error of {len(pairs)} sampled pairs {pe:.2e}; max row sum {rows.max():.6f}")


if __name__ == "__main__":
    main()
