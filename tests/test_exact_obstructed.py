"""`analytic` and `contour` where a polygon may block: the pair is the exact visible region
integrated over the source (`clipping` to `obstructed_tol`) from the method's own
unobstructed value; a point gets Lambert's formula on the exact visible region. Where
nothing can block, the value is the method's closed form, bit for bit.

The references are independent of the core: closed forms for rectangles (corner
superposition of the point-to-rectangle form, Hottel's directly opposed rectangles) and, for
a blocker between plates, the area integral of the point form over the source by a Gauss rule
on the pieces where the shadow's outline has no kink."""

import numpy as np
import pytest
from conftest import rect
from test_obstructed import room_with_crate

import nusselt

EXACT = ["analytic", "contour"]
LO, HI = rect(0, 1, 0, 1), rect(0, 1, 0, 1, z=1.0, flip=True)
CENTRED = rect(0.25, 0.75, 0.25, 0.75, z=0.5)
# a partition standing through both plates along x = 0.5, wider than they are
PARTITION = np.array([[0.5, -0.2, 0.0], [0.5, 1.2, 0.0], [0.5, 1.2, 1.0], [0.5, -0.2, 1.0]])


def corner_f(a, b, c):
    """F from a plane element to a parallel a x b rectangle at distance c with one corner
    straight above it; odd in a and in b, so signed sizes give the signed corner rectangles."""
    x, y = a / c, b / c
    sx, sy = np.sqrt(1 + x * x), np.sqrt(1 + y * y)
    return (x / sx * np.arctan(y / sx) + y / sy * np.arctan(x / sy)) / (2 * np.pi)


def point_to_rect(x, y, x0, x1, y0, y1, c):
    """F from an upward element at (x, y, 0) to the rectangle [x0, x1] x [y0, y1] at height c
    (facing down), by inclusion-exclusion of corner rectangles."""
    return (
        corner_f(x1 - x, y1 - y, c)
        - corner_f(x0 - x, y1 - y, c)
        - corner_f(x1 - x, y0 - y, c)
        + corner_f(x0 - x, y0 - y, c)
    )


def point_behind_centred_blocker(x, y):
    """F from (x, y, 0) to the unit plate at z = 1 behind the blocker [1/4, 3/4]^2 at z = 1/2:
    the blocker's shadow on the plate is [1/2 - x, 3/2 - x] x [1/2 - y, 3/2 - y], and the
    visible F is the plate's less the part of the shadow on the plate."""
    sx0, sx1 = np.maximum(0.0, 0.5 - x), np.minimum(1.0, 1.5 - x)
    sy0, sy1 = np.maximum(0.0, 0.5 - y), np.minimum(1.0, 1.5 - y)
    return point_to_rect(x, y, 0, 1, 0, 1, 1.0) - point_to_rect(x, y, sx0, sx1, sy0, sy1, 1.0)


def plates_behind_centred_blocker(order=24):
    """F between the unit plates with the centred blocker: the point form integrated over the
    source by Gauss-Legendre on the four quadrants (the shadow's clamps switch at x, y = 1/2,
    the integrand is analytic inside each)."""
    t, w = np.polynomial.legendre.leggauss(order)
    u, wu = np.concatenate([0.25 * (t + 1), 0.25 * (t + 3)]), np.concatenate([0.25 * w, 0.25 * w])
    x, y = np.meshgrid(u, u, indexing="ij")
    return float(np.sum(np.outer(wu, wu) * point_behind_centred_blocker(x, y)))


def opposed_rectangles(a, b, c):
    """Hottel's F between directly opposed parallel a x b rectangles at distance c."""
    x, y = a / c, b / c
    sx, sy = np.sqrt(1 + x * x), np.sqrt(1 + y * y)
    return (
        2
        / (np.pi * x * y)
        * (
            np.log(sx * sy / np.sqrt(1 + x * x + y * y))
            + x * sy * np.arctan(x / sy)
            + y * sx * np.arctan(y / sx)
            - x * np.arctan(x)
            - y * np.arctan(y)
        )
    )


def test_the_references_are_right_where_they_are_known():
    # unobstructed: corner superposition and Hottel's form give the unit plates' 0.19982...
    assert point_to_rect(0.3, 0.6, 0, 1, 0, 1, 1.0) > 0
    t, w = np.polynomial.legendre.leggauss(24)
    u, wu = 0.5 * (t + 1), 0.5 * w
    x, y = np.meshgrid(u, u, indexing="ij")
    free = np.sum(np.outer(wu, wu) * point_to_rect(x, y, 0, 1, 0, 1, 1.0))
    assert free == pytest.approx(opposed_rectangles(1, 1, 1), rel=1e-13)
    assert free == pytest.approx(nusselt.view_factor(LO, HI, method="analytic"), rel=1e-13)
    # the blocked integral converges: orders 16 and 24 agree to rounding
    assert plates_behind_centred_blocker(16) == pytest.approx(plates_behind_centred_blocker(24), rel=1e-12)


@pytest.mark.parametrize("method", EXACT)
def test_a_centred_blocker_between_plates(method):
    ref = plates_behind_centred_blocker()
    free = nusselt.view_factor(LO, HI, method=method)
    f = nusselt.view_factor(LO, HI, obstacles=[CENTRED], method=method)
    assert 0.4 * free < f < free
    # the default obstructed_tol (1e-6 relative to the unobstructed F), and a tight one
    assert f == pytest.approx(ref, abs=1e-6 * free)
    tight = nusselt.view_factor(LO, HI, obstacles=[CENTRED], method=method, obstructed_tol=1e-10)
    assert tight == pytest.approx(ref, abs=1e-9 * free)
    clip = nusselt.view_factor(LO, HI, obstacles=[CENTRED], method="clipping", tol=1e-10)
    assert tight == pytest.approx(clip, abs=1e-9 * free)


@pytest.mark.parametrize("method", EXACT)
def test_a_partition_through_both_plates(method):
    # each half of the source sees only the half of the receiver on its side
    ref = opposed_rectangles(0.5, 1.0, 1.0)
    f = nusselt.view_factor(LO, HI, obstacles=[PARTITION], method=method, obstructed_tol=1e-10)
    assert f == pytest.approx(ref, abs=1e-9)


@pytest.mark.parametrize("method", EXACT)
def test_reciprocity_and_never_more_than_unobstructed(method):
    rng = np.random.default_rng(5)
    wide = rect(-0.5, 1.5, 0, 1, z=1.0, flip=True)  # area 2
    for _ in range(6):
        x, y, z, s = rng.uniform(0, 0.7), rng.uniform(0, 0.7), rng.uniform(0.2, 0.8), rng.uniform(0.1, 0.4)
        blocker = rect(x, x + s, y, y + s, z=z)
        ab = nusselt.view_factor(LO, wide, obstacles=[blocker], method=method, obstructed_tol=1e-9)
        ba = nusselt.view_factor(wide, LO, obstacles=[blocker], method=method, obstructed_tol=1e-9)
        free = nusselt.view_factor(LO, wide, method=method)
        assert 1.0 * ab == pytest.approx(2.0 * ba, abs=2e-8 * free)
        assert ab < free
    # a blocker no ray between the plates meets leaves the closed form as it is, bit for bit
    aside = rect(3, 4, 3, 4, z=0.5)
    assert nusselt.view_factor(LO, HI, obstacles=[aside], method=method) == nusselt.view_factor(LO, HI, method=method)


@pytest.mark.parametrize("method", EXACT)
def test_a_point_behind_a_blocker(method):
    for x, y in [(0.5, 0.5), (0.1, 0.7), (0.9, 0.05)]:
        p = [x, y, 0.0]
        ref = point_behind_centred_blocker(x, y)
        f = nusselt.point_view_factor(p, [0, 0, 1], HI, obstacles=[CENTRED], method=method)
        assert f == pytest.approx(ref, abs=1e-14)
        free = nusselt.point_view_factor(p, [0, 0, 1], HI, method=method)
        assert f < free and free == pytest.approx(point_to_rect(x, y, 0, 1, 0, 1, 1.0), abs=1e-14)


@pytest.fixture(scope="module")
def crate_room():
    polys, surf = room_with_crate(3, 1)
    walls = [k for k, s in enumerate(surf) if s < 6]
    scene = nusselt.Scene.from_polygons(polys)
    clip = nusselt.form_factors(scene, method="clipping", tol=1e-8).dense()
    return polys, walls, scene, clip


@pytest.mark.parametrize("method", EXACT)
def test_a_room_with_a_crate(method, crate_room):
    """On the 60-patch room with a floating crate, at the defaults: every pair the crate
    cannot block keeps the method's closed form bit for bit (the same as in the room without
    the crate), the others agree with `clipping` at a tight tol and are smaller; rows sum to 1."""
    polys, walls, scene, clip = crate_room
    got = nusselt.form_factors(scene, method=method).dense()
    empty = nusselt.form_factors(nusselt.Scene.from_polygons([polys[k] for k in walls]), method=method).dense()
    assert np.abs(got - clip).max() <= 2e-6
    assert np.abs(got.sum(axis=1) - 1).max() <= 2e-6
    g, e = got[np.ix_(walls, walls)], empty
    same, hidden = g == e, g < e * (1 - 1e-3)
    assert np.all(same | (g < e))
    assert same.sum() > 1000 and hidden.sum() > 100, (same.sum(), hidden.sum())
