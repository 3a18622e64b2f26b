"""Rays per CPU second of ``method="raytrace"`` through the public path, everything included.

``nusselt.form_factors(scene, method="raytrace")`` on :func:`scenes.urban` (k = 12: 23 040
patches, 4 096 rays per row, no ``row_tol``, so exactly 4 096 x n rays) on one thread
(``RAYON_NUM_THREADS=1``, set before nusselt is imported). CPU is user + sys of this process
from after the scene's polygons are generated to the finished result: scene build, BVH,
row blocks and the assembly of the n-row matrix. Also prints the mean row sum (the open
scene loses the sky) so a faster run can be checked to give the same answer.

    python bench/raytrace_rate.py            # k = 12, about 40 s of CPU
    python bench/raytrace_rate.py --k 4      # 2 560 patches, a few seconds
"""

from __future__ import annotations

import argparse
import os
import pathlib
import sys
import time

os.environ.setdefault("RAYON_NUM_THREADS", "1")
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))

from scenes import urban  # noqa: E402

import nusselt  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--k", type=int, default=12)
    ap.add_argument("--rays", type=int, default=4096)
    args = ap.parse_args()

    spec = urban(args.k)
    c0 = time.process_time()
    scene = spec.scene()
    res = nusselt.form_factors(scene, method="raytrace", rays=args.rays)
    dt = time.process_time() - c0
    n = len(spec.polygons)
    rays = n * args.rays
    sums = res.matrix.sum(axis=1)
    print(
        f"urban k={args.k}: {n} patches, {rays:.3e} rays in {dt:.2f} s CPU "
        f"(threads {os.environ['RAYON_NUM_THREADS']}): {rays / dt / 1e6:.3f} M rays/s per core; "
        f"mean row sum {sums.mean():.6f}, nnz {res.matrix.nnz}"
    )


if __name__ == "__main__":
    main()
