"""Writers for form-factor results, one module per output format (docs/formats/):
:mod:`.npz` (the complete result, and :func:`load_npz`), :mod:`.csv`, :mod:`.view3d` (View3D
text output), :mod:`.energyplus` (IDF / epJSON user view factors) and :mod:`.vtu` (ParaView);
:func:`write_result` picks one by the file's extension and writes a whole result.

All low-level writers take plain data: ``matrix`` is a scipy.sparse array or a dense
ndarray with F[i, j] = fraction leaving row i that reaches column j (row = source).
Files are written to a temporary name and renamed, so a killed run never leaves a
half-written output under the final name.
"""

from __future__ import annotations

import os

from ._common import MAX_DENSE_ROWS, _check_size, field, stored_matrix
from .csv import write_csv
from .energyplus import write_energyplus, write_result_energyplus, write_user_view_factors
from .npz import NPZ_FORMAT, NPZ_VERSION, load_npz, write_npz, write_result_npz
from .view3d import write_result_view3d, write_view3d
from .vtu import write_result_vtu, write_vtu

_EXT_FORMAT = {
    ".npz": "npz",
    ".csv": "csv",
    ".txt": "view3d",
    ".view3d": "view3d",
    ".vf": "view3d",
    ".idf": "energyplus",
    ".epjson": "epjson",
    ".vtu": "vtu",
}
FORMATS = ("npz", "csv", "view3d", "energyplus", "epjson", "vtu")


def result_format(path, format: str | None = None) -> str:
    """The output format for a path (by extension) or an explicit ``format`` name."""
    if format is not None:
        f = format.lower()
        f = {"txt": "view3d", "idf": "energyplus", "eplus": "energyplus"}.get(f, f)
        if f not in FORMATS:
            raise ValueError(f"unknown output format {format!r}; choose one of {', '.join(FORMATS)}")
        return f
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in _EXT_FORMAT:
        raise ValueError(
            f"{path}: cannot tell the output format from the extension {ext or '(none)'}; "
            "use .npz, .csv, .txt (View3D), .idf or .epJSON (EnergyPlus) or .vtu"
        )
    return _EXT_FORMAT[ext]


def write_result(
    path,
    result,
    *,
    format: str | None = None,
    scene=None,
    to_surface: str | None = None,
    zone_name: str | None = None,
    precision: int | None = None,
    compress: bool = False,
) -> None:
    """Write a form-factor result in the format given by ``format`` or the extension:
    ``.npz`` (sparse, everything), ``.csv``, ``.txt`` (View3D text output), ``.idf``
    (EnergyPlus), ``.vtu`` (the scene's polygons with per-cell data; needs ``scene``).

    ``result`` is a :class:`nusselt.FormFactors` (or any object/dict with ``matrix``,
    ``areas``, ``names`` and optionally ``faces``, ``surface``, ``surface_names``,
    ``std_err``, ``lost``, ``method``, ``info``, ``by_surface()``).

    * ``.idf`` / ``.epJSON`` are always per named surface (patch results are aggregated
      with the form-factor algebra), all N^2 pairs of every zone, zeros included. A scene
      from a building model (EnergyPlus) gives one object per zone of the result (compute
      it with :func:`nusselt.zones.zone_form_factors`); ``zone_name`` then picks one zone
      (or renames the only one). Other scenes are one zone, named ``zone_name`` (default:
      the scene file's stem).
    * ``.txt`` is per surface when the scene came from a View3D file (View3D's own output
      is per surface), else as given; emissivities and ``encl`` come from the scene. When
      the ``.vs3`` file says ``emit=1`` the matrix is Hottel's script-F of those
      emissivities (clamped to [0.001, 0.999] as View3D does), as View3D then writes.
    * ``.vtu``: cell data ``area``, ``surface``, ``obstruction``, ``row`` (row of the
      result, -1 for none), ``row_sum``, and ``F_to_<name>`` when ``to_surface`` is given.
    * ``precision``: CSV significant digits / View3D decimals (default: exact for CSV,
      6 decimals for View3D as View3D writes).
    * ``compress``: ``.npz`` only, zip-deflated (smaller file, slower to write and read).
    """
    path = os.fspath(path)
    fmt = result_format(path, format)
    if stored_matrix(result) is None or field(result, "areas") is None or field(result, "names") is None:
        raise ValueError("result needs matrix, areas and names")
    patch_level = field(result, "surface") is not None
    if fmt == "npz":
        write_result_npz(path, result, scene, compress=compress)
    elif fmt == "csv":
        write_csv(path, field(result, "matrix"), field(result, "names"), precision=precision)
    elif fmt == "view3d":
        write_result_view3d(path, result, scene, precision=precision, patch_level=patch_level)
    elif fmt in ("energyplus", "epjson"):
        write_result_energyplus(path, result, scene, zone_name, "epjson" if fmt == "epjson" else "idf", patch_level)
    else:
        if scene is None:
            raise ValueError(f"{path}: VTU output needs the scene geometry (pass scene=)")
        write_result_vtu(path, result, scene, to_surface, patch_level)


__all__ = [
    "FORMATS",
    "MAX_DENSE_ROWS",
    "NPZ_FORMAT",
    "NPZ_VERSION",
    "load_npz",
    "result_format",
    "write_csv",
    "write_energyplus",
    "write_npz",
    "write_result",
    "write_user_view_factors",
    "write_view3d",
    "write_vtu",
    "_check_size",
]
