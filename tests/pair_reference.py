"""Random polygon pairs in general position, and 40-digit references for view factors.

The reference is independent of nusselt's arithmetic: mpmath clips each polygon to the other's
front half-space and evaluates the double contour integral (docs/algorithms.md §1.2)

    A_a F_ab = (1/4 pi) sum_{edges p of a, q of b} (d_p . d_q) int_0^1 int_0^1 ln |x_p(s) - y_q(t)|^2 dt ds

with the inner integral in closed form (Mitalas & Stephenson: [m ln(m^2 + g^2) - 2m +
2g atan(m/g)] / |d_q|) and the outer one by tanh-sinh, split where edge p passes a vertex of b
or the closest point of an edge line (where the integrand has log singularities). At 40 digits
the cancellation between edge-pair terms, which limits double precision on slivers and on
pairs far apart, is harmless. The point form is Lambert's formula at 40 digits on the polygon
clipped to the point's front half-space. Used by tests/test_precision.py and
bench/pair_fuzz.py.
"""

import mpmath as mp
import numpy as np


def random_polygon(rng):
    """A triangle, convex or concave polygon (3-8 vertices), scaled, rotated and placed at
    random: pairs of them pierce, touch nearly, or cut each other to slivers."""
    kind = rng.choice(["triangle", "convex", "concave"])
    if kind == "triangle":
        v2 = rng.uniform(-1, 1, (3, 2))
        if (v2[1, 0] - v2[0, 0]) * (v2[2, 1] - v2[0, 1]) - (v2[1, 1] - v2[0, 1]) * (v2[2, 0] - v2[0, 0]) < 0:
            v2 = v2[::-1]
    else:
        m = rng.integers(5, 9) if kind == "concave" else rng.integers(3, 7)
        ang = np.sort(rng.uniform(0, 2 * np.pi, m))
        r = rng.uniform(0.3, 1, m) if kind == "concave" else np.ones(m)
        if kind == "concave":
            r[::2] *= 0.4
        v2 = np.c_[r * np.cos(ang), r * np.sin(ang)]
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return (np.c_[v2, np.zeros(len(v2))] * rng.uniform(0.2, 2)) @ q.T + rng.normal(size=3) * rng.uniform(0, 2)


def random_pairs(seed, count):
    """The first `count` pairs (k, a, b) drawn with `seed` (some outlines cross themselves:
    nusselt rejects those)."""
    rng = np.random.default_rng(seed)
    for k in range(count):
        yield k, random_polygon(rng), random_polygon(rng)


def _sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _axpy(a, t, d):
    return [a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]]


def _newell(p):
    n = [mp.mpf(0)] * 3
    for i in range(len(p)):
        a, b = p[i], p[(i + 1) % len(p)]
        n[0] += (a[1] - b[1]) * (a[2] + b[2])
        n[1] += (a[2] - b[2]) * (a[0] + b[0])
        n[2] += (a[0] - b[0]) * (a[1] + b[1])
    return n


def _clip(p, o, n):
    """Sutherland-Hodgman: the part of p with (x - o) . n >= 0."""
    out = []
    for i in range(len(p)):
        a, b = p[i], p[(i + 1) % len(p)]
        da, db = _dot(_sub(a, o), n), _dot(_sub(b, o), n)
        if da >= 0:
            out.append(a)
        if (da > 0 > db) or (da < 0 < db):
            out.append(_axpy(a, da / (da - db), _sub(b, a)))
    return out


def _inner(x, q0, q1):
    """int_0^1 ln |x - q0 - t (q1 - q0)|^2 dt, closed form."""
    d = _sub(q1, q0)
    length = mp.sqrt(_dot(d, d))
    v = [c / length for c in d]
    r = _cross(_sub(x, q0), v)
    g = mp.sqrt(_dot(r, r))  # distance of x from the line of q

    def h(m):
        s = m * mp.log(m * m + g * g) if (m != 0 or g != 0) else mp.mpf(0)
        return s - 2 * m + (2 * g * mp.atan(m / g) if g > 0 else 0)

    return (h(_dot(_sub(q1, x), v)) - h(_dot(_sub(q0, x), v))) / length


def view_factor_mp(a, b, dps=40):
    """F_ab of two planar polygons (vertex arrays, counter-clockwise about their front
    normals) with nothing in between, as an mpmath number."""
    with mp.workdps(dps):
        pa = [[mp.mpf(float(c)) for c in v] for v in a]
        pb = [[mp.mpf(float(c)) for c in v] for v in b]
        na, nb = _newell(pa), _newell(pb)
        area_a = mp.sqrt(_dot(na, na)) / 2
        ca, cb = _clip(pa, pb[0], nb), _clip(pb, pa[0], na)
        if len(ca) < 3 or len(cb) < 3:
            return mp.mpf(0)
        total = mp.mpf(0)
        for i in range(len(ca)):
            p0, p1 = ca[i], ca[(i + 1) % len(ca)]
            dp = _sub(p1, p0)
            lp2 = _dot(dp, dp)
            if lp2 == 0:
                continue
            breaks = {mp.mpf(0), mp.mpf(1)}
            for y in cb:
                t = _dot(_sub(y, p0), dp) / lp2
                if 0 < t < 1:
                    breaks.add(t)
            terms = []
            for j in range(len(cb)):
                q0, q1 = cb[j], cb[(j + 1) % len(cb)]
                dq = _sub(q1, q0)
                c = _cross(dp, dq)
                if _dot(c, c) > 0:
                    s = _dot(_cross(_sub(q0, p0), dq), c) / _dot(c, c)
                    if 0 < s < 1:
                        breaks.add(s)
                if _dot(dp, dq) != 0:
                    terms.append((_dot(dp, dq), q0, q1))
            total += mp.quad(lambda s: sum(w * _inner(_axpy(p0, s, dp), q0, q1) for w, q0, q1 in terms), sorted(breaks))
        return total / (4 * mp.pi) / area_a


def point_view_factor_mp(p, n, poly, dps=40):
    """F from a differential area at p (unit normal n) to the polygon `poly` (front side only),
    by Lambert's formula at `dps` digits, as an mpmath number."""
    with mp.workdps(dps):
        pt = [mp.mpf(float(c)) for c in p]
        nn = [mp.mpf(float(c)) for c in n]
        scale = mp.sqrt(_dot(nn, nn))
        nn = [c / scale for c in nn]
        v = [[mp.mpf(float(c)) for c in x] for x in poly]
        if _dot(_sub(pt, v[0]), _newell(v)) <= 0:
            return mp.mpf(0)
        c = _clip(v, pt, nn)
        if len(c) < 3:
            return mp.mpf(0)
        total = mp.mpf(0)
        for k in range(len(c)):
            a, b = _sub(c[k], pt), _sub(c[(k + 1) % len(c)], pt)
            x = _cross(a, b)
            length = mp.sqrt(_dot(x, x))
            if length > 0:
                total += mp.atan2(length, _dot(a, b)) * _dot(nn, x) / length
        return -total / (2 * mp.pi)
