"""Zone-by-zone form factors: every zone of a building model is its own enclosure.

A building model (EnergyPlus IDF/epJSON) holds many zones whose surfaces must not see each
other: an interzone wall is two coincident surfaces facing opposite ways, and the surfaces of
one zone lie behind the walls of the next. Computing the whole scene as one enclosure would
either need obstruction tests everywhere or be wrong; computing each zone alone is exact and
cheaper. The result is one block-diagonal matrix over the chosen zones' polygons, so every
writer (.npz, .csv, .txt, .vtu, .idf, .epJSON) and :meth:`FormFactors.by_surface` work on it
as on any other result; rows sum to 1 within each closed zone.
"""

from __future__ import annotations

import os

import numpy as np

from .result import FormFactors
from .scene import Scene


def scene_zones(scene: Scene) -> list[str]:
    """The zone names of a scene read from a building model (empty for other scenes)."""
    return list((scene.meta or {}).get("zones") or [])


def select_zone(scene: Scene, name: str) -> str:
    """The scene's zone called ``name`` (case-insensitive, as EnergyPlus compares names)."""
    zones = scene_zones(scene)
    for z in zones:
        if z.lower() == str(name).strip().lower():
            return z
    shown = ", ".join(zones[:20]) + (" ..." if len(zones) > 20 else "")
    raise ValueError(f"{scene.source or 'scene'}: no zone named {name!r} (zones: {shown or 'none'})")


def zone_faces(scene: Scene) -> dict[str, np.ndarray]:
    """Face indices of every zone, in zone order."""
    meta = scene.meta or {}
    surface_zone = meta.get("surface_zone")
    if not surface_zone:
        raise ValueError(
            f"{scene.source or 'scene'}: the scene has no zones (only building models, "
            "e.g. EnergyPlus .idf / .epJSON files, have them)"
        )
    zone_of_face = np.array([surface_zone[s] for s in scene.surface], dtype=object)
    return {z: np.flatnonzero(zone_of_face == z) for z in scene_zones(scene)}


def zone_scene(scene: Scene, faces: np.ndarray) -> Scene:
    """A scene of the given faces only (same vertices, names and tolerances)."""
    faces = np.asarray(faces, dtype=np.int64)
    origin = [scene._origin[k] for k in faces] if scene._origin is not None else None
    return Scene(
        scene.vertices,
        [scene.faces[k] for k in faces],
        surface=scene.surface[faces],
        names=scene.surface_names,
        obstruction=scene.obstruction[faces],
        emissivity=scene.emissivity,
        planarity_tol=scene.planarity_tol,
        source=scene.source,
        origin=origin,
        meta=scene.meta,
    )


def zone_form_factors(scene: Scene, *, zones: list[str] | None = None, checkpoint=None, **kwargs) -> FormFactors:
    """Patch-level form factors computed zone by zone (block diagonal).

    ``zones`` selects zones by name (default: all); ``checkpoint`` (a directory) keeps each
    zone's finished blocks in its own subdirectory ``zone<k>``, written from the first block
    when there is more than one zone (a deferral, ``checkpoint_after``, would count each zone
    alone and could lose every zone finished before a kill); every other keyword goes to
    :func:`nusselt.form_factors`. Rows and columns are the chosen zones' receiving faces in
    scene order; ``faces``, ``surface`` and ``surface_names`` refer to the whole scene, so
    ``by_surface()`` gives the per-surface matrix of those zones.
    """
    import scipy.sparse as sp

    from .api import form_factors

    by_zone = zone_faces(scene)
    chosen = list(by_zone) if zones is None else [select_zone(scene, z) for z in zones]
    if not chosen:
        raise ValueError(f"{scene.source or 'scene'}: no zones to compute")
    if len(chosen) > 1:
        kwargs["checkpoint_after"] = 0.0
    parts = []
    for z in chosen:
        faces = by_zone[z]
        sub = zone_scene(scene, faces)
        ck = None
        if checkpoint is not None:  # the Checkpoint makes the directories when it is opened
            ck = os.path.join(os.fspath(checkpoint), f"zone{list(by_zone).index(z)}")
        res = form_factors(sub, checkpoint=ck, **kwargs)
        parts.append((z, faces[res.faces], res))
    faces = np.concatenate([f for _, f, _ in parts])
    order = np.argsort(faces, kind="stable")
    blocks = [sp.csr_array(r.matrix) if not sp.issparse(r.matrix) else r.matrix for _, _, r in parts]
    matrix = sp.csr_array(sp.block_diag(blocks, format="csr"))[order][:, order]
    std = None
    if any(r.std_err is not None for _, _, r in parts):
        std = sp.csr_array(
            sp.block_diag(
                [r.std_err if r.std_err is not None else sp.csr_array(r.matrix.shape) for _, _, r in parts],
                format="csr",
            )
        )[order][:, order]
    lost = None
    if any(r.lost is not None for _, _, r in parts):
        lost = np.concatenate([r.lost if r.lost is not None else np.zeros(len(r)) for _, _, r in parts])[order]
    areas = np.concatenate([r.areas for _, _, r in parts])[order]
    faces = faces[order]
    names = [f"{scene.surface_names[scene.surface[k]]}[{k}]" for k in faces]
    first = parts[0][2]
    dense = not sp.issparse(first.matrix)
    info = dict(first.info)
    info["zones"] = chosen
    info["dropped"] = max(float(r.info.get("dropped", 0.0)) for _, _, r in parts)
    return FormFactors(
        matrix.toarray() if dense else matrix,
        areas,
        names,
        faces,
        first.method,
        surface=scene.surface[faces],
        surface_names=scene.surface_names,
        std_err=std,
        lost=lost,
        info=info,
    )
