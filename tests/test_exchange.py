"""Grey diffuse exchange (nusselt.exchange) against closed forms and identities."""

import numpy as np
import pytest
import scipy.sparse as sp
from conftest import cube_faces, rect

import nusselt
from nusselt import exchange

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


def plates(side, gap):
    return nusselt.form_factors(
        nusselt.Scene.from_polygons(
            [rect(0, side, 0, side, 0.0), rect(0, side, 0, side, gap, flip=True)], surface=["hot", "cold"]
        )
    )


def test_solve_finite_plates_against_dense_solve_and_infinite_limit():
    e1, e2, t1, t2 = 0.8, 0.5, 600.0, 300.0
    res = plates(1.0, 0.002)  # side 500 x the gap, exact F
    r = exchange.solve(res, [e1, e2], [t1, t2], ambient=0.0)
    q_ref = net_radiation(res.dense(), res.areas, np.array([e1, e2]), np.array([t1, t2]))
    np.testing.assert_allclose(r.heat, q_ref, rtol=1e-12)
    infinite = SIGMA * (t1**4 - t2**4) / (1 / e1 + 1 / e2 - 1)
    assert r.flux[0] == pytest.approx(infinite, rel=0.01)  # F12 = 0.996: the edges lose a little to 0 K
    # energy: what the plates lose is what the 0 K surroundings receive
    assert r.ambient_heat == pytest.approx(r.heat.sum(), rel=1e-12)
    assert r.ambient_heat > 0


def test_solve_concentric_cylinders_closed_form_and_conservation():
    # Modest eq. (5.41): q1 = sigma (T1^4 - T2^4) / (1/eps1 + A1/A2 (1/eps2 - 1))
    f, areas = concentric(np.pi * 2 * 0.1, np.pi * 2 * 0.25)
    e, t = np.array([0.35, 0.8]), np.array([900.0, 350.0])
    r = exchange.solve(f, e, t, areas=areas)
    q1 = SIGMA * (t[0] ** 4 - t[1] ** 4) / (1 / e[0] + areas[0] / areas[1] * (1 / e[1] - 1))
    assert r.flux[0] == pytest.approx(q1, rel=1e-12)
    assert abs(r.heat.sum()) <= 1e-12 * abs(r.heat[0])
    qij = r.pairwise()
    np.testing.assert_allclose(qij, -qij.T, atol=1e-12 * abs(r.heat[0]))
    np.testing.assert_allclose(qij.sum(axis=1), r.heat, rtol=1e-12)


def test_solve_mixed_conditions_round_trip_and_sparse_path(monkeypatch):
    polys, _ = cube_faces(n=3)
    res = nusselt.form_factors(nusselt.Scene.from_polygons(polys))
    n = len(res)
    rng = np.random.default_rng(7)
    eps = rng.uniform(0.1, 0.95, n)
    t = rng.uniform(250.0, 450.0, n)
    full = exchange.solve(res, eps, t)
    assert abs(full.heat.sum()) <= 1e-12 * np.abs(full.heat).sum()
    # give the fluxes of every other patch instead of its temperature: the same state
    tt, qq = t.copy(), np.full(n, np.nan)
    tt[::2], qq[::2] = np.nan, full.flux[::2]
    mixed = exchange.solve(res, eps, tt, qq)
    np.testing.assert_allclose(mixed.temperature, t, rtol=1e-10)
    np.testing.assert_allclose(mixed.radiosity, full.radiosity, rtol=1e-10)
    monkeypatch.setattr(exchange, "DENSE_LIMIT", 4)  # the sparse LU path
    sparse = exchange.solve(res, eps, tt, qq)
    np.testing.assert_allclose(sparse.radiosity, mixed.radiosity, rtol=1e-12)
    dense_sf = exchange.script_f(res.dense(), eps)
    np.testing.assert_allclose(exchange.script_f(res, eps), dense_sf, rtol=1e-10, atol=1e-15)


def test_solve_open_scene_sky_node():
    # A plate facing the sky at 3 K: q = eps sigma (T^4 - T_sky^4) (it sees nothing else)
    res = nusselt.form_factors(nusselt.Scene.from_polygons([rect(0, 1, 0, 1)]))
    r = exchange.solve(res, 0.85, 300.0, ambient=3.0)
    assert r.flux[0] == pytest.approx(0.85 * SIGMA * (300.0**4 - 3.0**4), rel=1e-12)
    assert r.ambient_heat == pytest.approx(r.heat[0], rel=1e-12)
    # radiative equilibrium (q = 0) of a plate between a 400 K plate and the 3 K sky
    res2 = plates(1.0, 0.2)
    r2 = exchange.solve(res2, [0.9, 0.6], [400.0, np.nan], [np.nan, 0.0], ambient=3.0)
    ref = net_radiation(res2.dense(), res2.areas, np.array([0.9, 0.6]), r2.temperature, t_amb=3.0)
    np.testing.assert_allclose(ref, r2.heat, atol=1e-9 * abs(r2.heat[0]))
    assert ref[1] == pytest.approx(0.0, abs=1e-9 * abs(ref[0]))


def test_band_fraction_against_planck_quadrature():
    from scipy.integrate import quad

    c2 = exchange.C2

    def planck(lt):  # (15/pi^4) integral of C2^4 / (l^5 (e^{C2/l} - 1)) dl, independent quadrature
        g = lambda x: 15 / np.pi**4 * c2**4 / x**5 / np.expm1(c2 / x) if x > 50 else 0.0
        return quad(g, 0.0, lt, epsabs=0, epsrel=1e-13, limit=500)[0]

    for lt in [500.0, 1000.0, 2897.77, 5000.0, 14387.0, 1.4e5, 1.5e5, 1e6]:
        assert exchange.blackbody_fraction(lt, 1.0) == pytest.approx(planck(lt), rel=1e-12, abs=1e-15)
    np.testing.assert_allclose(exchange.band_fractions([0, 3, 8, np.inf], [300.0, 1000.0]).sum(axis=1), 1.0, rtol=1e-14)


def test_band_mode_grey_limit_and_two_band_closed_form():
    f, areas = concentric(1.0, 3.0)
    t = np.array([800.0, 300.0])
    edges = [0.0, 4.0, np.inf]
    grey = exchange.solve(f, [0.4, 0.7], t, areas=areas)
    banded = exchange.solve(f, [[0.4, 0.4], [0.7, 0.7]], t, areas=areas, bands=edges)
    np.testing.assert_allclose(banded.heat, grey.heat, rtol=1e-12)
    # each band is a grey problem with its share of sigma T^4: closed form per band, summed
    e = np.array([[0.2, 0.9], [0.6, 0.1]])
    r = exchange.solve(f, e, t, areas=areas, bands=edges)
    fr = exchange.band_fractions(edges, t)
    ref = sum(
        areas[0]
        * SIGMA
        * (fr[0, b] * t[0] ** 4 - fr[1, b] * t[1] ** 4)
        / (1 / e[0, b] + areas[0] / areas[1] * (1 / e[1, b] - 1))
        for b in range(2)
    )
    assert r.heat[0] == pytest.approx(ref, rel=1e-12)
    assert abs(r.heat.sum()) <= 1e-12 * abs(r.heat[0])
    np.testing.assert_allclose(r.pairwise().sum(axis=1), r.heat, rtol=1e-12)


def test_solve_bad_input():
    f, areas = concentric(1.0, 2.0)
    with pytest.raises(ValueError, match="exactly one of temperature and flux"):
        exchange.solve(f, 0.5, [300.0, 300.0], [0.0, np.nan], areas=areas)
    with pytest.raises(ValueError, match="neither"):
        exchange.solve(f, 0.5, [300.0, np.nan], areas=areas)
    with pytest.raises(ValueError, match="at least one temperature"):
        exchange.solve(f, 0.5, None, [0.0, 0.0], areas=areas)
    with pytest.raises(ValueError, match="needs areas"):
        exchange.solve(f, 0.5, 300.0)
    with pytest.raises(ValueError, match="negative"):
        exchange.solve(f, 0.5, [-1.0, 300.0], areas=areas)
    with pytest.raises(ValueError, match="band mode needs a temperature"):
        exchange.solve(f, [[0.5, 0.5]] * 2, [300.0, np.nan], [np.nan, 0.0], areas=areas, bands=[0, 4, np.inf])
