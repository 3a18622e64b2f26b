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

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

if TYPE_CHECKING:
    from .result import MatrixLike

SIGMA = 5.670374419e-8  # Stefan-Boltzmann constant, W/(m2 K4) (CODATA 2018, exact in SI)

#: Above this many rows the linear systems are solved with a sparse LU factorisation.
DENSE_LIMIT = 2000


# --------------------------------------------------------------------------------------
# input handling


def _matrix(f) -> tuple[MatrixLike, np.ndarray | None, list | None]:
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
    bad = np.flatnonzero(
        ~np.isfinite(a) | ((a < lo) if lo is not None else False) | ((a > hi) if hi is not None else False)
    )
    if bad.size:
        k = int(bad[0])
        rng = (
            f" in [{lo:g}, {hi:g}]" if lo is not None and hi is not None else (f" >= {lo:g}" if lo is not None else "")
        )
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


_SINGULAR = (
    "the reflection system I - rho F is singular: the enclosure is closed and nothing in it absorbs "
    "(every reflectance is 1); give some surface a nonzero emissivity/absorptance"
)


# --------------------------------------------------------------------------------------
# exchange factors


def gebhart(F, emissivity) -> np.ndarray:
    """Gebhart absorption factors ``G[i, j]`` (dense (n, n)): the fraction of the energy emitted
    by surface i that surface j absorbs, directly and after diffuse reflections,
    ``G = (I - F diag(1 - eps))^-1 F diag(eps)``. Rows sum to 1 in a closed enclosure; in an
    open scene ``1 - sum_j G[i, j]`` is the fraction of i's emission that escapes.
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


# --------------------------------------------------------------------------------------
# blackbody band fractions

C2 = 14387.768775  # second radiation constant hc/k, um K (CODATA 2018)


def blackbody_fraction(wavelength_um, temperature) -> np.ndarray:
    """F_{0-lambda T}: the fraction of blackbody emission at ``temperature`` (K) below
    ``wavelength_um`` (micrometres); broadcasts. With zeta = C2 / (lambda T):
    zeta >= 0.1: the series (15/pi^4) sum_n e^{-n zeta}/n (zeta^3 + 3 zeta^2/n + 6 zeta/n^2 + 6/n^3)
    up to n zeta = 40 (e^-40 below rounding); zeta < 0.1: 1 - (15/pi^4) times the integral of
    x^3/(e^x - 1) from 0 to zeta by its Bernoulli-number expansion (Siegel & Howell, *Thermal
    Radiation Heat Transfer*, sec. 2.4)."""
    lam = np.asarray(wavelength_um, dtype=float)
    t = np.asarray(temperature, dtype=float)
    lam, t = np.broadcast_arrays(lam, t)
    out = np.zeros(lam.shape)
    with np.errstate(invalid="ignore"):
        lt = lam * t  # inf * 0 K: NaN, and a body at 0 K emits nothing (its fraction is left 0)
    out[np.isposinf(lt)] = 1.0
    fin = np.isfinite(lt) & (lt > 0)
    z = np.where(fin, C2 / np.where(fin, lt, 1.0), np.inf)
    big = fin & (z >= 0.1)
    if big.any():
        zb = z[big]
        n = np.arange(1, 401, dtype=float)[:, None]
        with np.errstate(under="ignore"):
            terms = np.exp(-n * zb) / n * (zb**3 + 3 * zb**2 / n + 6 * zb / n**2 + 6 / n**3)
        out[big] = 15.0 / np.pi**4 * terms.sum(axis=0)
    small = fin & (z < 0.1)
    if small.any():
        zs = z[small]
        # x^3/(e^x-1) = x^2 - x^3/2 + sum_k B_2k x^(2k+2)/(2k)!, integrated term by term
        integral = zs**3 / 3 - zs**4 / 8
        for k, b2k in enumerate((1 / 6, -1 / 30, 1 / 42, -1 / 30, 5 / 66), start=1):
            integral = integral + b2k / math.factorial(2 * k) * zs ** (2 * k + 3) / (2 * k + 3)
        out[small] = 1.0 - 15.0 / np.pi**4 * integral
    return out


def band_fractions(edges_um, temperature) -> np.ndarray:
    """(n, nb) fractions of sigma T^4 emitted in each band between consecutive ``edges_um``
    (micrometres, increasing; use 0 and ``np.inf`` at the ends to cover the spectrum)."""
    e = np.asarray(edges_um, dtype=float)
    if e.ndim != 1 or e.size < 2 or np.any(np.diff(e) <= 0) or e[0] < 0:
        raise ValueError(f"band edges must be >= 2 increasing wavelengths >= 0 (um), got {e.tolist()}")
    t = np.atleast_1d(np.asarray(temperature, dtype=float))
    cum = blackbody_fraction(e[None, :], t[:, None])
    return np.diff(cum, axis=1)


# --------------------------------------------------------------------------------------
# the net-radiation method


@dataclass
class ExchangeResult:
    """The solved enclosure (per row of F: patches or named surfaces).

    Attributes (SI; area unit as in the scene): ``temperature`` (K, for flux-given surfaces the
    solved one; NaN where eps = 0 makes it undefined), ``radiosity`` J and ``irradiation`` H
    (W/m2), ``flux`` q = J - H (W/m2, positive: the surface loses heat by radiation),
    ``heat`` Q = A q (W), ``ambient_heat`` (W, the net heat the ambient/sky node receives,
    equal to sum(Q) by energy conservation), ``bands`` (band edges in um, or None for grey);
    in band mode ``radiosity``/``irradiation`` are (n, nb) per band and the totals are summed.
    """

    names: list
    areas: np.ndarray
    emissivity: np.ndarray
    temperature: np.ndarray
    radiosity: np.ndarray
    irradiation: np.ndarray
    flux: np.ndarray
    heat: np.ndarray
    ambient_heat: float
    ambient: float | None
    bands: np.ndarray | None = None
    _f: object = field(default=None, repr=False)
    _sigma: float = field(default=SIGMA, repr=False)

    def pairwise(self) -> np.ndarray:
        """Dense (n, n) net heat rates Q_ij (W) from i to j, A_i SF_ij sigma (T_i^4 - T_j^4)
        (summed over bands), antisymmetric; row sums plus the exchange with the ambient give Q."""
        if not np.isfinite(self.temperature).all():
            raise ValueError("pairwise exchange needs every temperature (a surface with eps = 0 has none)")
        if self.bands is None:
            sf = script_f(self._f, self.emissivity)
            eb = self._sigma * self.temperature**4
            return self.areas[:, None] * sf * (eb[:, None] - eb[None, :])
        frac = band_fractions(self.bands, self.temperature)
        out = np.zeros((len(self.areas), len(self.areas)))
        for b in range(frac.shape[1]):
            sf = script_f(self._f, self.emissivity[:, b])
            eb = frac[:, b] * self._sigma * self.temperature**4
            out += self.areas[:, None] * sf * (eb[:, None] - eb[None, :])
        return out

    def table(self) -> str:
        """A readable per-surface table."""
        w = max([7] + [len(n) for n in self.names])
        eps = self.emissivity if self.emissivity.ndim == 1 else self.emissivity.mean(axis=1)
        lines = [f"{'surface':<{w}} {'area':>10} {'eps':>6} {'T K':>9} {'J W/m2':>11} {'q W/m2':>11} {'Q W':>11}"]
        for k, n in enumerate(self.names):
            j = self.radiosity[k] if self.radiosity.ndim == 1 else self.radiosity[k].sum()
            lines.append(
                f"{n:<{w}} {self.areas[k]:10.4g} {eps[k]:6.3f} {self.temperature[k]:9.3f} {j:11.5g} "
                f"{self.flux[k]:11.5g} {self.heat[k]:11.5g}"
            )
        amb = "" if self.ambient is None else f" at {self.ambient:g} K"
        lines.append(f"sum of Q = {self.heat.sum():.6g} W; heat to the ambient{amb} = {self.ambient_heat:.6g} W")
        return "\n".join(lines)


def solve(
    result,
    emissivity,
    temperature=None,
    flux=None,
    *,
    ambient: float | None = None,
    areas=None,
    names=None,
    bands=None,
    sigma: float = SIGMA,
) -> ExchangeResult:
    """Grey (or band-wise grey) diffuse exchange by the net-radiation method.

    ``result``: a :class:`nusselt.FormFactors` (patch or surface level) or an (n, n) dense or
    sparse F with ``areas``. Per row, give the temperature (K) or the net flux q (W/m2, positive
    leaving): ``temperature`` and ``flux`` are (n,) arrays with NaN where not given (a scalar
    applies to all); exactly one must be finite per row. ``emissivity``: scalar or (n,), or
    with ``bands`` (band edges in um, e.g. ``[0, 4, np.inf]``) an (n, nb) array of per-band
    emissivities (band mode needs every temperature). ``ambient``: the temperature (K) of the
    black ambient/sky node that receives each row's deficit 1 - sum_j F_ij (None: 0 K).

    Per band the radiosities solve ``(I - diag(c) F) J = b`` with c_i = 1 - eps_i, b_i = eps_i
    E_b,i + (1 - eps_i) d_i E_amb where T is given, and c_i = 1, b_i = q_i + d_i E_amb where q is
    given (d_i = 1 - sum_j F_ij); then H = F J + d E_amb, q = J - H. Dense LU up to
    :data:`DENSE_LIMIT` rows, sparse LU above."""
    m, a0, n0 = _matrix(result)
    d = 1.0 - _check_rows(m)
    d = np.where(np.abs(d) < 1e-12, 0.0, np.maximum(d, 0.0))
    n = m.shape[0]
    if a0 is None:
        if areas is None:
            raise ValueError("solve(F, ...) needs areas= when F is a plain matrix")
        a0 = per_surface(areas, n, "areas", lo=0.0)
    names = list(names) if names is not None else (n0 if n0 is not None else [str(k) for k in range(n)])
    if len(names) != n:
        raise ValueError(f"names: expected {n}, got {len(names)}")
    t = np.full(n, np.nan) if temperature is None else np.asarray(temperature, dtype=float) * np.ones(n)
    q = np.full(n, np.nan) if flux is None else np.asarray(flux, dtype=float) * np.ones(n)
    if t.shape != (n,) or q.shape != (n,):
        raise ValueError(f"temperature/flux: expected one value per surface ({n})")
    has_t, has_q = np.isfinite(t), np.isfinite(q)
    for k in range(n):
        if has_t[k] == has_q[k]:
            raise ValueError(
                f"surface {k} ({names[k]!r}): give exactly one of temperature and flux "
                f"(got {'both' if has_t[k] else 'neither'})"
            )
        if has_t[k] and t[k] < 0:
            raise ValueError(f"surface {k} ({names[k]!r}): temperature {t[k]:g} K is negative")
    t_amb = 0.0 if ambient is None else float(ambient)
    if not (np.isfinite(t_amb) and t_amb >= 0):
        raise ValueError(f"ambient temperature must be a finite number of kelvin >= 0, got {ambient!r}")
    if has_q.all() and not d.any():
        raise ValueError(
            "every surface has a given flux in a closed enclosure: the temperatures are undetermined; "
            "give at least one temperature"
        )

    if bands is None:
        eps = per_surface(emissivity, n, "emissivity", lo=0.0, hi=1.0)
        frac = np.ones((n, 1))
        frac_amb = np.ones(1)
        eps_b = eps[:, None]
    else:
        if not has_t.all():
            raise ValueError("band mode needs a temperature for every surface (the band fractions depend on it)")
        edges = np.asarray(bands, dtype=float)
        frac = band_fractions(edges, t)
        frac_amb = band_fractions(edges, t_amb)[0]
        eb = np.asarray(emissivity, dtype=float)
        if eb.ndim < 2:
            eb = np.broadcast_to(eb, (n, frac.shape[1])) if eb.ndim == 0 or eb.shape == (frac.shape[1],) else eb
        eps_b = np.array(eb, dtype=float)
        if eps_b.shape != (n, frac.shape[1]):
            raise ValueError(f"emissivity: expected ({n}, {frac.shape[1]}) per-band values, got {eps_b.shape}")
        if not (np.isfinite(eps_b).all() and (eps_b >= 0).all() and (eps_b <= 1).all()):
            raise ValueError("emissivity: per-band values must be finite numbers in [0, 1]")
        eps = eps_b

    e_amb = frac_amb * sigma * t_amb**4  # (nb,)
    tk = np.where(has_t, t, 0.0)
    ebb = frac * (sigma * tk**4)[:, None]  # (n, nb)
    c = np.where(has_t[:, None], 1.0 - eps_b, 1.0)
    rhs = np.where(
        has_t[:, None],
        eps_b * ebb + (1.0 - eps_b) * d[:, None] * e_amb[None, :],
        np.where(has_q, q, 0.0)[:, None] + d[:, None] * e_amb[None, :],
    )
    nb = rhs.shape[1]
    if nb == 1 or np.allclose(c, c[:, :1]):
        j = reflection_solve(m, c[:, 0], rhs) if nb > 1 else reflection_solve(m, c[:, 0], rhs[:, 0])[:, None]
    else:
        j = np.column_stack([reflection_solve(m, c[:, b], rhs[:, b]) for b in range(nb)])
    h = np.asarray(m @ j) + d[:, None] * e_amb[None, :]
    qq = (j - h).sum(axis=1)
    t_out = t.copy()
    if (~has_t).any():
        # q = eps (E_b - H) for a grey surface: E_b = H + q / eps
        with np.errstate(divide="ignore", invalid="ignore"):
            e_b = h[:, 0] + np.where(has_q, q, 0.0) / eps
        e_b = np.where(eps > 0, e_b, np.nan)
        if np.any(e_b[~has_t] < -1e-9 * max(1.0, float(np.nanmax(np.abs(h))))):
            raise ValueError(
                "the given fluxes need a negative emissive power somewhere (no temperature satisfies them)"
            )
        t_out = np.where(has_t, t, (np.maximum(e_b, 0.0) / sigma) ** 0.25)
        qq = np.where(has_q, q, qq)
    heat = a0 * qq
    squeeze = bands is None
    return ExchangeResult(
        names=names,
        areas=a0,
        emissivity=eps,
        temperature=t_out,
        radiosity=j[:, 0] if squeeze else j,
        irradiation=h[:, 0] if squeeze else h,
        flux=qq,
        heat=heat,
        ambient_heat=float(heat.sum()),
        ambient=ambient,
        bands=None if squeeze else np.asarray(bands, dtype=float),
        _f=m,
        _sigma=sigma,
    )
