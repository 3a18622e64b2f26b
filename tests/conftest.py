import numpy as np
import pytest


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


@pytest.fixture
def unit_square():
    return rect(0, 1, 0, 1)
