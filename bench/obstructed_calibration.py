"""Calibration of the obstructed error estimate: on random obstructed pairs of the building and
the office of bench/scenes.py (every other polygon an obstacle), the achieved error of `auto`
at `obstructed_tol` = tol, relative to tol x the pair's unobstructed F (the quantity tol
bounds), against `clipping` at tol 1e-11. A calibrated estimate puts the ratios between 1/30
and 1; the script prints their quantiles, the share in [1/30, 1] and the largest.

    python bench/obstructed_calibration.py --pairs 500 --tol 1e-3 1e-5
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


def obstructed_pairs(spec: scenes.Spec, n: int, rng) -> list[tuple[int, int, float, float]]:
    """Up to n random pairs (i, j, free F, reference F) that are partly hidden."""
    polys = spec.polygons
    out, tries = [], 0
    while len(out) < n and tries < 50 * n:
        tries += 1
        i, j = (int(x) for x in rng.choice(len(polys), 2, replace=False))
        free = nusselt.view_factor(polys[i], polys[j])
        if free < 1e-6:
            continue
        obs = [p for k, p in enumerate(polys) if k not in (i, j)]
        ref = nusselt.view_factor(polys[i], polys[j], obstacles=obs, method="clipping", tol=1e-11)
        if ref < free * (1 - 1e-6):
            out.append((i, j, free, ref))
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--pairs", type=int, default=500)
    p.add_argument("--tol", type=float, nargs="+", default=[1e-3, 1e-5])
    p.add_argument("--cache", default=None, help="file (.npy) to keep the pairs and references in")
    a = p.parse_args()
    rng = np.random.default_rng(7)
    specs = [scenes.building(), scenes.office()]
    t0 = time.perf_counter()
    if a.cache and os.path.exists(a.cache):
        pairs = [(specs[int(k)], int(i), int(j), free, ref) for k, i, j, free, ref in np.load(a.cache)]
    else:
        pairs = [(s, *q) for s in specs for q in obstructed_pairs(s, a.pairs // len(specs), rng)]
        if a.cache:
            np.save(a.cache, np.array([(specs.index(s), *q) for s, *q in pairs], float))
    print(f"{len(pairs)} obstructed pairs (references in {time.perf_counter() - t0:.0f} s)")
    for tol in a.tol:
        ratios, t0 = [], time.perf_counter()
        for s, i, j, free, ref in pairs:
            obs = [q for k, q in enumerate(s.polygons) if k not in (i, j)]
            f = nusselt.view_factor(s.polygons[i], s.polygons[j], obstacles=obs, method="auto", obstructed_tol=tol)
            ratios.append(abs(f - ref) / (tol * free))
        r = np.array(ratios)
        q = np.quantile(r, [0.05, 0.25, 0.5, 0.75, 0.95])
        inside = np.mean((r >= 1 / 30) & (r <= 1))
        print(
            f"tol {tol:.0e}: error / (tol F_free) quantiles 5/25/50/75/95 % = "
            + " ".join(f"{x:.2e}" for x in q)
            + f"; max {r.max():.2e}; in [1/30, 1]: {100 * inside:.1f} %; above 1: {np.sum(r > 1)};"
            f" {time.perf_counter() - t0:.1f} s"
        )


if __name__ == "__main__":
    main()
