"""Radiosity (nusselt.radiosity): every method against a dense direct solve, furnace, energy."""

import warnings

import numpy as np
import pytest
from conftest import cube_faces, rect

import nusselt
from nusselt import radiosity


@pytest.fixture(scope="module")
def open_box():
    """A unit cube with its top missing (open), 3 x 3 patches per face: rows sum to < 1."""
    polys, face = cube_faces(n=3)
    keep = [k for k, p in enumerate(polys) if not np.allclose(np.asarray(p)[:, 2], 1.0)]
    return nusselt.form_factors(nusselt.Scene.from_polygons([polys[k] for k in keep]))


def colours(n, seed=3):
    rng = np.random.default_rng(seed)
    rho = rng.uniform(0.05, 0.9, (n, 3))
    e = np.zeros((n, 3))
    e[:4] = rng.uniform(1.0, 10.0, (4, 3))
    return rho, e


@pytest.mark.parametrize("method", radiosity.METHODS)
def test_methods_agree_with_dense_solve(open_box, method):
    f = open_box.dense()
    rho, e = colours(len(f))
    ref = np.column_stack([np.linalg.solve(np.eye(len(f)) - rho[:, c, None] * f, e[:, c]) for c in range(3)])
    r = radiosity.solve(open_box, rho, e, method=method, tol=1e-12)
    np.testing.assert_allclose(r.radiosity, ref, rtol=1e-10, atol=1e-12 * ref.max())
    assert r.residual <= 1e-12
    if method != "direct":
        assert r.iterations > 1


def test_energy_balance_open_scene(open_box):
    rho, e = colours(len(open_box))
    r = radiosity.solve(open_box, rho, e)
    bal = r.energy_balance(open_box.areas, rho, e, open_box)
    np.testing.assert_allclose(bal["emitted"], bal["absorbed"] + bal["escaping"], rtol=1e-12)
    assert (bal["escaping"] > 0.1 * bal["emitted"]).all()


def test_furnace_closed_enclosure():
    # Closed cube, uniform rho and E: B = E + rho F B with F rows summing to 1 gives B = E / (1 - rho)
    polys, _ = cube_faces(n=3)
    res = nusselt.form_factors(nusselt.Scene.from_polygons(polys))
    n, rho = len(res), np.array([0.5, 0.8, 0.95])
    e = np.tile([1.0, 2.0, 3.0], (n, 1))
    for method in radiosity.METHODS:
        r = radiosity.solve(res, np.tile(rho, (n, 1)), e, method=method, tol=1e-13)
        np.testing.assert_allclose(r.radiosity, e / (1 - rho), rtol=1e-11)


def test_shooting_plain_matrix_and_bad_input():
    res = nusselt.form_factors(nusselt.Scene.from_polygons([rect(0, 1, 0, 1), rect(0, 1, 0, 1, 0.3, flip=True)]))
    f = res.dense()
    rho, e = np.array([0.6, 0.7]), np.array([1.0, 0.0])
    d = radiosity.solve(f, rho, e)
    s = radiosity.solve(f, rho, e, method="shooting", areas=res.areas, tol=1e-13)
    np.testing.assert_allclose(s.radiosity, d.radiosity, rtol=1e-12)
    with pytest.raises(ValueError, match="needs the patch areas"):
        radiosity.solve(f, rho, e, method="shooting")
    with pytest.raises(ValueError, match="unknown radiosity method"):
        radiosity.solve(f, rho, e, method="cg")
    with pytest.raises(ValueError, match="reflectance"):
        radiosity.solve(f, [0.5, 1.5], e)
    with pytest.raises(ValueError, match="emission"):
        radiosity.solve(f, rho, [[1.0, 0.0]])
    with pytest.raises(ValueError, match="did not reach"):
        radiosity.solve(f, rho, e, method="jacobi", tol=1e-15, max_iter=2)


def test_cornell_box_colour_bleeding():
    # White floor patches next to the red wall (x near 556 mm) reflect redder light than those
    # next to the green wall (x near 0): the red/green ratio of B must differ by a wide margin.
    from nusselt.data import bundled

    scene = nusselt.Scene.from_file(bundled("cornell_box.obj")).refined(150.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", nusselt.ZeroRowWarning)  # floor patches hidden under the blocks
        f = nusselt.form_factors(scene, method="hemicube", resolution=64)
    rho, e = radiosity.cornell_colours(scene)
    b = radiosity.solve(f, rho, e, method="gauss-seidel", tol=1e-9).radiosity
    names = [scene.surface_names[s] for s in scene.surface]
    x = np.array([np.asarray(p)[:, 0].mean() for p in scene.polygons])
    floor = np.array([n == "floor" for n in names]) & (b[:, 1] > 0)
    near_red, near_green = floor & (x > 420), floor & (x < 136)
    ratio = lambda m: b[m, 0].sum() / b[m, 1].sum()
    assert ratio(near_red) > 1.4 * ratio(near_green)
