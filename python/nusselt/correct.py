"""Reciprocity- and closure-preserving correction of estimated form factors.

Sampling methods give F with statistical error: A_i F_ij and A_j F_ji differ, and rows of a
closed enclosure do not sum exactly to 1. The correction finds the symmetric G = A F closest
to the estimates in the weighted least-squares sense,

    minimise  sum_ij (G_ij / A_i - F_ij)^2 / s_ij^2
    subject to G_ij = G_ji,   sum_j G_ij = A_i  (closure, for enclosures only),

with s_ij the standard error of F_ij. Nonzero entries with s_ij = 0 are exact: they are never
changed, so error is never spread into them (plain row normalisation would). A zero entry with
no error is a direction that was not sampled (no ray hit it): the pair then takes the other
direction's estimate. Negative results are
pinned to zero and the problem is solved again (a small active-set loop).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def correct(matrix, areas, std_err=None, *, closure: bool = True, max_iter: int = 10):
    """Returns the corrected F (csr_array) for the estimate ``matrix`` with ``std_err``.

    ``std_err``: sparse/dense array of the standard error of each entry (0 = exact). Without it,
    every nonzero entry gets s_ij = sqrt(F_ij (1 - F_ij)) (the binomial shape of sampled F).
    ``closure``: also enforce row sums of 1 (only meaningful for a closed enclosure).
    """
    f = sp.csr_array(matrix, dtype=float)
    n = f.shape[0]
    areas = np.asarray(areas, float)
    if f.shape != (n, n) or areas.shape != (n,):
        raise ValueError("matrix must be square with one area per row")
    if std_err is None:
        s = f.copy()
        s.data = np.sqrt(np.clip(f.data * (1 - f.data), 1e-30, None))
    else:
        s = sp.csr_array(std_err, dtype=float)
        if s.shape != f.shape:
            raise ValueError("std_err must have the shape of the matrix")
    # union of the sparsity patterns of F and F^T: the unordered pairs
    pat = (abs(f) + abs(f.T) + abs(s) + abs(s.T)).tocoo()
    keep = pat.row < pat.col
    pi, pj = pat.row[keep], pat.col[keep]
    fij, fji = _take(f, pi, pj), _take(f, pj, pi)
    sij, sji = _take(s, pi, pj), _take(s, pj, pi)
    # A side with s = 0 is exact when it has a value; a side with neither value nor error
    # was simply not sampled (no ray hit it): it carries no information, not an exact 0.
    exact_ij, exact_ji = (sij == 0) & (fij != 0), (sji == 0) & (fji != 0)
    exact = exact_ij | exact_ji
    # per pair, the weighted mean of the two estimates of G (exact pairs: the exact side)
    wij, wji = np.zeros(len(pi)), np.zeros(len(pi))
    wij[sij > 0] = 1 / (areas[pi] * sij)[sij > 0] ** 2
    wji[sji > 0] = 1 / (areas[pj] * sji)[sji > 0] ** 2
    g_ij, g_ji = areas[pi] * fij, areas[pj] * fji
    both = (wij > 0) & (wji > 0)
    g0 = np.where(exact_ij | (wij > 0), g_ij, g_ji)
    g0[exact_ji] = g_ji[exact_ji]
    g0[both & ~exact] = ((wij * g_ij + wji * g_ji) / np.where(both, wij + wji, 1.0))[both & ~exact]
    w = wij + wji  # curvature of the objective in g
    free = ~exact & (w > 0)
    g = g0.copy()
    if closure:
        for _ in range(max_iter):
            g = _close(g0, w, free, pi, pj, areas, n)
            neg = free & (g < 0)
            if not neg.any():
                break
            g0 = np.where(neg, 0.0, g0)
            free = free & ~neg
        g = np.where(free, g, g0)
    g = np.maximum(g, 0.0)
    rows = np.concatenate([pi, pj])
    cols = np.concatenate([pj, pi])
    vals = np.concatenate([g / areas[pi], g / areas[pj]])
    out = sp.csr_array((vals, (rows, cols)), shape=(n, n))
    out.eliminate_zeros()
    return out


def _close(g0, w, free, pi, pj, areas, n):
    """Minimise sum_free w (g - g0)^2 s.t. row sums of the symmetric G equal the areas."""
    fixed_sum = np.bincount(pi, weights=np.where(free, 0, g0), minlength=n) + np.bincount(
        pj, weights=np.where(free, 0, g0), minlength=n
    )
    idx = np.flatnonzero(free)
    if idx.size == 0:
        return g0
    rhs_rows = areas - fixed_sum
    b = sp.csr_array(
        (np.ones(2 * idx.size), (np.concatenate([pi[idx], pj[idx]]), np.tile(np.arange(idx.size), 2))),
        shape=(n, idx.size),
    )
    touched = np.asarray(b.sum(axis=1)).ravel() > 0  # rows with something to adjust
    b = b[touched]
    winv = 1.0 / w[idx]
    r = rhs_rows[touched] - b @ g0[idx]
    k = (b * winv) @ b.T
    lam = spla.minres(k, r, rtol=1e-14, maxiter=10_000)[0]
    g = g0.copy()
    g[idx] = g0[idx] + winv * (b.T @ lam)
    return g


def _take(m, r, c):
    return np.asarray(m[r, c]).ravel() if len(r) else np.zeros(0)
