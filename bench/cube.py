"""Whole-run benchmark: the closed unit cube with n x n quads per face (6 n^2 patches).

For each n, nusselt (method `auto`, at several accuracy targets `tol`) and, for small n,
pyviewfactor (from PyPI) compute the full matrix in a fresh subprocess each, so that the peak
memory (max RSS, read as soon as the matrix is computed) belongs to that run alone. Reported:
wall and CPU time, peak memory, pairs/s,
max |row sum - 1|, max relative reciprocity error and the error of the face-to-face sums
against the closed forms (Howell C-11, C-14).

    python bench/cube.py                       # n = 4, 8, 16, 32; pyviewfactor up to 16
    python bench/cube.py --n 32 --tol 1e-6 1e-10 --no-peer

``--whole-run`` measures instead the whole ``nusselt matrix cube.obj -o cube.npz --option
tol=T -q`` process (import, OBJ read, compute, assembly, output), each run a fresh child:
its CPU user and sys seconds, its peak RSS, and the RSS over the bytes of the CSR result
(data + indices + indptr, as read back); ``--repeat`` runs each size that many times.

    python bench/cube.py --whole-run --n 32 --tol 1e-3 --repeat 3   # the 6 144-patch cube
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time

import numpy as np

C11 = 0.19982489569838746
C14 = 0.20004377607540316


def cube_faces(n):
    polys, which = [], []
    t = np.linspace(0.0, 1.0, n + 1)
    for axis in range(3):
        for side in (0.0, 1.0):
            u, w = [a for a in range(3) if a != axis]
            normal = np.zeros(3)
            normal[axis] = 1.0 if side == 0.0 else -1.0
            for a in range(n):
                for b in range(n):
                    q = np.zeros((4, 3))
                    for k, (da, db) in enumerate([(0, 0), (1, 0), (1, 1), (0, 1)]):
                        q[k, axis], q[k, u], q[k, w] = side, t[a + da], t[b + db]
                    if np.cross(q[1] - q[0], q[2] - q[0]) @ normal < 0:
                        q = q[::-1].copy()
                    polys.append(q)
                    which.append(2 * axis + (side > 0))
    return polys, np.array(which)


def errors(f: np.ndarray, areas: np.ndarray, which: np.ndarray) -> dict:
    g = f * areas[:, None]
    den = np.maximum(np.abs(g), np.abs(g.T))
    mask = den > 0
    s = np.zeros((6, 6))
    np.add.at(s, (which[:, None], which[None, :]), g)
    fs = s / np.bincount(which, weights=areas)[:, None]
    exact = np.where(np.eye(6, dtype=bool), 0.0, C14)
    for k in range(0, 6, 2):
        exact[k, k + 1] = exact[k + 1, k] = C11
    return {
        "row_sum_err": float(np.max(np.abs(f.sum(1) - 1))),
        "reciprocity_err": float(np.max(np.abs(g - g.T)[mask] / den[mask])),
        "face_sum_err": float(np.max(np.abs(fs - exact))),
    }


def run_nusselt(n: int, tol: float) -> dict:
    import nusselt

    polys, which = cube_faces(n)
    scene = nusselt.Scene.from_polygons(polys)
    t0, c0 = time.perf_counter(), time.process_time()
    res = nusselt.form_factors(scene, method="auto", tol=tol)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    peak = peak_mb()
    f = res.dense()
    return {"wall_s": wall, "cpu_s": cpu, "peak_mb": peak, **errors(f, res.areas, which)}


def run_pyviewfactor(n: int) -> dict:
    import pyviewfactor as pvf
    import pyvista as pv

    polys, which = cube_faces(n)
    pts = np.concatenate(polys)
    faces = np.hstack([[4, 4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 3] for k in range(len(polys))])
    mesh = pv.PolyData(pts, faces)
    pvf.compute_viewfactor_matrix(pv.PolyData(*cube_faces_mesh(1)), skip_obstruction=True)  # JIT warm-up
    t0, c0 = time.perf_counter(), time.process_time()
    f = pvf.compute_viewfactor_matrix(mesh, skip_obstruction=True).T  # theirs: F[i, j] = F(j -> i)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    peak = peak_mb()
    areas = np.array([np.linalg.norm(np.cross(p[2] - p[0], p[3] - p[1])) / 2 for p in polys])
    return {"wall_s": wall, "cpu_s": cpu, "peak_mb": peak, **errors(np.asarray(f), areas, which)}


def cube_faces_mesh(n):
    polys, _ = cube_faces(n)
    pts = np.concatenate(polys)
    faces = np.hstack([[4, 4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 3] for k in range(len(polys))])
    return pts, faces


def peak_mb() -> float:
    """Peak memory of this process so far (max RSS), taken right after the computation: the
    error analysis that follows works on dense copies of the matrix."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def child(args) -> None:
    out = run_nusselt(args.n[0], args.tol[0]) if args.tool == "nusselt" else run_pyviewfactor(args.n[0])
    print(json.dumps(out))


def write_cube_obj(path: str, n: int) -> None:
    polys, _ = cube_faces(n)
    with open(path, "w") as fh:
        for q in polys:
            fh.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in q.tolist())
        fh.writelines("f " + " ".join(str(4 * k + i) for i in range(1, 5)) + "\n" for k in range(len(polys)))


def whole_run(n: int, tol: float, work: str, extra: list[str]) -> dict:
    """One ``nusselt matrix`` process on the n x n cube: CPU (user, sys), peak RSS and CSR size."""
    import os

    scene = os.path.join(work, f"cube{6 * n * n}.obj")
    if not os.path.exists(scene):
        write_cube_obj(scene, n)
    out = os.path.join(work, "cube.npz")
    entry = "import sys; from nusselt.cli import main; sys.exit(main(sys.argv[1:]))"  # as the console script
    cmd = [sys.executable, "-c", entry, "matrix", scene, "-o", out, "--option", f"tol={tol}", "-q", *extra]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, use = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t0
    err = proc.stderr.read().decode() if proc.stderr else ""
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise RuntimeError(f"nusselt matrix failed: {err.strip().splitlines()[-1:]}")
    import nusselt.io

    m = nusselt.io.load_npz(out)["matrix"]
    csr = m.data.nbytes + m.indices.nbytes + m.indptr.nbytes
    os.unlink(out)
    return {"user": use.ru_utime, "sys": use.ru_stime, "wall": wall, "rss": use.ru_maxrss * 1024, "csr": csr}


def main_whole_run(args) -> None:
    import tempfile

    print(
        f"{'n':>3s} {'patches':>7s} {'tol':>7s} {'user s':>7s} {'sys s':>6s} {'cpu s':>6s} {'wall s':>7s}"
        f" {'RSS MB':>7s} {'CSR MB':>7s} {'RSS/CSR':>7s}"
    )
    with tempfile.TemporaryDirectory(prefix="nusselt-cube-") as work:
        for n in args.n:
            for tol in args.tol:
                for _ in range(args.repeat):
                    r = whole_run(n, tol, work, args.extra)
                    print(
                        f"{n:3d} {6 * n * n:7d} {tol:7g} {r['user']:7.2f} {r['sys']:6.2f} {r['user'] + r['sys']:6.2f}"
                        f" {r['wall']:7.2f} {r['rss'] / 1e6:7.0f} {r['csr'] / 1e6:7.0f} {r['rss'] / r['csr']:7.2f}",
                        flush=True,
                    )


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--n", type=int, nargs="+", default=[4, 8, 16, 32])
    p.add_argument("--tol", type=float, nargs="+", default=[0.03, 1e-3, 1e-6, 1e-10])
    p.add_argument("--peer-max-n", type=int, default=16)
    p.add_argument("--no-peer", action="store_true")
    p.add_argument("--child", choices=["nusselt", "pyviewfactor"], dest="tool")
    p.add_argument("--whole-run", action="store_true", help="time whole `nusselt matrix` processes (see above)")
    p.add_argument("--repeat", type=int, default=1, help="--whole-run: runs per size and tol")
    p.add_argument("--extra", nargs=argparse.REMAINDER, default=[], help="--whole-run: more nusselt matrix arguments")
    args = p.parse_args()
    if args.whole_run:
        main_whole_run(args)
        return
    if args.tool:
        child(args)
        return
    print(
        f"{'tool':14s} {'n':>3s} {'patches':>7s} {'tol':>7s} {'wall s':>8s} {'cpu s':>8s} {'peak MB':>8s}"
        f" {'Mpairs/s':>9s} {'row-sum err':>11s} {'recip err':>10s} {'face err':>10s}"
    )
    for n in args.n:
        runs = [("nusselt", t) for t in args.tol]
        if not args.no_peer and n <= args.peer_max_n:
            runs.append(("pyviewfactor", None))
        for tool, tol in runs:
            cmd = [sys.executable, __file__, "--child", tool, "--n", str(n)]
            if tol is not None:
                cmd += ["--tol", str(tol)]
            run = subprocess.run(cmd, capture_output=True, text=True)
            if run.returncode != 0:
                last = (run.stderr.strip().splitlines() or ["no output"])[-1]
                hint = " (pip install '.[bench]')" if "No module named" in last else ""
                print(f"{tool:14s} {n:3d} failed: {last}{hint}", flush=True)
                continue
            r = json.loads(run.stdout.splitlines()[-1])
            npatch = 6 * n * n
            pairs = npatch * (npatch - 1) / 2
            print(
                f"{tool:14s} {n:3d} {npatch:7d} {tol if tol else '-':>7} {r['wall_s']:8.2f} {r['cpu_s']:8.2f}"
                f" {r['peak_mb']:8.0f} {pairs / r['wall_s'] / 1e6:9.2f} {r['row_sum_err']:11.2e}"
                f" {r['reciprocity_err']:10.2e} {r['face_sum_err']:10.2e}",
                flush=True,
            )


if __name__ == "__main__":
    main()
