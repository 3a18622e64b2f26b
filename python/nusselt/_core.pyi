"""Typed stub of the compiled core (crates/nusselt-py). Private: use the nusselt API."""

from collections.abc import Callable
from typing import Any, final

import numpy as np
import numpy.typing as npt
from typing_extensions import Self

__all__ = [
    "__version__",
    "GeometryError",
    "SceneCore",
    "mirror_pairs",
    "pair_reciprocity",
    "methods",
    "view_factor",
    "point_view_factor",
    "num_threads",
    "work_units",
    "_panic_guard_selftest",
]

__version__: str

class GeometryError(ValueError):
    """A polygon failed validation. args: (message, index, kind, reason, degenerate); index is the
    polygon's position in the list the core was given, and the Python package names the face from it."""

@final
class SceneCore:
    def __new__(
        cls,
        coords: npt.NDArray[np.float64],
        offsets: npt.NDArray[np.int64],
        receiver: npt.NDArray[np.bool_],
        planarity_tol: float,
    ) -> Self: ...
    def unobstructed(self) -> bool:
        """True when no polygon of the scene can block another pair."""
    def errors(self) -> list[GeometryError | None]: ...
    def areas(self) -> npt.NDArray[np.float64]: ...
    def normals(self) -> npt.NDArray[np.float64]: ...
    def centroids(self) -> npt.NDArray[np.float64]: ...
    def triangulate(self, k: int) -> list[tuple[int, int, int]]: ...
    def strictly_convex(self, k: int) -> bool: ...
    def pair_rows(
        self, rows: npt.NDArray[np.int64], method: str, opts: dict
    ) -> tuple[
        npt.NDArray[np.int64],
        npt.NDArray[np.int32],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64] | None,
    ]:
        """G_ij = A_i F_ij for the rows and receivers j > i as CSR parts (indptr, indices, G,
        standard errors of G or None for exact methods)."""
    def full_rows(
        self, rows: npt.NDArray[np.int64], method: str, opts: dict
    ) -> tuple[
        npt.NDArray[np.int64],
        npt.NDArray[np.int64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
    ]: ...
    def point_rows(
        self,
        points: npt.NDArray[np.float64],
        normals: npt.NDArray[np.float64],
        method: str,
        opts: dict,
        obstructed: bool,
    ) -> tuple[
        npt.NDArray[np.int64],
        npt.NDArray[np.int32],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64] | None,
    ]:
        """F from each point ((P, 3), unit normals (P, 3)) to every receiver as CSR parts
        (indptr, receiver polygon ids, F, standard errors or None)."""
    def point_sphere_rows(
        self, points: npt.NDArray[np.float64], obstructed: bool
    ) -> tuple[
        npt.NDArray[np.int64],
        npt.NDArray[np.int32],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64] | None,
    ]:
        """F from a small sphere at each point to every receiver (visible solid angle / 4 pi)."""
    def point_sky(self, points: npt.NDArray[np.float64], normals: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Sky view factor of each point: 1 - the fraction the scene's polygons intercept."""
    def patch_sky(self, rows: npt.NDArray[np.int64], order: int) -> npt.NDArray[np.float64]:
        """Sky view factor of each polygon in rows (Gauss rule of order over the polygon)."""
    def rays_blocked(self, origins: npt.NDArray[np.float64], dirs: npt.NDArray[np.float64]) -> npt.NDArray[np.bool_]:
        """Whether each ray origin + t dir (t > 1e-9 of the scene size) meets a polygon."""

def mirror_pairs(
    areas: npt.NDArray[np.float64],
    col_of: npt.NDArray[np.int64],
    blocks: list[
        tuple[
            npt.NDArray[np.int64],
            npt.NDArray[np.int64],
            npt.NDArray[np.int32],
            npt.NDArray[np.float64],
            npt.NDArray[np.float64] | None,
        ]
    ],
    float32: bool,
    alloc: Callable[[int, str], npt.NDArray[Any]],
) -> tuple[
    npt.NDArray[np.int64],
    npt.NDArray[np.int32],
    npt.NDArray[np.float64] | npt.NDArray[np.float32],
    npt.NDArray[np.float64] | npt.NDArray[np.float32] | None,
]: ...
def pair_reciprocity(
    areas: npt.NDArray[np.float64],
    blocks: list[tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.int32], npt.NDArray[np.float64]]],
    float32: bool,
) -> float: ...
def view_factor(
    a: npt.NDArray[np.float64],
    b: npt.NDArray[np.float64],
    obstacles: list[npt.NDArray[np.float64]],
    method: str,
    opts: dict,
    planarity_tol: float,
) -> tuple[float, float]:
    """(F, standard error); KeyboardInterrupt on Ctrl-C, ValueError past the `budget` option,
    GeometryError with index a = 0, b = 1, obstacle k = 2 + k."""

def point_view_factor(
    p: npt.NDArray[np.float64],
    n: npt.NDArray[np.float64],
    b: npt.NDArray[np.float64],
    obstacles: list[npt.NDArray[np.float64]],
    method: str,
    opts: dict,
    planarity_tol: float,
) -> tuple[float, float]:
    """(F, standard error); KeyboardInterrupt on Ctrl-C, ValueError past the `budget` option,
    GeometryError with index b = 0, obstacle k = 1 + k."""

def methods() -> list[dict[str, Any]]:
    """The core's method registry: per method {name, kind ("pairs" | "rows"), obstructed,
    doc, options: [{name, type ("float" | "int" | "bool" | "source"), default, lo, hi,
    keywords, doc}]}."""

def num_threads() -> int: ...
def work_units() -> int: ...
def _panic_guard_selftest() -> None: ...
