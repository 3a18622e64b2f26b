"""Two-sided faces: computed as a front and a back patch, joined into one row and column.

A face that emits and receives on both sides (a thin plate, a fin, a partition seen from
both rooms) is, for radiation, two coincident one-sided patches of area A facing opposite
ways. The core computes those; the pair is then joined with the form-factor algebra
(as for named surfaces): the joined patch has area 2 A, its column is the sum of what
reaches either side (additivity), its row the area-weighted mean of the two rows,

    F_(p -> j) = (A F_(front -> j) + A F_(back -> j)) / (2 A),

so reciprocity (2 A) F_(p -> j) = A_j F_(j -> p) and closure hold as for any patch.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.sparse as sp

from .result import FormFactors
from .scene import Scene


def one_sided(scene: Scene) -> tuple[Scene, np.ndarray]:
    """The scene with a reversed copy (the back) of every two-sided face appended, all
    one-sided, and ``owner``: the original face of each face of that scene."""
    two = np.flatnonzero(scene.two_sided)
    nf = len(scene)
    faces = list(scene.faces) + [scene.faces[k][::-1] for k in two]
    origin = None
    if scene._origin is not None:
        origin = list(scene._origin) + [f"{scene._origin[k]}, back" for k in two]
    expanded = Scene(
        scene.vertices,
        faces,
        surface=np.concatenate([scene.surface, scene.surface[two]]),
        names=scene.surface_names,
        obstruction=np.concatenate([scene.obstruction, np.zeros(len(two), dtype=bool)]),
        emissivity=scene.emissivity,
        planarity_tol=scene.planarity_tol,
        source=scene.source,
        origin=origin,
        meta=scene.meta,
        orient="as-is",
    )
    return expanded, np.concatenate([np.arange(nf), two])


def join_sides(res: FormFactors, owner: np.ndarray, scene: Scene, dense: bool) -> FormFactors:
    """A result of :func:`one_sided`'s scene with each two-sided face's patches joined."""
    recv = scene.receivers
    col_of = np.full(len(scene), -1, dtype=np.int64)
    col_of[recv] = np.arange(len(recv))
    col = col_of[owner[np.asarray(res.faces)]]
    n, m = len(res.areas), len(recv)
    s = sp.csr_array((np.ones(n), (np.arange(n), col)), shape=(n, m))
    mat = res.matrix if sp.issparse(res.matrix) else sp.csr_array(res.matrix)
    a = s.T @ res.areas
    g = (s.T @ sp.csr_array(mat.multiply(res.areas[:, None])) @ s).tocsr()
    f = sp.csr_array(g.multiply(1.0 / a[:, None]))
    f.sort_indices()
    std = None
    if res.std_err is not None:
        v = sp.csr_array(sp.csr_array(res.std_err).power(2).multiply(res.areas[:, None] ** 2))
        std = sp.csr_array((s.T @ v @ s).tocsr().sqrt().multiply(1.0 / a[:, None]))
    lost = None if res.lost is None else (s.T @ (res.lost * res.areas)) / a
    names = [f"{scene.surface_names[scene.surface[k]]}[{k}]" for k in recv]
    return dataclasses.replace(
        res,
        matrix=f.toarray() if dense else f,
        areas=a,
        names=names,
        faces=recv,
        surface=scene.surface[recv],
        surface_names=scene.surface_names,
        std_err=std,
        lost=lost,
        info={**res.info, "two_sided": np.flatnonzero(scene.two_sided[recv]).tolist()},
    )


def two_sided_form_factors(form_factors, scene: Scene, *, dense: bool = False, **kw) -> FormFactors:
    """``form_factors`` of a scene with two-sided faces (see the module doc)."""
    expanded, owner = one_sided(scene)
    return join_sides(form_factors(expanded, dense=False, **kw), owner, scene, dense)
