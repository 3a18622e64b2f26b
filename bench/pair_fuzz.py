"""Cross-check of the three exact unobstructed methods on random polygon pairs in general
position (triangles, convex and concave polygons, rotated, scaled and placed at random, so
that many pairs pierce or are cut by each other's plane).

    python bench/pair_fuzz.py [--seed S] [--pairs N] [--floor F]

Prints every pair whose analytic, contour and auto values spread by more than 1e-10
relative (pairs with F above --floor, default 1e-6), and the worst spread. A spread names no
culprit: judge it against an independent reference (Lambert's point formula integrated over
the source, for instance).
"""

import argparse

import numpy as np

import nusselt


def random_polygon(rng):
    kind = rng.choice(["triangle", "convex", "concave"])
    if kind == "triangle":
        v2 = rng.uniform(-1, 1, (3, 2))
        if (v2[1, 0] - v2[0, 0]) * (v2[2, 1] - v2[0, 1]) - (v2[1, 1] - v2[0, 1]) * (v2[2, 0] - v2[0, 0]) < 0:
            v2 = v2[::-1]
    else:
        m = rng.integers(5, 9) if kind == "concave" else rng.integers(3, 7)
        ang = np.sort(rng.uniform(0, 2 * np.pi, m))
        r = rng.uniform(0.3, 1, m) if kind == "concave" else np.ones(m)
        if kind == "concave":
            r[::2] *= 0.4
        v2 = np.c_[r * np.cos(ang), r * np.sin(ang)]
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return (np.c_[v2, np.zeros(len(v2))] * rng.uniform(0.2, 2)) @ q.T + rng.normal(size=3) * rng.uniform(0, 2)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--pairs", type=int, default=1500)
    ap.add_argument("--floor", type=float, default=1e-6)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    worst, tried = (0.0, None), 0
    for k in range(args.pairs):
        a, b = random_polygon(rng), random_polygon(rng)
        try:
            vals = [nusselt.view_factor(a, b, method=m) for m in ("analytic", "contour", "auto")]
        except ValueError:
            continue  # a random outline that crosses itself
        tried += 1
        if vals[0] > args.floor:
            spread = (max(vals) - min(vals)) / vals[0]
            if spread > 1e-10:
                print(f"pair {k}: F {vals[0]:.3e}, analytic/contour/auto spread {spread:.1e}")
            worst = max(worst, (spread, k), key=lambda t: t[0])
    print(f"{tried} pairs, worst relative spread {worst[0]:.1e} (pair {worst[1]})")


if __name__ == "__main__":
    main()
