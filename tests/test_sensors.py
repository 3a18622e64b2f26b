"""Sensors: point_view_factors against Lambert's closed forms and numerical integration,
closure in an enclosure, the per-point API with obstacles, surface sums; sphere sensors
against the solid angle of a rectangle; radiant temperatures against enclosures whose answer
is known; the points CSV and the `nusselt sensors` command."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import dblquad

import nusselt
from nusselt import sensors


def rect(p0, u, v) -> np.ndarray:
    p0, u, v = (np.asarray(x, float) for x in (p0, u, v))
    return np.array([p0, p0 + u, p0 + u + v, p0 + v])


def box(lo, hi, inward=True):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    out = [
        rect([x0, y0, z0], [0, y1 - y0, 0], [x1 - x0, 0, 0]),  # -z face, front down
        rect([x0, y0, z1], [x1 - x0, 0, 0], [0, y1 - y0, 0]),  # +z face, front up
        rect([x0, y0, z0], [x1 - x0, 0, 0], [0, 0, z1 - z0]),  # -y
        rect([x0, y1, z0], [0, 0, z1 - z0], [x1 - x0, 0, 0]),  # +y
        rect([x0, y0, z0], [0, 0, z1 - z0], [0, y1 - y0, 0]),  # -x
        rect([x1, y0, z0], [0, y1 - y0, 0], [0, 0, z1 - z0]),  # +x
    ]
    return [f[::-1].copy() for f in out] if inward else out


def corner(a, b, c):
    """Howell's catalogue B-3: plane element at the corner of a parallel a x b rectangle at
    distance c (checked against dblquad in test_corner_formula_checked)."""
    x, y = a / c, b / c
    return (
        x / np.sqrt(1 + x * x) * np.arctan(y / np.sqrt(1 + x * x))
        + y / np.sqrt(1 + y * y) * np.arctan(x / np.sqrt(1 + y * y))
    ) / (2 * np.pi)


def kernel_quad(p, n, poly):
    """F by direct numerical integration of cos1 cos2 / (pi r^2) over a rectangle p0 + s u + t v."""
    p0, u, v = poly[0], poly[1] - poly[0], poly[3] - poly[0]
    nb = np.cross(u, v)
    area = np.linalg.norm(nb)
    nb = nb / area

    def f(t, s):
        r = p0 + s * u + t * v - p
        r2 = r @ r
        c1, c2 = r @ n, -(r @ nb)
        return c1 * c2 / (np.pi * r2 * r2) * area if c1 > 0 and c2 > 0 else 0.0

    return dblquad(f, 0, 1, 0, 1, epsabs=1e-13, epsrel=1e-12)[0]


def test_corner_formula_checked():
    for a, b, c in [(1.0, 2.0, 0.7), (0.3, 0.5, 1.5)]:
        ref = kernel_quad(np.zeros(3), np.array([0, 0, 1.0]), rect([0, 0, c], [0, b, 0], [a, 0, 0]))
        assert corner(a, b, c) == pytest.approx(ref, rel=1e-10, abs=0)


def test_parallel_and_perpendicular_rectangles_against_closed_form_and_quadrature():
    roof = rect([-0.4, -0.3, 1.2], [0, 1.3, 0], [1.1, 0, 0])  # front faces down, x in [-0.4, 0.7], y in [-0.3, 1.0]
    side = rect([2.0, -0.5, 0.2], [0, 0, 1.0], [0, 1.5, 0])  # the plane x = 2, front faces -x
    scene = nusselt.Scene.from_polygons([roof, side])
    pts = np.array([[0.0, 0.0, 0.0], [0.1, 0.2, 0.3]])
    f = sensors.point_view_factors(pts, [0, 0, 1], scene, dense=True)
    # parallel: superposition of four corner rectangles around the foot of the point
    for k, p in enumerate(pts):
        c = 1.2 - p[2]
        ref = sum(corner(abs(x - p[0]), abs(y - p[1]), c) for x in (-0.4, 0.7) for y in (-0.3, 1.0))
        assert f[k, 0] == pytest.approx(ref, rel=1e-12, abs=0)
    # perpendicular: direct numerical integration
    for k, p in enumerate(pts):
        assert f[k, 1] == pytest.approx(kernel_quad(p, np.array([0, 0, 1.0]), side), rel=1e-9, abs=0)
    # tilted normals, one per point, against the per-point API
    normals = np.array([[0.3, -0.2, 0.9], [0.8, 0.1, 0.4]])
    g = sensors.point_view_factors(pts, normals, scene, dense=True)
    for k in range(2):
        n = normals[k] / np.linalg.norm(normals[k])
        for j, poly in enumerate([roof, side]):
            assert g[k, j] == pytest.approx(nusselt.point_view_factor(pts[k], n, poly), rel=1e-13, abs=1e-16)


def test_closure_inside_a_box_and_symmetry_at_its_centre():
    scene = nusselt.Scene.from_polygons(box((0, 0, 0), (1, 2, 1.5))).refined(0.4)
    rng = np.random.default_rng(3)
    pts = rng.uniform([0.05, 0.05, 0.05], [0.95, 1.95, 1.45], size=(40, 3))
    normals = rng.normal(size=(40, 3))
    f = sensors.point_view_factors(pts, normals, scene)
    assert np.abs(f.sum(axis=1) - 1).max() < 1e-12
    # the centre of a cube facing +z: the ceiling is four corner rectangles, the walls share the rest
    cube = nusselt.Scene.from_polygons(box((0, 0, 0), (1, 1, 1)), surface=["floor", "ceiling", "s", "n", "w", "e"])
    row = sensors.point_view_factors([0.5, 0.5, 0.5], [0, 0, 1], cube, by_surface=True, dense=True)[0]
    assert row[1] == pytest.approx(4 * corner(0.5, 0.5, 0.5), rel=1e-13, abs=0)
    assert row[0] == 0
    assert np.allclose(row[2:], (1 - row[1]) / 4, rtol=1e-13, atol=0)


def test_obstructed_rows_equal_the_per_point_api_with_obstacles():
    room = box((0, 0, 0), (4, 3, 2.5))
    crate = box((1.0, 1.0, 0.3), (2.2, 2.0, 1.1), inward=False)
    screen = [rect([2.5, 0.5, 0.2], [0, 1.5, 0], [0, 0, 1.5])]  # a thin screen, obstruction only
    polys = room + crate + screen
    scene = nusselt.Scene.from_polygons(polys, obstruction=[False] * 12 + [True])
    pts = np.array([[0.5, 0.5, 0.6], [3.0, 2.5, 0.5], [1.6, 1.5, 1.8], [3.5, 1.0, 1.0]])
    normals = np.array([[1, 0.2, 0.1], [-1, -0.5, 0.3], [0, 0, -1], [-1, 0, 0]], float)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    f = sensors.point_view_factors(pts, normals, scene, dense=True)
    assert f.shape == (4, 12)
    hidden = 0
    for k in range(4):
        for j in range(12):
            others = [polys[i] for i in range(13) if i != j]
            want = nusselt.point_view_factor(pts[k], normals[k], polys[j], obstacles=others)
            free = nusselt.point_view_factor(pts[k], normals[k], polys[j])
            hidden += want < free * (1 - 1e-6)
            assert f[k, j] == pytest.approx(want, rel=1e-12, abs=1e-15), (k, j)
    assert hidden >= 5
    # the screen takes what it hides: the row sums miss exactly the screen's share
    assert np.all(f.sum(axis=1) <= 1 + 1e-12)


@pytest.mark.parametrize("offset", [0.0, 7.0, 1e3])
def test_obstructed_rows_of_a_tiny_scene_far_out(offset):
    # a room 1e-6 across at (offset, offset, offset): the candidate test's triangle around each
    # sensor was below the rounding of its coordinates and the crate hid nothing (0.2395 for
    # 0.1387), or at 1e3 the call raised
    s = 1e-6
    room = [s * f + offset for f in box((0, 0, 0), (4, 3, 2.5))]
    crate = [s * f + offset for f in box((1.0, 1.0, 0.3), (2.2, 2.0, 1.1), inward=False)]
    polys = room + crate
    scene = nusselt.Scene.from_polygons(polys)
    pts = s * np.array([[0.5, 0.5, 0.6], [3.0, 2.5, 0.5], [1.6, 1.5, 0.01]]) + offset
    normals = np.array([[1, 0.2, 0.1], [-1, -0.5, 0.3], [0, 0, 1]], float)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    f = sensors.point_view_factors(pts, normals, scene, dense=True)
    hidden = 0
    for k in range(len(pts)):
        for j in range(len(polys)):
            others = [polys[i] for i in range(len(polys)) if i != j]
            want = nusselt.point_view_factor(pts[k], normals[k], polys[j], obstacles=others)
            free = nusselt.point_view_factor(pts[k], normals[k], polys[j])
            hidden += want < free * (1 - 1e-3)
            # (coordinates carry 1e-16 x offset, 1e-10 x offset of the scene's size)
            assert f[k, j] == pytest.approx(want, abs=1e-9 + 1e-8 * offset), (k, j)
    assert hidden >= 3
    # closed room: every sensor sees all of it, crate included
    np.testing.assert_allclose(f.sum(axis=1), 1.0, atol=1e-8 + 1e-8 * offset)


def test_by_surface_is_the_sum_of_patch_columns_and_dense_equals_sparse():
    scene = nusselt.Scene.from_polygons(box((0, 0, 0), (2, 1, 1)), surface=["a", "b", "c", "c", "d", "a"]).refined(0.3)
    pts = np.array([[0.3, 0.5, 0.5], [1.5, 0.2, 0.8]])
    patch = sensors.point_view_factors(pts, [1, 0, 0], scene)
    surf = sensors.point_view_factors(pts, [1, 0, 0], scene, by_surface=True, dense=True)
    assert surf.shape == (2, 4)
    for s in range(len(scene.surface_names)):
        cols = np.flatnonzero(scene.surface[scene.receivers] == s)
        assert surf[:, s] == pytest.approx(patch.toarray()[:, cols].sum(axis=1), rel=1e-14, abs=1e-16)
    assert np.array_equal(patch.toarray(), sensors.point_view_factors(pts, [1, 0, 0], scene, dense=True))


def test_sphere_sensor_solid_angle_of_a_rectangle_and_mean_over_normals():
    # On the axis of an a x b rectangle at distance d: omega = 4 asin(ab / sqrt((a^2 + 4d^2)(b^2 + 4d^2)))
    a, b, d = 1.0, 2.0, 0.8
    plate = rect([-a / 2, -b / 2, d], [0, b, 0], [a, 0, 0])
    scene = nusselt.Scene.from_polygons([plate])
    s = sensors.sphere_view_factors([0, 0, 0], scene, dense=True)[0, 0]
    omega = 4 * np.arcsin(a * b / np.sqrt((a * a + 4 * d * d) * (b * b + 4 * d * d)))
    assert s == pytest.approx(omega / (4 * np.pi), rel=1e-13, abs=0)
    # inside a box: six faces at the centre of a cube are 1/6 each; anywhere the row sums to 1
    cube = nusselt.Scene.from_polygons(box((0, 0, 0), (1, 1, 1)))
    f = sensors.sphere_view_factors([[0.5, 0.5, 0.5], [0.2, 0.7, 0.9]], cube, dense=True)
    assert np.allclose(f[0], 1 / 6, rtol=1e-13, atol=0)
    assert f[1].sum() == pytest.approx(1.0, abs=1e-13)
    # obstructed: the mean of the plane element's F over normals (Fibonacci sphere, 4000)
    room = box((0, 0, 0), (4, 3, 2.5)) + box((1.0, 1.0, 0.3), (2.2, 2.0, 1.1), inward=False)
    scene = nusselt.Scene.from_polygons(room)
    p = np.array([0.6, 0.8, 0.9])
    k = np.arange(4000) + 0.5
    z = 1 - 2 * k / 4000
    phi = np.pi * (1 + 5**0.5) * k
    normals = np.column_stack([np.sqrt(1 - z * z) * np.cos(phi), np.sqrt(1 - z * z) * np.sin(phi), z])
    mean = sensors.point_view_factors(np.repeat(p[None], 4000, 0), normals, scene, dense=True).mean(axis=0)
    sph = sensors.sphere_view_factors(p, scene, dense=True)[0]
    assert sph.sum() == pytest.approx(1.0, abs=1e-12)
    assert np.abs(sph - mean).max() < 2e-4
    assert sph[6:].sum() > 0.05  # the crate is seen, and hides part of the floor
    assert sph[0] < nusselt.sensors.sphere_view_factors(p, scene, obstructed=False, dense=True)[0, 0] - 0.01


def split_box(t_up: float, t_down: float, z: float):
    """A 2 x 2 x 2 box whose walls are cut at height z: surfaces above at t_up, below at t_down."""
    polys, names = [], []
    floor, ceil = box((0, 0, 0), (2, 2, 2))[:2]
    polys += [floor, ceil]
    names += ["low", "high"]
    for lo_hi, name in [((0, z), "low"), ((z, 2), "high")]:
        for f in box((0, 0, lo_hi[0]), (2, 2, lo_hi[1]))[2:]:
            polys.append(f)
            names.append(name)
    return nusselt.Scene.from_polygons(polys, surface=names), {"high": t_up, "low": t_down}


def test_radiant_temperatures_uniform_enclosure_and_halves():
    scene, _ = split_box(300.0, 300.0, 1.0)
    pts = np.array([[1.0, 1.0, 1.0], [0.3, 1.6, 0.4]])
    for form in ("sphere", "standing", "seated"):
        t = sensors.mean_radiant_temperature(pts, scene, {"high": 300.0, "low": 300.0}, form=form)
        assert np.allclose(t, 300.0, rtol=1e-13, atol=0)
    # split by the plane z = 1 through the point: facing up sees only the hot half, down the cold
    scene, temps = split_box(310.0, 290.0, 1.0)
    c = np.array([[1.0, 1.0, 1.0]])
    tpr = sensors.plane_radiant_temperatures(c, scene, temps)
    assert tpr["up"][0] == pytest.approx(310.0, rel=1e-13)
    assert tpr["down"][0] == pytest.approx(290.0, rel=1e-13)
    # sideways the element sees each half over half of its field of view, by symmetry
    assert tpr["front"][0] == pytest.approx(((310.0**4 + 290.0**4) / 2) ** 0.25, rel=1e-12)
    sphere = sensors.mean_radiant_temperature(c, scene, temps)
    assert sphere[0] == pytest.approx(((310.0**4 + 290.0**4) / 2) ** 0.25, rel=1e-12)
    # ISO 7726 Annex B: the projected-area weights applied to the six plane radiant temperatures
    for form, (wu, wl, wf) in sensors.ISO7726_WEIGHTS.items():
        t = sensors.mean_radiant_temperature(c, scene, temps, form=form)[0]
        want = (
            wu * (tpr["up"] + tpr["down"]) + wl * (tpr["left"] + tpr["right"]) + wf * (tpr["front"] + tpr["back"])
        ) / (2 * (wu + wl + wf))
        assert t == pytest.approx(want[0], rel=1e-14)


def test_radiant_temperature_errors_and_open_scenes():
    scene = nusselt.Scene.from_polygons([rect([-1, -1, 1], [0, 2, 0], [2, 0, 0])], surface=["roof"])
    with pytest.raises(ValueError, match="give the temperature of the rest"):
        sensors.mean_radiant_temperature([0, 0, 0], scene, {"roof": 300.0})
    f = sensors.sphere_view_factors([0, 0, 0], scene, by_surface=True, dense=True)[0, 0]
    t = sensors.mean_radiant_temperature([0, 0, 0], scene, {"roof": 300.0}, rest=250.0)[0]
    assert t == pytest.approx((f * 300.0**4 + (1 - f) * 250.0**4) ** 0.25, rel=1e-14)
    with pytest.raises(ValueError, match="unknown surface 'wall'"):
        sensors.mean_radiant_temperature([0, 0, 0], scene, {"wall": 300.0}, rest=250.0)
    with pytest.raises(ValueError, match="'roof' is seen by a sensor but has no temperature"):
        sensors.mean_radiant_temperature([0, 0, 0], scene, {}, rest=250.0)
    with pytest.raises(ValueError, match="normals row 1: the normal is zero"):
        sensors.point_view_factors([[0, 0, 0], [1, 0, 0]], [[0, 0, 1], [0, 0, 0]], scene)
    with pytest.raises(ValueError, match=r"points row 0: not finite"):
        sensors.point_view_factors([[np.nan, 0, 0]], [0, 0, 1], scene)
    with pytest.raises(ValueError, match="row method"):
        sensors.point_view_factors([0, 0, 0], [0, 0, 1], scene, method="hemicube")
    assert sensors.point_view_factors([0, 0, 0], [0, 0, 1], scene, method="analytic", obstructed=False).shape == (1, 1)


@pytest.mark.parametrize("method", ["analytic", "contour"])
def test_closed_form_methods_see_the_visible_region(method):
    """`analytic` and `contour` at sensor points behind a blocker: Lambert's formula on the
    exact visible region, against the closed form of the plate less the blocker's shadow."""
    from test_exact_obstructed import CENTRED, HI, point_behind_centred_blocker, point_to_rect

    scene = nusselt.Scene.from_polygons([HI, CENTRED[::-1]], surface=["plate", "blocker"])  # blocker faces down
    pts = np.array([[0.5, 0.5, 0.0], [0.1, 0.7, 0.0], [0.9, 0.05, 0.0]])
    f = sensors.point_view_factors(pts, [0, 0, 1], scene, method=method, dense=True)
    free = sensors.point_view_factors(pts, [0, 0, 1], scene, method=method, obstructed=False, dense=True)
    for k, (x, y, _) in enumerate(pts):
        assert f[k, 0] == pytest.approx(point_behind_centred_blocker(x, y), abs=1e-14)
        assert f[k, 1] == pytest.approx(point_to_rect(x, y, 0.25, 0.75, 0.25, 0.75, 0.5), abs=1e-14)
        assert free[k, 0] == pytest.approx(point_to_rect(x, y, 0, 1, 0, 1, 1.0), abs=1e-14)
    assert np.all(f[:, 0] < free[:, 0])


def test_sampled_method_matches_exact_within_its_error():
    room = box((0, 0, 0), (4, 3, 2.5)) + box((1.0, 1.0, 0.3), (2.2, 2.0, 1.1), inward=False)
    scene = nusselt.Scene.from_polygons(room)
    p, n = [[3.0, 2.5, 0.5]], [[-1, -0.6, -0.2]]
    exact = sensors.point_view_factors(p, n, scene, dense=True)
    sub = sensors.point_view_factors(p, n, scene, method="subdivision", divisions=64, dense=True)
    assert np.abs(exact - sub).max() < 2e-3
    assert np.abs(exact - sub).max() > 0  # the crate is in view: the sampled method did sample
    mc, err = sensors.point_view_factors(p, n, scene, method="montecarlo", samples=4096, dense=True, return_std=True)
    assert err.max() > 0 and np.all(np.abs(mc - exact) <= 6 * err + 1e-14)


def test_points_csv_errors_name_the_line(tmp_path):
    good = tmp_path / "p.csv"
    good.write_text("name,x,y,z,nx,ny,nz\na,0,0,1,0,0,1\n\nb,1,2,3,0,0,2\n")
    p, n = sensors.read_points_csv(good)
    assert p.tolist() == [[0, 0, 1], [1, 2, 3]] and n[1].tolist() == [0, 0, 2]
    for text, msg in [
        ("x,y,z,nx,ny\n", r"p\.csv:1: missing column\(s\) nz"),
        ("x,y,z,nx,ny,nz\n0,0,0,0,0,1\n0,0,zero,0,0,1\n", r"p\.csv:3: not a number"),
        ("x,y,z,nx,ny,nz\n0,0,0,0,0\n", r"p\.csv:2: 5 fields"),
        ("x,y,z,nx,ny,nz\n0,0,0,0,0,0\n", r"p\.csv:2: the normal \(nx, ny, nz\) is zero"),
        ("x,y,z,nx,ny,nz\n", r"p\.csv: no points"),
    ]:
        good.write_text(text)
        with pytest.raises(ValueError, match=msg):
            sensors.read_points_csv(good)
