"""The Cornell box in colour: RGB radiosity with colour bleeding, from the bundled OBJ to a PNG.

1. Load the bundled Cornell box (``python/nusselt/data/cornell_box.obj``, millimetres; surfaces
   ``red``, ``green``, ``light``, white walls and two white blocks) and mesh it into patches.
2. Hemicube form factors between the patches (``method="hemicube"``).
3. Solve ``(I - diag(rho) F) B = E`` per colour channel with :func:`nusselt.radiosity.solve`,
   using the approximate RGB reflectances of the published Cornell Box Data
   (:data:`nusselt.radiosity.CORNELL_REFLECTANCE`) and a warm-white light.
4. Draw it smooth-shaded (radiosity averaged at shared vertices, Gouraud interpolation) with
   :func:`nusselt.render.render_rgb`. The white walls, floor, ceiling and blocks pick up red
   near the red wall and green near the green wall: light reflected once off a coloured wall
   (colour bleeding).

Run (about 5-10 s on two cores):

    python examples/cornell_colour.py                     # writes cornell_colour.png
    python examples/cornell_colour.py --refine 40 --solver shooting --output box.png
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import time

import numpy as np

import nusselt
from nusselt import radiosity
from nusselt.data import bundled
from nusselt.render import CORNELL, render_rgb, vertex_values, write_png


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--refine", type=float, default=60.0, metavar="MM", help="largest patch edge (default: %(default)s)")
    p.add_argument("--solver", default="direct", choices=radiosity.METHODS)
    p.add_argument("--size", type=int, default=400)
    p.add_argument("--output", default="cornell_colour.png")
    args = p.parse_args(argv)

    t0 = time.perf_counter()
    scene = nusselt.Scene.from_file(bundled("cornell_box.obj")).refined(args.refine)
    f = nusselt.form_factors(scene, method="hemicube", resolution=128)
    rho, emit = radiosity.cornell_colours(scene)
    sol = radiosity.solve(f, rho, emit, method=args.solver, tol=1e-8)
    bal = sol.energy_balance(f.areas, rho, emit, f)
    print(f"{len(scene)} patches, {args.solver}: {sol.iterations} iterations, residual {sol.residual:.1e}")
    print(
        "energy per channel (R, G, B): emitted",
        np.round(bal["emitted"] / 1e6, 4),
        "= absorbed",
        np.round(bal["absorbed"] / 1e6, 4),
        "+ escaping through the open front",
        np.round(bal["escaping"] / 1e6, 4),
        "(x 1e6, units of the emission x mm2)",
    )
    # Colour bleeding in numbers: the mean radiosity of the white surfaces near each coloured wall.
    names = [scene.surface_names[s] for s in scene.surface]
    centre = np.array([np.asarray(q).mean(axis=0) for q in scene.polygons])
    for wall in ("floor", "ceiling", "back"):
        m = np.array([n == wall for n in names])
        left, right = m & (centre[:, 0] > 456), m & (centre[:, 0] < 100)
        bl = (sol.radiosity[left] * scene.areas[left, None]).sum(0) / scene.areas[left].sum()
        br = (sol.radiosity[right] * scene.areas[right, None]).sum(0) / scene.areas[right].sum()
        print(
            f"  {wall:8s} next to the red wall: R/G = {bl[0] / bl[1]:.2f}; next to the green wall: "
            f"R/G = {br[0] / br[1]:.2f} (white paint alone: {0.73 / 0.71:.2f} x the light's R/G)"
        )
    colours = radiosity.display_colours(sol.radiosity, emit)
    camera = dataclasses.replace(CORNELL, size=args.size)
    image = render_rgb(scene.polygons, vertex_values(scene.polygons, colours, scene.surface), camera)
    write_png(args.output, image)
    print(f"wrote {os.path.abspath(args.output)} ({time.perf_counter() - t0:.1f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
