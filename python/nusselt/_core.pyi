"""Typed stub of the compiled core (crates/nusselt-py). Private: use the nusselt API."""

import numpy as np
import numpy.typing as npt

__version__: str

class SceneCore:
    def __init__(
        self,
        coords: npt.NDArray[np.float64],
        offsets: npt.NDArray[np.int64],
        receiver: npt.NDArray[np.bool_],
        planarity_tol: float,
    ) -> None: ...
    def errors(self) -> list[str | None]: ...
    def areas(self) -> npt.NDArray[np.float64]: ...
    def normals(self) -> npt.NDArray[np.float64]: ...
    def centroids(self) -> npt.NDArray[np.float64]: ...
    def triangulate(self, k: int) -> list[tuple[int, int, int]]: ...
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
) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.int32], npt.NDArray[np.float64], npt.NDArray[np.float64] | None]: ...
def view_factor(
    a: npt.NDArray[np.float64],
    b: npt.NDArray[np.float64],
    obstacles: list[npt.NDArray[np.float64]],
    method: str,
    opts: dict,
    planarity_tol: float,
) -> float: ...
def point_view_factor(
    p: npt.NDArray[np.float64],
    n: npt.NDArray[np.float64],
    b: npt.NDArray[np.float64],
    obstacles: list[npt.NDArray[np.float64]],
    method: str,
    opts: dict,
    planarity_tol: float,
) -> float: ...
def _panic_guard_selftest() -> None: ...
