"""The `nusselt` command line."""

from __future__ import annotations

import argparse
import contextlib
import sys
import warnings
from typing import Any

from . import __version__
from .data import bundled, cornell_box  # noqa: F401 (bundled: its home before nusselt.data)


def _option_value(text: str):
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    if text.lower() in ("true", "false"):
        return text.lower() == "true"
    return text


def _parse_options(pairs: list[str]) -> dict:
    out = {}
    for p in pairs or []:
        if "=" not in p:
            raise ValueError(f"--option expects NAME=VALUE, got {p!r}")
        k, v = p.split("=", 1)
        out[k.strip()] = _option_value(v.strip())
    return out


def cmd_demo(args) -> int:
    """The bundled Cornell box with its two blocks: the surface matrix (obstructed, auto) and a
    picture of every patch coloured by its form factor to the light."""
    import dataclasses
    import os
    import time

    import numpy as np

    from .api import form_factors
    from .render import CORNELL, render, value_range, write_png
    from .scene import Scene

    base = cornell_box()
    # One surface per block for the summary (the OBJ has one object per block face).
    names = [
        base.surface_names[s].split("_")[0] + " block" if "_" in base.surface_names[s] else base.surface_names[s]
        for s in base.surface
    ]
    scene = Scene.from_polygons(base.polygons, surface=names)
    t0 = time.perf_counter()
    res = form_factors(scene, method="auto", obstructed_tol=args.tol)
    t1 = time.perf_counter()
    surf = res.by_surface()
    print(
        f"Cornell box with two blocks ({len(scene)} polygons, mm): form factors F[from, to], method auto, "
        f"obstructed pairs to {args.tol:g} relative ({t1 - t0:.1f} s)"
    )
    print(surf.summary())
    print("(rows sum to less than 1: the box is open at the camera side; the block bottoms stand on the floor)")

    # The light's row on a finer mesh: F(light -> patch) for every patch, obstructed, and the
    # same information per unit area by reciprocity, F(patch -> light) = A_light F(light -> patch) / A_patch.
    fine = scene.refined(args.refine)
    is_light = np.array([fine.surface_names[s] == "light" for s in fine.surface])
    (k_light,) = np.flatnonzero(scene.surface == scene.surface_names.index("light"))
    light, a_light = scene.polygons[k_light], float(scene.areas[k_light])
    polys = fine.polygons
    others = np.flatnonzero(~is_light)
    f_light = _light_row(light, polys, others, args.tol)
    t2 = time.perf_counter()
    f_to_light = np.full(len(fine), np.nan)
    f_to_light[others] = a_light * f_light / fine.areas[others]
    check = abs(f_light.sum() - surf.row_sums[surf.names.index("light")])
    print(
        f"Light row on {len(fine)} patches (edges <= {args.refine:g} mm): sum {f_light.sum():.8f}, "
        f"differs from the surface row by {check:.1e} (additivity) ({t2 - t1:.1f} s)"
    )
    camera = dataclasses.replace(CORNELL, size=args.size)
    image = render(polys, f_to_light, camera, label="F to light", smooth=True, groups=fine.surface)
    out = os.path.abspath(args.output)
    write_png(out, image)
    lo, hi = value_range(f_to_light)
    print(
        f"wrote {out}: every patch coloured by its form factor to the light (colour bar on the right, "
        f"log scale {10**lo:.1e} .. {10**hi:.1e}; darkest = smaller or 0, i.e. in shadow; the light grey)"
    )
    from .cli_radiation import colour_picture

    colour = os.path.splitext(out)[0] + "_colour.png"
    print(colour_picture(fine, colour, camera))
    return 0


def _light_row(light, polys, others, tol):
    """F(light -> patch) for each patch in ``others``, every other patch an obstacle; both
    cores busy (the core releases the GIL)."""
    import os
    from concurrent.futures import ThreadPoolExecutor

    import numpy as np

    from .api import view_factor

    def one(j):
        obstacles = [polys[k] for k in others if k != j]
        return view_factor(light, polys[j], obstacles=obstacles, obstructed_tol=tol)

    with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        return np.array(list(pool.map(one, others)))


def cmd_methods(args) -> int:
    from .methods import describe

    print(describe())
    return 0


#: Seconds a ``nusselt matrix`` run computes before its checkpoint is first written (unless
#: ``--checkpoint DIR`` asks for it from the start): a run that ends sooner writes none, and a
#: kill before then loses at most these seconds of work (Ctrl-C loses nothing).
CHECKPOINT_AFTER = 10.0


def cmd_matrix(args) -> int:
    import os
    import shutil

    from . import zones
    from .api import form_factors
    from .io import write_result
    from .io.writers import MAX_DENSE_ROWS, _check_size, result_format
    from .methods import resolve
    from .scene import Scene

    fmt = result_format(args.output)  # an unknown extension fails before any work
    opts = _parse_options(args.option)
    resolve(args.method, dict(opts))  # an unknown method or option fails before any work
    if args.to_surface is not None and fmt != "vtu":
        raise ValueError(
            f"--to-surface is for .vtu output (F from every patch to a surface, for ParaView); "
            f"{args.output} is .{fmt}: every entry is there already"
        )
    scene = Scene.from_file(args.scene, orient=args.orient, repair=args.repair)
    _report_orientation(scene)
    if args.two_sided:
        scene = scene.with_two_sided(_faces_of_surfaces(scene, args.two_sided, "--two-sided"))
    if args.refine is not None:
        scene = scene.refined(args.refine)  # 0 or negative is refused there
    if args.to_surface is not None and args.to_surface not in scene.surface_names:
        _faces_of_surfaces(scene, [args.to_surface], "--to-surface")  # a typo fails before any work
    n = len(scene.receivers)
    if fmt == "csv" and not args.surfaces:
        _check_size(args.output, n, MAX_DENSE_ROWS, "CSV")  # the writer's check, before any work
    from . import budget
    from .checkpoint import holds_run, remove_dir

    partial = args.checkpoint or args.output + ".partial"
    if holds_run(partial) and not args.resume:
        raise ValueError(f"{partial} holds an interrupted run: add --resume to continue it, or remove it")
    created = not os.path.exists(partial)

    dtype = "float32" if args.float32 else "float64"
    method_info, _ = resolve(args.method, dict(opts))
    sizes = {
        "kind": method_info.kind,
        "threshold": args.threshold,
        "dtype": dtype,
        "with_std": "seed" in method_info.options,
    }
    most, avail = budget.peak_bytes(n, **sizes), budget.available_memory()
    expect = budget.estimated_entries(scene, scene.receivers)
    print(
        f"{args.scene}: {len(scene)} polygons, {n} with rows, {len(scene.surface_names)} surfaces; "
        f"method {args.method}",
        file=sys.stderr,
    )
    print(
        f"memory: about {_gib(budget.peak_bytes(n, entries=expect, **sizes))} for the sparse result "
        f"(~{expect:,} entries: the facing pairs of sampled rows; at most {_gib(most)} if every pair "
        "exchanged radiation)" + (f", {_gib(avail)} available" if avail else ""),
        file=sys.stderr,
    )
    budget.check_disk(args.output, n, **sizes)  # refused before any work; memory: by form_factors
    run_opts: dict[str, Any] = {"dtype": dtype}
    if args.dask:
        run_opts["client"] = _dask_client(args.dask)
    compute = form_factors
    zone_opts: dict[str, Any] = {}
    if zones.scene_zones(scene):
        # a building model: every zone is its own enclosure, computed alone
        compute = zones.zone_form_factors
        if args.zone_name:
            zone_opts["zones"] = [zones.select_zone(scene, args.zone_name)]
        print(
            f"zones: {', '.join(zone_opts.get('zones') or zones.scene_zones(scene))} (each its own enclosure)",
            file=sys.stderr,
        )
    try:
        res = compute(
            scene,
            method=args.method,
            progress=not args.quiet,
            checkpoint=partial,
            resume=args.resume,
            checkpoint_after=0.0 if args.checkpoint else CHECKPOINT_AFTER,
            block_size=args.block_size,
            threshold=args.threshold,
            **run_opts,
            **zone_opts,
            **opts,
        )
    except BaseException as e:
        # keep finished blocks for --resume; a run that finished none leaves nothing behind
        kept = sum(f.startswith("block_") for _, _, fs in os.walk(partial) for f in fs) if os.path.isdir(partial) else 0
        if created and os.path.isdir(partial) and not kept:
            shutil.rmtree(partial, ignore_errors=True)
        if isinstance(e, KeyboardInterrupt) and kept:
            raise KeyboardInterrupt(
                f"interrupted; {kept} finished block(s) are kept in {partial}: "
                "run the same command with --resume to continue"
            ) from None
        raise
    # every row is computed, possibly held in memory only (a deferred checkpoint): a Ctrl-C
    # from here on finishes the output instead of losing the work; a second one abandons it
    with _interrupt_finishes(args.output, partial) as interrupted:
        if args.correct:
            res = _corrected(res, closure=args.correct == "closure")
        if args.surfaces:
            patch_level = res.trust()
            res = res.by_surface()
            res.info["patch_level"] = patch_level
        res.info.update(res.trust())
        write_result(
            args.output, res, scene=scene, to_surface=args.to_surface, zone_name=args.zone_name, compress=args.compress
        )
        remove_dir(partial)  # the manifest last: a Ctrl-C here leaves a checkpoint that resumes
    print(res.summary())
    print(f"written {args.output}")
    if interrupted:
        print(f"nusselt: interrupted after every row was computed; {args.output} is written in full", file=sys.stderr)
        return 130
    return 0


@contextlib.contextmanager
def _interrupt_finishes(output: str, partial: str):
    """Within the block, the first SIGINT only sets the yielded list (and says so on stderr):
    the work it protects (writing a finished result) runs to its end. A second SIGINT raises
    KeyboardInterrupt, naming the checkpoint that holds the finished blocks if there is one."""
    import os
    import signal
    import threading

    interrupted: list[bool] = []
    if threading.current_thread() is not threading.main_thread():
        yield interrupted  # signals reach the main thread only
        return

    def on_sigint(signum, frame) -> None:
        if not interrupted:
            interrupted.append(True)
            print(
                f"nusselt: every row is computed; finishing {output} (Ctrl-C again to abandon it)",
                file=sys.stderr,
            )
            return
        kept = os.path.isdir(partial) and any(f.startswith("block_") for f in os.listdir(partial))
        raise KeyboardInterrupt(
            f"interrupted again: {output} is not written"
            + (f"; the finished blocks are kept in {partial}: run the same command with --resume" if kept else "")
        )

    previous = signal.signal(signal.SIGINT, on_sigint)
    try:
        yield interrupted
    finally:
        signal.signal(signal.SIGINT, previous)


def _dask_client(address: str):
    """A dask.distributed Client: ``local`` or ``local:N`` starts a LocalCluster of N worker
    processes here; a path to a scheduler file (``dask scheduler --scheduler-file``, SLURM
    jobs) or a scheduler address (``tcp://host:8786``) connects to a running cluster."""
    import atexit
    import os

    from .distributed import connect

    if address == "local" or address.startswith("local:"):
        client = connect(local_workers=int(address.split(":", 1)[1]) if ":" in address else None)
    elif address.endswith(".json") and os.path.exists(address):
        client = connect(scheduler_file=address)
    else:
        client = connect(address=address)
    atexit.register(client.close)
    return client


def _report_orientation(scene) -> None:
    """Say on stderr which faces orient turned (a room exported as a solid, say)."""
    info = scene.meta.get("orient", {})
    if info.get("flipped"):
        print(
            f"{scene.source}: turned {len(info['flipped'])} faces of a closed shell facing outward to face "
            f"inward (--orient {info['orient']}; --orient as-is keeps them)",
            file=sys.stderr,
        )


def _faces_of_surfaces(scene, names: list[str], option: str):
    """Face indices of the named surfaces; an unknown name is an error listing the names."""
    import numpy as np

    bad = [n for n in names if n not in scene.surface_names]
    if bad:
        shown = ", ".join(scene.surface_names[:10]) + (" ..." if len(scene.surface_names) > 10 else "")
        raise ValueError(f"{option}: {scene.source} has no surface named {bad[0]!r} (surfaces: {shown})")
    idx = [scene.surface_names.index(n) for n in names]
    return np.flatnonzero(np.isin(scene.surface, idx))


def _gib(b: float) -> str:
    return f"{b / 2**30:.2f} GiB" if b >= 2**28 else f"{b / 2**20:.1f} MiB"


def _corrected(res, *, closure: bool):
    """The weighted least-squares correction (nusselt.correct) applied to a result."""
    import dataclasses

    from .correct import correct
    from .methods import METHODS

    if res.std_err is None and METHODS[res.method].kind == "pairs":
        print(
            f"nusselt: --correct: nothing to do, method {res.method!r} computes every pair once "
            "(reciprocity is exact) and reports no statistical error",
            file=sys.stderr,
        )
        return res
    if closure and res.lost is not None and len(res.lost) and res.lost.max() > 1e-2:
        k = int(res.lost.argmax())
        raise ValueError(
            f"--correct closure needs a closed enclosure, but row {res.names[k]} leaves "
            f"{res.lost[k]:.3g} of its hemisphere unassigned; use --correct reciprocity "
            "(with --resume the finished blocks are reused)"
        )
    before = (res.closure_error, res.reciprocity_error)
    fixed = correct(res.matrix, res.areas, res.std_err, closure=closure)
    out = dataclasses.replace(
        res, matrix=fixed, info={**res.info, "corrected": "closure" if closure else "reciprocity"}
    )
    print(
        f"corrected ({'reciprocity and closure' if closure else 'reciprocity'}): max |row sum - 1| "
        f"{before[0]:.2e} -> {out.closure_error:.2e}, reciprocity error {before[1]:.2e} -> "
        f"{out.reciprocity_error:.2e}",
        file=sys.stderr,
    )
    return out


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="nusselt",
        description="Form factors (view factors) between planar polygons, fast and exact.",
    )
    p.add_argument("--version", action="version", version=f"nusselt {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    d = sub.add_parser(
        "demo",
        help="the bundled Cornell box with two blocks: form factors and a PNG of F to the light",
        description="Computes the form factors of the bundled Cornell box with its two blocks (obstructed, "
        "method auto), prints them per surface, and writes a PNG of the box with every patch coloured by "
        "its form factor to the light.",
    )
    d.add_argument("-o", "--output", default="cornell_box.png", help="PNG to write (default: %(default)s)")
    d.add_argument(
        "--refine",
        type=float,
        default=60.0,
        metavar="MM",
        help="patch edge length for the picture, mm (default: %(default)s)",
    )
    d.add_argument(
        "--tol", type=float, default=1e-4, help="relative accuracy target of obstructed pairs (default: %(default)s)"
    )
    d.add_argument("--size", type=int, default=512, help="image size in pixels (default: %(default)s)")
    d.set_defaults(func=cmd_demo)

    m = sub.add_parser(
        "matrix",
        help="compute the form-factor matrix of a scene file",
        description="Computes F[i, j] (row = source) for every pair of polygons of a scene file and writes "
        "it in the format given by the output's extension. Checkpoint: from the "
        f"{CHECKPOINT_AFTER:g}th second of computing on, finished row blocks are kept in OUTPUT.partial "
        "(or --checkpoint DIR, from the first block) as they finish, so an interrupted run continues with "
        "--resume; a run that ends sooner writes no checkpoint. Ctrl-C loses no finished work (it writes "
        f"the finished blocks first); a kill loses at most the first {CHECKPOINT_AFTER:g} seconds "
        "(none with --checkpoint).",
        epilog="output formats: .npz (sparse matrix, areas, names, row sums, errors; read it with "
        "nusselt.io.load_npz), .csv (dense table), .txt (View3D text output), .idf / .epJSON (EnergyPlus "
        "ZoneProperty:UserViewFactors:BySurfaceName, per surface, one object per zone, all pairs), "
        ".vtu (ParaView: per-cell area, row sum, "
        "and F to --to-surface). Exit status: 0 done, 2 bad input or error, 130 interrupted.",
    )
    m.add_argument(
        "scene",
        help="scene file: .obj, .vs3 (View3D), .idf / .epJSON (EnergyPlus: every zone is "
        "computed as its own enclosure) or any mesh format meshio reads",
    )
    m.add_argument("-o", "--output", required=True, help="output file (.npz, .csv, .txt View3D, .idf, .epJSON, .vtu)")
    m.add_argument("--method", default="auto", help="method name (default: %(default)s; see `nusselt methods`)")
    m.add_argument(
        "--surfaces",
        action="store_true",
        help="aggregate to named surfaces (additivity over receivers, area-weighted sources)",
    )
    m.add_argument(
        "--option",
        action="append",
        metavar="NAME=VALUE",
        help="method option, repeatable (e.g. --option obstructed_tol=1e-4; see `nusselt methods`)",
    )
    m.add_argument(
        "--refine",
        type=float,
        metavar="LENGTH",
        help="split polygons into patches with edges no longer than LENGTH (scene units)",
    )
    m.add_argument(
        "--threshold",
        type=float,
        default=0.0,
        metavar="F",
        help="sparse threshold: drop pairs with F_ij < F and F_ji < F (default 0: keep every nonzero "
        "entry; reciprocity is kept); the largest row mass dropped is reported and stored",
    )
    m.add_argument(
        "--correct",
        choices=["reciprocity", "closure"],
        help="weighted least-squares correction of sampled results: enforce reciprocity "
        "(and, with 'closure', row sums of 1: closed enclosures only); exact entries never change",
    )
    m.add_argument(
        "--resume",
        action="store_true",
        help="continue an interrupted run from OUTPUT.partial or --checkpoint DIR (finished blocks are kept)",
    )
    m.add_argument(
        "--checkpoint",
        metavar="DIR",
        help="keep finished row blocks in DIR from the first block on (default: OUTPUT.partial, written "
        f"only once the run has computed for {CHECKPOINT_AFTER:g} s); removed when the output is written",
    )
    m.add_argument(
        "--block-size",
        type=int,
        default=2_000_000,
        metavar="N",
        help="the most work per block: pairs (pair methods) or row entries (row methods); blocks are "
        "sized from the measured speed to take about half a second each, up to this",
    )
    m.add_argument(
        "--float32",
        action="store_true",
        help="store F as float32 (a third less memory and disk; about 7 significant digits)",
    )
    m.add_argument("--compress", action="store_true", help=".npz output: zip-deflated (smaller, slower)")
    m.add_argument(
        "--dask",
        metavar="SCHEDULER",
        help="run the row blocks on a Dask cluster: a scheduler address (tcp://host:8786), a "
        "scheduler file (.json), or local[:N] for N local worker processes; blocks go to "
        "OUTPUT.partial as they finish, so --resume works as for a local run",
    )
    m.add_argument(
        "--orient",
        choices=["auto", "inward", "outward", "as-is"],
        default="auto",
        help="how closed shells of faces are turned: auto (default) turns a closed shell facing "
        "outward that holds everything else (a room exported as a solid) inward and leaves the "
        "rest; inward / outward turn every closed shell; as-is keeps the file's order",
    )
    m.add_argument(
        "--repair",
        action="store_true",
        help="drop faces of zero area and faces duplicating another (counted in a warning) "
        "instead of refusing the file",
    )
    m.add_argument(
        "--two-sided",
        action="append",
        metavar="SURFACE",
        help="faces of this named surface emit and receive on both sides (repeatable)",
    )
    m.add_argument("--to-surface", metavar="NAME", help="for .vtu output: also store F from every patch to NAME")
    m.add_argument(
        "--zone-name",
        metavar="NAME",
        help="EnergyPlus models (.idf, .epJSON): compute and write only zone NAME; other scenes: the "
        "zone name written to .idf/.epJSON output (default: the scene file's name)",
    )
    m.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    m.set_defaults(func=cmd_matrix)

    ms = sub.add_parser(
        "methods",
        help="list the methods and their options",
        description="Lists every method with its options and defaults.",
    )
    ms.set_defaults(func=cmd_methods)

    from .cli_sensors import add_sensors_parser

    add_sensors_parser(sub)
    from .cli_radiation import add_radiation_parsers

    add_radiation_parsers(sub)
    return p


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    # one line on stderr, as the errors are
    print(f"nusselt: warning: {' '.join(str(message).split())}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    try:
        return _run(argv)
    except KeyboardInterrupt as e:  # at any point of the command, parsing included
        print(f"nusselt: {' '.join(str(e).split()) or 'interrupted'}", file=sys.stderr)
        return 130


def _run(argv: list[str] | None) -> int:
    parser = build_parser()
    if not (sys.argv[1:] if argv is None else argv):
        parser.print_help()  # no command: the help, not an argparse error
        return 2
    args = parser.parse_args(argv)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("always")
            warnings.showwarning = _show_warning
            return args.func(args)
    except (ValueError, TypeError, OSError, MemoryError) as e:
        msg = " ".join(str(e).split()) or type(e).__name__  # one line
        if isinstance(e, MemoryError):
            scene = getattr(args, "scene", None)
            msg = f"out of memory{' with ' + scene if scene and scene not in msg else ''}: {msg}"
        print(f"nusselt: error: {msg}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
