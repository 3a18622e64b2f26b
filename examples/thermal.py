"""Radiant exchange in an office: view factors with an obstruction, then grey-body heat flows.

What it shows (for thermal / building engineers):

1. A small room written as a View3D ``.vs3`` input file (the format EnergyPlus's tools
   use), in a temporary directory: a 5 x 4 x 2.7 m office with a window and a radiator
   panel as sub-surfaces of the south wall, and a 1.0 x 0.5 x 1.8 m cabinet standing on the
   floor. The cabinet blocks views between the other surfaces (it is an obstruction) and
   takes part in the exchange: its five faces are combined into one surface ``cabinet``
   (View3D's ``cmb`` field), and its footprint is cut out of the floor by a null surface.
2. Form factors with ``method="auto"`` (exact visible regions for the pairs the cabinet may
   block), aggregated to the named surfaces, with the reciprocity and closure checks.
3. The grey-body (net radiation) method with :func:`nusselt.exchange.solve`: radiosities J from

       sum_j (delta_ij - (1 - eps_i) F_ij) J_j = eps_i sigma T_i^4,

   then the net radiative flux leaving each surface, q_i = J_i - sum_j F_ij J_j (W/m2),
   and Q_i = A_i q_i (W). In a closed enclosure the Q_i add up to zero.
4. The view factors written for other tools with ``nusselt.io.write_result``: an EnergyPlus
   ``ZoneProperty:UserViewFactors:BySurfaceName`` object (``.idf``) and View3D's text output
   (``.txt``, with the emissivities of the ``.vs3`` file).

Run (about 10 s on two cores):

    python examples/thermal.py                    # outputs go to a new temporary directory
    python examples/thermal.py --outdir results   # or to a directory of your choice

Lengths are in metres here, but any unit gives the same view factors.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

import numpy as np

import nusselt

SIGMA = 5.670374419e-8  # Stefan-Boltzmann constant, W/(m2 K4)

# View3D 3.2 input, geometry form 'F 3': vertices (V n x y z) and surfaces
# (S n v1 v2 v3 v4 base cmb emit name), vertices counter-clockwise seen from the front (the
# side facing into the room). x east, y north, z up, metres.
OFFICE_VS3 = """\
T Office 5 x 4 x 2.7 m with a window, a radiator and a cabinet
C encl=1 list=0 eps=1.0e-6
F 3
!  n    x    y    z
V  1  0.0  0.0  0.0      ! room corners, floor
V  2  5.0  0.0  0.0
V  3  5.0  4.0  0.0
V  4  0.0  4.0  0.0
V  5  0.0  0.0  2.7      ! room corners, ceiling
V  6  5.0  0.0  2.7
V  7  5.0  4.0  2.7
V  8  0.0  4.0  2.7
V  9  1.5  0.0  0.9      ! window, 2.0 x 1.2 m
V 10  3.5  0.0  0.9
V 11  3.5  0.0  2.1
V 12  1.5  0.0  2.1
V 13  1.5  0.0  0.15     ! radiator panel under the window, 2.0 x 0.6 m
V 14  3.5  0.0  0.15
V 15  3.5  0.0  0.75
V 16  1.5  0.0  0.75
V 17  3.9  1.5  0.0      ! cabinet, 1.0 x 0.5 x 1.8 m
V 18  4.9  1.5  0.0
V 19  4.9  2.0  0.0
V 20  3.9  2.0  0.0
V 21  3.9  1.5  1.8
V 22  4.9  1.5  1.8
V 23  4.9  2.0  1.8
V 24  3.9  2.0  1.8
!  n  v1 v2 v3 v4  base cmb  emit  name
S  1   1  2  3  4   0   0   0.90  floor
S  2   5  8  7  6   0   0   0.90  ceiling
S  3   1  5  6  2   0   0   0.90  south_wall
S  4   9 12 11 10   3   0   0.84  window          ! sub-surface of the south wall (base 3)
S  5  13 16 15 14   3   0   0.95  radiator        ! sub-surface of the south wall (base 3)
S  6   3  7  8  4   0   0   0.90  north_wall
S  7   2  6  7  3   0   0   0.90  east_wall
S  8   4  8  5  1   0   0   0.90  west_wall
N  9  17 20 19 18   1   0   0.00  footprint       ! null surface: a hole in the floor (base 1), facing down as View3D wants
S 10  21 22 23 24   0   0   0.80  cabinet         ! top
S 11  17 21 24 20   0  10   0.80  cabinet_west    ! sides, combined into surface 10 (cmb)
S 12  18 19 23 22   0  10   0.80  cabinet_east
S 13  17 18 22 21   0  10   0.80  cabinet_south
S 14  20 24 23 19   0  10   0.80  cabinet_north
End of data
"""

# Surface temperatures, degrees Celsius (a winter day: cold window, hot radiator).
TEMPERATURE_C = {
    "floor": 20.0,
    "ceiling": 21.0,
    "south_wall": 17.0,
    "window": 6.0,
    "radiator": 55.0,
    "north_wall": 19.5,
    "east_wall": 19.0,
    "west_wall": 19.0,
    "cabinet": 20.0,
}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument(
        "--outdir", help="directory for office.vs3, office.idf and office.txt (default: a new temporary directory)"
    )
    args = p.parse_args(argv)
    outdir = args.outdir or tempfile.mkdtemp(prefix="nusselt-thermal-")
    os.makedirs(outdir, exist_ok=True)

    # 1. the scene, from a View3D file
    vs3 = os.path.join(outdir, "office.vs3")
    with open(vs3, "w") as fh:
        fh.write(OFFICE_VS3)
    scene = nusselt.Scene.from_file(vs3)
    print(f"{vs3}: {scene}")
    print(f"  named surfaces: {', '.join(scene.surface_names)}")
    print("  (the floor with the cabinet's footprint cut out and the south wall around the window and the")
    print("   radiator are split into convex polygons; they stay one named surface each)")

    # 2. form factors, exact visibility around the cabinet
    t0 = time.perf_counter()
    patches = nusselt.form_factors(scene, method="auto")
    print(f"\nform factors of {len(patches)} polygons, method auto: {time.perf_counter() - t0:.1f} s")
    surf = patches.by_surface()  # F_ST = sum_{i in S, j in T} A_i F_ij / A_S
    print(surf.summary())
    print(f"reciprocity: max |A_i F_ij - A_j F_ji| / max(A_i F_ij, A_j F_ji) = {surf.reciprocity_error:.1e}")
    print(
        f"closure:     max |sum_j F_ij - 1| = {surf.closure_error:.1e} "
        f"(obstructed pairs are computed to obstructed_tol = {patches.info['options']['obstructed_tol']:g})"
    )
    assert surf.reciprocity_error < 1e-12 and surf.closure_error < 1e-4

    # 3. grey-body radiant exchange between the named surfaces
    eps = scene.emissivity[surf.faces]  # the .vs3 emissivities, one per named surface
    t_k = np.array([TEMPERATURE_C[name] for name in surf.names]) + 273.15
    ex = nusselt.exchange.solve(surf, eps, t_k)  # net-radiation method, closed enclosure
    j, q, big_q = ex.radiosity, ex.flux, ex.heat
    print("\nnet radiation (positive: the surface loses heat by radiation)")
    print(f"{'surface':12s} {'area m2':>8s} {'eps':>5s} {'T C':>6s} {'J W/m2':>8s} {'q W/m2':>8s} {'Q W':>8s}")
    for k, name in enumerate(surf.names):
        print(
            f"{name:12s} {surf.areas[k]:8.2f} {eps[k]:5.2f} {t_k[k] - 273.15:6.1f} {j[k]:8.1f} {q[k]:8.2f} "
            f"{big_q[k]:8.1f}"
        )
    print(f"sum of Q = {big_q.sum():.2e} W (energy balance: zero in a closed enclosure, up to the closure error)")
    mrt = (np.sum(surf.areas * t_k**4) / surf.areas.sum()) ** 0.25 - 273.15
    print(
        f"the radiator gives off {big_q[surf.names.index('radiator')]:.0f} W by radiation, the window takes in "
        f"{-big_q[surf.names.index('window')]:.0f} W; area-weighted radiant temperature {mrt:.1f} C"
    )

    # 4. view factors for EnergyPlus and for View3D users (both per named surface)
    idf = os.path.join(outdir, "office.idf")
    txt = os.path.join(outdir, "office.txt")
    nusselt.io.write_result(idf, patches, scene=scene)  # zone name: the file's stem ("office")
    nusselt.io.write_result(txt, patches, scene=scene)  # View3D output, emissivities from the .vs3
    print(f"\nwrote {idf} (EnergyPlus ZoneProperty:UserViewFactors:BySurfaceName, zone 'office')")
    print(f"wrote {txt} (View3D 3.2 text output)")
    with open(idf) as fh:
        print("".join(fh.readlines()[:8]) + "    ...")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
