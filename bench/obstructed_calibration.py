"""Calibration of the obstructed error estimate: on random obstructed pairs of the building and
the office of bench/scenes.py (every other polygon an obstacle), the achieved error of `auto`
at `obstructed_tol` = tol, relative to tol x the pair's unobstructed F (the quantity tol
bounds), against `clipping` at tol 1e-11. A calibrated estimate puts the ratios between 1/30
and 1; the script prints their quantiles, the share in [1/30, 1] and the largest.

    python bench/obstructed_calibration.py --pairs 500 --tol 1e-3 1e-5

With --all SCENE, every partly hidden pair of that scene instead (`form_factors` at each tol
against `form_factors` at --reference-tol, kept in --cache): the building's 16 362 such pairs
take one core about 7 minutes for the reference at 1e-9 and 15-60 s per tol.

    RAYON_NUM_THREADS=1 python bench/obstructed_calibration.py --all building \
        --cache /tmp/building_ref.npy --tol 1e-2 1e-3 1e-4 1e-5 1e-6
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings

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


def report(tol: float, r: np.ndarray, seconds: float) -> None:
    """One line of the ratios r = error / (tol x F_free)."""
    q = np.quantile(r, [0.05, 0.25, 0.5, 0.75, 0.95])
    inside = np.mean((r >= 1 / 30) & (r <= 1))
    print(
        f"tol {tol:.0e}: error / (tol F_free) quantiles 5/25/50/75/95 % = "
        + " ".join(f"{x:.2e}" for x in q)
        + f"; max {r.max():.2e}; in [1/30, 1]: {100 * inside:.1f} %; above 1: {np.sum(r > 1)};"
        f" {seconds:.1f} s",
        flush=True,
    )


def whole_scene(spec: scenes.Spec, tols: list[float], reference_tol: float, cache: str | None) -> None:
    """Every partly hidden pair of `spec`: `form_factors` at each tol against the reference."""
    scene = spec.scene()
    polys = spec.polygons

    def dense(tol: float) -> tuple[np.ndarray, np.ndarray]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", nusselt.ToleranceWarning)  # std_err says it
            res = nusselt.form_factors(scene, obstructed_tol=tol)
        out = [res.matrix, res.std_err if res.std_err is not None else np.zeros(res.matrix.shape)]
        return tuple(m.toarray() if hasattr(m, "toarray") else np.asarray(m) for m in out)

    t0 = time.process_time()
    cached = bool(cache and os.path.exists(cache))
    if cached:
        ref, ref_err = np.load(cache)
    else:
        ref, ref_err = dense(reference_tol)
        if cache:
            np.save(cache, np.stack([ref, ref_err]))
    if ref.shape != (len(polys), len(polys)):
        raise SystemExit(f"{spec.name}: not every polygon receives ({ref.shape[0]} of {len(polys)})")
    i, j = np.triu_indices(len(polys), 1)
    free = np.array([nusselt.view_factor(polys[a], polys[b]) for a, b in zip(i, j)])
    hidden = ref[i, j] < free * (1 - 1e-9)
    whole = hidden & (ref[i, j] == 0.0)
    i, j, free = i[hidden & ~whole], j[hidden & ~whole], free[hidden & ~whole]
    print(
        f"{spec.name}: {len(i)} pairs partly hidden, {np.sum(whole)} hidden whole (reference at"
        f" {reference_tol:.0e}: " + ("from the cache)" if cached else f"{time.process_time() - t0:.0f} s of CPU)")
    )
    for tol in tols:
        t0 = time.process_time()
        f, _ = dense(tol)
        seconds = time.process_time() - t0
        # (a reference entry that fell short of a tenth of this target says nothing)
        known = ref_err[i, j] <= 0.1 * tol * free
        r = np.abs(f[i, j] - ref[i, j])[known] / (tol * free[known])
        report(tol, r, seconds)
        if not known.all():
            print(f"    ({np.sum(~known)} pairs left out: reference short of tol / 10)")
        i_k, j_k = i[known], j[known]
        for k in np.argsort(r)[::-1][: min(5, int(np.sum(r > 1)))]:
            print(
                f"    pair ({i_k[k]}, {j_k[k]}): {r[k]:.2f} x tol, F {f[i_k[k], j_k[k]]:.9e} for {ref[i_k[k], j_k[k]]:.9e}"
            )


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--pairs", type=int, default=500)
    p.add_argument("--tol", type=float, nargs="+", default=[1e-3, 1e-5])
    p.add_argument("--cache", default=None, help="file (.npy) to keep the pairs and references in")
    p.add_argument("--all", metavar="SCENE", choices=["building", "office"], help="every pair of this scene")
    p.add_argument("--reference-tol", type=float, default=1e-9, help="obstructed_tol of the --all reference")
    a = p.parse_args()
    if a.all:
        whole_scene(getattr(scenes, a.all)(), a.tol, a.reference_tol, a.cache)
        return
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
        report(tol, np.array(ratios), time.perf_counter() - t0)


if __name__ == "__main__":
    main()
