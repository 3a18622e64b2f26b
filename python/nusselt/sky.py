"""The sky of open scenes: sky view factors of points and patches, and the sky split into the
standard patches of daylight and solar work (Tregenza 145, Reinhart subdivisions).

Frame: z is up (the zenith), y north, x east; azimuth is measured from north towards east
(Radiance's convention, ``atan2(Dx, Dy)``). The sky is the upper hemisphere at infinity; the
ground below the horizon is not sky.

Sky view factor of a point (plane element, unit normal n): the fraction of the radiation
leaving it that no polygon of the scene intercepts (polygons block from both sides, whichever
side faces the point). Computed exactly as 1 - sum_k F(p -> visible part of occluder k), each
occluder seen from its side facing p: every direction meets one first polygon, so the sum is
the covered fraction. Its error is the rounding of the sum (~1e-15 per term) and of the exact
visible regions. For a normal pointing below the horizon it includes the part of the lower
hemisphere no polygon covers (the "sky" of an element is everything it sees unobstructed).

``1 - row sum`` of a form-factor matrix is the same thing only when no receiver sees the back
of a polygon (backs do not receive, so they are left out of the rows) and when the rows are
exact; :func:`sky_view_factors` given a scene computes it directly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .scene import Scene
from .sensors import _rows, _unit


def sky_view_factors_points(points, normals, scene: Scene) -> np.ndarray:
    """Sky view factor of each point ((P, 3), normals (P, 3) or (3,)), obstructed by every
    polygon of ``scene`` (see the module docstring). Shape (P,)."""
    p = _rows(points, "points")
    n = _unit(_rows(normals, "normals", len(p)))
    if len(n) != len(p):
        raise ValueError(f"{len(p)} points but {len(n)} normals")
    return np.asarray(scene._core.point_sky(p, n))


def sky_view_factors(scene_or_result, *, order: int = 6) -> np.ndarray:
    """Sky view factor of each receiving patch (in the order of ``scene.receivers``).

    Given a :class:`~nusselt.Scene`: the point sky view factor integrated over each patch by
    a Gauss rule of ``order`` (per triangle, or a tensor rule on quads), divided by the area.
    The point value is smooth inside a patch, but its derivative is singular along edges the
    patch shares with another polygon (a wall standing on a floor patch), where Gauss rules
    converge slowly: on a canyon of 0.5 m patches the largest error against exact rows was
    1e-4 at order 4, 2.3e-5 at 6, 3.5e-6 at 10, 5.8e-7 at 16. Given a :class:`~nusselt.FormFactors` result:
    ``1 - row sums`` (see the module
    docstring for when that is right).
    """
    if isinstance(scene_or_result, Scene):
        if not (isinstance(order, (int, np.integer)) and 1 <= order <= 64):
            raise ValueError(f"order must be an integer in 1..64, got {order!r}")
        rows = scene_or_result.receivers.astype(np.int64)
        return np.asarray(scene_or_result._core.patch_sky(rows, int(order)))
    rs = getattr(scene_or_result, "row_sums", None)
    if rs is None:
        raise TypeError(f"expected a Scene or a FormFactors result, got {type(scene_or_result).__name__}")
    return np.clip(1.0 - np.asarray(rs), 0.0, 1.0)


@dataclass(frozen=True)
class SkyPatches:
    """A split of the sky hemisphere into patches bounded by altitude circles and azimuth
    meridians (radians). Patch k spans altitudes [alt_lo[k], alt_hi[k]] and azimuths
    [az_lo[k], az_hi[k]] (az_hi - az_lo = 2 pi for the zenith cap)."""

    name: str
    alt_lo: np.ndarray
    alt_hi: np.ndarray
    az_lo: np.ndarray
    az_hi: np.ndarray

    def __len__(self) -> int:
        return len(self.alt_lo)

    @property
    def solid_angles(self) -> np.ndarray:
        """Solid angle of each patch (sr): (az_hi - az_lo)(sin alt_hi - sin alt_lo)."""
        return (self.az_hi - self.az_lo) * (np.sin(self.alt_hi) - np.sin(self.alt_lo))

    @property
    def centres(self) -> np.ndarray:
        """Unit direction of each patch's centre (mid altitude and azimuth; the zenith for the cap)."""
        alt = np.where(self.alt_hi >= np.pi / 2 - 1e-15, np.pi / 2, 0.5 * (self.alt_lo + self.alt_hi))
        return _direction(alt, 0.5 * (self.az_lo + self.az_hi))

    def horizontal_factors(self) -> np.ndarray:
        """Unobstructed F from an upward-facing plane element to each patch, closed form:
        F = (1/pi) int int cos(zenith angle) dw = (az_hi - az_lo)/(2 pi) (sin^2 alt_hi - sin^2 alt_lo)
        (with dw = cos(alt) d(alt) d(az) and cos(zenith angle) = sin(alt)). Sums to 1."""
        return (self.az_hi - self.az_lo) / (2 * np.pi) * (np.sin(self.alt_hi) ** 2 - np.sin(self.alt_lo) ** 2)


def _direction(alt, az) -> np.ndarray:
    ca = np.cos(alt)
    return np.stack([ca * np.sin(az), ca * np.cos(az), np.sin(alt)], axis=-1)


def reinhart(mf: int = 1) -> SkyPatches:
    """Reinhart's subdivision of the Tregenza sky as in Radiance's ``reinhart.cal`` (G. Ward,
    2009): 7 MF rows of altitude width alpha = 90/(7 MF + 1/2) degrees, row r having MF times
    Tregenza's count of its band (30, 30, 24, 24, 18, 12, 6), patch 0 of each row centred on
    north, and a zenith cap of half-width alpha/2: 144 MF^2 + 1 patches (145, 577, 2305 for
    MF = 1, 2, 4). MF = 1 is Tregenza's sky (Tregenza 1987, Lighting Res. Technol. 19(1)
    13-14: 12-degree bands of 30, 30, 24, 24, 18, 12, 6 patches and a zenith cap)."""
    if not (isinstance(mf, (int, np.integer)) and mf >= 1):
        raise ValueError(f"MF must be a positive integer, got {mf!r}")
    alpha = np.radians(90.0 / (7 * mf + 0.5))
    counts = [30, 30, 24, 24, 18, 12, 6]
    lo, hi, a0, a1 = [], [], [], []
    for r in range(7 * mf):
        m = mf * counts[r // mf]
        w = 2 * np.pi / m
        c = np.arange(m)
        lo += [r * alpha] * m
        hi += [(r + 1) * alpha] * m
        a0 += list((c - 0.5) * w)
        a1 += list((c + 0.5) * w)
    lo.append(7 * mf * alpha)
    hi.append(np.pi / 2)
    a0.append(0.0)
    a1.append(2 * np.pi)
    name = "tregenza" if mf == 1 else f"reinhart{mf}"
    return SkyPatches(name, np.array(lo), np.array(hi), np.array(a0), np.array(a1))


def tregenza() -> SkyPatches:
    """Tregenza's 145 sky patches (:func:`reinhart` with MF = 1)."""
    return reinhart(1)


def _gauss(k: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(k)
    return 0.5 * (x + 1), 0.5 * w


def _patch_nodes(sky: SkyPatches, k: int):
    """k x k Gauss nodes per patch in (altitude, azimuth): directions (S, k*k, 3) and the
    solid-angle weights cos(alt) d(alt) d(az) (S, k*k)."""
    u, wu = _gauss(k)
    da, dz = sky.alt_hi - sky.alt_lo, sky.az_hi - sky.az_lo
    alt = sky.alt_lo[:, None, None] + da[:, None, None] * u[None, :, None]
    az = sky.az_lo[:, None, None] + dz[:, None, None] * u[None, None, :]
    w = (da * dz)[:, None, None] * wu[None, :, None] * wu[None, None, :] * np.cos(alt)
    d = _direction(np.broadcast_to(alt, w.shape), np.broadcast_to(az, w.shape))
    return d.reshape(len(sky), k * k, 3), w.reshape(len(sky), k * k)


def unobstructed_patch_factors(normals, sky: SkyPatches | None = None, *, nodes: int = 16) -> np.ndarray:
    """Unobstructed F from plane elements with the given unit normals ((P, 3) or (3,)) to each
    sky patch: (1/pi) int max(0, n.d) dw over the patch. Shape (P, n_patches).

    Normals along +z: the closed form of :meth:`SkyPatches.horizontal_factors`. Otherwise, at
    altitude a, n.d = R cos(az - az_n) + b with R = cos(a) |n_xy|, b = n_z sin(a), whose
    positive part integrates over the patch's azimuths in closed form (the interval where
    cos(az - az_n) > -b/R); the altitude integral is a Gauss rule of ``nodes`` points on each
    piece of the patch's altitudes between the altitudes where the element's horizon meets the
    patch's meridians or turns (where the integrand is analytic): the whole sky of an element
    tilted by beta comes within 1e-12 of (1 + cos beta)/2 at 16 nodes (3e-10 at 8).
    """
    sky = sky or tregenza()
    n = _unit(_rows(normals, "normals"))
    step = max(1, 400_000 // (len(sky) * nodes))
    if len(n) > step:
        return np.concatenate(
            [unobstructed_patch_factors(n[s : s + step], sky, nodes=nodes) for s in range(0, len(n), step)]
        )
    u, wu = _gauss(nodes)
    rho = np.hypot(n[:, 0], n[:, 1])[:, None, None]
    azn = np.arctan2(n[:, 0], n[:, 1])[:, None, None]  # azimuth of the normal, from north
    nz = n[:, 2][:, None, None]
    x0 = sky.az_lo[None, :, None]
    x1 = sky.az_hi[None, :, None]
    # Altitudes where the element's horizon n.d = 0 meets the patch's meridians or has its
    # extremes (azimuths azn, azn + pi): the integrand over altitude is smooth between them.
    azs = np.concatenate(
        [
            np.broadcast_to(x0, (len(n), len(sky), 1)),
            np.broadcast_to(x1, (len(n), len(sky), 1)),
            np.broadcast_to(azn, (len(n), len(sky), 1)),
            np.broadcast_to(azn + np.pi, (len(n), len(sky), 1)),
        ],
        axis=2,
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        brk = np.arctan(-rho * np.cos(azs - azn) / nz)
    lo, hi = sky.alt_lo[None, :, None], sky.alt_hi[None, :, None]
    brk = np.clip(np.nan_to_num(brk, nan=-np.pi), lo, hi)
    edges = np.sort(
        np.concatenate(
            [np.broadcast_to(lo, brk.shape[:2] + (1,)), brk, np.broadcast_to(hi, brk.shape[:2] + (1,))], axis=2
        ),
        axis=2,
    )
    width = np.diff(edges, axis=2)  # (P, S, 5)
    alt = (edges[..., :-1, None] + width[..., None] * u).reshape(len(n), len(sky), -1)  # (P, S, 5K)
    wa = (width[..., None] * wu).reshape(alt.shape) * np.cos(alt)
    R = rho * np.cos(alt)
    b = nz * np.sin(alt)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(R > 0, -b / R, np.sign(-b) * 2.0)
    c = np.arccos(np.clip(ratio, -1.0, 1.0))
    full = np.where(R > 0, ratio <= -1.0, b > 0)
    # positive intervals (azn - c, azn + c) + 2 pi k, intersected with [x0, x1]
    inner = np.zeros(R.shape)
    for k in range(-2, 3):
        a0 = np.maximum(x0, azn - c + 2 * np.pi * k)
        a1 = np.minimum(x1, azn + c + 2 * np.pi * k)
        term = R * (np.sin(a1 - azn) - np.sin(a0 - azn)) + b * (a1 - a0)
        inner += np.where((a1 > a0) & ~full, term, 0.0)
    whole = R * (np.sin(x1 - azn) - np.sin(x0 - azn)) + b * (x1 - x0)
    inner = np.where(full, whole, inner)
    f = (np.clip(inner, 0.0, None) * wa).sum(axis=2) / np.pi
    up = np.all(np.abs(n - [0.0, 0.0, 1.0]) < 1e-15, axis=1)
    f[up] = sky.horizontal_factors()
    return f


def sky_patch_factors(
    points, normals, scene: Scene | None, sky: SkyPatches | None = None, *, nodes: int = 4, batch: int = 2_000_000
) -> np.ndarray:
    """F from plane elements at ``points`` (unit ``normals``) to each sky patch, obstructed by
    the polygons of ``scene`` (None: unobstructed). Shape (P, n_patches).

    Per patch, ``nodes`` x ``nodes`` Gauss directions in (altitude, azimuth) weighted by
    max(0, n.d) cos(alt) are traced to infinity through the scene (the core's BVH); the
    unobstructed F (:func:`unobstructed_patch_factors`, exact for upward normals) is scaled
    by the weighted fraction of unblocked directions. Exact where a patch is wholly seen or
    wholly hidden; where an obstacle's edge crosses a patch, the error is that of sampling
    the edge with nodes^2 directions (raise ``nodes`` or use a finer sky).
    """
    sky = sky or tregenza()
    p = _rows(points, "points")
    n = _unit(_rows(normals, "normals", len(p)))
    if len(n) != len(p):
        raise ValueError(f"{len(p)} points but {len(n)} normals")
    free = unobstructed_patch_factors(n, sky)
    if scene is None or len(scene) == 0:
        return free
    d, w = _patch_nodes(sky, nodes)
    dflat = d.reshape(-1, 3)
    per = dflat.shape[0]
    out = np.empty_like(free)
    step = max(1, batch // per)
    for s in range(0, len(p), step):
        ps, ns = p[s : s + step], n[s : s + step]
        cos = np.clip(ns @ dflat.T, 0.0, None)  # (B, S*K)
        origins = np.repeat(ps, per, axis=0)
        dirs = np.tile(dflat, (len(ps), 1))
        lit = cos > 0
        blocked = np.zeros(cos.shape, dtype=bool)
        if lit.any():
            blocked[lit] = scene._core.rays_blocked(
                np.ascontiguousarray(origins[lit.ravel()]), np.ascontiguousarray(dirs[lit.ravel()])
            )
        wk = (cos * w.reshape(1, -1)).reshape(len(ps), len(sky), -1)
        total = wk.sum(axis=2)
        seen = np.where(blocked.reshape(wk.shape), 0.0, wk).sum(axis=2)
        frac = np.divide(seen, total, out=np.zeros_like(seen), where=total > 0)
        out[s : s + step] = free[s : s + step] * frac
    return out


def patch_quadrature(scene: Scene, order: int = 3) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gauss points on every receiving patch: (points (Q, 3), weights (Q,) in area units,
    patch column (Q,)). Each triangle of a patch (ear clipping, concave patches too) gets the
    collapsed Gauss-Legendre rule x = a + u (b - a) + u v (c - b), dA = 2 A_tri u du dv, with
    ``order`` points per direction."""
    if not (isinstance(order, (int, np.integer)) and 1 <= order <= 32):
        raise ValueError(f"order must be an integer in 1..32, got {order!r}")
    g, w = _gauss(int(order))
    uu, vv = np.meshgrid(g, g, indexing="ij")
    ww = (w[:, None] * w[None, :] * uu).ravel()
    uu, vv = uu.ravel(), vv.ravel()
    pts, wts, col = [], [], []
    for c, k in enumerate(scene.receivers):
        v = scene.vertices[scene.faces[k]]
        for i, j, l in scene._core.triangulate(int(k)):
            a, b, cc = v[i], v[j], v[l]
            area2 = np.linalg.norm(np.cross(b - a, cc - a))
            pts.append(a + uu[:, None] * (b - a) + (uu * vv)[:, None] * (cc - b))
            wts.append(area2 * ww)
            col.append(np.full(len(ww), c))
    if not pts:
        return np.zeros((0, 3)), np.zeros(0), np.zeros(0, dtype=np.int64)
    return np.concatenate(pts), np.concatenate(wts), np.concatenate(col)


def sky_patch_factors_patches(
    scene: Scene, sky: SkyPatches | None = None, *, order: int = 3, nodes: int = 4
) -> np.ndarray:
    """F from every receiving patch (rows in the order of ``scene.receivers``) to each sky
    patch, obstructed by the scene: :func:`sky_patch_factors` at the points of
    :func:`patch_quadrature` (each with its patch's normal), area-weighted. The points lie on
    the patch, whose own plane does not block them (rays start 1e-9 of the scene's size off
    it). Shape (n_receivers, n_patches)."""
    sky = sky or tregenza()
    pts, wts, col = patch_quadrature(scene, order)
    normals = scene.normals[scene.receivers][col]
    f = sky_patch_factors(pts, normals, scene, sky, nodes=nodes)
    out = np.zeros((len(scene.receivers), len(sky)))
    np.add.at(out, col, f * wts[:, None])
    area = np.zeros(len(scene.receivers))
    np.add.at(area, col, wts)
    return out / area[:, None]
