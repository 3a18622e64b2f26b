"""The ``nusselt exchange`` and ``nusselt render`` subcommands (grey exchange, radiosity pictures)."""

from __future__ import annotations

import csv

import numpy as np

from .render import Camera


def _per_surface(items: list[str] | None, names: list[str], what: str, default: np.ndarray) -> np.ndarray:
    """``VALUE`` (every surface) or ``NAME=VALUE`` (one surface), applied in order."""
    out = default.copy()
    for it in items or []:
        name, _, text = it.rpartition("=")
        try:
            v = float(text)
        except ValueError:
            raise ValueError(f"--{what} {it!r}: expected VALUE or SURFACE=VALUE with a number") from None
        if not name:
            out[:] = v
        elif name in names:
            out[names.index(name)] = v
        else:
            raise ValueError(f"--{what} {it!r}: no surface {name!r}; surfaces: {', '.join(names)}")
    return out


def _read_values(path: str, names: list[str], eps, t, q) -> None:
    """CSV with a header ``surface,emissivity,temperature,flux`` (empty cells: not given)."""
    from .io.scenedata import csv_rows

    rows = csv_rows(path, "CSV")
    header = next(rows, (0, []))[1]
    for line, cells in rows:
        if not cells:
            continue  # a blank line, as csv.DictReader skips it
        row = dict(zip(header, cells))
        name = (row.get("surface") or "").strip()
        if name not in names:
            raise ValueError(f"{path}, line {line}: no surface {name!r}; surfaces: {', '.join(names)}")
        k = names.index(name)
        for col, arr in (("emissivity", eps), ("temperature", t), ("flux", q)):
            cell = (row.get(col) or "").strip()
            if cell:
                try:
                    arr[k] = float(cell)
                except ValueError:
                    raise ValueError(f"{path}, line {line}: {col} {cell!r} is not a number") from None


def cmd_exchange(args) -> int:
    from . import exchange
    from .api import form_factors
    from .scene import Scene

    scene = Scene.from_file(args.scene)
    res = form_factors(scene, method=args.method).by_surface()
    names = list(res.names)
    first = [int(np.flatnonzero(scene.surface == k)[0]) for k in res.faces]
    file_eps = np.full(len(names), 0.9) if scene.emissivity is None else np.asarray(scene.emissivity, float)[first]
    eps = _per_surface(args.emissivity, names, "emissivity", file_eps)
    t = _per_surface(args.temperature, names, "temperature", np.full(len(names), np.nan))
    q = _per_surface(args.flux, names, "flux", np.full(len(names), np.nan))
    if args.values:
        _read_values(args.values, names, eps, t, q)
    t[np.isfinite(q)] = np.nan  # a flux replaces a temperature given earlier (e.g. for every surface)
    r = exchange.solve(res, eps, t, q, ambient=args.ambient)
    print(
        f"{args.scene}: {len(names)} surfaces, grey diffuse exchange (net-radiation method), "
        f"T in K, q in W per unit area, Q in W (positive: the surface loses heat)"
    )
    print(r.table())
    if args.output:
        with open(args.output, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(
                ["surface", "area", "emissivity", "temperature_K", "radiosity_W_per_area", "flux_W_per_area", "heat_W"]
            )
            for k, n in enumerate(names):
                w.writerow([n, res.areas[k], eps[k], r.temperature[k], r.radiosity[k], r.flux[k], r.heat[k]])
        print(f"wrote {args.output}")
    return 0


def _triple(text: str, what: str) -> np.ndarray:
    try:
        v = np.array([float(x) for x in text.split(",")])
    except ValueError:
        v = np.zeros(0)
    if v.shape != (3,):
        raise ValueError(f"{what} {text!r}: expected three comma-separated numbers")
    return v


def cmd_render(args) -> int:
    from . import radiosity
    from .scene import Scene

    scene = Scene.from_file(args.scene)
    fine = scene.refined(args.refine) if args.refine else scene
    rho, emit = radiosity.cornell_colours(fine)
    names = list(fine.surface_names)
    for opt, arr in (("reflectance", rho), ("emission", emit)):
        for it in getattr(args, opt) or []:
            name, _, text = it.partition("=")
            if name not in names:
                raise ValueError(f"--{opt} {it!r}: no surface {name!r}; surfaces: {', '.join(names)}")
            arr[fine.surface == names.index(name)] = _triple(text, f"--{opt}")
    if not emit.any():
        raise ValueError("nothing emits: give --emission SURFACE=R,G,B (or name a surface 'light')")
    lo, hi = np.min(fine.vertices, axis=0), np.max(fine.vertices, axis=0)
    centre, extent = (lo + hi) / 2, float(max(hi[0] - lo[0], hi[1] - lo[1]))
    camera = Camera(
        eye=_triple(args.eye, "--eye") if args.eye else np.array([centre[0], centre[1], lo[2] - 1.44 * extent]),
        look=_triple(args.look, "--look") if args.look else np.array([0.0, 0.0, 1.0]),
        up=_triple(args.up, "--up"),
        size=args.size,
    )
    print(
        f"{args.scene}: "
        + colour_picture(
            fine,
            args.output,
            rho=rho,
            emit=emit,
            camera=camera,
            resolution=args.resolution,
            solver=args.solver,
        )
    )
    return 0


def colour_picture(
    fine, path, camera: Camera, *, rho=None, emit=None, resolution: int = 128, solver: str = "direct"
) -> str:
    """Hemicube form factors of the patches of ``fine``, the RGB radiosity solve (Cornell box
    colours unless given) and a smooth-shaded PNG at ``path`` as ``camera`` sees it; returns a
    one-line summary."""
    import os

    from . import radiosity
    from .api import form_factors
    from .render import render_rgb, vertex_values, write_png

    if rho is None or emit is None:
        rho, emit = radiosity.cornell_colours(fine)
    res = form_factors(fine, method="hemicube", resolution=resolution)
    sol = radiosity.solve(res, rho, emit, method=solver)
    colours = radiosity.display_colours(sol.radiosity, emit)
    image = render_rgb(fine.polygons, vertex_values(fine.polygons, colours, fine.surface), camera)
    write_png(path, image)
    return (
        f"{len(fine)} patches, hemicube form factors, RGB radiosity ({solver}, residual {sol.residual:.1e}); "
        f"wrote {os.path.abspath(path)} (smooth shading, colour bleeding from the red and green walls)"
    )


def add_radiation_parsers(sub) -> None:
    e = sub.add_parser(
        "exchange",
        help="grey diffuse radiant exchange between the named surfaces of a scene",
        description="Form factors per named surface, then the net-radiation method. Per surface give a "
        "temperature (K) or a net flux (W per unit area, positive leaving): --temperature 293.15 sets every "
        "surface, --temperature floor=300 one surface (later options win, a --flux replaces a temperature). "
        "--emissivity likewise (default: the file's emissivities, 0.9 for formats without them). Or a CSV "
        "--values with header surface,emissivity,temperature,flux (empty cell: not given). Open scenes: "
        "what escapes goes to a black ambient at --ambient K.",
    )
    e.add_argument("scene")
    e.add_argument("--emissivity", action="append", metavar="[SURFACE=]EPS")
    e.add_argument("--temperature", action="append", metavar="[SURFACE=]K")
    e.add_argument("--flux", action="append", metavar="[SURFACE=]W_PER_AREA")
    e.add_argument("--values", metavar="CSV", help="per-surface values (surface,emissivity,temperature,flux)")
    e.add_argument(
        "--ambient",
        type=float,
        default=None,
        metavar="K",
        help="ambient/sky temperature for an open scene (default: 0 K)",
    )
    e.add_argument("--method", default="auto", help="form-factor method (default: %(default)s)")
    e.add_argument("-o", "--output", help="CSV of the per-surface results")
    e.set_defaults(func=cmd_exchange)

    r = sub.add_parser(
        "render",
        help="RGB radiosity picture of a scene (colour bleeding, smooth shading)",
        description="Meshes the scene, computes hemicube form factors, solves the RGB radiosity system and "
        "draws it. Surfaces named red/green/light get the Cornell box colours, others white (0.73, 0.71, 0.68); "
        "override with --reflectance NAME=R,G,B and --emission NAME=R,G,B.",
    )
    r.add_argument("scene")
    r.add_argument("-o", "--output", required=True, help="PNG to write")
    r.add_argument("--refine", type=float, default=None, metavar="LENGTH", help="largest patch edge (scene units)")
    r.add_argument("--resolution", type=int, default=128, help="hemicube resolution (default: %(default)s)")
    r.add_argument("--solver", default="direct", choices=["direct", "jacobi", "gauss-seidel", "shooting"])
    r.add_argument("--reflectance", action="append", metavar="SURFACE=R,G,B")
    r.add_argument("--emission", action="append", metavar="SURFACE=R,G,B")
    r.add_argument("--eye", metavar="X,Y,Z", help="camera position (default: in front of the scene, at -z)")
    r.add_argument("--look", metavar="X,Y,Z", help="view direction (default: 0,0,1)")
    r.add_argument("--up", default="0,1,0", metavar="X,Y,Z")
    r.add_argument("--size", type=int, default=512, help="image size in pixels (default: %(default)s)")
    r.set_defaults(func=cmd_render)
