"""Sky view factors and sky patches: the patch tables (Tregenza, Reinhart counts), the closed
form per patch against numerical integration, sky fractions of tilted elements, an urban
canyon against its closed form (verified here by integration), a roof against Lambert's
form, closure in a closed room, and patch values against the exact form-factor rows."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import dblquad, quad
from test_sensors import box, corner, rect

import nusselt
from nusselt import sky


def test_patch_tables_follow_tregenza_and_reinhart():
    for mf, count in [(1, 145), (2, 577), (4, 2305)]:
        s = sky.reinhart(mf)
        assert len(s) == count
        assert s.solid_angles.sum() == pytest.approx(2 * np.pi, rel=1e-14)
        assert s.horizontal_factors().sum() == pytest.approx(1.0, rel=1e-14)
    t = sky.tregenza()
    bands = np.round(np.degrees(t.alt_lo)).astype(int)
    assert [int((bands == b).sum()) for b in range(0, 96, 12)] == [30, 30, 24, 24, 18, 12, 6, 1]
    assert np.degrees(t.alt_lo[-1]) == pytest.approx(84.0)
    # patch 0 of each row is centred on north (azimuth 0 from +y towards +x)
    assert t.centres[0] == pytest.approx([0.0, np.cos(np.radians(6.0)), np.sin(np.radians(6.0))])


@pytest.mark.parametrize("normal", [[0, 0, 1.0], [1.0, 0, 0], [0.3, 0.4, 0.866], [0.6, 0, -0.8], [-0.2, 0.7, 0.1]])
def test_unobstructed_patch_factors_against_numerical_integration(normal):
    n = np.asarray(normal) / np.linalg.norm(normal)
    s = sky.tregenza()
    f = sky.unobstructed_patch_factors(n, s)[0]
    # the whole sky of an element tilted by beta from the zenith: (1 + cos beta) / 2
    assert f.sum() == pytest.approx((1 + n[2]) / 2, abs=1e-12)

    def g(az, a):
        return max(0.0, np.cos(a) * (n[0] * np.sin(az) + n[1] * np.cos(az)) + n[2] * np.sin(a)) * np.cos(a) / np.pi

    for k in [0, 17, 45, 80, 111, 135, 144]:
        ref = dblquad(g, s.alt_lo[k], s.alt_hi[k], s.az_lo[k], s.az_hi[k], epsabs=1e-12, epsrel=1e-10)[0]
        assert f[k] == pytest.approx(ref, rel=1e-8, abs=1e-11), k  # dblquad on a kinked integrand: ~1e-12


def canyon(w: float, h: float, length: float):
    half = length / 2
    return [
        rect([0, -half, 0], [w, 0, 0], [0, length, 0]),  # floor, up
        rect([0, -half, 0], [0, length, 0], [0, 0, h]),  # west wall, facing +x
        rect([w, -half, 0], [0, 0, h], [0, length, 0]),  # east wall, facing -x
    ]


def test_canyon_floor_centre_against_the_closed_form():
    w, h = 1.0, 1.3
    # closed form of the infinite canyon: W / sqrt(W^2 + 4 H^2); verified by integrating
    # (1/pi) cos(theta) over the escaping directions: theta < atan(W / (2 H |cos phi|))
    integrand = lambda phi: np.sin(np.arctan2(w, 2 * h * abs(np.cos(phi)))) ** 2 / 2 / np.pi
    closed = w / np.sqrt(w * w + 4 * h * h)
    assert quad(integrand, 0, 2 * np.pi, epsabs=1e-13, limit=200)[0] == pytest.approx(closed, rel=1e-11)
    scene = nusselt.Scene.from_polygons(canyon(w, h, 4000.0))
    svf = sky.sky_view_factors_points([[0.5, 0, 0]], [0, 0, 1], scene)[0]
    assert svf == pytest.approx(closed, rel=1e-6)  # the open ends add ~ (W H / L^2)
    patches = sky.sky_patch_factors([[0.5, 0, 0]], [0, 0, 1], scene, nodes=8)[0]
    assert patches.sum() == pytest.approx(closed, abs=3e-3)
    # the zenith cap (within 6 deg of the zenith: 0.14 sideways at the walls' height) is wholly
    # seen, the patch of the first row across the canyon (azimuth 84 deg) wholly hidden, the one
    # along it (north) in part
    t = sky.tregenza()
    assert patches[144] == pytest.approx(t.horizontal_factors()[144], rel=1e-12)
    assert patches[7] == 0.0
    assert 0.2 < patches[0] / t.horizontal_factors()[0] < 0.8


def test_point_under_a_roof_and_in_a_closed_room():
    roof = rect([-3, -2, 2.0], [0, 4, 0], [6, 0, 0])  # faces down, 6 x 4 at height 2
    ground = rect([-50, -50, 0], [100, 0, 0], [0, 100, 0])  # faces up, the point lies on it
    scene = nusselt.Scene.from_polygons([roof, ground], obstruction=[True, False])
    p = np.array([[0.5, -0.5, 0.0], [0.5, -0.5, 1.0]])
    svf = sky.sky_view_factors_points(p, [0, 0, 1], scene)
    for k in range(2):
        c = 2.0 - p[k, 2]
        lam = sum(corner(abs(x - 0.5), abs(y + 0.5), c) for x in (-3, 3) for y in (-2, 2))
        assert svf[k] == pytest.approx(1 - lam, rel=1e-12)
    # nothing above: 1; a vertical element above a ground plane: all but what the ground
    # covers (Lambert's form, tested in test_sensors), a little more than 0.5
    open_ = sky.sky_view_factors_points(
        [[0, 0, 1.0], [0, 0, 1.0]], [[0, 0, 1.0], [1.0, 0, 0]], nusselt.Scene.from_polygons([ground])
    )
    assert open_[0] == 1.0
    assert open_[1] == pytest.approx(1 - nusselt.point_view_factor([0, 0, 1.0], [1.0, 0, 0], ground), rel=1e-12)
    assert 0.5 < open_[1] < 0.5 + 2 * np.arctan(1 / 50) / np.pi  # the ground ends 50 away
    assert sky.sky_patch_factors([[0, 0, 1.0]], [1.0, 0, 0], nusselt.Scene.from_polygons([ground]))[
        0
    ].sum() == pytest.approx(0.5, abs=1e-12)
    room = nusselt.Scene.from_polygons(box((0, 0, 0), (3, 2, 2.5))).refined(0.7)
    rng = np.random.default_rng(5)
    assert (
        np.abs(sky.sky_view_factors_points(rng.uniform(0.1, 1.9, (20, 3)), rng.normal(size=(20, 3)), room)).max()
        < 1e-12
    )
    assert np.abs(sky.sky_view_factors(room)).max() < 1e-12


def test_patch_sky_equals_one_minus_exact_rows_where_no_back_is_seen():
    # A short canyon: the floor and walls see only fronts, so 1 - row sum is the sky view factor
    scene = nusselt.Scene.from_polygons(canyon(1.0, 0.8, 3.0)).refined(0.5)
    rows = nusselt.form_factors(scene)
    svf = sky.sky_view_factors(scene, order=10)
    assert np.abs(svf - (1 - rows.row_sums)).max() < 5e-6  # 3.5e-6 measured
    assert np.array_equal(sky.sky_view_factors(rows), np.clip(1 - rows.row_sums, 0, 1))


def test_errors():
    scene = nusselt.Scene.from_polygons(canyon(1.0, 1.0, 3.0))
    with pytest.raises(ValueError, match="MF must be a positive integer"):
        sky.reinhart(0)
    with pytest.raises(ValueError, match="order must be an integer in 1..64"):
        sky.sky_view_factors(scene, order=0)
    with pytest.raises(ValueError, match="normals row 0: the normal is zero"):
        sky.sky_view_factors_points([[0, 0, 1]], [0, 0, 0], scene)
    with pytest.raises(TypeError, match="expected a Scene or a FormFactors"):
        sky.sky_view_factors("scene.obj")


def test_patch_rows_to_sky_patches():
    # canyon patches over a ground that reaches far enough for the lower hemisphere to be covered:
    # the sum over the sky patches is the patch's sky view factor up to the sampling of edges
    base = nusselt.Scene.from_polygons(canyon(1.0, 0.8, 3.0)).refined(0.5)
    ground = rect([-2000, -2000, -1e-6], [4000, 0, 0], [0, 4000, 0])
    scene = nusselt.Scene.from_polygons(base.polygons + [ground], obstruction=[False] * len(base) + [True])
    pts, w, col = sky.patch_quadrature(scene, 3)
    assert np.bincount(col, w) == pytest.approx(scene.areas[scene.receivers], rel=1e-13)
    f = sky.sky_patch_factors_patches(scene, nodes=8, order=4)
    assert f.shape == (len(base), 145)
    assert np.abs(f.sum(axis=1) - sky.sky_view_factors(scene, order=10)).max() < 3e-3  # 1.3e-3 measured
    # a lone horizontal plate sees every sky patch unobstructed: the closed form exactly
    plate = nusselt.Scene.from_polygons([rect([0, 0, 0], [1, 0, 0], [0, 1, 0])])
    assert sky.sky_patch_factors_patches(plate)[0] == pytest.approx(sky.tregenza().horizontal_factors(), rel=1e-12)
