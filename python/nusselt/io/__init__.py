"""File input and output for nusselt: scene readers and result writers.

Readers return a plain :class:`SceneData` (``Scene.from_file`` builds a ``Scene`` from it);
every parse error is a one-line ``ValueError`` (or ``OSError`` for missing/unreadable
files) naming the file, the line or element, and the problem.

>>> from nusselt.io import read_scene, load_npz
>>> data = read_scene("room.vs3")            # .obj, .vs3, or any meshio format
>>> r = load_npz("out.npz"); F = r["matrix"]  # scipy.sparse.csr_array, row = source

This package does not import the compiled core, so files can be read and written without it.
"""

from __future__ import annotations

import importlib
import os
from typing import TYPE_CHECKING, Any

from .scenedata import SceneData

if TYPE_CHECKING:
    from .energyplus import read_energyplus, read_user_view_factors
    from .meshes import read_mesh
    from .obj import read_obj
    from .view3d import read_view3d, read_view3d_output
    from .writers import (
        load_npz,
        result_format,
        write_csv,
        write_energyplus,
        write_npz,
        write_result,
        write_user_view_factors,
        write_view3d,
        write_vtu,
    )

# Each reader and writer is imported when first used: a run reads one format and writes one,
# and importing them all cost a tenth of the start-up of a small run (docs/scale.md).
_LAZY = {
    "read_energyplus": "energyplus",
    "read_user_view_factors": "energyplus",
    "read_mesh": "meshes",
    "read_obj": "obj",
    "orient_faces": "topology",
    "read_view3d": "view3d",
    "read_view3d_output": "view3d",
    **dict.fromkeys(
        (
            "load_npz",
            "result_format",
            "write_csv",
            "write_energyplus",
            "write_npz",
            "write_result",
            "write_user_view_factors",
            "write_view3d",
            "write_vtu",
        ),
        "writers",
    ),
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


_OWN = {".obj": "obj", ".vs3": "view3d", ".idf": "energyplus", ".epjson": "energyplus"}


def _read_by_format(path, format: str | None = None) -> SceneData:
    """Read a scene file: ``.obj`` (own reader: objects/groups become surfaces), ``.vs3``
    (View3D), ``.idf`` / ``.epJSON`` (EnergyPlus zone geometry), anything else through meshio.
    ``format`` overrides the extension: ``"obj"``, ``"view3d"`` (or ``"vs3"``),
    ``"energyplus"`` (or ``"idf"``, ``"epjson"``), or a meshio format name (``"stl"``,
    ``"gmsh"``, ``"vtu"`` ...)."""
    path = os.fspath(path)
    kind = format.lower() if format is not None else _OWN.get(os.path.splitext(path)[1].lower())
    kind = {"vs3": "view3d", "idf": "energyplus", "epjson": "energyplus"}.get(kind or "", kind)
    if kind == "obj":
        from .obj import read_obj

        return read_obj(path)
    if kind == "view3d":
        from .view3d import read_view3d

        return read_view3d(path)
    if kind == "energyplus":
        from .energyplus import read_energyplus

        return read_energyplus(path)
    from .meshes import read_mesh

    return read_mesh(path, format=format) if format is not None else read_mesh(path)


def read_scene(path, format: str | None = None, orient: str = "as-is") -> SceneData:
    """Read a scene file (see :func:`_read_by_format` for the formats and ``format``).

    ``orient`` turns closed shells as :func:`nusselt.io.topology.orient_faces` says
    (``"as-is"``: faces as the file lists them; ``Scene.from_file`` defaults to ``"auto"``).
    Running out of memory while reading is a ``MemoryError`` naming the file."""
    path = os.fspath(path)
    try:
        data = _read_by_format(path, format)
    except MemoryError as e:
        size = os.path.getsize(path) if os.path.exists(path) else 0
        raise MemoryError(
            f"{path}: not enough memory to read this {size / 2**20:.0f} MiB file" + (f" ({e})" if str(e) else "")
        ) from None
    if orient != "as-is":
        from .topology import orient_faces

        data.faces, report = orient_faces(data.vertices, data.faces, orient)
        data.meta["orient"] = {"orient": orient, "flipped": report["flipped"].tolist()}
    return data


__all__ = [
    "SceneData",
    "read_scene",
    "read_obj",
    "read_view3d",
    "read_mesh",
    "read_view3d_output",
    "read_energyplus",
    "read_user_view_factors",
    "write_user_view_factors",
    "write_npz",
    "load_npz",
    "write_csv",
    "write_view3d",
    "write_energyplus",
    "write_vtu",
    "write_result",
    "result_format",
]
