"""Row methods (hemicube, single-plane, raytrace, nusselt) against the exact `auto` matrix:
accuracy versus cost on a closed room with a floating crate, and throughput on a
few-thousand-patch refinement of the same room.

The room is the cube [0, 3]^3 split into n x n quads per wall (normals inward) with a unit
crate floating inside (one quad per face, normals outward; every crate face sees the room),
the scene of tests/test_obstructed.py::room_with_crate. The reference is
``method="auto"`` with ``obstructed_tol=1e-6`` (exact visible-region clipping for every pair
the crate may block; its real error is about 100x below the tolerance). Surfaces are the six
walls and the six crate faces, so surface-level form factors do not depend on the mesh and the
refined throughput scene is checked against the same surface-level reference.

    python bench/row_methods.py            # full run: the tables of docs/row-methods.md and
                                           # docs/row-methods.svg (about 6 minutes on 2 cores)
    python bench/row_methods.py --quick    # smoke run (tiny settings, seconds), SVG to a temp dir
"""

from __future__ import annotations

import argparse
import math
import os
import pathlib
import platform
import sys
import tempfile
import time

import numpy as np

import nusselt

# The room is the test suite's (one definition for tests and benchmarks).
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests"))
from test_obstructed import room_with_crate  # noqa: E402

# --------------------------------------------------------------------------- geometry


WALLS = ["x=0", "x=3", "y=0", "y=3", "z=0", "z=3"]
SURFACES = WALLS + ["crate " + w.replace("0", "lo").replace("3", "hi").replace("=", "") for w in WALLS]


def room_scene(n):
    polys, surf = room_with_crate(n)
    return nusselt.Scene.from_polygons(polys, surface=[SURFACES[k] for k in surf])


# --------------------------------------------------------------------------- measuring


def timed(fn, min_total=0.5, max_reps=20):
    """Wall time of fn() (best of repeats while the total stays under min_total s; every
    method here is deterministic, so the result of the last call is returned)."""
    best, total, reps = math.inf, 0.0, 0
    while True:
        t0 = time.perf_counter()
        res = fn()
        dt = time.perf_counter() - t0
        best, total, reps = min(best, dt), total + dt, reps + 1
        if total >= min_total or reps >= max_reps:
            return res, best


def label(opts):
    if not opts:
        return "default"
    parts = []
    for k, v in opts.items():
        if k == "min_cell":
            parts.append(f"min_cell=1/{round(1 / v)}")
        elif isinstance(v, float):
            parts.append(f"{k}={v:g}")
        else:
            parts.append(f"{k}={v}")
    return ", ".join(parts)


DEFAULTS = {
    "hemicube": {"resolution": 128},
    "single-plane": {"min_cell": 1 / 128},
    "raytrace": {"rays": 4096},
    "nusselt": {"cells": 4096},
}


def is_default(method, opts):
    return method in DEFAULTS and all(DEFAULTS[method].get(k) == v for k, v in opts.items())


def notes(res, ref_dense=None):
    """Method-specific trust measures: the single-plane horizon loss, raytrace standard errors."""
    out = []
    if res.lost is not None and np.max(res.lost) > 0:
        out.append(f"lost<={np.max(res.lost):.2e}")
    if res.std_err is not None:
        se = res.std_err.toarray() if hasattr(res.std_err, "toarray") else np.asarray(res.std_err)
        out.append(f"max se={se.max():.1e}")
        if ref_dense is not None:
            err = np.abs(res.dense() - ref_dense)
            m = se > 0
            if m.any():
                out.append(f"abs(err)<=2se: {np.mean(err[m] <= 2 * se[m]):.0%}")
            # entries the rays never hit (estimate 0, se 0) although the exact F is not 0
            miss = (~m) & (ref_dense > 0)
            if miss.any():
                out.append(f"unhit F<={ref_dense[miss].max():.1e}")
    return "; ".join(out)


def print_table(header, rows):
    print("| " + " | ".join(header) + " |")
    print("|" + "|".join("---" if i < 2 or i == len(header) - 1 else "---:" for i in range(len(header))) + "|")
    for r in rows:
        print("| " + " | ".join(r) + " |")
    print(flush=True)


# --------------------------------------------------------------------------- parts


def accuracy(n, sweeps, auto_tols, ref_tol):
    scene = room_scene(n)
    N = len(scene)
    print(f"## Accuracy vs cost: room_with_crate({n}), {N} patches, {len(SURFACES)} surfaces\n")
    print(f"Reference: auto, obstructed_tol={ref_tol:g} ...", flush=True)
    ref, t_ref = timed(lambda: nusselt.form_factors(scene, method="auto", obstructed_tol=ref_tol), min_total=0)
    R, Rs = ref.dense(), ref.by_surface().dense()
    print(
        f"(reference computed in {t_ref:.1f} s; max |row sum - 1| = {ref.closure_error:.1e}, "
        f"reciprocity error = {ref.reciprocity_error:.1e})\n",
        flush=True,
    )

    header = [
        "method",
        "setting",
        "wall s",
        "rows/s",
        "max abs err (patch)",
        "max abs err (surface)",
        "max abs(row sum - 1)",
        "notes",
    ]
    rows, points = [], []
    for tol in auto_tols:
        if tol == ref_tol:
            res, dt = ref, t_ref
            pe = se = "reference"
        else:
            res, dt = timed(lambda: nusselt.form_factors(scene, method="auto", obstructed_tol=tol), min_total=0)
            e, es = np.abs(res.dense() - R).max(), np.abs(res.by_surface().dense() - Rs).max()
            pe, se = f"{e:.2e}", f"{es:.2e}"
            points.append(("auto", {"obstructed_tol": tol}, dt, e, es))
        rows.append(
            ["auto", f"obstructed_tol={tol:g}", f"{dt:.2f}", f"{N / dt:.1f}", pe, se, f"{res.closure_error:.1e}", ""]
        )
        print(f"  auto tol={tol:g}: {dt:.2f} s", flush=True)
    for method, settings in sweeps.items():
        for opts in settings:
            res, dt = timed(lambda: nusselt.form_factors(scene, method=method, **opts))
            e = np.abs(res.dense() - R).max()
            es = np.abs(res.by_surface().dense() - Rs).max()
            points.append((method, opts, dt, e, es))
            lab = label(opts) + (" (default)" if is_default(method, opts) else "")
            rows.append(
                [
                    method,
                    lab,
                    f"{dt:.2f}",
                    f"{N / dt:.0f}",
                    f"{e:.2e}",
                    f"{es:.2e}",
                    f"{res.closure_error:.1e}",
                    notes(res, R),
                ]
            )
            print(f"  {method} {lab}: {dt:.2f} s", flush=True)
    print()
    print_table(header, rows)
    return points, t_ref, Rs


def throughput(n, refine, Rs, auto_room, auto_limit):
    base = room_scene(n)
    scene = base.refined(1.0 / refine) if refine > 1 else base
    N = len(scene)
    print(
        f"## Throughput: room_with_crate({n}).refined(max_edge=1/{refine}), {N} patches, default settings\n", flush=True
    )
    header = ["method", "patches", "wall s", "rows/s", "max abs err (surface)", "max abs(row sum - 1)", "notes"]
    rows = []
    for method in DEFAULTS:
        t0 = time.perf_counter()
        res = nusselt.form_factors(scene, method=method)
        dt = time.perf_counter() - t0
        es = np.abs(res.by_surface().dense() - Rs).max()
        rows.append([method, f"{N}", f"{dt:.1f}", f"{N / dt:.0f}", f"{es:.2e}", f"{res.closure_error:.1e}", notes(res)])
        print(f"  {method}: {dt:.1f} s", flush=True)
        del res
    # auto: all pairs, O(N^2); it cannot run on a subset of rows, so it runs on the largest
    # room (finer walls, the same crate) that finishes in about auto_limit seconds (chosen beforehand)
    a_scene = room_scene(auto_room)
    t0 = time.perf_counter()
    res = nusselt.form_factors(a_scene, method="auto")
    dt = time.perf_counter() - t0
    es = np.abs(res.by_surface().dense() - Rs).max()
    rows.append(
        [
            "auto (obstructed_tol=1e-6)",
            f"{len(a_scene)}",
            f"{dt:.1f}",
            f"{len(a_scene) / dt:.1f}",
            f"{es:.2e}",
            f"{res.closure_error:.1e}",
            f"room_with_crate({auto_room}): the largest room that finishes in ~{auto_limit:.0f} s"
            + (f"; not run on {N} patches" if len(a_scene) != N else ""),
        ]
    )
    print(f"  auto on {len(a_scene)} patches: {dt:.1f} s\n", flush=True)
    print_table(header, rows)


# --------------------------------------------------------------------------- SVG


COLORS = {
    "hemicube": "#1f77b4",
    "single-plane": "#ff7f0e",
    "raytrace": "#2ca02c",
    "nusselt": "#d62728",
    "auto": "#444444",
}
MARKERS = {
    "hemicube": "circle",
    "single-plane": "square",
    "raytrace": "diamond",
    "nusselt": "triangle",
    "auto": "cross",
}


def _marker(kind, x, y, color, r=4.5):
    if kind == "circle":
        return f'<circle cx="{x:.1f}" cy="{y:.1f}" r="{r}" fill="{color}"/>'
    if kind == "square":
        return f'<rect x="{x - r:.1f}" y="{y - r:.1f}" width="{2 * r}" height="{2 * r}" fill="{color}"/>'
    if kind == "diamond":
        r *= 1.3
        return (
            f'<polygon points="{x:.1f},{y - r:.1f} {x + r:.1f},{y:.1f} {x:.1f},{y + r:.1f} {x - r:.1f},{y:.1f}" '
            f'fill="{color}"/>'
        )
    if kind == "triangle":
        r *= 1.25
        return (
            f'<polygon points="{x:.1f},{y - r:.1f} {x + 0.87 * r:.1f},{y + 0.5 * r:.1f} '
            f'{x - 0.87 * r:.1f},{y + 0.5 * r:.1f}" fill="{color}"/>'
        )
    return (
        f'<path d="M{x - r:.1f},{y - r:.1f}L{x + r:.1f},{y + r:.1f}M{x - r:.1f},{y + r:.1f}L{x + r:.1f},{y - r:.1f}" '
        f'stroke="{color}" stroke-width="2.5"/>'
    )


def _pow10(k):
    return f'10<tspan dy="-6" font-size="9">{k}</tspan>'


def write_svg(path, points, t_ref, ref_tol, title):
    """Two log-log panels (patch-level and surface-level max abs error vs wall time)."""
    W, H, pw, ph, ml, mt = 1060, 440, 360, 320, 70, 50
    times = [p[2] for p in points] + [t_ref]
    errs = [e for p in points for e in (p[3], p[4]) if e > 0]
    # decades, with room for a marker at the edge
    x0, x1 = math.floor(math.log10(min(times)) - 0.1), math.ceil(math.log10(max(times)) + 0.1)
    y0, y1 = math.floor(math.log10(min(errs)) - 0.1), math.ceil(math.log10(max(errs)) + 0.1)
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" '
        f'font-family="Helvetica, Arial, sans-serif" font-size="12">',
        f'<rect width="{W}" height="{H}" fill="white"/>',
        f'<text x="{W / 2}" y="22" text-anchor="middle" font-size="14">{title}</text>',
    ]
    for panel, (col, name) in enumerate([(3, "patch level (max over F_ij)"), (4, "surface level (by_surface)")]):
        ox = ml + panel * (pw + 110)
        X = lambda t: ox + (math.log10(t) - x0) / (x1 - x0) * pw
        Y = lambda e: mt + (y1 - math.log10(e)) / (y1 - y0) * ph
        out.append(f'<rect x="{ox}" y="{mt}" width="{pw}" height="{ph}" fill="none" stroke="black"/>')
        out.append(f'<text x="{ox + pw / 2}" y="{mt - 8}" text-anchor="middle">{name}</text>')
        for k in range(x0, x1 + 1):
            x = X(10.0**k)
            out.append(f'<line x1="{x:.1f}" y1="{mt}" x2="{x:.1f}" y2="{mt + ph}" stroke="#ddd"/>')
            out.append(f'<text x="{x:.1f}" y="{mt + ph + 18}" text-anchor="middle">{_pow10(k)}</text>')
            for m in range(2, 10):
                if k < x1:
                    xm = X(m * 10.0**k)
                    out.append(f'<line x1="{xm:.1f}" y1="{mt + ph}" x2="{xm:.1f}" y2="{mt + ph - 4}" stroke="black"/>')
        for k in range(y0, y1 + 1):
            y = Y(10.0**k)
            out.append(f'<line x1="{ox}" y1="{y:.1f}" x2="{ox + pw}" y2="{y:.1f}" stroke="#ddd"/>')
            out.append(f'<text x="{ox - 6}" y="{y + 4:.1f}" text-anchor="end">{_pow10(k)}</text>')
        out.append(f'<text x="{ox + pw / 2}" y="{mt + ph + 40}" text-anchor="middle">wall time [s] (2 cores)</text>')
        out.append(
            f'<text transform="translate({ox - 48},{mt + ph / 2}) rotate(-90)" text-anchor="middle">'
            f"max abs error vs exact</text>"
        )
        # the reference's own time: a vertical dashed line (its error, ~ref_tol/100, is not measured)
        xr = X(t_ref)
        out.append(f'<line x1="{xr:.1f}" y1="{mt}" x2="{xr:.1f}" y2="{mt + ph}" stroke="#444" stroke-dasharray="5,4"/>')
        out.append(
            f'<text x="{xr - 4:.1f}" y="{mt + 14}" text-anchor="end" font-size="10" fill="#444">'
            f"auto {ref_tol:g} (reference)</text>"
        )
        for method in COLORS:
            pts = sorted((p for p in points if p[0] == method and p[col] > 0), key=lambda p: p[2])
            if not pts:
                continue
            c = COLORS[method]
            if len(pts) > 1:
                xy = " ".join(f"{X(p[2]):.1f},{Y(p[col]):.1f}" for p in pts)
                out.append(f'<polyline points="{xy}" fill="none" stroke="{c}" stroke-width="1.6"/>')
            for p in pts:
                x, y = X(p[2]), Y(p[col])
                if is_default(method, p[1]):
                    out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="8.5" fill="none" stroke="black"/>')
                out.append(_marker(MARKERS[method], x, y, c))
    # legend, right of the second panel
    lx, ly = ml + 2 * pw + 110 + 16, mt + 10
    for i, method in enumerate(COLORS):
        y = ly + i * 22
        out.append(f'<line x1="{lx}" y1="{y}" x2="{lx + 24}" y2="{y}" stroke="{COLORS[method]}" stroke-width="1.6"/>')
        out.append(_marker(MARKERS[method], lx + 12, y, COLORS[method]))
        out.append(f'<text x="{lx + 32}" y="{y + 4}">{method}</text>')
    y = ly + len(COLORS) * 22
    out.append(f'<circle cx="{lx + 12}" cy="{y}" r="8.5" fill="none" stroke="black"/>')
    out.append(f'<text x="{lx + 32}" y="{y + 4}">default</text>')
    out.append(f'<text x="{lx}" y="{y + 28}" font-size="10">auto: obstructed_tol</text>')
    tols = sorted({p[1]["obstructed_tol"] for p in points if p[0] == "auto"}, reverse=True)
    out.append(f'<text x="{lx}" y="{y + 42}" font-size="10">{", ".join(f"{t:g}" for t in tols)}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


# --------------------------------------------------------------------------- main


FULL = dict(
    n=3,
    sweeps={
        "hemicube": [{"resolution": r} for r in (16, 32, 64, 128, 256)],
        "single-plane": [{"min_cell": 1 / c} for c in (8, 16, 32, 64, 128)],
        "raytrace": [{"rays": r} for r in (256, 1024, 4096, 16384, 65536)],
        "nusselt": [{"cells": c} for c in (256, 1024, 4096, 16384)],
    },
    auto_tols=(1e-3, 1e-4, 1e-6),
    ref_tol=1e-6,
    refine=6,  # 18 x 18 quads per wall, 6 x 6 per crate face: 2160 patches
    auto_room=6,  # 82 s; room_with_crate(8) did not finish in 5 minutes
    auto_limit=120,
)

QUICK = dict(
    n=1,
    sweeps={
        "hemicube": [{"resolution": r} for r in (16, 32)],
        "single-plane": [{"min_cell": 1 / c} for c in (2, 4)],
        "raytrace": [{"rays": r} for r in (256, 1024)],
        "nusselt": [{"cells": c} for c in (64, 256)],
    },
    auto_tols=(1e-3, 1e-4),
    ref_tol=1e-4,
    refine=1,
    auto_room=1,
    auto_limit=5,
)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true", help="tiny smoke run")
    p.add_argument("--svg", help="where to write the plot (default docs/row-methods.svg; --quick: a temp dir)")
    p.add_argument("--no-throughput", action="store_true", help="only the accuracy table and the plot")
    p.add_argument("--refine", type=int, help="throughput scene: room refined to max_edge 1/K m (K x K per 1 m quad)")
    p.add_argument("--auto-room", type=int, help="auto throughput scene: room_with_crate(N)")
    a = p.parse_args()
    cfg = dict(QUICK if a.quick else FULL)
    if a.refine:
        cfg["refine"] = a.refine
    if a.auto_room:
        cfg["auto_room"] = a.auto_room
    svg = a.svg or (
        os.path.join(tempfile.gettempdir(), "row-methods-quick.svg")
        if a.quick
        else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs", "row-methods.svg")
    )
    start = time.perf_counter()
    print(
        f"nusselt {getattr(nusselt, '__version__', '?')}, Python {platform.python_version()}, "
        f"{os.cpu_count()} cores, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}\n",
        flush=True,
    )
    points, t_ref, Rs = accuracy(cfg["n"], cfg["sweeps"], cfg["auto_tols"], cfg["ref_tol"])
    N = len(room_scene(cfg["n"]))
    write_svg(
        svg,
        points,
        t_ref,
        cfg["ref_tol"],
        f"Row methods on room_with_crate({cfg['n']}) ({N} patches): max abs error vs exact auto, against wall time",
    )
    print(f"plot written to {os.path.normpath(svg)}\n", flush=True)
    if not a.no_throughput:
        throughput(cfg["n"], cfg["refine"], Rs, cfg["auto_room"], cfg["auto_limit"])
    print(f"total wall time {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
