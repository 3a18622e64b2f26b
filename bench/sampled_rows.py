"""Exact pairs or sampled rows: where would a hybrid ``auto`` pay?

A hybrid would compute some rows by ray sampling (``raytrace``) instead of exact pairs, where
that is cheaper at the same error. This script measures the two costs per row on one scene and
says, for per-entry targets eps, on how many rows sampling would be the cheaper way to reach
eps (max |F_ij - F_ij(exact)| over the row's entries).

- exact: ``form_factors(scene, method="auto", **EXACT)`` on the whole scene, one thread; its
  CPU divided by the number of rows is the exact cost per row (pair methods compute each
  unordered pair once, so this is the fair share of a row). Its result is the reference: its
  own error (about 1e-7 on the urban grid, docs/scale.md) is far below every eps here.
- sampled: the core's ``raytrace`` rows on s sample rows at 4 096 .. 1 048 576 rays per row,
  one thread; CPU per row and the max entry error of each row against the reference.

A row "pays" at eps if the cheapest ray count whose max entry error is <= eps costs less CPU
than the exact row. The error of one sampled row at N rays is measured, not predicted, so this
includes the max over a row's entries (an extreme of many binomial errors, about
sqrt(2 ln n) standard errors).

    RAYON_NUM_THREADS=1 python bench/sampled_rows.py              # urban(4), 2 560 patches
    RAYON_NUM_THREADS=1 python bench/sampled_rows.py --scene building
    RAYON_NUM_THREADS=1 python bench/sampled_rows.py --quick      # urban(2), fewer rays
"""

from __future__ import annotations

import argparse
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from scenes import building, urban  # noqa: E402

EXACT = {
    "urban": {"tol": 1e-3, "obstructed_tol": 1e-2},
    "building": {"tol": 1e-3, "obstructed_tol": 1e-3},
}
TARGETS = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4)


def sampled_rows(scene, rows: np.ndarray, rays: int) -> tuple[np.ndarray, float]:
    """Dense raytrace rows and the CPU seconds per row."""
    from nusselt.methods import resolve

    _, full = resolve("raytrace", {"rays": rays})
    c0 = time.process_time()
    ip, idx, val = scene._core.full_rows(rows.astype(np.int64), "raytrace", full)[:3]
    cpu = (time.process_time() - c0) / len(rows)
    dense = np.zeros((len(rows), len(scene)))
    for a in range(len(rows)):
        dense[a, idx[ip[a] : ip[a + 1]]] = val[ip[a] : ip[a + 1]]
    return dense, cpu


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", choices=sorted(EXACT), default="urban")
    ap.add_argument("--rows", type=int, default=64, help="sample rows")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()

    import nusselt

    spec = (urban(2 if args.quick else 4)) if args.scene == "urban" else building()
    scene = spec.scene()
    n = len(scene)
    c0 = time.process_time()
    ref = nusselt.form_factors(scene, method="auto", **EXACT[args.scene])
    exact_row = (time.process_time() - c0) / n
    dense_ref = ref.matrix
    rng = np.random.default_rng(1)
    rows = np.sort(rng.choice(n, min(args.rows, n), replace=False))
    fref = np.asarray(dense_ref[rows].toarray() if hasattr(dense_ref, "toarray") else dense_ref[rows])

    counts = [4096 << (2 * k) for k in range(2 if args.quick else 6)]
    err = np.empty((len(counts), len(rows)))
    cost = np.empty(len(counts))
    for c, rays in enumerate(counts):
        f, cost[c] = sampled_rows(scene, rows, rays)
        err[c] = np.abs(f - fref).max(axis=1)

    print(f"scene {args.scene}: {n} patches, exact auto {EXACT[args.scene]}: {exact_row * 1e3:.2f} ms CPU per row")
    print(f"max F per row (sample rows): median {np.median(fref.max(axis=1)):.2e}, max {fref.max():.2e}")
    print("\n| rays per row | CPU ms per row | rays/s | max entry error: median row | worst row |")
    print("|---:|---:|---:|---:|---:|")
    for c, rays in enumerate(counts):
        print(f"| {rays} | {cost[c] * 1e3:.2f} | {rays / cost[c]:.3g} | {np.median(err[c]):.2e} | {err[c].max():.2e} |")
    print("\n| target eps | rows where sampling is cheaper | sampled CPU / exact CPU (median row) |")
    print("|---:|---:|---:|")
    for eps in TARGETS:
        ratio = np.full(len(rows), np.inf)
        for a in range(len(rows)):
            ok = np.nonzero(err[:, a] <= eps)[0]
            if len(ok):
                ratio[a] = cost[ok[0]] / exact_row
        cheaper = int(np.sum(ratio < 1))
        med = np.median(ratio)
        med_s = f"{med:.3g}" if np.isfinite(med) else f"> {cost[-1] / exact_row:.3g} (not reached)"
        print(f"| {eps:g} | {cheaper} of {len(rows)} | {med_s} |")


if __name__ == "__main__":
    main()
