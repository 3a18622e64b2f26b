"""What every result writer shares: checks of the matrix, names and areas, dense rows a block
at a time, the size limit of dense text tables, and reading a result's fields.

All writers take plain data: ``matrix`` is a scipy.sparse array or a dense ndarray with
F[i, j] = fraction leaving row i that reaches column j (row = source). Files are written to a
temporary name and renamed (:mod:`nusselt.io.atomic`), so a killed run never leaves a
half-written output under the final name.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..._sparse import Csr, issparse

if TYPE_CHECKING:
    import scipy.sparse as sp

from ..atomic import atomic_open

#: Largest matrix written as a dense text table (CSV, View3D text) unless asked otherwise.
MAX_DENSE_ROWS = 20000


def _atomic(path: str, mode: str = "w"):
    """A temporary file next to ``path``, renamed to ``path`` durably on success (see
    :mod:`nusselt.io.atomic`)."""
    return atomic_open(path, mode)


def _square(matrix, what: str = "matrix"):
    shape = matrix.shape
    if len(shape) != 2 or shape[0] != shape[1]:
        raise ValueError(f"{what} must be square, got shape {shape}")
    return shape[0]


def _csr(matrix) -> sp.csr_array | Csr:
    """The matrix in CSR form with sorted, summed entries (a :class:`Csr`, canonical by
    construction, stays as it is: no scipy)."""
    if isinstance(matrix, Csr):
        return matrix
    import scipy.sparse as sp

    if issparse(matrix):
        return sp.csr_array(matrix)
    return sp.csr_array(np.asarray(matrix, dtype=np.float64))


def _names(names, n: int) -> list[str]:
    names = [str(s) for s in names]
    if len(names) != n:
        raise ValueError(f"{len(names)} names for {n} rows")
    return names


def _areas(areas, n: int) -> np.ndarray:
    a = np.asarray(areas, dtype=np.float64).ravel()
    if a.shape != (n,):
        raise ValueError(f"{a.size} areas for {n} rows")
    return a


def _dense_rows(matrix, n: int, block: int = 256):
    """Rows of the matrix as dense float arrays, a block at a time (bounded memory)."""
    import scipy.sparse as sp

    if issparse(matrix):
        m = sp.csr_array(matrix)
        for s in range(0, n, block):
            for r in m[s : s + block].toarray():
                yield r
    else:
        m = np.asarray(matrix, dtype=np.float64)
        for r in m:
            yield r


def _check_size(path: str, n: int, max_rows: int | None, kind: str) -> None:
    if max_rows is not None and n > max_rows:
        gb = n * n * 10 / 1e9
        raise ValueError(
            f"{path}: a dense {kind} of {n} x {n} values (about {gb:.3g} GB of text) is too large "
            f"(limit {max_rows} rows); write .npz instead (sparse, read back with "
            "nusselt.io.load_npz), or aggregate to surfaces"
        )


def stored_matrix(result):
    """A result's matrix as it holds it: a FormFactors' may still be the scipy-free
    :class:`nusselt._sparse.Csr` of the assembly (writing it to ``.npz`` then loads no
    scipy); other results: their ``matrix``."""
    get = getattr(result, "_stored_matrix", None)
    return get() if callable(get) else field(result, "matrix")


def row_sums(matrix) -> np.ndarray:
    if isinstance(matrix, Csr):
        return matrix.row_sums()
    return np.asarray(matrix.sum(axis=1), dtype=np.float64).ravel()


def field(result, key, default=None):
    """``result[key]`` of a dict, else the attribute ``key`` (a FormFactors or any object)."""
    if isinstance(result, dict):
        return result.get(key, default)
    return getattr(result, key, default)
