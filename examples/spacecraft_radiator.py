"""A spacecraft radiator panel that sees deep space, a warm body wall and a solar array.

For spacecraft thermal engineers: from a geometry file to heat rates, with deep space as the
ambient (sky) node of an open scene.

1. The geometry is written as an OBJ file (metres) and read back: a 1 x 2 m radiator on the
   spacecraft's +z face, the body's side wall rising 1 m at one edge (multi-layer insulation,
   low emissivity), and a 2 x 2 m solar array wing standing 0.2 m beyond the other edge,
   its back (cell-free, high emissivity) towards the radiator.
2. Form factors (``method="auto"``, exact) per named surface; rows sum to less than 1: the rest
   of each hemisphere is deep space.
3. :func:`nusselt.exchange.solve` with deep space at 3 K (``ambient=3.0``): the radiator's
   temperature is given (290 K), and the body wall and array back carry given net fluxes (the
   MLI passes almost nothing: q = 0; the array rejects 150 W/m2 of absorbed sunlight not turned
   into electricity from its back). The answer: the heat the radiator rejects, what it gains
   back from its neighbours compared with a radiator that sees only space, the equilibrium
   temperatures of the neighbours, and the pairwise exchanges (script-F).
4. Then the inverse question: the radiator carries a dissipation of 350 W/m2 and its
   temperature is the unknown.

Run (about 1 s):

    python examples/spacecraft_radiator.py
"""

from __future__ import annotations

import os
import tempfile

import numpy as np

import nusselt
from nusselt import exchange

SIGMA = exchange.SIGMA

# x along the radiator's 1 m side, y along its 2 m side, z out of the spacecraft face.
# Faces are counter-clockwise seen from their front (radiating) side.
OBJ = """\
# spacecraft radiator, body side wall, solar array wing (metres)
v 0 0 0
v 1 0 0
v 1 2 0
v 0 2 0
v 0 0 1
v 0 2 1
v 1.2 0 0.2
v 1.2 2 0.2
v 1.2 0 2.2
v 1.2 2 2.2
o radiator
f 1 2 3 4
o body_wall
f 1 4 6 5
o array_back
f 7 9 10 8
"""

EMISSIVITY = {"radiator": 0.85, "body_wall": 0.05, "array_back": 0.82}  # white paint, MLI, black paint


def main(argv=None) -> int:
    path = os.path.join(tempfile.mkdtemp(prefix="nusselt-radiator-"), "radiator.obj")
    with open(path, "w") as fh:
        fh.write(OBJ)
    scene = nusselt.Scene.from_file(path)
    ff = nusselt.form_factors(scene, method="auto").by_surface()
    print(f"{path}: {scene}")
    print(ff.summary())
    names = ff.names
    eps = np.array([EMISSIVITY[n] for n in names])
    space = 1.0 - ff.row_sums
    print("view of deep space: " + ", ".join(f"{n} {s:.4f}" for n, s in zip(names, space)))

    nan = np.nan
    t = np.array([{"radiator": 290.0}.get(n, nan) for n in names])
    q = np.array([{"body_wall": 0.0, "array_back": 150.0}.get(n, nan) for n in names])
    r = exchange.solve(ff, eps, t, q, ambient=3.0)
    print("\nradiator at 290 K, body wall adiabatic, array back rejecting 150 W/m2, deep space at 3 K:")
    print(r.table())
    k = names.index("radiator")
    alone = eps[k] * SIGMA * (290.0**4 - 3.0**4) * ff.areas[k]
    print(
        f"the radiator rejects {r.heat[k]:.1f} W; seeing only space it would reject {alone:.1f} W "
        f"({100 * (1 - r.heat[k] / alone):.1f} % less: its neighbours hide part of the sky and send radiation back)"
    )
    pair = r.pairwise()
    for j, n in enumerate(names):
        if j != k:
            print(f"  net exchange radiator -> {n}: {pair[k, j]:+.2f} W")
    sf = exchange.script_f(ff, eps)
    print("script-F (A_i SF_ij sigma (T_i^4 - T_j^4) = net exchange i -> j):")
    for i, n in enumerate(names):
        print(f"  {n:11s} " + " ".join(f"{x:8.5f}" for x in sf[i]))
    assert abs(r.heat.sum() - r.ambient_heat) <= 1e-9 * abs(r.heat).max()

    q2 = np.array([{"radiator": 350.0, "body_wall": 0.0, "array_back": 150.0}[n] for n in names])
    r2 = exchange.solve(ff, eps, None, q2, ambient=3.0)
    print(
        f"\nwith 350 W/m2 dissipated in the radiator its temperature is {r2.temperature[k]:.2f} K "
        f"(alone under the sky: {(350.0 / (eps[k] * SIGMA) + 3.0**4) ** 0.25:.2f} K); all to space: "
        f"{r2.ambient_heat:.1f} W = sum of the given heat loads {np.sum(q2 * ff.areas):.1f} W"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
