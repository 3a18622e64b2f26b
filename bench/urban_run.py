"""The whole urban run: ``nusselt matrix`` on the 23 040-patch urban grid, its CPU, peak RSS and
its error at patch and at surface level.

The scene is :func:`scenes.urban` (k = 12: ground 48 x 48, 16 buildings with 144-patch roofs
and 1 152-patch walls; 17 named surfaces), written as an OBJ with one group per surface and
run through the command line as a user would::

    nusselt matrix urban23040.obj -o urban23040.npz --option tol=1e-3 --option obstructed_tol=1e-2

under ``/usr/bin/time -v`` on 2 threads (``nice -n 10``; CPU = user + sys of the process,
peak RSS its own). Errors of the result, against references computed here:

- per patch: on ``--rows`` sample rows (a quarter on the ground, two roofs, the rest walls;
  seeded), max |F_ij - F_ref| over every entry of those rows and the largest row-sum
  difference; F_ref by ``auto`` at ``tol=1e-9, obstructed_tol=1e-6`` (its error bound is
  1e-6 of the pair's unobstructed F), computed on the scene reordered with the sample rows
  first (bench/scale.py's ``pair_sample_rows``);
- per surface: F_IJ = sum_{i in I} A_i sum_{j in J} F_ij / A_I for every pair of the 17
  surfaces. The exact F_IJ is a property of the surfaces, not of their meshing (each patch F is
  an exact integral and F_IJ their area-weighted sum), so the reference is the whole
  surface matrix of the same scene meshed coarsely (k = 4, 2 560 patches, ``tol=1e-9,
  obstructed_tol=1e-7``); the same at k = 2 is printed beside it as the reference's own
  consistency.

    python bench/urban_run.py                 # k = 12, prints a markdown row and JSON
    python bench/urban_run.py --k 2 --rows 8 --surface-k 2   # the same steps on 640 patches, quick
    python bench/urban_run.py --whole 6      # every entry of urban(6) (5 760 patches) against
                                             # the row reference's targets, through the API
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from scale import pair_sample_rows  # noqa: E402
from scenes import urban  # noqa: E402

RUN = {"tol": 1e-3, "obstructed_tol": 1e-2}
ROW_REFERENCE = {"tol": 1e-9, "obstructed_tol": 1e-6}
SURFACE_REFERENCE = {"tol": 1e-9, "obstructed_tol": 1e-7}


def write_obj(spec, path: pathlib.Path) -> None:
    """One OBJ group per named surface, every face with its own vertices (the reader welds)."""
    lines, nv, cur = [], 0, None
    for p, s in zip(spec.polygons, spec.surface):
        if s != cur:
            lines.append(f"g {s}")
            cur = s
        lines += [f"v {v[0]:.17g} {v[1]:.17g} {v[2]:.17g}" for v in p]
        lines.append("f " + " ".join(str(nv + 1 + t) for t in range(len(p))))
        nv += len(p)
    path.write_text("\n".join(lines) + "\n")


def sample_rows(k: int, s: int, seed: int = 1) -> np.ndarray:
    """s rows of urban(k): a quarter on the ground, two roofs (which see nothing), the rest walls."""
    n, ground, per = 160 * k * k, 16 * k * k, 9 * k * k
    rest = np.arange(ground, n)
    roof = rest[(rest - ground) % per < k * k]
    wall = np.setdiff1d(rest, roof)
    rng = np.random.default_rng(seed)
    ng, nr = s // 4, min(2, s // 4)
    pick = [rng.choice(ground, ng, replace=False), rng.choice(roof, nr, replace=False)]
    pick.append(rng.choice(wall, s - ng - nr, replace=False))
    return np.sort(np.concatenate(pick))


def reference_rows(spec, rows: np.ndarray) -> np.ndarray:
    from nusselt.methods import resolve

    _, full = resolve("auto", ROW_REFERENCE)
    return pair_sample_rows(spec.polygons, rows, "auto", full)[0]


def surface_matrix(F, areas: np.ndarray, surface: np.ndarray, m: int) -> np.ndarray:
    """F_IJ = sum_{i in I} A_i sum_{j in J} F_ij / A_I (sparse F, surface index per patch)."""
    import scipy.sparse as sp

    n = len(areas)
    member = sp.csr_array((np.ones(n), (np.arange(n), surface)), shape=(n, m))
    g = member.T @ (sp.csr_array(F).multiply(areas[:, None])) @ member
    a = np.bincount(surface, weights=areas, minlength=m)
    return np.asarray(g.toarray() if sp.issparse(g) else g) / a[:, None]


def reference_surfaces(k: int) -> tuple[np.ndarray, list[str], float]:
    """The exact surface matrix from urban(k) computed whole at SURFACE_REFERENCE; CPU s."""
    import nusselt

    c0 = time.process_time()
    spec = urban(k)
    res = nusselt.form_factors(spec.scene(), method="auto", **SURFACE_REFERENCE)
    names = list(res.surface_names)
    return surface_matrix(res.matrix, res.areas, res.surface, len(names)), names, time.process_time() - c0


def whole_check(k: int) -> dict:
    """Every entry of urban(k) at RUN against ROW_REFERENCE (both whole, one process)."""
    import nusselt

    scene = urban(k).scene()
    c0 = time.process_time()
    run = nusselt.form_factors(scene, method="auto", **RUN)
    c1 = time.process_time()
    ref = nusselt.form_factors(scene, method="auto", **ROW_REFERENCE)
    c2 = time.process_time()
    return {
        "patches": len(scene),
        "run_cpu_s": c1 - c0,
        "reference_cpu_s": c2 - c1,
        "max_entry_err": float(abs(run.matrix - ref.matrix).max()),
        "max_row_sum_err": float(np.abs(run.row_sums - ref.row_sums).max()),
    }


def timed_run(obj: pathlib.Path, out: pathlib.Path, threads: int, extra: list[str]) -> dict:
    """``nusselt matrix`` under /usr/bin/time -v: wall, user, sys, peak RSS and its summary."""
    exe = shutil.which("nusselt", path=os.path.dirname(sys.executable)) or "nusselt"  # this venv's
    cmd = ["nice", "-n", "10", "/usr/bin/time", "-v", exe, "matrix", str(obj)]
    cmd += ["-o", str(out), "-q"] + [a for key, v in RUN.items() for a in ("--option", f"{key}={v!r}")] + extra
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    if p.returncode != 0:
        raise SystemExit(f"run failed ({p.returncode}): {p.stderr[-2000:]}")

    def field(name: str) -> str:
        m = re.search(rf"{re.escape(name)}: (.+)", p.stderr)
        if m is None:
            raise SystemExit(f"/usr/bin/time printed no {name!r}")
        return m[1].strip()

    wall = [float(x) for x in field("Elapsed (wall clock) time (h:mm:ss or m:ss)").split(":")]
    user, sys_ = float(field("User time (seconds)")), float(field("System time (seconds)"))
    return {
        "command": " ".join(["nusselt"] + cmd[6:]),
        "threads": threads,
        "wall_s": sum(x * 60 ** (len(wall) - 1 - i) for i, x in enumerate(wall)),
        "cpu_s": user + sys_,
        "rss_mb": int(field("Maximum resident set size (kbytes)")) / 1024.0,
        "summary": p.stdout.strip().splitlines(),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--k", type=int, default=12, help="urban(k): 160 k^2 patches (default 12: 23 040)")
    ap.add_argument("--rows", type=int, default=48, help="sample rows of the per-patch reference")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument(
        "--surface-k", default="4,2", help="k of the surface reference, then of its consistency checks (default 4,2)"
    )
    ap.add_argument("--work", help="directory for the OBJ and the result (default: a temp dir)")
    ap.add_argument("--reuse", action="store_true", help="use the result and timing already in --work (no new run)")
    ap.add_argument("--whole", type=int, help="only compare every entry of urban(WHOLE) with its reference")
    # anything else is passed on to nusselt matrix (e.g. --float32)
    args, args.option = ap.parse_known_args()
    if args.whole is not None:
        print(json.dumps(whole_check(args.whole)))
        return
    import nusselt.io

    work = pathlib.Path(args.work or tempfile.mkdtemp(prefix="urban-run-"))
    work.mkdir(parents=True, exist_ok=True)
    spec = urban(args.k)
    n = len(spec.polygons)
    obj, out = work / f"urban{n}.obj", work / f"urban{n}.npz"
    if not obj.exists():
        write_obj(spec, obj)
    saved = work / f"urban{n}.run.json"
    if args.reuse and out.exists() and saved.exists():
        run = json.loads(saved.read_text())
    else:
        run = timed_run(obj, out, args.threads, args.option)
        saved.write_text(json.dumps(run))
    print(json.dumps(run), flush=True)
    rows = sample_rows(args.k, args.rows)
    c0 = time.process_time()
    fref = reference_rows(spec, rows)
    ref_cpu = time.process_time() - c0
    ks = [int(x) for x in args.surface_k.split(",")]
    sref, names, sref_cpu = reference_surfaces(ks[0])
    consistency = {}
    for k in ks[1:]:
        other, names2, _ = reference_surfaces(k)
        assert names == names2
        consistency[f"surface_reference_k{k}_vs_k{ks[0]}"] = float(np.abs(other - sref).max())
    r = nusselt.io.load_npz(out)
    F, areas = r["matrix"], r["areas"]
    f = F[rows].toarray()
    surf = surface_matrix(F, areas, np.asarray(r["surface"]), len(names))
    assert [str(s) for s in r["surface_names"]] == names
    errors = {
        "patches": n,
        "nnz": int(F.nnz),
        "sample_rows": len(rows),
        "max_entry_err": float(np.abs(f - fref).max()),
        "max_row_sum_err": float(np.abs(f.sum(1) - fref.sum(1)).max()),
        "max_surface_err": float(np.abs(surf - sref).max()),
        **consistency,
        "row_reference_cpu_s": ref_cpu,
        "surface_reference_cpu_s": sref_cpu,
    }
    print(json.dumps(errors), flush=True)
    print(
        f"| urban | {n} | auto tol={RUN['tol']:g} obstructed_tol={RUN['obstructed_tol']:g}"
        f"{' ' + ' '.join(args.option) if args.option else ''} | {run['threads']} | {run['cpu_s']:.0f} | "
        f"{run['wall_s']:.0f} | {run['rss_mb']:.0f} | {errors['max_entry_err']:.1e} | "
        f"{errors['max_row_sum_err']:.1e} | {errors['max_surface_err']:.1e} |"
    )


if __name__ == "__main__":
    main()
