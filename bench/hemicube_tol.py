"""`hemicube` with a per-row aliasing target (`row_tol`) against the fixed default resolution:
one core's CPU and the error against `auto` on the room with a crate (270 patches, reference
obstructed_tol=1e-7) and the urban grid urban(4) (2 560 patches, reference tol=1e-3,
obstructed_tol=1e-2, whose entries are within about 2e-6: docs/scale.md).

    RAYON_NUM_THREADS=1 python bench/hemicube_tol.py      # a few minutes on one core
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

import nusselt

sys.path.insert(0, os.path.dirname(__file__))
import scenes  # noqa: E402

SETTINGS = [
    ("resolution=128 (default)", {}),
    ("row_tol=1e-3", {"row_tol": 1e-3, "resolution": 1024}),
    ("row_tol=3e-4", {"row_tol": 3e-4, "resolution": 1024}),
    ("row_tol=1e-4", {"row_tol": 1e-4, "resolution": 1024}),
    ("resolution=512", {"resolution": 512}),
]


def run(scene, method, **opts):
    t = time.process_time()
    res = nusselt.form_factors(scene, method=method, progress=False, **opts)
    return res, time.process_time() - t


def main() -> None:
    cases = [
        ("room with crate", scenes.room_with_crate(), {"obstructed_tol": 1e-7}),
        ("urban(4)", scenes.urban(4), {"tol": 1e-3, "obstructed_tol": 1e-2}),
    ]
    print(f"load average at start: {os.getloadavg()}")
    print(
        "| scene | patches | hemicube | CPU s | max abs err (patch) | max abs err (surface) | max abs(row sum - ref) |"
    )
    print("|---|---:|---|---:|---:|---:|---:|")
    for name, spec, ref_opts in cases:
        scene = spec.scene()
        ref, tref = run(scene, "auto", **ref_opts)
        fr, sr = ref.matrix.toarray(), ref.by_surface().matrix
        sr = sr.toarray() if hasattr(sr, "toarray") else np.asarray(sr)
        print(
            f"| {name} | {scene.n_polygons if hasattr(scene, 'n_polygons') else fr.shape[0]} | reference auto "
            f"{ref_opts} | {tref:.2f} | | | |"
        )
        for label, opts in SETTINGS:
            res, t = run(scene, "hemicube", **opts)
            f = res.matrix.toarray()
            s = res.by_surface().matrix
            s = s.toarray() if hasattr(s, "toarray") else np.asarray(s)
            row = np.abs(f.sum(1) - fr.sum(1)).max()
            print(
                f"| {name} | {f.shape[0]} | {label} | {t:.2f} | {np.abs(f - fr).max():.2e} | "
                f"{np.abs(s - sr).max():.2e} | {row:.1e} |",
                flush=True,
            )
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
