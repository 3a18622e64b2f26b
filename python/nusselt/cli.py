"""The `nusselt` command line."""

from __future__ import annotations

import argparse
import sys
from importlib import resources

from . import __version__


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


def bundled(name: str) -> str:
    """Path of a scene shipped with the package (python/nusselt/data)."""
    return str(resources.files("nusselt") / "data" / name)


def cmd_demo(args) -> int:
    from .api import form_factors
    from .scene import Scene

    scene = Scene.from_file(bundled("cornell_empty.obj"))
    res = form_factors(scene, method="auto").by_surface()
    print(f"Empty Cornell box ({len(scene)} polygons, mm), exact form factors F[from, to]:")
    print(res.summary())
    print("(rows sum to less than 1: the box is open at the camera side)")
    return 0


def cmd_methods(args) -> int:
    from .methods import METHODS

    for m in METHODS.values():
        print(f"{m.name:14s} {m.doc}")
        for k, o in m.options.items():
            print(f"{'':16s}{k} = {o.default!r:8}  {o.doc}")
    return 0


def cmd_matrix(args) -> int:
    import os

    from .api import form_factors
    from .scene import Scene

    scene = Scene.from_file(args.scene)
    if args.refine:
        scene = scene.refined(args.refine)
    partial = args.output + ".partial"
    if os.path.exists(partial) and not args.resume:
        raise ValueError(f"{partial} holds an interrupted run: add --resume to continue it, or remove it")
    opts = _parse_options(args.option)
    print(f"{args.scene}: {len(scene)} polygons, {len(scene.receivers)} with rows, "
          f"{len(scene.surface_names)} surfaces; method {args.method}", file=sys.stderr)
    res = form_factors(
        scene,
        method=args.method,
        progress=not args.quiet,
        checkpoint=partial,
        resume=args.resume,
        block_size=args.block_size,
        **opts,
    )
    if args.surfaces:
        res = res.by_surface()
    from .io import write_result

    write_result(args.output, res, scene=scene, to_surface=args.to_surface)
    import shutil

    shutil.rmtree(partial, ignore_errors=True)
    print(res.summary() if len(res) <= 12 else "\n".join(res.summary().splitlines()[:2]))
    print(f"written {args.output}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="nusselt",
        description="Form factors (view factors) between planar polygons, fast and exact.",
    )
    p.add_argument("--version", action="version", version=f"nusselt {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    d = sub.add_parser("demo", help="compute and print the bundled Cornell box")
    d.set_defaults(func=cmd_demo)

    m = sub.add_parser("matrix", help="compute the form-factor matrix of a scene file")
    m.add_argument("scene", help="scene file: .obj, .vs3 or any mesh format meshio reads")
    m.add_argument("-o", "--output", required=True, help="output file (.npz, .csv, .txt View3D, .idf, .vtu)")
    m.add_argument("--method", default="auto", help="method name (see `nusselt methods`)")
    m.add_argument("--surfaces", action="store_true", help="aggregate to named surfaces")
    m.add_argument("--option", action="append", metavar="NAME=VALUE", help="method option, repeatable")
    m.add_argument("--refine", type=float, metavar="LENGTH",
                   help="split polygons into patches with edges no longer than LENGTH (scene units)")
    m.add_argument("--resume", action="store_true",
                   help="continue an interrupted run from OUTPUT.partial (finished blocks are kept)")
    m.add_argument("--block-size", type=int, default=2_000_000, metavar="N",
                   help="work per checkpointed block: pairs (pair methods) or row entries (row methods)")
    m.add_argument("--to-surface", metavar="NAME", help="for .vtu output: also store F from every patch to NAME")
    m.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    m.set_defaults(func=cmd_matrix)

    ms = sub.add_parser("methods", help="list the methods and their options")
    ms.set_defaults(func=cmd_methods)
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except KeyboardInterrupt:
        print("nusselt: interrupted", file=sys.stderr)
        return 130
    except (ValueError, TypeError, OSError) as e:
        print(f"nusselt: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
