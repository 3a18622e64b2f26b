"""Grey diffuse radiant exchange in an enclosure, on top of form factors.

Conventions (all SI): temperatures in K, fluxes in W/m2, heat rates in W, areas in the
scene's length unit squared (fluxes are per that unit of area). ``F[i, j]`` is the fraction
of the radiation leaving i that reaches j (row = source), as in :class:`nusselt.FormFactors`.
Every surface is grey, diffuse and opaque: reflectance rho_i = 1 - eps_i.

Definitions (e.g. Modest, *Radiative Heat Transfer*, 3rd ed., ch. 5; Hottel & Sarofim,
*Radiative Transfer*, 1967, ch. 3; Gebhart, *Heat Transfer*, 2nd ed., 1971):

* Gebhart absorption factor ``G[i, j]``: the fraction of the energy *emitted* by i that is
  *absorbed* by j, directly or after any number of diffuse reflections,
  ``G = (I - F diag(rho))^-1 F diag(eps)``. In a closed enclosure every row sums to 1.
* Total exchange factor ("script-F", View3D's ``emit=1`` output) ``SF[i, j] = eps_i G[i, j]``,
  so that ``A_i SF[i, j] sigma (T_i^4 - T_j^4)`` is the net radiant exchange from i to j.
  It is reciprocal, ``A_i SF[i, j] = A_j SF[j, i]``; rows sum to eps_i in a closed enclosure.
  For black surfaces SF = F.

Open scenes: the row deficit ``1 - sum_j F[i, j]`` is the view of an ambient (sky) node,
black at the ambient temperature; :func:`solve` accounts for it when ``ambient`` is given.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

SIGMA = 5.670374419e-8  # Stefan-Boltzmann constant, W/(m2 K4) (CODATA 2018, exact in SI)

#: Above this many rows the linear systems are solved with a sparse LU factorisation.
DENSE_LIMIT = 2000


# --------------------------------------------------------------------------------------
# input handling


def _matrix(f) -> tuple[object, np.ndarray | None, list | None]:
    """(matrix, areas or None, names or None) from a FormFactors or a (n, n) array."""
    from .result import FormFactors

    if isinstance(f, FormFactors):
        return f.matrix, np.asarray(f.areas, dtype=float), list(f.names)
    if sp.issparse(f):
        m = sp.csr_array(f, dtype=float)
    else:
        m = np.asarray(f, dtype=float)
    if m.ndim != 2 or m.shape[0] != m.shape[1]:
        raise ValueError(f"F must be a square (n, n) matrix, got shape {m.shape}")
    data = m.data if sp.issparse(m) else m
    if not np.isfinite(data).all():
        raise ValueError("F has non-finite entries")
    if (data < 0).any():
        raise ValueError(f"F has negative entries (smallest {data.min():g})")
    return m, None, None


def _check_rows(m) -> np.ndarray:
    rs = np.asarray(m.sum(axis=1)).ravel()
    bad = np.flatnonzero(rs > 1.0 + 1e-6)
    if bad.size:
        k = int(bad[np.argmax(rs[bad])])
        raise ValueError(f"row {k} of F sums to {rs[k]:.9g} > 1: not a form-factor matrix (row = source)")
    return rs


def per_surface(values, n: int, what: str, *, lo: float | None = None, hi: float | None = None) -> np.ndarray:
    """A scalar or an (n,) array as a float (n,) array, checked to be finite and in [lo, hi]."""
    a = np.asarray(values, dtype=float)
    if a.ndim == 0:
        a = np.full(n, float(a))
    a = a.ravel()
    if a.shape != (n,):
        raise ValueError(f"{what}: expected one value per surface ({n}), got {np.asarray(values).shape}")
    bad = np.flatnonzero(~np.isfinite(a) | ((a < lo) if lo is not None else False) | ((a > hi) if hi is not None else False))
    if bad.size:
        k = int(bad[0])
        rng = f" in [{lo:g}, {hi:g}]" if lo is not None and hi is not None else (f" >= {lo:g}" if lo is not None else "")
        raise ValueError(f"{what}[{k}] = {a[k]!r}: expected a finite number{rng}")
    return a


# --------------------------------------------------------------------------------------
# the linear solve shared by exchange and radiosity


def reflection_solve(f, rho: np.ndarray, rhs: np.ndarray, *, transpose: bool = False) -> np.ndarray:
    """The multiple-reflection solve of a diffuse enclosure.

    ``transpose=False`` solves ``(I - diag(rho) F) X = rhs`` (radiosity: B = E + rho F B);
    ``transpose=True`` solves ``(I - F diag(rho)) X = rhs`` (the Gebhart form). ``rhs`` is (n,)
    or (n, k). Dense LU up to :data:`DENSE_LIMIT` rows, sparse LU (SuperLU) above.
    Raises ValueError when the system is singular (a closed enclosure with no absorption)."""
    n = f.shape[0]
    rho = np.asarray(rho, dtype=float)
    if sp.issparse(f):
        fs = sp.csr_array(f)
        m = (fs @ sp.diags_array(rho)) if transpose else (sp.diags_array(rho) @ fs)
        a = sp.identity(n, format="csc") - sp.csc_array(m)
        if n <= DENSE_LIMIT:
            a = a.toarray()
    else:
        fd = np.asarray(f, dtype=float)
        m = fd * rho[None, :] if transpose else rho[:, None] * fd
        a = np.eye(n) - m
        if n > DENSE_LIMIT:
            a = sp.csc_array(a)
    if sp.issparse(a):
        try:
            lu = spla.splu(sp.csc_array(a))
        except RuntimeError as e:  # SuperLU: "Factor is exactly singular"
            raise ValueError(_SINGULAR) from e
        x = lu.solve(np.asarray(rhs, dtype=float))
    else:
        try:
            x = np.linalg.solve(a, rhs)
        except np.linalg.LinAlgError as e:
            raise ValueError(_SINGULAR) from e
    if not np.isfinite(x).all():
        raise ValueError(_SINGULAR)
    return x


_SINGULAR = ("the reflection system I - rho F is singular: the enclosure is closed and nothing in it absorbs "
             "(every reflectance is 1); give some surface a nonzero emissivity/absorptance")


# --------------------------------------------------------------------------------------
# exchange factors


def gebhart(F, emissivity) -> np.ndarray:
    """Gebhart absorption factors ``G[i, j]`` (dense (n, n)): the fraction of the energy emitted
    by surface i that surface j absorbs, directly and after diffuse reflections,
    ``G = (I - F diag(1 - eps))^-1 F diag(eps)``. Rows sum to 1 in a closed enclosure (to
    ``sum_j F[i, j]``-weighted escape otherwise: ``1 - sum_j G[i, j]`` leaves an open scene).
    ``F`` is a dense or sparse (n, n) matrix or a :class:`nusselt.FormFactors`."""
    m, _, _ = _matrix(F)
    _check_rows(m)
    n = m.shape[0]
    eps = per_surface(emissivity, n, "emissivity", lo=0.0, hi=1.0)
    rhs = (m * eps[None, :]) if not sp.issparse(m) else (sp.csr_array(m) @ sp.diags_array(eps)).toarray()
    return reflection_solve(m, 1.0 - eps, np.asarray(rhs), transpose=True)


def script_f(F, emissivity) -> np.ndarray:
    """Total exchange factors ("script-F", View3D's ``emit=1`` quantity), dense (n, n):
    ``SF[i, j] = eps_i G[i, j]`` with :func:`gebhart`'s G, so that
    ``A_i SF[i, j] sigma (T_i^4 - T_j^4)`` is the net radiant heat rate from i to j in a grey
    diffuse enclosure. Reciprocal (``A_i SF_ij = A_j SF_ji``); rows sum to eps_i when the
    enclosure is closed; SF = F for black surfaces.

    ``F``: dense or sparse (n, n) form factors (patch or surface level) or a
    :class:`nusselt.FormFactors`; ``emissivity``: a scalar or (n,) array in [0, 1]."""
    m, _, _ = _matrix(F)
    n = m.shape[0]
    eps = per_surface(emissivity, n, "emissivity", lo=0.0, hi=1.0)
    return eps[:, None] * gebhart(m, eps)
