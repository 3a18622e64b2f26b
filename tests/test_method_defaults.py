"""Every listed method at its defaults on a closed room with a floating crate, against `auto`
(issue: every listed method usable on a scene at its defaults; timings in bench/methods.py).

Surface-level form factors (area-weighted aggregation to the six walls and six crate faces)
must be within 2e-3 of `auto` for pair methods and 1e-2 for row methods (`analytic` and
`contour` compute the pairs the crate may block by the exact visible region, as `auto`)."""

import numpy as np
import pytest
from conftest import rect
from test_obstructed import room_with_crate

import nusselt

PAIR_TOL, ROW_TOL = 2e-3, 1e-2
SAMPLED_PAIR_METHODS = ["quadrature", "montecarlo", "subdivision", "adaptive"]


def room_scene(n, m):
    polys, surf = room_with_crate(n, m)
    names = [("crate" if k >= 6 else "wall") + str(k) for k in surf]
    return nusselt.Scene.from_polygons(polys, surface=names)


def check_defaults(scene, method, ref):
    spec = nusselt.METHODS[method]
    res = nusselt.form_factors(scene, method=method)
    diff = np.abs(res.by_surface().dense() - ref.by_surface().dense()).max()
    assert diff <= (PAIR_TOL if spec.kind == "pairs" else ROW_TOL), (method, diff)
    # closed: every row sums to 1 within the same bound (the single plane's lost horizon aside)
    lost = 0.0 if res.lost is None else np.max(res.lost)
    assert np.abs(res.row_sums - 1).max() <= (PAIR_TOL if spec.kind == "pairs" else ROW_TOL) + lost


@pytest.fixture(scope="module")
def small_room():
    scene = room_scene(3, 1)  # 60 patches
    return scene, nusselt.form_factors(scene, obstructed_tol=1e-7)


def test_twelve_methods_are_listed():
    assert len(nusselt.METHODS) == 12


@pytest.mark.slow  # ~20-60 s under load: the crate's 1 m faces make large obstructed pairs
@pytest.mark.parametrize("method", list(nusselt.METHODS))
def test_defaults_on_a_small_room_with_a_crate(small_room, method):
    check_defaults(small_room[0], method, small_room[1])


@pytest.fixture(scope="module")
def room_270():
    scene = room_scene(6, 3)
    assert len(scene) == 270
    return scene, nusselt.form_factors(scene, obstructed_tol=1e-7)


@pytest.mark.slow
@pytest.mark.parametrize("method", list(nusselt.METHODS))
def test_defaults_on_the_270_patch_room_with_a_crate(room_270, method):
    check_defaults(room_270[0], method, room_270[1])


LO, HI = rect(0, 1, 0, 1), rect(0, 1, 0, 1, z=1, flip=True)
FLOOR = rect(0, 1, 0, 1)
WALL = np.array([[0, 0, 0], [0, 1, 0], [0, 1, 1], [0, 0, 1]], float)  # x = 0, facing +x
PAIRS = {
    "turned blocker": (LO, HI, [np.array([[0.2, 0.2, 0.3], [0.65, 0.35, 0.3], [0.55, 0.8, 0.3], [0.1, 0.7, 0.3]])]),
    "blocker near source": (LO, HI, [rect(0.3, 0.8, 0.2, 0.7, z=0.08)]),
    "partition": (LO, HI, [np.array([[0.4, 0.2, 0], [0.4, 0.8, 0], [0.4, 0.8, 1], [0.4, 0.2, 1]], float)]),
    "fin": (FLOOR, WALL, [np.array([[0.2, 0.5, 0], [0.6, 0.5, 0], [0.6, 0.5, 0.4], [0.2, 0.5, 0.4]], float)]),
}


@pytest.mark.parametrize("method", SAMPLED_PAIR_METHODS)
@pytest.mark.parametrize("case", list(PAIRS))
def test_sampled_pair_methods_meet_2e3_at_their_defaults(method, case):
    # the accuracy their docs promise on obstructed pairs, against the exact visible region
    a, b, obs = PAIRS[case]
    ref = nusselt.view_factor(a, b, obstacles=obs, method="clipping", tol=1e-10)
    assert ref < 0.95 * nusselt.view_factor(a, b)  # really obstructed
    f = nusselt.view_factor(a, b, obstacles=obs, method=method)
    assert f == pytest.approx(ref, abs=2e-3)
