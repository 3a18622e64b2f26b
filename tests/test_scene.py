"""Scene-level matrices: closure, reciprocity, surfaces, units."""

import numpy as np
import pytest
from conftest import cube_faces, rect

import nusselt

C11 = 0.19982489569838746
C14 = 0.20004377607540316


@pytest.mark.parametrize("method", ["auto", "analytic", "contour"])
def test_subdivided_cube(method):
    polys, face = cube_faces(3)
    scene = nusselt.Scene.from_polygons(polys, surface=[f"side{k}" for k in face])
    res = nusselt.form_factors(scene, method=method)
    assert res.matrix.shape == (54, 54)
    assert res.closure_error < 1e-12
    assert res.reciprocity_error < 1e-12
    s = res.by_surface()
    assert s.names == [f"side{k}" for k in range(6)]
    f = s.dense()
    assert f[0, 1] == pytest.approx(C11, rel=1e-11, abs=0)  # opposite faces
    assert f[0, 2] == pytest.approx(C14, rel=1e-11, abs=0)  # adjacent faces
    assert np.allclose(np.diag(f), 0)


@pytest.mark.parametrize("tol", [0.1, 1e-3])
def test_loose_tol_meets_its_bound_per_pair(tol):
    # A loose target makes auto use the moment rule and low Gauss orders for distant pairs:
    # every entry stays within tol (relative) of the exact matrix, the pair API picks the same
    # rule, and reciprocity still holds exactly.
    polys, _ = cube_faces(6)
    scene = nusselt.Scene.from_polygons(polys)
    exact = nusselt.form_factors(scene, method="analytic").dense()
    res = nusselt.form_factors(scene, tol=tol)
    f = res.dense()
    nz = exact > 0
    assert np.array_equal(nz, f > 0)
    rel = np.abs(f[nz] - exact[nz]) / exact[nz]
    assert rel.max() <= tol
    assert rel.max() > 1e-12  # the cheap rules were used at all
    assert res.reciprocity_error < 1e-14
    rng = np.random.default_rng(5)
    for i, j in rng.integers(0, len(polys), size=(200, 2)):
        if i != j:
            assert f[i, j] == pytest.approx(nusselt.view_factor(polys[i], polys[j], tol=tol), rel=1e-13, abs=1e-300)


def test_units_do_not_matter():
    polys, face = cube_faces(2)
    a = nusselt.form_factors(nusselt.Scene.from_polygons(polys)).dense()
    b = nusselt.form_factors(nusselt.Scene.from_polygons([p * 1000.0 for p in polys])).dense()
    assert np.max(np.abs(a - b)) < 1e-12


def test_dense_and_sparse_agree():
    polys, _ = cube_faces(2)
    scene = nusselt.Scene.from_polygons(polys)
    a = nusselt.form_factors(scene).dense()
    b = nusselt.form_factors(scene, dense=True).matrix
    assert isinstance(b, np.ndarray) and np.array_equal(a, b)


def test_obstruction_only_faces_get_no_row():
    polys, _ = cube_faces(1)
    scene = nusselt.Scene.from_polygons(polys, obstruction=[False] * 5 + [True])
    res = nusselt.form_factors(scene)
    assert res.matrix.shape == (5, 5)
    assert list(res.faces) == [0, 1, 2, 3, 4]


def test_scene_errors_name_the_face():
    polys, _ = cube_faces(1)
    polys[3] = polys[3].copy()
    polys[3][0, 1] += 0.01  # face 3 is y = 1: move a vertex off that plane
    with pytest.raises(ValueError, match="face 3 .*not planar"):
        nusselt.Scene.from_polygons(polys)
    with pytest.raises(ValueError, match="no faces"):
        nusselt.Scene(np.zeros((0, 3)), [])
    with pytest.raises(ValueError, match="refers to vertex 9"):
        nusselt.Scene(np.zeros((4, 3)), [[0, 1, 9]])
    with pytest.raises(TypeError):
        nusselt.form_factors("not a scene")


@pytest.mark.slow
def test_cube_32_acceptance():
    # Issue acceptance: 6144 patches; row sums to 1e-10, reciprocity 1e-12, face sums to 1e-10.
    polys, face = cube_faces(32)
    scene = nusselt.Scene.from_polygons(polys, surface=[f"side{k}" for k in face])
    res = nusselt.form_factors(scene)
    assert res.closure_error <= 1e-10
    assert res.reciprocity_error <= 1e-12
    f = res.by_surface().dense()
    assert np.abs(f[0, 1] - C11) <= 1e-10 and np.abs(f[0, 2] - C14) <= 1e-10


def test_refined_keeps_obstruction_only_polygons_whole():
    # A large obstruction-only ground plane used to be tiled like a receiver (here 400^2 tiles);
    # it gets no row or column, so refining it only costs time: it is kept whole, and blocks the same.
    lower, upper = rect(0, 1, 0, 1), rect(0, 1, 0, 1, z=2.0, flip=True)
    blocker = rect(0.25, 0.75, 0.25, 0.75, z=1.0)
    ground = rect(-50, 50, -50, 50, z=-1.0)
    scene = nusselt.Scene.from_polygons(
        [lower, upper, blocker, ground],
        surface=["lower", "upper", "blocker", "ground"],
        obstruction=[False, False, True, True],
    )
    fine = scene.refined(0.25)
    assert len(fine) == 16 + 16 + 2
    kept = np.flatnonzero(fine.obstruction)
    assert [fine.surface_names[fine.surface[k]] for k in kept] == ["blocker", "ground"]
    for k, original in zip(kept, [blocker, ground]):
        np.testing.assert_array_equal(fine.polygons[k], original)
    # the receivers' tiles see the blocker as the whole surfaces do (additivity)
    coarse = nusselt.form_factors(scene).by_surface()
    tiled = nusselt.form_factors(fine).by_surface()
    i, j = coarse.names.index("lower"), coarse.names.index("upper")
    assert tiled.dense()[i, j] == pytest.approx(coarse.dense()[i, j], abs=1e-6)
