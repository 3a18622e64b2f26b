"""Trust measures of a form-factor matrix without densifying it or copying it whole.

* row sums sum_j F_ij (1 in a closed enclosure), closure error max_i |sum_j F_ij - 1|;
* reciprocity error max_ij |A_i F_ij - A_j F_ji| / max(|A_i F_ij|, |A_j F_ji|) over the pairs
  where either is nonzero (an entry present in one direction only counts 1).

The reciprocity check compares G = A F with its transpose a band of rows at a time: rows
[s, e) of G against columns [s, e) transposed, so the memory needed is that of one band,
not of a second matrix.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._sparse import Csr, issparse

if TYPE_CHECKING:
    import scipy.sparse as sp

#: Entries per band of the reciprocity check (bounds its extra memory to ~16 bytes each).
BAND_ENTRIES = 1 << 23


def row_sums(matrix) -> np.ndarray:
    if isinstance(matrix, Csr):
        return matrix.row_sums()
    return np.asarray(matrix.sum(axis=1), dtype=np.float64).ravel()


def reciprocity_error(matrix, areas: np.ndarray) -> float:
    """max |A_i F_ij - A_j F_ji| / max(|A_i F_ij|, |A_j F_ji|) over nonzero pairs."""
    import scipy.sparse as sp

    a = np.asarray(areas, dtype=np.float64)
    n = len(a)
    if n == 0:
        return 0.0
    if not issparse(matrix):
        g = np.asarray(matrix, dtype=np.float64) * a[:, None]
        den = np.maximum(np.abs(g), np.abs(g.T))
        ok = den > 0
        return float(np.max(np.abs(g - g.T)[ok] / den[ok])) if ok.any() else 0.0
    m = sp.csr_array(matrix.to_scipy() if isinstance(matrix, Csr) else matrix)
    if not m.has_sorted_indices:
        m = m.copy()
        m.sort_indices()
    per_row = max(1, m.nnz // n)
    width = max(1, BAND_ENTRIES // per_row)
    worst = 0.0
    for s in range(0, n, width):
        e = min(n, s + width)
        rows = m[s:e]  # F[s:e, :]
        cols = sp.csr_array(m[:, s:e].T)  # row c: F[r, s + c] at column r
        cols.sort_indices()
        worst = max(worst, _band_error(rows, cols, a, s))
    return worst


def _band_error(rows: sp.csr_array, cols: sp.csr_array, a: np.ndarray, s: int) -> float:
    import scipy.sparse as sp

    n_band = rows.shape[0]
    if rows.nnz == cols.nnz and np.array_equal(rows.indptr, cols.indptr) and np.array_equal(rows.indices, cols.indices):
        # the usual case, a symmetric pattern: compare entry by entry
        r = np.repeat(np.arange(s, s + n_band), np.diff(rows.indptr))
        g1 = rows.data * a[r]  # A_i F_ij, i in the band
        g2 = cols.data * a[cols.indices]  # A_j F_ji
        den = np.maximum(np.abs(g1), np.abs(g2))
        ok = den > 0
        return float(np.max(np.abs(g1 - g2)[ok] / den[ok])) if ok.any() else 0.0
    g1 = sp.csr_array(rows.multiply(a[s : s + n_band, None]))
    g2 = sp.csr_array(cols.multiply(a[None, :]))
    diff = abs(g1 - g2).tocoo()
    scale = sp.csr_array(abs(g1).maximum(abs(g2)))
    if diff.nnz == 0:
        return 0.0
    den = np.asarray(scale[diff.row, diff.col]).ravel()
    ok = den > 0
    return float(np.max(diff.data[ok] / den[ok])) if ok.any() else 0.0
