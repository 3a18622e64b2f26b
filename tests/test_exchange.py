"""Grey diffuse exchange (nusselt.exchange) against closed forms and identities."""

import numpy as np
import pytest
import scipy.sparse as sp

import nusselt
from nusselt import exchange
from conftest import cube_faces, rect

SIGMA = 5.670374419e-8


def concentric(a1, a2):
    """Exact form factors of a convex body 1 inside an enclosing surface 2 (form-factor algebra:
    F_12 = 1, reciprocity F_21 = A1/A2, closure F_22 = 1 - A1/A2)."""
    return np.array([[0.0, 1.0], [a1 / a2, 1.0 - a1 / a2]]), np.array([a1, a2])


def net_radiation(f, areas, eps, t, t_amb=0.0):
    """Independent dense net-radiation solve (Modest ch. 5): unknown radiosities J from
    J_i = eps_i sigma T_i^4 + (1 - eps_i) (sum_j F_ij J_j + (1 - sum_j F_ij) sigma T_amb^4);
    returns the heat rate each surface loses, Q_i = A_i (J_i - H_i)."""
    n = len(areas)
    e_amb = SIGMA * t_amb**4
    deficit = 1.0 - f.sum(axis=1)
    a = np.eye(n) - (1.0 - eps)[:, None] * f
    b = eps * SIGMA * t**4 + (1.0 - eps) * deficit * e_amb
    j = np.linalg.solve(a, b)
    h = f @ j + deficit * e_amb
    return areas * (j - h)


def test_script_f_concentric_spheres_closed_form():
    # Modest eq. (5.41) for concentric spheres/cylinders: A1 SF12 = A1 / (1/eps1 + A1/A2 (1/eps2 - 1))
    for a1, a2, e1, e2 in [(1.0, 4.0, 0.3, 0.6), (2.0, 2.5, 0.9, 0.05), (0.1, 50.0, 1.0, 0.2)]:
        f, areas = concentric(a1, a2)
        sf = exchange.script_f(f, [e1, e2])
        expect = 1.0 / (1.0 / e1 + a1 / a2 * (1.0 / e2 - 1.0))
        assert sf[0, 1] == pytest.approx(expect, rel=1e-12)
        np.testing.assert_allclose(sf.sum(axis=1), [e1, e2], rtol=1e-12)
        assert areas[0] * sf[0, 1] == pytest.approx(areas[1] * sf[1, 0], rel=1e-12)


def test_script_f_black_is_f_and_sparse_matches_dense():
    polys, _ = cube_faces(n=2)
    res = nusselt.form_factors(nusselt.Scene.from_polygons(polys))
    np.testing.assert_allclose(exchange.script_f(res, 1.0), res.dense(), atol=1e-15)
    eps = np.linspace(0.1, 0.95, len(res))
    d = exchange.script_f(res.dense(), eps)
    s = exchange.script_f(sp.csr_array(res.dense()), eps)
    np.testing.assert_allclose(s, d, rtol=1e-12, atol=1e-15)


def test_script_f_reciprocity_and_rows_in_a_closed_room():
    polys, _ = cube_faces(n=3)
    res = nusselt.form_factors(nusselt.Scene.from_polygons(polys))
    eps = np.random.default_rng(1).uniform(0.05, 1.0, len(res))
    sf = exchange.script_f(res, eps)
    g = res.areas[:, None] * sf
    assert np.max(np.abs(g - g.T)) / g.max() < 1e-12
    # rows sum to eps_i up to the closure of the exact F (rounding)
    np.testing.assert_allclose(sf.sum(axis=1), eps * res.row_sums, rtol=1e-12)
    gb = exchange.gebhart(res, eps)
    np.testing.assert_allclose(gb.sum(axis=1), 1.0, atol=1e-12)


def test_script_f_open_plates_is_the_pairwise_exchange():
    # Two finite parallel plates in a black 0 K surrounding: with T2 = 0 the heat plate 2 absorbs
    # from plate 1 is A1 SF12 sigma T1^4 (independent dense net-radiation solve).
    res = nusselt.form_factors(nusselt.Scene.from_polygons([rect(0, 1, 0, 1, 0.0), rect(0, 1, 0, 1, 0.5, flip=True)]))
    f, areas = res.dense(), res.areas
    eps = np.array([0.7, 0.4])
    sf = exchange.script_f(f, eps)
    q = net_radiation(f, areas, eps, np.array([500.0, 0.0]))
    assert -q[1] == pytest.approx(areas[0] * sf[0, 1] * SIGMA * 500.0**4, rel=1e-12)


def test_script_f_bad_input():
    f, _ = concentric(1.0, 2.0)
    with pytest.raises(ValueError, match=r"emissivity\[1\]"):
        exchange.script_f(f, [0.5, 1.5])
    with pytest.raises(ValueError, match="one value per surface"):
        exchange.script_f(f, [0.5, 0.5, 0.5])
    with pytest.raises(ValueError, match="square"):
        exchange.script_f(np.ones((2, 3)), 0.5)
    with pytest.raises(ValueError, match="row 0 of F sums"):
        exchange.script_f(np.array([[0.0, 1.5], [0.5, 0.5]]), 0.5)
    with pytest.raises(ValueError, match="singular"):
        exchange.script_f(f, 0.0)
