"""Every listed method at its defaults on three scenes, the accuracy-versus-cost curves behind
the defaults of the sampled pair methods, and the calibration of the work budget.

    python bench/methods.py scenes          # docs/methods.md's table and docs/methods.png
    python bench/methods.py curves          # error vs CPU over option values (docs/methods.md)
    python bench/methods.py budget          # work units per CPU second (docs/guide.md)
    python bench/methods.py interrupt       # seconds from Ctrl-C to KeyboardInterrupt, per method
    python bench/methods.py extremes        # every option at its range ends: finishes or budget error
    python bench/methods.py plot room.json office.json urban.json   # docs/methods.png from `scenes --json`
    python bench/methods.py scenes --scenes room --methods subdivision adaptive

`scenes`: each method at its defaults on the 270-patch closed room with a floating crate
(:func:`scenes.room_with_crate`), the furnished office (:func:`scenes.office`, 2 322 patches)
and the urban grid (:func:`scenes.urban` k=4, 2 560 patches), against `auto` with
`obstructed_tol=1e-7` (with `--sampled-reference` on the sampled rows only: the whole office
costs about 15 CPU minutes). CPU is user + sys of this process over the call (all threads;
run with RAYON_NUM_THREADS=2, the default here), wall the elapsed time. Errors: "surface" is
the largest |F - F_ref| of the matrices aggregated to named surfaces (area-weighted,
`FormFactors.by_surface`), "patch" the largest over patch pairs. On the big scenes every
method first runs on `--rows` sampled whole rows (:func:`scale.pair_sample_rows` for pair
methods) and its CPU is projected to the scene (the fixed costs of a call once, plus the rows' CPU
over their share of the pairs or rows); only if that is under `--cap` CPU seconds is the whole scene run and timed.
Sampled rows give the patch error and the patch-to-surface error (F of a sampled patch to
each named surface) on those rows.

`curves`: the sampled pair methods (`quadrature`, `montecarlo`, `subdivision`, `adaptive`) over
their option values on a suite of obstructed pairs (:func:`obstructed_pairs`: big plates with
blockers of every kind, a partition, a fin, large room walls past a crate, triangles, pairs of
the 270-patch room) against `clipping` at tol 1e-10, and on the whole 270-patch room: the
largest absolute F error over the suite, its CPU, the room's CPU and its surface and patch
errors.

`interrupt`: each method on a call that would run for minutes (extreme but allowed options,
budget unlimited: one pair with 10 blockers, a point, or the 5 400-patch box for `analytic`,
`contour` and `auto`), interrupted after 0.3 s as Ctrl-C does (`_thread.interrupt_main`); the
wall seconds from the interrupt to the KeyboardInterrupt, worst of `--repeats`.

`extremes`: every method with each option at the low and the high end of its range (and the
costliest combination, `LONG_CALLS`) on a pair with 10 blockers, an unobstructed pair and a
point, at a small budget (default 2^20 units): every call must finish or stop with the
budget error, within a time that budget bounds.

`budget`: work units per CPU second of each method (one unit: a ray test, a hemicube or
single-plane cell, a disk cell, a traced ray), from the smallest budget a pair or row passes.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import pathlib
import sys
import time

os.environ.setdefault("RAYON_NUM_THREADS", "2")

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(__file__))
import scenes  # noqa: E402
from conftest import LONG_CALLS  # noqa: E402  (tests/ is on the path through scenes)

import nusselt  # noqa: E402

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs"
PAIR_METHODS = ["quadrature", "montecarlo", "subdivision", "adaptive"]


# --------------------------------------------------------------------------- measuring


def cpu_wall(fn):
    """(result, CPU seconds of the whole process, wall seconds) of fn()."""
    c0, t0 = time.process_time(), time.perf_counter()
    r = fn()
    return r, time.process_time() - c0, time.perf_counter() - t0


def repeated_cpu(fn, min_total=0.05, max_reps=50):
    """(result, mean CPU seconds per call) over repeats while the total stays below min_total."""
    total, reps = 0.0, 0
    while True:
        r, c, _ = cpu_wall(fn)
        total, reps = total + c, reps + 1
        if total >= min_total or reps >= max_reps:
            return r, total / reps


# --------------------------------------------------------------------------- obstructed pairs


def rect(x0, x1, y0, y1, z=0.0, flip=False):
    v = np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]], float)
    return v[::-1].copy() if flip else v


def rotz(p, deg, about=(0.5, 0.5)):
    a = np.radians(deg)
    c, s = np.cos(a), np.sin(a)
    q = np.asarray(p, float).copy()
    x, y = q[:, 0] - about[0], q[:, 1] - about[1]
    q[:, 0], q[:, 1] = about[0] + c * x - s * y, about[1] + s * x + c * y
    return q


def obstructed_pairs(quick: bool = False) -> list[tuple[str, np.ndarray, np.ndarray, list[np.ndarray]]]:
    """Obstructed pairs (name, source, receiver, obstacles) on which the sampled methods must
    meet 2e-3 absolute: F from 0.006 to 0.2, blockers in the middle, near either polygon,
    touching both, many small ones, at angles to every edge; large patches of a room."""
    lo, hi = rect(0, 1, 0, 1), rect(0, 1, 0, 1, z=1, flip=True)
    out = [
        ("plates, centred blocker", lo, hi, [rect(0.25, 0.75, 0.25, 0.75, z=0.5)]),
        ("plates, turned blocker", lo, hi, [rotz(rect(0.1, 0.6, 0.3, 0.9, z=0.3), 20)]),
        ("plates, blocker near receiver", lo, hi, [rect(0.2, 0.7, 0.15, 0.65, z=0.9)]),
        ("plates, blocker near source", lo, hi, [rotz(rect(0.3, 0.8, 0.2, 0.7, z=0.08), 35)]),
        (
            "plates, 4 x 4 small blockers",
            lo,
            hi,
            [
                rect(0.1 + 0.22 * a, 0.2 + 0.22 * a, 0.1 + 0.22 * b, 0.2 + 0.22 * b, z=0.5)
                for a in range(4)
                for b in range(4)
            ],
        ),
        # a partition standing between the plates, touching both
        ("plates, partition", lo, hi, [np.array([[0.4, 0.2, 0], [0.4, 0.8, 0], [0.4, 0.8, 1], [0.4, 0.2, 1]], float)]),
    ]
    # perpendicular plates sharing an edge, a fin standing on the floor between them
    floor = rect(0, 1, 0, 1)
    wall = np.array([[0, 0, 0], [0, 1, 0], [0, 1, 1], [0, 0, 1]], float)  # x = 0, facing +x
    fin = np.array([[0.2, 0.5, 0], [0.6, 0.5, 0], [0.6, 0.5, 0.4], [0.2, 0.5, 0.4]], float)
    out.append(("floor to wall, fin", floor, wall, [fin]))
    out.append(("floor to wall, post", floor, wall, [rotz(rect(0.15, 0.35, 0.3, 0.6, z=0.3), 10)]))
    # triangles in general position
    tri_a = np.array([[0, 0, 0], [1.2, 0.1, 0], [0.3, 0.9, 0]], float)
    tri_b = np.array([[0.1, 0.2, 1.0], [0.4, 1.1, 0.8], [1.0, 0.0, 0.9]], float)
    tri_k = np.array([[0.2, 0.2, 0.45], [0.7, 0.3, 0.5], [0.4, 0.7, 0.55]], float)
    if np.cross(tri_b[1] - tri_b[0], tri_b[2] - tri_b[0])[2] > 0:
        tri_b = tri_b[::-1].copy()
    out.append(("triangles, triangle between", tri_a, tri_b, [tri_k]))
    # the room of scenes.room_with_crate with one patch per wall and crate face: large patches
    big = scenes.room_with_crate(1, 1)
    p = big.polygons
    out.append(("room 1 x 1: floor to ceiling", p[4], p[5], [q for k, q in enumerate(p) if k not in (4, 5)]))
    out.append(("room 1 x 1: wall to wall", p[0], p[1], [q for k, q in enumerate(p) if k not in (0, 1)]))
    out.append(("room 1 x 1: wall to floor", p[2], p[4], [q for k, q in enumerate(p) if k not in (2, 4)]))
    if not quick:
        for i, j in room_pairs():
            p = scenes.room_with_crate().polygons
            out.append((f"room 6 x 6: {i} to {j}", p[i], p[j], [q for k, q in enumerate(p) if k not in (i, j)]))
    return out


def room_pairs(count=6, seed=1):
    """`count` pairs of the 270-patch room that the crate hides a quarter to three quarters
    of (the largest unobstructed F among 3000 random pairs)."""
    p = scenes.room_with_crate().polygons
    rng = np.random.default_rng(seed)
    found = []
    for _ in range(3000):
        i, j = (int(x) for x in rng.choice(len(p), 2, replace=False))
        free = nusselt.view_factor(p[i], p[j])
        if free > 1e-3:
            obs = [q for k, q in enumerate(p) if k not in (i, j)]
            f = nusselt.view_factor(p[i], p[j], obstacles=obs, obstructed_tol=1e-3)
            if 0.25 * free < f < 0.75 * free:
                found.append((free, i, j))
        if len(found) >= 4 * count:
            break
    return [(i, j) for _, i, j in sorted(found, reverse=True)[:count]]


def pair_references(pairs):
    """`clipping` at tol 1e-10 for each pair (the plates' is checked against dblquad)."""
    ref = []
    for _name, a, b, obs in pairs:
        f = nusselt.view_factor(a, b, obstacles=obs, method="clipping", tol=1e-10)
        free = nusselt.view_factor(a, b)
        ref.append((f, free))
    exact = scenes.blocker_plates_exact()
    assert abs(ref[0][0] - exact) < 1e-9, (ref[0][0], exact)
    return ref


CURVES = {
    "quadrature": [{"order": k} for k in (2, 3, 4, 6, 8, 12, 16, 24)],
    "montecarlo": [{"samples": n} for n in (64, 256, 1024, 4096, 16384)],
    "subdivision": [
        {"divisions": d, "source": s} for s in ("centre", 2, 3, 4, "auto") for d in (4, 8, 16, 32, 48) if s != "auto"
    ]
    + [{"divisions": d, "source": "auto"} for d in (4, 8, 16, 48)],
    "adaptive": [
        {"tol": t, "source": s} for s in ("centre", 2, 3, 4, "auto") for t in (1e-3, 1e-4, 1e-5) if s != "auto"
    ]
    + [{"tol": t, "source": "auto"} for t in (1e-3, 1e-4)],
}


def curves(args):
    pairs = obstructed_pairs(args.quick)
    ref = pair_references(pairs)
    print(f"{len(pairs)} obstructed pairs; F from {min(r[0] for r in ref):.3g} to {max(r[0] for r in ref):.3g}")
    for name, (f, free) in zip((p[0] for p in pairs), ref):
        print(f"  {name:34s} F {f:.6f}  unobstructed {free:.6f}")
    room = scenes.room_with_crate()
    room_scene = room.scene()
    room_ref = reference(room_scene, "room")
    rows = []
    settings = args.settings or [(m, o) for m in args.methods for o in CURVES.get(m, [{}])]
    for method, opts in settings:
        errs, cpu = [], 0.0
        for (name, a, b, obs), (f, _) in zip(pairs, ref):
            try:
                v, c = repeated_cpu(lambda: nusselt.view_factor(a, b, obstacles=obs, method=method, **opts))
            except ValueError as e:  # over the work budget
                print(f"  {name}: {e}", flush=True)
                v, c = math.nan, math.nan
            errs.append(abs(v - f))
            cpu += c
        worst = int(np.nanargmax(errs))
        line = {
            "method": method,
            "opts": opts,
            "pair_err": float(np.nanmax(errs)),
            "worst": pairs[worst][0],
            "pair_cpu": cpu,
        }
        if not args.no_room:
            res, c, w = cpu_wall(lambda: nusselt.form_factors(room_scene, method=method, **opts))
            line.update(room_cpu=c, room_wall=w, **errors(res, room_ref))
        rows.append(line)
        print(json.dumps(line), flush=True)
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(rows, indent=1))


# --------------------------------------------------------------------------- scenes


def scene_specs(names):
    out = {}
    for n in names:
        if n == "room":
            out[n] = scenes.room_with_crate()
        elif n == "office":
            out[n] = scenes.office()
        elif n == "urban":
            out[n] = scenes.urban(k=4)
    return out


_REFS: dict[str, object] = {}


def reference(scene, key):
    """The tight `auto` result of a scene (cached per run)."""
    if key not in _REFS:
        opts = {"obstructed_tol": 1e-7} if key == "room" else {"obstructed_tol": 1e-5}
        res, c, w = cpu_wall(lambda: nusselt.form_factors(scene, method="auto", **opts))
        print(f"reference {key}: auto {opts or 'defaults'}: CPU {c:.1f} s, wall {w:.1f} s", flush=True)
        _REFS[key] = res
    return _REFS[key]


def errors(res, ref):
    d = np.abs(res.by_surface().dense() - ref.by_surface().dense())
    return {"surface_err": float(d.max()), "patch_err": float(np.abs(res.dense() - ref.dense()).max())}


ALL_METHODS = list(nusselt.METHODS)


def scenes_table(args):
    specs = scene_specs(args.scenes)
    rows_out = []
    for key, spec in specs.items():
        scene = spec.scene()
        n = len(scene)
        print(f"== {key}: {n} patches", flush=True)
        if key == "room":
            ref = reference(scene, key)
            for method in args.methods:
                load = os.getloadavg()[0]
                res, c, w = cpu_wall(lambda: nusselt.form_factors(scene, method=method))
                line = {"scene": key, "patches": n, "method": method, "cpu": c, "wall": w, **errors(res, ref)}
                line["load"] = load
                rows_out.append(line)
                print(json.dumps(line), flush=True)
        else:
            rows_out += big_scene_rows(key, spec, scene, args)
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(rows_out, indent=1))
    return rows_out


def surface_onehot(surface):
    """(n, surfaces) 0/1 matrix: F @ it sums each row of F over every named surface's patches."""
    names = sorted(set(surface))
    m = np.zeros((len(surface), len(names)))
    m[np.arange(len(surface)), [names.index(x) for x in surface]] = 1.0
    return m


def sample_full_rows(spec, rows, method, opts=None):
    """(F on `rows` x all columns, CPU s) of a method: pair methods by `scale.pair_sample_rows`
    (the sample patches put first, so each row's pairs are computed once), row methods by the
    core's row calls. Also the CPU projected to the whole scene."""
    from scale import _cpu_rss, pair_sample_rows

    n, s = len(spec.polygons), len(rows)
    m, o = nusselt.methods.resolve(method, opts or {})
    if m.kind == "pairs":
        (dense, after_fixed), c, _ = cpu_wall(lambda: pair_sample_rows(spec.polygons, rows, method, o))
        rows_cpu = _cpu_rss()[0] - after_fixed
        share = (s * (n - 1) - s * (s - 1) / 2) / (n * (n - 1) / 2)
        # the fixed costs (scene, first call) once, the rows' CPU scaled to all pairs
        return dense, c, c - rows_cpu + rows_cpu / share
    else:
        core = spec.scene()._core
        (indptr, indices, data, _, _), c, _ = cpu_wall(lambda: core.full_rows(np.asarray(rows, np.int64), method, o))
        dense = np.zeros((s, n))
        for r in range(s):
            sl = slice(indptr[r], indptr[r + 1])
            dense[r, indices[sl]] = data[sl]
    return dense, c, c * n / s


def big_scene_rows(key, spec, scene, args):
    """The office or urban rows of the table. Every method first runs on `--rows` sampled rows
    (whole rows, all columns), its CPU projected to the scene; if that is under `--cap` CPU s
    it then runs on the whole scene and its CPU is measured. The reference is `auto` at
    obstructed_tol 1e-7, on the whole scene, or with `--sampled-reference` on the sample rows
    only. Errors against a whole reference on a whole run: surface-level and patch-level;
    otherwise on the sample rows: patch-level and patch-to-surface (F of a sample patch to each
    named surface, of which the surface-level F is an area-weighted mean)."""
    n = len(scene)
    rows = np.sort(np.random.default_rng(0).choice(n, args.rows, replace=False))
    onehot = surface_onehot(spec.surface)
    ref_opts = {"obstructed_tol": 1e-7}
    if args.sampled_reference:
        ref_rows, c, _ = sample_full_rows(spec, rows, "auto", ref_opts)
        ref = None
        print(f"reference {key}: auto {ref_opts} on {len(rows)} rows: CPU {c:.1f} s", flush=True)
    else:
        res, c, w = cpu_wall(lambda: nusselt.form_factors(scene, method="auto", **ref_opts))
        print(f"reference {key}: auto {ref_opts}: CPU {c:.1f} s, wall {w:.1f} s", flush=True)
        ref, ref_rows = res, res.dense()[rows]

    def sampled_errors(f):
        return {
            "row_surface_err": float(np.abs((f - ref_rows) @ onehot).max()),
            "patch_err": float(np.abs(f - ref_rows).max()),
        }

    out = []
    for method in args.methods:
        line = {"scene": key, "patches": n, "method": method}
        try:
            f, c, projected = sample_full_rows(spec, rows, method)
        except ValueError as e:
            line["note"] = f"error on sampled rows: {e}"
            out.append(line)
            print(json.dumps(line), flush=True)
            continue
        line.update(sample_cpu=c, projected_cpu=projected, **sampled_errors(f))
        if projected <= args.cap:
            res, c, w = cpu_wall(lambda: nusselt.form_factors(scene, method=method))
            line.update(cpu=c, wall=w, sampled=False)
            line.update(errors(res, ref) if ref is not None else sampled_errors(res.dense()[rows]))
            line["note"] = "whole scene"
        else:
            line.update(cpu=projected, sampled=True, note=f"{len(rows)} rows, CPU projected")
        line["load"] = os.getloadavg()[0]
        out.append(line)
        print(json.dumps(line), flush=True)
    return out


def budget(args):
    """Work units per CPU second: the smallest budget a pair passes (bisection to 2 %), over
    the CPU of the unbudgeted call (plates with a turned blocker)."""
    a, b = rect(0, 1, 0, 1), rect(0, 1, 0, 1, z=1, flip=True)
    obs = [rotz(rect(0.1, 0.6, 0.3, 0.9, z=0.3), 20)]

    def passes(m, o, units):
        try:
            nusselt.view_factor(a, b, obstacles=obs, method=m, budget=units, **o)
            return True
        except ValueError as e:
            assert "budget" in str(e), e
            return False

    settings = [("subdivision", {}), ("adaptive", {}), ("montecarlo", {}), ("quadrature", {}), ("clipping", {})]
    settings += [("analytic", {}), ("montecarlo", {"control_variate": False})]
    settings.append(("subdivision", {"divisions": 64, "source": 16}))
    for m, o in settings:
        lo, hi = 1, 1 << 40
        while hi - lo > max(1, lo // 50):
            mid = (lo + hi) // 2
            lo, hi = (lo, mid) if passes(m, o, mid) else (mid, hi)
        _, c = repeated_cpu(lambda: nusselt.view_factor(a, b, obstacles=obs, method=m, **o), min_total=0.3)
        print(f"{m:12s} {str(o):34s} units {hi:>11d}  CPU {c * 1e3:9.2f} ms  units/s {hi / c:.2e}", flush=True)


def extreme_settings(method):
    """Option sets of `method` at the ends of their allowed ranges: each option alone at its
    low and its high end (the others at their defaults; both values of a flag), and the
    costliest combination (`LONG_CALLS`)."""
    out = [{}]
    for k, o in nusselt.METHODS[method].options.items():
        if k in ("budget", "seed"):
            continue
        if o.kind is bool:
            out.append({k: not o.default})
            continue
        for v in (o.lo, o.hi):
            v = int(v) if o.kind is not float else v
            if (method, k) == ("hemicube", "resolution"):
                v -= v % 2
            out.append({k: v})
    return out + [dict(LONG_CALLS[method])]


def extremes(args):
    """Every method at the ends of its options' ranges on an obstructed and an unobstructed
    pair (and the obstructed one from a point), with a small budget: each call must finish or
    stop with the budget error, in a time the budget bounds (work that the budget does not
    count would show as a call that runs long). Calls still running after `--limit` s are
    interrupted (as Ctrl-C) and reported."""
    import _thread
    import threading

    a, b = rect(0, 1, 0, 1), rect(0, 1, 0, 1, z=1, flip=True)
    cases = {
        "obstructed pair": (a, b, [rect(0.1 * k, 0.1 * k + 0.05, 0.2, 0.8, z=0.5) for k in range(10)]),
        "unobstructed pair": (a, b, []),
    }
    p, n = np.array([0.5, 0.5, 0.0]), np.array([0.0, 0.0, 1.0])
    worst = []
    for method in args.methods:
        point = nusselt.METHODS[method].kind == "pairs"
        for opts in extreme_settings(method):
            calls = {
                k: (lambda a=a, b=b, obs=obs: nusselt.view_factor(a, b, obstacles=obs, method=method, **o))
                for k, (a, b, obs) in cases.items()
                for o in [{**opts, "budget": args.budget}]
            }
            if point:
                o = {**opts, "budget": args.budget}
                obs = cases["obstructed pair"][2]
                calls["obstructed point"] = lambda o=o, obs=obs: nusselt.point_view_factor(
                    p, n, b, obstacles=obs, method=method, **o
                )
            for what, call in calls.items():
                timer = threading.Timer(args.limit, _thread.interrupt_main)
                c0, t0 = time.process_time(), time.perf_counter()
                timer.start()
                try:
                    call()
                    outcome = "finished"
                except ValueError as e:
                    outcome = "budget" if "needs more than budget" in str(e) else f"error: {e}"
                except KeyboardInterrupt:
                    outcome = f"RUNNING after {args.limit} s"
                finally:
                    timer.cancel()
                c, w = time.process_time() - c0, time.perf_counter() - t0
                line = {"method": method, "opts": opts, "call": what, "outcome": outcome, "cpu": round(c, 3)}
                line["wall"] = round(w, 3)
                worst.append(line)
                if args.verbose or c > args.report or not outcome.startswith(("finished", "budget")):
                    print(json.dumps(line), flush=True)
    top = sorted(worst, key=lambda r: -r["cpu"])[:10]
    print(f"{len(worst)} calls at budget={args.budget}; the 10 costliest (CPU s):")
    for r in top:
        print(f"  {r['cpu']:7.2f}  {r['method']:12s} {r['call']:18s} {r['outcome']:10s} {r['opts']}")
    bad = [r for r in worst if not r["outcome"].startswith(("finished", "budget"))]
    print(f"{len(bad)} calls neither finished nor stopped at the budget")


def interrupt_latency(call, after=0.3):
    """Wall seconds from an interrupt (as Ctrl-C, `after` s into `call` repeated) to the
    KeyboardInterrupt; None if the calls ran 60 s without one."""
    import _thread
    import threading

    fired = []

    def fire():
        fired.append(time.perf_counter())
        _thread.interrupt_main()

    timer = threading.Timer(after, fire)
    t0 = time.perf_counter()
    timer.start()
    try:
        while time.perf_counter() - t0 < 60:
            call()
        return None
    except KeyboardInterrupt:
        return time.perf_counter() - fired[0]
    finally:
        timer.cancel()


def interrupt(args):
    a, b = rect(0, 1, 0, 1), rect(0, 1, 0, 1, z=1, flip=True)
    many = [rect(0.1 * k, 0.1 * k + 0.05, 0.2, 0.8, z=0.5) for k in range(10)]
    p, n = np.array([0.5, 0.5, 0.0]), np.array([0.0, 0.0, 1.0])
    cube = None
    for m in args.methods:
        calls = {}
        if m in ("analytic", "contour", "auto"):
            if cube is None:
                room = scenes.room_with_crate(30, 1)  # its walls: a closed 30 x 30 x 6-patch box
                cube = nusselt.Scene.from_polygons([q for q, s in zip(room.polygons, room.surface) if s[0] == "w"])
            calls["scene, 5 400 patches"] = lambda m=m: nusselt.form_factors(cube, method=m)
        if m in LONG_CALLS:
            o = {**LONG_CALLS[m], "budget": 2**62}
            calls["pair, 10 blockers"] = lambda m=m, o=o: nusselt.view_factor(a, b, obstacles=many, method=m, **o)
            if nusselt.METHODS[m].kind == "pairs":
                po = {**o, "panels": 64} if m == "quadrature" else o
                calls["point, 10 blockers"] = lambda m=m, o=po: nusselt.point_view_factor(
                    p, n, b, obstacles=many, method=m, **o
                )
        for what, call in calls.items():
            lat = [interrupt_latency(call) for _ in range(args.repeats)]
            worst = None if None in lat else max(lat)
            line = {"method": m, "call": what, "worst_s": worst, "latency_s": lat}
            print(json.dumps(line), flush=True)


def plot(rows, path):
    """Surface error vs CPU (log-log), one marker per method and scene (matplotlib). Where a
    method ran on sample rows only (office, urban), its error is the sample rows'
    patch-to-surface error (hollow marker), of which the surface-level F is a mean."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5.5))
    exact = PAIR_METHODS + ["auto", "clipping", "analytic", "contour"]
    for key, marker in (("room", "o"), ("office", "s"), ("urban", "^")):
        for r in rows:
            if r.get("scene") != key or r.get("cpu") is None:
                continue
            whole = r.get("surface_err") is not None
            err = max(r["surface_err"] if whole else r.get("row_surface_err", math.nan), 1e-16)
            if not math.isfinite(err):
                continue
            color = "C0" if r["method"] in exact else "C3"
            ax.scatter(r["cpu"], err, marker=marker, facecolors=color if whole else "none", edgecolors=color)
            ax.annotate(r["method"], (r["cpu"], err), fontsize=6, xytext=(3, 3), textcoords="offset points")
    for key, marker in (("room (270)", "o"), ("office (2 322)", "s"), ("urban (2 560)", "^")):
        ax.scatter([], [], marker=marker, facecolors="none", edgecolors="k", label=key)
    ax.legend(fontsize=7, loc="lower right")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("CPU seconds (user + sys, RAYON_NUM_THREADS=2; sampled runs projected)")
    ax.set_ylabel("max surface-level |F - F_auto| (hollow: patch-to-surface, sample rows)")
    ax.set_title("Every method at its defaults (blue: pair methods, red: row methods)")
    ax.title.set_fontsize(9)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="what", required=True)
    c = sub.add_parser("curves")
    c.add_argument("--methods", nargs="+", default=PAIR_METHODS)
    c.add_argument("--quick", action="store_true")
    c.add_argument("--no-room", action="store_true")
    c.add_argument("--json")
    t = sub.add_parser("scenes")
    t.add_argument("--scenes", nargs="+", default=["room", "office", "urban"])
    t.add_argument("--methods", nargs="+", default=ALL_METHODS)
    t.add_argument("--rows", type=int, default=24, help="rows sampled on the big scenes")
    t.add_argument("--cap", type=float, default=60.0, help="CPU s above which a method is only sampled")
    t.add_argument("--sampled-reference", action="store_true", help="the reference on the sample rows only")
    t.add_argument("--json")
    t.add_argument("--plot", help="write the accuracy-vs-CPU plot (PNG) here")
    c.add_argument(
        "--setting", action="append", default=[], help="METHOD:JSON options, e.g. 'quadrature:{\"order\": 8}'"
    )
    i = sub.add_parser("interrupt")
    i.add_argument("--methods", nargs="+", default=ALL_METHODS)
    i.add_argument("--repeats", type=int, default=3)
    sub.add_parser("budget")
    p = sub.add_parser("plot", help="the accuracy-vs-CPU plot from the JSON of `scenes` runs")
    p.add_argument("json", nargs="+")
    p.add_argument("--out", default="docs/methods.png")
    e = sub.add_parser("extremes")
    e.add_argument("--methods", nargs="+", default=ALL_METHODS)
    e.add_argument("--budget", type=int, default=2**20, help="work units per pair or row")
    e.add_argument("--limit", type=float, default=30.0, help="seconds before a call is interrupted")
    e.add_argument("--report", type=float, default=1.0, help="print every call above this CPU s")
    e.add_argument("--verbose", action="store_true")
    args = ap.parse_args()
    if args.what == "curves":
        args.settings = [(s.split(":", 1)[0], json.loads(s.split(":", 1)[1])) for s in args.setting] or None
        curves(args)
    elif args.what == "scenes":
        rows = scenes_table(args)
        if args.plot:
            plot(rows, args.plot)
    elif args.what == "interrupt":
        interrupt(args)
    elif args.what == "plot":
        plot([r for f in args.json for r in json.loads(pathlib.Path(f).read_text())], args.out)
    elif args.what == "extremes":
        extremes(args)
    else:
        budget(args)


if __name__ == "__main__":
    main()
