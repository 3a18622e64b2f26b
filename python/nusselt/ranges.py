"""The range of coordinates nusselt computes with in double precision.

Form factors do not depend on the length unit, but the kernels form areas, squared
distances and products of them: coordinates beyond ~1e75 overflow there (F came out 0 at
1e77) and geometry below ~1e-75 underflows (F off by 1e-6 at 1e-80). Within ±1e60 and for
sizes down to 1e-60 every kernel was checked to agree with the unit-scale result to 1e-11
(tests/test_robustness.py). Outside, the input is refused with the numbers instead of giving
a silent wrong F.
"""

from __future__ import annotations

import numpy as np

#: Largest coordinate magnitude, and smallest extent of a polygon or scene, accepted.
MAX_COORDINATE = 1e60
MIN_EXTENT = 1e-60

_HINT = "rescale the geometry (F does not depend on the length unit)"


def check_coordinates(points: np.ndarray, what: str) -> None:
    """Refuse coordinates beyond ±MAX_COORDINATE (``points``: (n, 3), finite)."""
    if points.size == 0:
        return
    big = float(np.max(np.abs(points)))
    if big > MAX_COORDINATE:
        raise ValueError(
            f"{what}: a coordinate of {big:.3g} is beyond ±{MAX_COORDINATE:.0e}, where areas and "
            f"squared distances overflow double precision; {_HINT}"
        )


def check_extent(points: np.ndarray, what: str) -> None:
    """Refuse a set of vertices whose bounding box is smaller than MIN_EXTENT (but not 0:
    degenerate polygons get their own message)."""
    if len(points) < 2:
        return
    extent = float(np.max(points.max(axis=0) - points.min(axis=0)))
    if 0 < extent < MIN_EXTENT:
        raise ValueError(
            f"{what}: its size {extent:.3g} is below {MIN_EXTENT:.0e}, where areas and squared "
            f"distances underflow double precision; {_HINT}"
        )
