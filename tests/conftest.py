"""Shared test helpers: polygons and scenes (rect, cube_faces, prism, uv_sphere), areas, and
Howell's point-to-rectangle closed form. bench/ imports them too."""

import ast
import pathlib
import sys
import types

import numpy as np
import pytest

try:
    import nusselt  # noqa: F401
except ImportError:
    # The compiled core is not built: the pure-Python modules (nusselt.io, nusselt.result) stay
    # importable without nusselt/__init__, so the file-format tests run; the others fail to import.
    _pkg = types.ModuleType("nusselt")
    _pkg.__path__ = [str(pathlib.Path(__file__).resolve().parents[1] / "python" / "nusselt")]
    sys.modules["nusselt"] = _pkg


def data_literal(name):
    """The nested list of numbers in tests/data/`name`, written as a literal that Rust tests
    include too (lines starting with // are comments)."""
    text = (pathlib.Path(__file__).parent / "data" / name).read_text()
    return ast.literal_eval("\n".join(line for line in text.splitlines() if not line.lstrip().startswith("//")))


def rect(x0, x1, y0, y1, z=0.0, flip=False):
    """Axis-aligned rectangle in the plane z, normal +z (or -z with flip)."""
    v = np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]], dtype=float)
    return v[::-1].copy() if flip else v


def polygon_area(p):
    """Area of a planar polygon (half the length of its Newell normal)."""
    p = np.asarray(p, dtype=float)
    return float(np.linalg.norm(0.5 * np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)))


def cube_faces(n=1, size=1.0):
    """A closed cube [0, size]^3 of 6 n x n quads per face, normals pointing inward.
    Returns (polygons, face index of each polygon)."""
    polys, which = [], []
    t = np.linspace(0.0, size, n + 1)
    for axis in range(3):
        for side in (0.0, size):
            u, w = [a for a in range(3) if a != axis]
            for a in range(n):
                for b in range(n):
                    q = np.zeros((4, 3))
                    for k, (da, db) in enumerate([(0, 0), (1, 0), (1, 1), (0, 1)]):
                        q[k, axis] = side
                        q[k, u] = t[a + da]
                        q[k, w] = t[b + db]
                    normal = np.zeros(3)
                    normal[axis] = 1.0 if side == 0.0 else -1.0
                    nq = np.cross(q[1] - q[0], q[2] - q[0])
                    if nq @ normal < 0:
                        q = q[::-1].copy()
                    polys.append(q)
                    which.append(2 * axis + (side > 0))
    return polys, np.array(which)


def write_cube_obj(path, n):
    """The closed n x n cube of :func:`cube_faces` as an OBJ file (4 vertices per face)."""
    polys, _ = cube_faces(n)
    with open(path, "w") as fh:
        for p in polys:
            fh.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in p.tolist())
        fh.writelines("f " + " ".join(str(4 * k + i) for i in range(1, 5)) + "\n" for k in range(len(polys)))


def corner(a, b, c):
    """F from dA to an a x b rectangle in a parallel plane at distance c, the normal of dA
    through one corner of it (Howell's catalogue, B-4)."""
    if a <= 0 or b <= 0:
        return 0.0
    x, y = a / c, b / c
    return (
        x / np.sqrt(1 + x * x) * np.arctan(y / np.sqrt(1 + x * x))
        + y / np.sqrt(1 + y * y) * np.arctan(x / np.sqrt(1 + y * y))
    ) / (2 * np.pi)


def parallel_rect(px, py, x0, x1, y0, y1, c):
    """F from dA at (px, py) facing an axis-aligned rectangle at distance c, by corner superposition."""
    s = lambda u, v: np.sign(u) * np.sign(v) * corner(abs(u), abs(v), c)
    return s(x1 - px, y1 - py) - s(x0 - px, y1 - py) - s(x1 - px, y0 - py) + s(x0 - px, y0 - py)


def prism(r, n, inward, rings=1):
    """The n side walls of a regular prism of radius r, height 1 (open ends), each wall split
    into ``rings`` quads along the height; normals inward or outward."""
    out = []
    for k in range(n):
        a0, a1 = 2 * np.pi * k / n, 2 * np.pi * (k + 1) / n
        for h in range(rings):
            z0, z1 = h / rings, (h + 1) / rings
            q = np.array(
                [
                    [r * np.cos(a0), r * np.sin(a0), z0],
                    [r * np.cos(a1), r * np.sin(a1), z0],
                    [r * np.cos(a1), r * np.sin(a1), z1],
                    [r * np.cos(a0), r * np.sin(a0), z1],
                ]
            )
            out.append(q[::-1].copy() if inward else q)  # counter-clockwise seen from outside
    return out


def uv_sphere(radius, nu, nv, centre):
    """A closed faceted sphere, normals inward (quads, triangles at the poles)."""
    centre = np.asarray(centre, float)
    out = []
    at = lambda t, a: centre + radius * np.array([np.sin(t) * np.cos(a), np.sin(t) * np.sin(a), np.cos(t)])
    for i in range(nv):
        t0, t1 = np.pi * i / nv, np.pi * (i + 1) / nv
        for k in range(nu):
            a0, a1 = 2 * np.pi * k / nu, 2 * np.pi * (k + 1) / nu
            q = [at(t0, a0), at(t1, a0), at(t1, a1), at(t0, a1)]
            q = np.array(q[:3] if i == 0 else [q[0], q[1], q[3]] if i == nv - 1 else q)
            if np.cross(q[1] - q[0], q[2] - q[0]) @ (q.mean(0) - centre) > 0:
                q = q[::-1].copy()
            out.append(q)
    return out


@pytest.fixture
def unit_square():
    return rect(0, 1, 0, 1)


# options that make one call run for minutes, per method (budget unlimited): the Ctrl-C tests
# and `bench/methods.py interrupt`
LONG_CALLS = {
    "auto": {"obstructed_tol": 1e-14},
    "analytic": {"obstructed_tol": 1e-14},
    "contour": {"obstructed_tol": 1e-14},
    "clipping": {"tol": 1e-14, "max_depth": 16},
    "quadrature": {"order": 32, "tol": 1e-14, "control_variate": False},
    "montecarlo": {"samples": 2**24, "control_variate": False},
    "subdivision": {"divisions": 256, "source": 16},
    "adaptive": {"tol": 1e-14, "max_depth": 16, "source": 16},
    "hemicube": {"resolution": 4096, "source": 16},
    "single-plane": {"min_cell": 1e-4, "half_width": 1e4, "source": 16},
    "raytrace": {"rays": 2**26},
    "nusselt": {"cells": 2**24, "source": 16},
}
