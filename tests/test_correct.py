"""The reciprocity/closure correction: improves noisy estimates, never touches exact entries."""

import numpy as np
import pytest

from nusselt.correct import correct

C11, C14 = 0.19982489569838746, 0.20004377607540316


def cube_f():
    f = np.full((6, 6), C14)
    np.fill_diagonal(f, 0)
    for k in range(0, 6, 2):
        f[k, k + 1] = f[k + 1, k] = C11
    return f


def test_noisy_cube_is_closed_reciprocal_and_closer():
    rng = np.random.default_rng(0)
    f = cube_f()
    areas = np.array([1.0, 1.0, 2.0, 2.0, 0.5, 0.5])  # a non-uniform area set: reciprocity matters
    g = f.copy()
    s = np.where(f > 0, 0.003, 0.0)
    errs_before, errs_after = [], []
    for _ in range(20):
        noisy = f + rng.normal(size=f.shape) * s
        c = correct(noisy, np.ones(6), s).toarray()
        assert np.abs(c.sum(1) - 1).max() < 1e-12
        assert np.abs(c - c.T).max() < 1e-15
        errs_before.append(np.abs(noisy - f).mean())
        errs_after.append(np.abs(c - f).mean())
    assert np.mean(errs_after) < 0.7 * np.mean(errs_before)
    # with areas: A_i F_ij = A_j F_ji after correction
    noisy = g * 1.0 + rng.normal(size=f.shape) * s
    c = correct(noisy, areas, s, closure=False).toarray()
    ga = c * areas[:, None]
    assert np.abs(ga - ga.T).max() < 1e-15


def test_exact_entries_are_never_changed():
    rng = np.random.default_rng(1)
    f = cube_f()
    s = np.where(f > 0, 0.003, 0.0)
    s[0, :] = s[:, 0] = 0.0  # row and column 0 exact
    noisy = f.copy()
    noisy[1:, 1:] += rng.normal(size=(5, 5)) * s[1:, 1:]
    c = correct(noisy, np.ones(6), s).toarray()
    assert np.array_equal(c[0], f[0]) and np.array_equal(c[:, 0], f[:, 0])
    assert np.abs(c.sum(1) - 1).max() < 1e-12


def test_unsampled_direction_is_not_an_exact_zero():
    # Row 0 sampled pair (0, 1); row 1 saw nothing of 0 (no ray hit it): no value, no error.
    areas = np.array([1.0, 4.0, 2.0])
    f = np.array([[0.0, 0.6, 0.4], [0.0, 0.0, 0.5], [0.2, 1.0, 0.0]])
    s = np.array([[0.0, 0.05, 0.05], [0.0, 0.0, 0.05], [0.05, 0.05, 0.0]])
    g = correct(f, areas, s, closure=False).toarray()
    assert g[0, 1] > 0 and g[1, 0] > 0  # the pair survives, taken from row 0's estimate
    assert g[0, 1] == pytest.approx(0.6)
    np.testing.assert_allclose(areas[:, None] * g, (areas[:, None] * g).T, rtol=1e-12)
    # a nonzero entry with zero error stays exact
    s[2, 0] = 0.0
    g = correct(f, areas, s, closure=False).toarray()
    assert g[2, 0] == pytest.approx(0.2) and g[0, 2] == pytest.approx(0.4)
