"""A small z-buffer rasteriser to look at a scene false-coloured by a per-patch value, and a
PNG writer (stdlib zlib), so that the demo needs no plotting library."""

from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

# A perceptually ordered colour map (samples of matplotlib's "inferno"), interpolated linearly.
_INFERNO = np.array(
    [
        [0.001, 0.000, 0.014],
        [0.087, 0.045, 0.225],
        [0.258, 0.039, 0.406],
        [0.416, 0.090, 0.433],
        [0.578, 0.148, 0.404],
        [0.735, 0.216, 0.330],
        [0.865, 0.317, 0.226],
        [0.955, 0.469, 0.099],
        [0.988, 0.645, 0.040],
        [0.964, 0.837, 0.226],
        [0.988, 0.998, 0.645],
    ]
)


def colormap(t: np.ndarray) -> np.ndarray:
    """Maps values in [0, 1] to RGB in [0, 1]."""
    t = np.clip(np.asarray(t, dtype=float), 0.0, 1.0) * (len(_INFERNO) - 1)
    k = np.minimum(t.astype(int), len(_INFERNO) - 2)
    f = (t - k)[..., None]
    return _INFERNO[k] * (1 - f) + _INFERNO[k + 1] * f


@dataclass(frozen=True)
class Camera:
    """A pinhole camera: position ``eye``, view direction ``look``, ``up`` (any vector not
    along ``look``), the field of view ``fov_deg`` (degrees, across the picture) and a square
    picture of ``size`` x ``size`` pixels."""

    eye: npt.ArrayLike
    look: npt.ArrayLike = (0.0, 0.0, 1.0)
    up: npt.ArrayLike = (0.0, 1.0, 0.0)
    fov_deg: float = 39.3
    size: int = 512


#: The camera of the Cornell box data (https://www.graphics.cornell.edu/online/box/data.html):
#: at (278, 273, -800) mm looking along +z, a 39.3 degree field of view.
CORNELL = Camera(eye=(278.0, 273.0, -800.0))


def render(
    polygons,
    values,
    camera: Camera,
    *,
    log: bool = True,
    decades: float = 3.0,
    background=(0.08, 0.08, 0.1),
    label: str = "",
    smooth: bool = False,
    groups=None,
) -> np.ndarray:
    """Renders polygons (list of (n, 3) arrays, convex) coloured by ``values`` (one per polygon,
    NaN = grey) as ``camera`` sees them. With ``log`` the colour scale spans ``decades``
    decades below the largest value; smaller values and zeros get the darkest colour (see
    :func:`value_range`). ``smooth``: Gouraud shading of values averaged at shared vertices
    (within the same entry of ``groups``, e.g. the surface index, so edges between surfaces
    stay sharp). Returns a (size, size + bar, 3) uint8 image with a colour bar on the right
    (low values at the bottom), its ticks labelled with numbers and ``label`` (e.g. the unit)
    written above them."""
    vals = np.asarray(values, float)
    ok = np.isfinite(vals)
    lo, hi = value_range(vals, log=log, decades=decades)

    def scale(v):
        if log:
            return (np.log10(np.maximum(v, 10.0**lo)) - lo) / max(hi - lo, 1e-12)
        return (v - lo) / max(hi - lo, 1e-12)

    if smooth:
        vv = vertex_values(polygons, np.where(ok, vals, np.nan), groups)
        colours: list[np.ndarray] | np.ndarray = [
            np.where(np.isfinite(v)[:, None], colormap(scale(np.nan_to_num(v, nan=hi))), 0.35) for v in vv
        ]
    else:
        colours = np.where(ok[:, None], colormap(scale(np.where(ok, vals, hi))), 0.35)
    img = rasterise(polygons, colours, camera, background=background)
    out = np.concatenate([img, colour_bar(camera.size, lo, hi, log=log, label=label, background=background)], axis=1)
    return (np.clip(out, 0, 1) * 255 + 0.5).astype(np.uint8)


def render_rgb(polygons, colours, camera: Camera, *, background=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Renders polygons in colour: ``colours`` is per polygon an RGB triple or an (nv, 3) array
    of vertex colours (Gouraud-interpolated), display values in [0, 1]. Returns (size, size, 3) uint8."""
    img = rasterise(polygons, colours, camera, background=background)
    return (np.clip(img, 0, 1) * 255 + 0.5).astype(np.uint8)


def vertex_values(polygons, values, groups=None) -> list[np.ndarray]:
    """Per polygon, the area-weighted mean of ``values`` ((n,) or (n, k)) over the polygons of the
    same group that share each vertex (positions matched to 1e-9 of the scene size): the
    vertex values of smooth shading. NaN values are left out of the means."""
    vals = np.asarray(values, float)
    polys = [np.asarray(p, float) for p in polygons]
    g = np.zeros(len(polys), np.int64) if groups is None else np.asarray(groups)
    allv = np.concatenate(polys)
    span = float(np.ptp(allv, axis=0).max()) or 1.0
    key = np.round(allv / (span * 1e-9)).astype(np.int64)
    owner = np.repeat(np.arange(len(polys)), [len(p) for p in polys])
    area = np.array([0.5 * np.linalg.norm(np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)) for p in polys])
    rows = np.column_stack([key, g[owner]])
    _, vid = np.unique(rows, axis=0, return_inverse=True)
    vid = vid.ravel()
    v2 = vals[owner].reshape(len(owner), -1)
    good = np.isfinite(v2)
    w = area[owner][:, None] * good
    num = np.zeros((vid.max() + 1, v2.shape[1]))
    den = np.zeros_like(num)
    np.add.at(num, vid, w * np.where(good, v2, 0.0))
    np.add.at(den, vid, w)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = num / den
    per_corner = mean[vid] if vals.ndim > 1 else mean[vid, 0]
    return np.split(per_corner, np.cumsum([len(p) for p in polys])[:-1])


def rasterise(polygons, colours, camera: Camera, *, background=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Z-buffered pinhole view (float RGB image, (size, size, 3)) of convex polygons with a colour
    per polygon or per vertex."""
    eye = np.asarray(camera.eye, float)
    fwd = np.asarray(camera.look, float) / np.linalg.norm(camera.look)
    right = np.cross(fwd, np.asarray(camera.up, float))
    right /= np.linalg.norm(right)
    upv = np.cross(right, fwd)
    size = camera.size
    f = 0.5 * size / np.tan(np.radians(camera.fov_deg) / 2)
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
        col = np.asarray(col, float)
        for k in range(1, len(poly) - 1):
            tri = [0, k, k + 1]
            _fill_triangle(img, zbuf, px, py, sx[tri], sy[tri], 1.0 / z[tri], col if col.ndim == 1 else col[tri])
    return img


def colour_bar(
    height: int, lo: float, hi: float, *, log: bool, label: str = "", background=(0.08, 0.08, 0.1), ticks: int = 5
) -> np.ndarray:
    """A vertical colour bar (float RGB, (height, width, 3)) for the scale lo..hi (log10 values
    when ``log``), with ``ticks`` labelled tick marks and ``label`` at the top, in the built-in
    bitmap font (so no plotting library is needed)."""
    scale = max(1, height // 256)
    pad, strip_w, glyph = 8, 24, 8 * scale  # a glyph advances 4 font pixels of 2 x scale
    width = max(pad + strip_w + 12 + 8 * glyph, 4 + len(label) * glyph)  # ticks up to "-1.0e-3"
    top = 9 * scale * (2 if label else 1) + 4
    bottom = 6 * scale
    h = height - top - bottom
    out = np.empty((height, width, 3))
    out[:] = background
    bar = np.linspace(1, 0, h)[:, None]
    out[top : top + h, pad : pad + strip_w] = np.repeat(colormap(bar), strip_w, axis=1)
    for k in range(ticks):
        frac = k / (ticks - 1)
        y = top + int(round((1 - frac) * (h - 1)))
        v = lo + frac * (hi - lo)
        text = _format_tick(10.0**v if log else v)
        out[y, pad + strip_w : pad + strip_w + 4] = 1.0
        draw_text(out, text, pad + strip_w + 8, y - 5 * scale, scale=scale)
    if label:
        draw_text(out, label, 2, 2, scale=scale)
    return out


def _format_tick(v: float) -> str:
    if v == 0:
        return "0"
    a = abs(v)
    return f"{v:.3g}" if 1e-2 <= a < 1e4 else f"{v:.1e}".replace("e-0", "e-").replace("e+0", "e")


# A 3 x 5 bitmap font (rows top to bottom, 3 bits each): digits, signs and the letters that
# units and short labels need; other characters are drawn as blanks.
_FONT = {
    "0": "111101101101111",
    "1": "010110010010111",
    "2": "111001111100111",
    "3": "111001111001111",
    "4": "101101111001001",
    "5": "111100111001111",
    "6": "111100111101111",
    "7": "111001010010010",
    "8": "111101111101111",
    "9": "111101111001111",
    ".": "000000000000010",
    "-": "000000111000000",
    "+": "000010111010000",
    "/": "001001010100100",
    "(": "010100100100010",
    ")": "010001001001010",
    "^": "010101000000000",
    ":": "000010000010000",
    "=": "000111000111000",
    " ": "000000000000000",
    "a": "000111011101111",
    "b": "100100111101111",
    "c": "000111100100111",
    "d": "001001111101111",
    "e": "000111111100111",
    "f": "011100110100100",
    "g": "111101111001111",
    "h": "100100111101101",
    "i": "010000010010010",
    "k": "100101110101101",
    "l": "010010010010010",
    "m": "000111111101101",
    "n": "000110101101101",
    "o": "000111101101111",
    "p": "000111101111100",
    "r": "000111100100100",
    "s": "000111110011111",
    "t": "010111010010011",
    "u": "000101101101111",
    "v": "000101101101010",
    "w": "000101101111111",
    "x": "000101010101101",
    "y": "000101111001111",
    "z": "000111010100111",
    "B": "110101110101110",
    "E": "111100111100111",
    "F": "111100110100100",
    "G": "111100101101111",
    "J": "001001001101111",
    "K": "101101110101101",
    "L": "100100100100111",
    "Q": "111101101111001",
    "R": "110101110101101",
    "T": "111010010010010",
    "W": "101101101111101",
    "Y": "101101010010010",
}


def draw_text(img: np.ndarray, text: str, x: int, y: int, *, scale: int = 1, colour=(1.0, 1.0, 1.0)) -> None:
    """Draws ``text`` into a float RGB image at pixel (x, y) (top left), 2x ``scale`` pixels per
    font pixel, clipped at the image border."""
    s = 2 * scale
    for ch in text:
        glyph = _FONT.get(ch, _FONT.get(ch.lower(), "0" * 15))
        for r in range(5):
            for c in range(3):
                if glyph[3 * r + c] == "1":
                    y0, x0 = y + r * s, x + c * s
                    if 0 <= y0 and y0 + s <= img.shape[0] and 0 <= x0 and x0 + s <= img.shape[1]:
                        img[y0 : y0 + s, x0 : x0 + s] = colour
        x += 4 * s


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
    col = np.asarray(col, float)
    if col.ndim == 1:
        img[y0 : y1 + 1, x0 : x1 + 1][win] = col
    else:  # one colour per vertex: Gouraud, perspective-correct (weights w_k / z_k, normalised)
        wz = np.stack([w0[win] * invz[0], w1[win] * invz[1], w2[win] * invz[2]], axis=1) * depth[win][:, None]
        img[y0 : y1 + 1, x0 : x1 + 1][win] = wz @ col


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
