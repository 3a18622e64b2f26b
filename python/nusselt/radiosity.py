"""Radiosity for images: per-band (e.g. RGB) diffuse reflectance and emission per patch.

Per band c the radiosity B (exitance, the emission's unit) solves B = E + diag(rho) F B, i.e.
``(I - diag(rho_c) F) B_c = E_c`` (Goral, Torrance, Greenberg & Battaile, SIGGRAPH 1984),
the same multiple-reflection system as :mod:`nusselt.exchange` (it calls the same solve).
Methods: ``direct`` (LU, :func:`nusselt.exchange.reflection_solve`), ``jacobi``,
``gauss-seidel`` (sweeps of the splitting, each a sparse triangular solve), and ``shooting``
(progressive refinement, Cohen, Chen, Wallace & Greenberg, SIGGRAPH 1988: the patch with the
most unshot power A_i dB_i shoots it to every patch j, dB_j += rho_j F_ji dB_i). Iterative
methods stop when the residual max|E + rho F B - B| is at most ``tol`` times max|B|.
Open scenes: the row deficit 1 - sum_j F_ij escapes (is lost).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .exchange import _check_rows, _matrix, reflection_solve

METHODS = ("direct", "jacobi", "gauss-seidel", "shooting")


@dataclass
class RadiosityResult:
    """``radiosity`` B and ``irradiation`` H = F B, (n, nb) in the emission's unit;
    ``iterations`` (sweeps, or shots for ``shooting``; 0 for ``direct``), ``residual``
    (max|E + rho F B - B| / max|B|), ``method``."""

    radiosity: np.ndarray
    irradiation: np.ndarray
    iterations: int
    residual: float
    method: str

    def energy_balance(self, areas, reflectance, emission, f) -> dict:
        """Power emitted, absorbed and escaping (open scenes) per band: emitted = absorbed + escaping."""
        m, _, _ = _matrix(f)
        a = np.asarray(areas, float)[:, None]
        d = (1.0 - np.asarray(m.sum(axis=1)).ravel())[:, None]
        return {
            "emitted": (a * emission).sum(axis=0),
            "absorbed": (a * (1.0 - reflectance) * self.irradiation).sum(axis=0),
            "escaping": (a * d * self.radiosity).sum(axis=0),
        }


def _bands(x, n: int, what: str) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.ndim == 1 and a.shape[0] == n:
        a = a[:, None]
    if a.ndim != 2 or a.shape[0] != n:
        raise ValueError(f"{what}: expected an (n, bands) array with n = {n} rows, got shape {a.shape}")
    if not np.isfinite(a).all():
        raise ValueError(f"{what}: non-finite values (row {int(np.argwhere(~np.isfinite(a))[0, 0])})")
    return a


def solve(
    F,
    reflectance,
    emission,
    *,
    method: str = "direct",
    areas=None,
    tol: float = 1e-10,
    max_iter: int = 10_000,
) -> RadiosityResult:
    """Radiosity B of every patch per band: ``(I - diag(rho) F) B = E``.

    ``F``: a :class:`nusselt.FormFactors` or a dense/sparse (n, n) matrix (row = source);
    ``reflectance``: (n, nb) (or (n,)) in [0, 1]; ``emission``: (n, nb) >= 0, emitted exitance;
    ``method``: one of :data:`METHODS`; ``areas`` (needed by ``shooting`` when ``F`` is a plain
    matrix); ``tol``: relative residual for the iterative methods; ``max_iter``: sweeps (or, for
    ``shooting``, shots per patch), after which a ValueError says it did not converge."""
    m, a0, _ = _matrix(F)
    _check_rows(m)
    n = m.shape[0]
    rho = _bands(reflectance, n, "reflectance")
    e = _bands(emission, n, "emission")
    if rho.shape[1] == 1 and e.shape[1] > 1:
        rho = np.repeat(rho, e.shape[1], axis=1)
    if rho.shape != e.shape:
        raise ValueError(f"reflectance {rho.shape} and emission {e.shape} must have the same bands")
    if (rho < 0).any() or (rho > 1).any():
        raise ValueError("reflectance: values must lie in [0, 1]")
    if (e < 0).any():
        raise ValueError("emission: values must be >= 0")
    if method not in METHODS:
        raise ValueError(f"unknown radiosity method {method!r}; choose one of {', '.join(METHODS)}")
    if not (tol > 0):
        raise ValueError(f"tol must be > 0, got {tol!r}")
    fs = sp.csr_array(m)
    if method == "direct":
        b = np.column_stack([reflection_solve(m, rho[:, c], e[:, c]) for c in range(e.shape[1])])
        it = 0
    elif method == "shooting":
        if a0 is None:
            if areas is None:
                raise ValueError("shooting needs the patch areas (areas=) when F is a plain matrix")
            a0 = np.asarray(areas, dtype=float)
        b, it = _shoot(fs, np.asarray(a0, float), rho, e, tol, max_iter)
    else:
        b, it = _sweep(fs, rho, e, tol, max_iter, gauss_seidel=(method == "gauss-seidel"))
    h = np.asarray(fs @ b)
    return RadiosityResult(b, h, it, _residual(b, e + rho * h), method)


def _residual(b: np.ndarray, new: np.ndarray) -> float:
    scale = float(np.abs(b).max())
    return float(np.abs(new - b).max()) / scale if scale > 0 else 0.0


def _sweep(fs, rho, e, tol, max_iter, *, gauss_seidel: bool):
    """Jacobi B <- E + rho F B, or Gauss-Seidel (I - rho L) B <- E + rho U B (L: the lower
    triangle of F with its diagonal, U: strictly upper), one triangular solve per band."""
    b = e.copy()
    low = sp.csr_array(sp.tril(fs, k=0)) if gauss_seidel else None
    up = sp.csr_array(sp.triu(fs, k=1)) if gauss_seidel else None
    eye = sp.identity(fs.shape[0], format="csr")
    lows = [sp.csr_array(eye - sp.diags_array(rho[:, c]) @ low) for c in range(e.shape[1])] if gauss_seidel else []
    for it in range(1, max_iter + 1):
        if gauss_seidel:
            rhs = e + rho * np.asarray(up @ b)
            new = np.column_stack([spla.spsolve_triangular(lows[c], rhs[:, c], lower=True) for c in range(e.shape[1])])
        else:
            new = e + rho * np.asarray(fs @ b)
        done = _residual(new, e + rho * np.asarray(fs @ new)) <= tol
        b = new
        if done:
            return b, it
    raise ValueError(
        f"radiosity {'gauss-seidel' if gauss_seidel else 'jacobi'} did not reach tol {tol:g} in "
        f"{max_iter} sweeps (residual {_residual(b, e + rho * np.asarray(fs @ b)):.2e}); "
        "raise max_iter or use method='direct'"
    )


def _shoot(fs, areas, rho, e, tol, max_iter):
    """Progressive refinement. The unshot radiosity dB is exactly the residual E + rho F B - B,
    so stopping on max|dB| <= tol max|B| is the same test as the other methods'."""
    n, nb = e.shape
    col = sp.csc_array(fs)  # column i of F: F_ji for every j
    b, unshot = e.copy(), e.copy()
    power = areas * unshot.sum(axis=1)
    limit = max_iter * max(n, 1)
    for shot in range(1, limit + 1):
        i = int(np.argmax(power))
        if np.abs(unshot).max() <= tol * np.abs(b).max():
            return b, shot - 1
        lo, hi = col.indptr[i], col.indptr[i + 1]
        j, fji = col.indices[lo:hi], col.data[lo:hi]
        d = unshot[i].copy()
        unshot[i] = 0.0
        gain = rho[j] * fji[:, None] * d[None, :]  # dB_j = rho_j F_ji dB_i
        b[j] += gain
        unshot[j] += gain
        power[i] = 0.0
        power[j] = areas[j] * unshot[j].sum(axis=1)
    raise ValueError(
        f"radiosity shooting did not reach tol {tol:g} in {limit} shots "
        f"(unshot {np.abs(unshot).max() / np.abs(b).max():.2e}); use method='direct'"
    )


# --------------------------------------------------------------------------------------
# the Cornell box in colour

#: Approximate linear-RGB diffuse reflectances of the Cornell box surfaces, from the measured
#: spectra of the Cornell Program of Computer Graphics "Cornell Box Data"
#: (https://www.graphics.cornell.edu/online/box/data.html) averaged over roughly 600-700 nm (R),
#: 500-600 nm (G) and 400-500 nm (B): the values widely used in renderer test scenes.
CORNELL_REFLECTANCE = {
    "white": (0.73, 0.71, 0.68),
    "red": (0.63, 0.065, 0.05),
    "green": (0.14, 0.45, 0.091),
}
#: The light's emitted exitance in the same bands (warm white, arbitrary units; the published
#: emission spectrum rises steeply towards the red).
CORNELL_EMISSION = (17.0, 12.0, 4.0)


def cornell_colours(scene) -> tuple[np.ndarray, np.ndarray]:
    """(reflectance, emission), (n, 3) each, for a scene whose surface names follow the bundled
    ``cornell_box.obj`` (``red``, ``green``, ``light``; everything else white)."""
    names = [scene.surface_names[s] for s in scene.surface]
    rho = np.array([CORNELL_REFLECTANCE.get(n, CORNELL_REFLECTANCE["white"]) for n in names], float)
    emit = np.array([CORNELL_EMISSION if n == "light" else (0.0, 0.0, 0.0) for n in names], float)
    rho[np.array([n == "light" for n in names], bool)] = 0.78
    return rho, emit


def display_colours(b: np.ndarray, emission: np.ndarray, *, gamma: float = 2.2) -> np.ndarray:
    """Tone mapping for a picture (not physics): radiosity scaled so the brightest non-emitting
    patch is white, clipped (emitters saturate), then display gamma."""
    lit = ~(np.asarray(emission).sum(axis=1) > 0)
    top = float(b[lit].max()) if lit.any() and b[lit].max() > 0 else float(b.max() or 1.0)
    return np.clip(b / top, 0.0, 1.0) ** (1.0 / gamma)
