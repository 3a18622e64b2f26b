"""scipy.sparse on demand: importing it costs more than numpy itself (0.2 s of CPU here, as
much as reading and writing a 6 144-patch result), and reading a scene, computing a pair
method's matrix and writing it to ``.npz`` never need it."""

from __future__ import annotations

import sys
from typing import Any

import numpy as np


def issparse(m: Any) -> bool:
    """``scipy.sparse.issparse`` without importing scipy: nothing is sparse before it loads
    (a :class:`Csr` is not: it is turned into a scipy array where one is asked for)."""
    mod = sys.modules.get("scipy.sparse")
    return mod is not None and bool(mod.issparse(m))


class Csr:
    """A square CSR matrix in canonical form (columns ascending in every row, no duplicates)
    held as its three arrays, as the assembly builds it: what a whole run needs of it (row
    sums, entry count, the arrays for the ``.npz``) without scipy. :meth:`to_scipy` wraps the
    same arrays in a ``scipy.sparse.csr_array`` without copying them."""

    __slots__ = ("data", "indices", "indptr", "shape", "_row_sums", "_scipy")

    def __init__(self, data: np.ndarray, indices: np.ndarray, indptr: np.ndarray, n: int):
        if len(indptr) != n + 1 or len(indices) != len(data) or (n and int(indptr[-1]) != len(data)):
            raise ValueError(f"inconsistent CSR parts: {len(indptr)} indptr, {len(indices)} indices, {len(data)} data")
        self.data, self.indices, self.indptr, self.shape = data, indices, indptr, (n, n)
        self._row_sums: np.ndarray | None = None
        self._scipy: Any = None

    @property
    def nnz(self) -> int:
        return len(self.data)

    @property
    def dtype(self) -> np.dtype:
        return self.data.dtype

    def row_sums(self) -> np.ndarray:
        """sum_j of each row, in float64 (entries added in column order)."""
        if self._row_sums is None:
            n = self.shape[0]
            out = np.zeros(n, dtype=np.float64)
            starts = self.indptr[:-1]
            full = np.flatnonzero(self.indptr[1:] > starts)
            if len(full):
                # reduceat over the starts of non-empty rows: each sums up to the next start
                out[full] = np.add.reduceat(self.data, starts[full], dtype=np.float64)
            self._row_sums = out
        return self._row_sums

    def abs_row_sums(self, rows: np.ndarray) -> np.ndarray:
        """sum_j |F_ij| of the given rows."""
        s, e = self.indptr[rows], self.indptr[np.asarray(rows) + 1]
        return np.array([float(np.abs(self.data[a:b]).sum()) for a, b in zip(s, e)], dtype=np.float64)

    def toarray(self) -> np.ndarray:
        n = self.shape[0]
        out = np.zeros((n, n), dtype=self.data.dtype)
        rows = np.repeat(np.arange(n), np.diff(self.indptr))
        out[rows, self.indices] = self.data
        return out

    def to_scipy(self):
        """The same matrix as a canonical ``scipy.sparse.csr_array`` over the same arrays.
        scipy keeps index arrays as given only when both have one dtype: int32 (the
        indices' dtype) while the entries fit, so the big indices array is not copied."""
        if self._scipy is None:
            import scipy.sparse as sp

            n = self.shape[0]
            indptr = self.indptr
            if self.indices.dtype == np.int32 and (not n or int(indptr[-1]) <= np.iinfo(np.int32).max):
                indptr = indptr.astype(np.int32)
            m = sp.csr_array((self.data, self.indices, indptr), shape=self.shape)
            m.has_sorted_indices = True
            m.has_canonical_format = True
            self._scipy = m
        return self._scipy


def as_scipy(m: Any) -> Any:
    """A :class:`Csr` as its scipy array; anything else as it is."""
    return m.to_scipy() if isinstance(m, Csr) else m
