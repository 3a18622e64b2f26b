"""The form-factor matrix of a scene, with its areas, names and error measures."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from . import trust as _trust
from ._sparse import Csr, issparse

# A scipy.sparse array or a dense ndarray. scipy ships no type stubs, so the sparse side is
# Any to mypy and the union collapses to Any; the name documents what the value is.
MatrixLike = Any


@dataclass
class FormFactors:
    """F[i, j]: the fraction of the radiation leaving row i that reaches column j.

    Attributes
    ----------
    matrix : scipy.sparse.csr_array or numpy.ndarray
        The form factors (row = source).
    areas : ndarray
        Area of each row/column.
    names : list of str
        Name of each row/column (patch labels, or surface names after :meth:`by_surface`).
    faces : ndarray
        For patch-level results, the scene face index of each row; for surface-level
        results, the index into the scene's surface names.
    surface : ndarray or None
        For patch-level results, the surface index of each row (used by :meth:`by_surface`).
    surface_names : list of str or None
    method : str
    std_err : sparse array or None
        Standard error of each entry for sampling methods.
    lost : ndarray or None
        Per row, the part of the hemisphere a row method did not assign (e.g. the horizon band
        of the single-plane method).
    """

    matrix: MatrixLike
    areas: np.ndarray
    names: list
    faces: np.ndarray
    method: str
    surface: np.ndarray | None = None
    surface_names: list | None = None
    std_err: MatrixLike | None = None
    lost: np.ndarray | None = None
    info: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.areas)

    def dense(self) -> np.ndarray:
        m = self._stored_matrix()
        return m.toarray() if issparse(m) or isinstance(m, Csr) else np.asarray(m)

    def _stored_matrix(self) -> MatrixLike:
        """The matrix as held: what ``matrix`` gives, or, while nothing asked for ``matrix``
        yet, the scipy-free :class:`nusselt._sparse.Csr` the assembly built (its ``data``,
        ``indices``, ``indptr``, ``shape``, ``nnz`` are those of the scipy array), so that a
        run that only writes its result never loads scipy."""
        return self.__dict__["_matrix"]

    def _measures(self) -> dict:
        """Closure, reciprocity and row-sum measures, computed once per matrix object
        (:mod:`nusselt.trust`: one pass, no dense or transposed copy of the matrix)."""
        m = self._stored_matrix()
        cached = self.__dict__.get("_measures_cache")
        out = cached[1] if cached is not None and cached[0] is m else {}
        if "row_sums" not in out:
            rs = _trust.row_sums(m)
            out["row_sums"] = rs
            out["closure_error"] = float(np.max(np.abs(rs - 1.0))) if len(rs) else 0.0
        if "reciprocity_error" not in out:
            out["reciprocity_error"] = _trust.reciprocity_error(self.matrix, self.areas)
        self.__dict__["_measures_cache"] = (self._stored_matrix(), out)
        return out

    def _seed_measures(self, **known: float) -> None:
        """Measures the assembly already knows for this matrix (e.g. the reciprocity error of a
        pair method, from its blocks), so they are not recomputed from the matrix."""
        self.__dict__["_measures_cache"] = (self._stored_matrix(), dict(known))

    @property
    def row_sums(self) -> np.ndarray:
        return self._measures()["row_sums"]

    @property
    def closure_error(self) -> float:
        """max_i |sum_j F_ij - 1| (meaningful for closed enclosures)."""
        return self._measures()["closure_error"]

    @property
    def reciprocity_error(self) -> float:
        """max_ij |A_i F_ij - A_j F_ji| / max(A_i F_ij, A_j F_ji), over nonzero pairs."""
        return self._measures()["reciprocity_error"]

    def by_surface(self) -> FormFactors:
        """The same result aggregated to named surfaces with the form-factor algebra:
        additivity over receivers and area-weighted composition of sources,
        F_(S->T) = sum_{i in S, j in T} A_i F_ij / sum_{i in S} A_i."""
        import scipy.sparse as sp

        if self.surface is None:
            raise ValueError("this result is already per surface")
        used = np.unique(self.surface)
        col = np.searchsorted(used, self.surface)
        n, m = len(self.areas), len(used)
        s = sp.csr_array((np.ones(n), (np.arange(n), col)), shape=(n, m))
        g = _as_sparse(self.matrix).multiply(self.areas[:, None]).tocsr()
        gs = (s.T @ g @ s).tocsr()
        a = s.T @ self.areas
        fs = sp.csr_array(gs.multiply(1.0 / a[:, None]))
        std = None
        if self.std_err is not None:
            # independent entries: variances add with the squared area weights
            v = _as_sparse(self.std_err).power(2).multiply(self.areas[:, None] ** 2).tocsr()
            vs = (s.T @ v @ s).tocsr()
            std = sp.csr_array(vs.sqrt().multiply(1.0 / a[:, None]))
        lost = None
        if self.lost is not None:
            lost = (s.T @ (self.lost * self.areas)) / a
        names = [self.surface_names[k] for k in used] if self.surface_names else [str(k) for k in used]
        matrix = fs if issparse(self.matrix) else fs.toarray()
        return FormFactors(matrix, a, names, used, self.method, None, None, std, lost, dict(self.info))

    @property
    def max_std_err(self) -> float | None:
        """The largest standard error of an entry (sampling methods), else None."""
        if self.std_err is None:
            return None
        s = self.std_err
        return float(s.max()) if (s.nnz if issparse(s) else np.size(s)) else 0.0

    def trust(self) -> dict:
        """The error measures as a dict (stored with the result by ``nusselt matrix``):
        closure error, reciprocity error, row-sum range, largest standard error, and the
        largest hemisphere fraction a row method left unassigned."""
        rs = self.row_sums
        out: dict[str, float | None] = {
            "closure_error": float(np.max(np.abs(rs - 1.0))) if len(rs) else 0.0,
            "reciprocity_error": self.reciprocity_error,
            "row_sum_min": float(rs.min()) if len(rs) else 0.0,
            "row_sum_max": float(rs.max()) if len(rs) else 0.0,
        }
        if self.std_err is not None:
            out["max_std_err"] = self.max_std_err
        if self.lost is not None:
            out["max_lost"] = float(np.max(self.lost)) if len(self.lost) else 0.0
        return out

    def summary(self) -> str:
        """A readable table (small results) or summary statistics (large ones)."""
        rs = self.row_sums
        lines = [
            f"{len(self)} x {len(self)} form factors, method {self.method!r}, {_nnz(self._stored_matrix())} nonzero",
            f"max |row sum - 1| = {self.closure_error:.3e}   reciprocity error = {self.reciprocity_error:.3e}"
            + (f"   row sums {rs.min():.6f} .. {rs.max():.6f}" if len(rs) else ""),
        ]
        if self.std_err is not None:
            lines.append(f"largest standard error of an entry = {self.max_std_err:.3e}")
        if self.lost is not None and len(self.lost):
            lines.append(f"largest unassigned hemisphere fraction of a row = {np.max(self.lost):.3e}")
        if self.info.get("dropped"):
            lines.append(
                f"largest row mass dropped by the threshold {self.info.get('threshold'):g} = {self.info['dropped']:.3e}"
            )
        if len(self) <= 12:
            f = self.dense()
            w = max(8, max(len(n) for n in self.names))
            lines.append(" " * (w + 12) + "".join(f"{n[:10]:>11}" for n in self.names) + "       sum")
            lines.append(f"{'from':<{w}} {'area':>11}")
            for i, n in enumerate(self.names):
                row = "".join(f"{x:11.6f}" for x in f[i])
                lines.append(f"{n:<{w}} {self.areas[i]:11.5g}{row}{f[i].sum():10.6f}")
        return "\n".join(lines)


def _get_matrix(self: FormFactors) -> MatrixLike:
    m = self.__dict__["_matrix"]
    if isinstance(m, Csr):  # asked for: the scipy array over the same arrays, from now on
        csr, m = m, m.to_scipy()
        self.__dict__["_matrix"] = m
        cached = self.__dict__.get("_measures_cache")
        if cached is not None and cached[0] is csr:  # the same matrix: its measures stand
            self.__dict__["_measures_cache"] = (m, cached[1])
    return m


def _set_matrix(self: FormFactors, m: MatrixLike) -> None:
    self.__dict__["_matrix"] = m


# ``matrix`` is a dataclass field read through this property: a Csr from the assembly becomes
# a scipy array the first time it is read (see FormFactors.stored_matrix).
FormFactors.matrix = property(_get_matrix, _set_matrix)


def _nnz(m) -> int:
    return int(m.nnz) if issparse(m) or isinstance(m, Csr) else int(np.count_nonzero(m))


def _as_sparse(m):
    import scipy.sparse as sp

    return m if issparse(m) else sp.csr_array(m)
