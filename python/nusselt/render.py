"""A small z-buffer rasteriser to look at a scene false-coloured by a per-patch value, and a
PNG writer (stdlib zlib), so that the demo needs no plotting library."""

from __future__ import annotations

import struct
import zlib

import numpy as np

# A perceptually ordered colour map (samples of matplotlib's "inferno"), interpolated linearly.
_INFERNO = np.array(
    [
        [0.001, 0.000, 0.014], [0.087, 0.045, 0.225], [0.258, 0.039, 0.406], [0.416, 0.090, 0.433],
        [0.578, 0.148, 0.404], [0.735, 0.216, 0.330], [0.865, 0.317, 0.226], [0.955, 0.469, 0.099],
        [0.988, 0.645, 0.040], [0.964, 0.837, 0.226], [0.988, 0.998, 0.645],
    ]
)


def colormap(t: np.ndarray) -> np.ndarray:
    """Maps values in [0, 1] to RGB in [0, 1]."""
    t = np.clip(np.asarray(t, dtype=float), 0.0, 1.0) * (len(_INFERNO) - 1)
    k = np.minimum(t.astype(int), len(_INFERNO) - 2)
    f = (t - k)[..., None]
    return _INFERNO[k] * (1 - f) + _INFERNO[k + 1] * f


def render(
    polygons,
    values,
    *,
    eye,
    look,
    up=(0.0, 1.0, 0.0),
    fov_deg: float = 39.3,
    size: int = 512,
    log: bool = True,
    decades: float = 3.0,
    background=(0.08, 0.08, 0.1),
) -> np.ndarray:
    """Renders polygons (list of (n, 3) arrays, convex) coloured by ``values`` (one per polygon,
    NaN = grey) as seen by a pinhole camera. With ``log`` the colour scale spans ``decades``
    decades below the largest value; smaller values and zeros get the darkest colour (see
    :func:`value_range`). Returns an (size, size + bar, 3) uint8 image with a colour bar on
    the right (low values at the bottom)."""
    eye = np.asarray(eye, float)
    fwd = np.asarray(look, float) / np.linalg.norm(look)
    right = np.cross(fwd, up)
    right /= np.linalg.norm(right)
    upv = np.cross(right, fwd)
    f = 0.5 * size / np.tan(np.radians(fov_deg) / 2)

    vals = np.asarray(values, float)
    ok = np.isfinite(vals)
    lo, hi = value_range(vals, log=log, decades=decades)
    if log:
        t = (np.log10(np.maximum(np.where(ok, vals, hi), 10.0**lo)) - lo) / max(hi - lo, 1e-12)
    else:
        t = (np.where(ok, vals, hi) - lo) / max(hi - lo, 1e-12)
    colours = np.where(ok[:, None], colormap(t), 0.35)

    img = np.empty((size, size, 3))
    img[:] = background
    zbuf = np.full((size, size), np.inf)
    ys, xs = np.mgrid[0:size, 0:size]
    px, py = xs + 0.5, ys + 0.5
    for poly, col in zip(polygons, colours):
        rel = np.asarray(poly, float) - eye
        z = rel @ fwd
        if np.any(z <= 1e-9):
            continue  # behind or at the camera: not drawn (the demo scenes lie in front)
        sx = size / 2 + f * (rel @ right) / z
        sy = size / 2 - f * (rel @ upv) / z
        for k in range(1, len(poly) - 1):
            tri = [0, k, k + 1]
            _fill_triangle(img, zbuf, px, py, sx[tri], sy[tri], 1.0 / z[tri], col)
    bar = np.linspace(1, 0, size)[:, None]
    strip = np.repeat(colormap(bar), 24, axis=1)
    gap = np.empty((size, 8, 3))
    gap[:] = background
    out = np.concatenate([img, gap, strip], axis=1)
    return (np.clip(out, 0, 1) * 255 + 0.5).astype(np.uint8)


def value_range(values, *, log: bool = True, decades: float = 3.0) -> tuple[float, float]:
    """The colour scale (lo, hi) that :func:`render` uses: log10 of the values when ``log``,
    from ``decades`` below the largest value (or the smallest positive one, if larger)."""
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if log:
        pos = v[v > 0]
        if not pos.size:
            return 0.0, 1.0
        hi = float(np.log10(pos.max()))
        return max(float(np.log10(pos.min())), hi - decades), hi
    if not v.size:
        return 0.0, 1.0
    return float(v.min()), float(v.max())


def _fill_triangle(img, zbuf, px, py, x, y, invz, col):
    x0, x1 = int(max(np.floor(x.min()), 0)), int(min(np.ceil(x.max()), img.shape[1] - 1))
    y0, y1 = int(max(np.floor(y.min()), 0)), int(min(np.ceil(y.max()), img.shape[0] - 1))
    if x0 > x1 or y0 > y1:
        return
    area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])
    if abs(area) < 1e-12:
        return
    qx, qy = px[y0 : y1 + 1, x0 : x1 + 1], py[y0 : y1 + 1, x0 : x1 + 1]
    w0 = ((x[1] - qx) * (y[2] - qy) - (x[2] - qx) * (y[1] - qy)) / area
    w1 = ((x[2] - qx) * (y[0] - qy) - (x[0] - qx) * (y[2] - qy)) / area
    w2 = 1.0 - w0 - w1
    inside = (w0 >= -1e-9) & (w1 >= -1e-9) & (w2 >= -1e-9)
    iz = w0 * invz[0] + w1 * invz[1] + w2 * invz[2]  # 1/z interpolates linearly on screen
    depth = np.where(inside, 1.0 / np.maximum(iz, 1e-300), np.inf)
    zb = zbuf[y0 : y1 + 1, x0 : x1 + 1]
    win = depth < zb
    zb[win] = depth[win]
    img[y0 : y1 + 1, x0 : x1 + 1][win] = col


def write_png(path, image: np.ndarray) -> None:
    """Writes an (h, w, 3) uint8 image as an 8-bit RGB PNG."""
    img = np.ascontiguousarray(image, dtype=np.uint8)
    h, w, _ = img.shape
    raw = b"".join(b"\x00" + img[r].tobytes() for r in range(h))

    def chunk(tag: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as fh:
        fh.write(b"\x89PNG\r\n\x1a\n")
        fh.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)))
        fh.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        fh.write(chunk(b"IEND", b""))
