"""`nusselt sensors`: view factors and radiant temperatures at points read from CSV."""

from __future__ import annotations

import csv
import sys

import numpy as np


def _temperatures(pairs: list[str] | None) -> dict[str, float]:
    out: dict[str, float] = {}
    for p in pairs or []:
        name, sep, value = p.partition("=")
        if not sep or not name.strip():
            raise ValueError(f"--temperature expects SURFACE=KELVIN, got {p!r}")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            raise ValueError(f"--temperature {p!r}: {value!r} is not a number (kelvin)") from None
    return out


def cmd_sensors(args) -> int:
    from . import sensors
    from .cli import _parse_options
    from .scene import Scene

    temps = _temperatures(args.temperature)
    scene = Scene.from_file(args.scene)
    pts, normals = sensors.read_points_csv(args.points)
    opts = _parse_options(args.option)
    f = sensors.point_view_factors(pts, normals, scene, method=args.method, by_surface=True, dense=True, **opts)
    unit = normals / np.linalg.norm(normals, axis=1)[:, None]
    cols = {"x": pts[:, 0], "y": pts[:, 1], "z": pts[:, 2], "nx": unit[:, 0], "ny": unit[:, 1], "nz": unit[:, 2]}
    for s, name in enumerate(scene.surface_names):
        cols[f"F_{name}"] = f[:, s]
    cols["F_uncovered"] = np.clip(1.0 - f.sum(axis=1), 0.0, None)
    if temps:
        cols["t_plane"] = sensors.radiant_temperature(f, scene, temps, rest=args.rest)
        cols[f"t_mrt_{args.form}"] = sensors.mean_radiant_temperature(
            pts, scene, temps, form=args.form, rest=args.rest, method=args.method
        )
    elif args.rest is not None:
        raise ValueError("--rest needs --temperature for the scene's surfaces")
    with open(args.output, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(list(cols))
        for k in range(len(pts)):
            w.writerow([repr(float(v[k])) for v in cols.values()])
    print(f"{len(pts)} points x {len(scene.surface_names)} surfaces -> {args.output}", file=sys.stderr)
    return 0


def add_sensors_parser(sub) -> None:
    s = sub.add_parser(
        "sensors",
        help="view factors and radiant temperatures at points read from CSV",
        description="Computes, for every point of a CSV file (columns x,y,z,nx,ny,nz; a header row naming them, "
        "other columns ignored), the view factor from a plane element with that normal to every named surface of "
        "the scene (obstructed by every polygon), and with --temperature the plane radiant temperature of that "
        "element and the mean radiant temperature (--form) at the point.",
        epilog="output CSV columns: x,y,z,nx,ny,nz, F_<surface> per surface, F_uncovered (1 - their sum: what no "
        "surface covers, e.g. the sky), and with --temperature t_plane and t_mrt_<form> (kelvin). Surfaces are "
        "taken as black (ISO 7726). Exit status: 0 done, 2 bad input or error.",
    )
    s.add_argument("scene", help="scene file (.obj, .vs3, any mesh format meshio reads)")
    s.add_argument("points", help="CSV of points: header with x,y,z,nx,ny,nz")
    s.add_argument("-o", "--output", required=True, help="CSV to write")
    s.add_argument(
        "--temperature",
        action="append",
        metavar="SURFACE=KELVIN",
        help="surface temperature in kelvin, repeatable; every surface a point sees needs one",
    )
    s.add_argument(
        "--rest",
        type=float,
        metavar="KELVIN",
        help="temperature of whatever the scene does not cover (sky, ambient) for open scenes",
    )
    s.add_argument(
        "--form",
        choices=["sphere", "standing", "seated"],
        default="sphere",
        help="mean radiant temperature of a small sphere (exact angle factors) or ISO 7726's six-"
        "direction form for a standing/seated person facing +x (default: %(default)s)",
    )
    s.add_argument("--method", default="auto", help="method (default: %(default)s; auto/clipping are exact)")
    s.add_argument("--option", action="append", metavar="NAME=VALUE", help="method option, repeatable")
    s.set_defaults(func=cmd_sensors)
