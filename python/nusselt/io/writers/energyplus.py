"""The EnergyPlus output: ``ZoneProperty:UserViewFactors:BySurfaceName`` objects in IDF or
epJSON (docs/formats/energyplus.md); :func:`nusselt.io.read_user_view_factors` reads them back."""

from __future__ import annotations

import json
import os

import numpy as np
import scipy.sparse as sp

from ..energyplus import OBJECT
from ._common import _atomic, _names, _square, field


def write_energyplus(path, matrix, names, zone_name: str, *, all_pairs: bool = False) -> None:
    """EnergyPlus ``ZoneProperty:UserViewFactors:BySurfaceName`` object (IDF text).

    Fields (EnergyPlus Input Output Reference / Energy+.idd, 22.1 and later):
    ``Zone or ZoneList or Space or SpaceList Name``, then repeated triplets
    ``From Surface <i>``, ``To Surface <i>``, ``View Factor <i>`` (the view factor from the
    "from" surface to the "to" surface, at most 1.0). Omitted pairs count as zero, so only
    nonzero entries are written unless ``all_pairs``. ``names`` must be the EnergyPlus
    surface names of the zone.
    """
    n = _square(matrix)
    write_user_view_factors(path, [(zone_name, matrix, _names(names, n))], format="idf", all_pairs=all_pairs)


def write_result_energyplus(path: str, result, scene, zone_name, fmt: str, patch_level: bool) -> None:
    """One ZoneProperty:UserViewFactors:BySurfaceName object per zone of the result."""
    if patch_level:
        if not hasattr(result, "by_surface"):
            raise ValueError(f"{path}: EnergyPlus needs surface names; aggregate the result to surfaces first")
        result = result.by_surface()
    matrix, names = field(result, "matrix"), list(field(result, "names"))
    f = matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix, dtype=np.float64)
    meta = getattr(scene, "meta", None) or {}
    surface_zone = meta.get("surface_zone")
    faces = field(result, "faces")
    if not surface_zone or faces is None:
        if zone_name is None:
            src = getattr(scene, "source", None)
            zone_name = os.path.splitext(os.path.basename(src))[0] if src else "Zone 1"
        write_user_view_factors(path, [(zone_name, f, names)], format=fmt)
        return
    row_zone = np.array([surface_zone[int(k)] for k in faces], dtype=object)
    zones = [z for z in meta.get("zones", []) if (row_zone == z).any()]
    groups = {z: np.flatnonzero(row_zone == z) for z in zones}
    for z, rows in groups.items():
        outside = np.abs(f[np.ix_(rows, np.setdiff1d(np.arange(len(names)), rows))]).max(initial=0.0)
        if outside > 0:
            raise ValueError(
                f"{path}: zone {z!r} has view factors to surfaces of other zones (up to {outside:.3g}); "
                "every zone is its own enclosure: compute zone by zone "
                "(nusselt.zones.zone_form_factors, as `nusselt matrix` does for building models)"
            )
    if zone_name is not None:
        want = str(zone_name).strip()
        match = [z for z in zones if z.lower() == want.lower()]
        if match:
            groups = {match[0]: groups[match[0]]}
        elif len(zones) == 1:
            groups = {want: groups[zones[0]]}  # rename the only zone
        else:
            raise ValueError(f"{path}: no zone named {want!r} in the result (zones: {', '.join(zones)})")
    write_user_view_factors(path, [(z, f[np.ix_(r, r)], [names[i] for i in r]) for z, r in groups.items()], format=fmt)


def _check_name(path, label: str) -> str:
    s = str(label).strip()
    if not s or any(ch in s for ch in ",;!\n\r"):
        raise ValueError(f"{path}: {label!r} cannot be an EnergyPlus name (empty, or holds , ; or !)")
    return s


def view_factor_triplets(path, matrix, names, *, all_pairs: bool = True) -> list[tuple[str, str, float]]:
    """The (from, to, F) triplets of a surface matrix, row = from: all N^2, or with
    ``all_pairs=False`` the nonzero ones; values checked to lie in [0, 1] (round-off up to
    1e-9 outside is clipped)."""
    f = matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix, dtype=np.float64)
    n = len(names)
    if f.shape != (n, n):
        raise ValueError(f"{path}: a {f.shape} matrix for {n} surface names")
    bad = np.argwhere((f < -1e-9) | (f > 1 + 1e-9) | ~np.isfinite(f))
    if len(bad):
        i, j = bad[0]
        raise ValueError(f"{path}: F[{names[i]} -> {names[j]}] = {float(f[i, j])!r} is not a view factor in [0, 1]")
    f = np.clip(f, 0.0, 1.0)
    return [(names[i], names[j], float(f[i, j])) for i in range(n) for j in range(n) if all_pairs or f[i, j] != 0]


def write_user_view_factors(
    path, zones: list[tuple[str, object, list[str]]], *, format: str | None = None, all_pairs: bool = True
) -> None:
    """Write one ``ZoneProperty:UserViewFactors:BySurfaceName`` object per zone.

    ``zones`` lists ``(zone name, F, surface names)`` with F the zone's square surface matrix
    (row = from surface). Every pair is written, zeros included (EnergyPlus warns about missing
    pairs); ``all_pairs=False`` writes only the nonzero ones, which EnergyPlus takes as zero.
    ``format`` is ``"idf"`` or
    ``"epjson"`` (default: from the extension, ``.epJSON`` -> epJSON).

    IDF fields (Energy+.idd): ``Zone or ZoneList or Space or SpaceList Name``, then the
    extensible group ``From Surface i``, ``To Surface i``, ``View Factor i``. epJSON
    (EnergyPlus's schema, generated from the IDD): the object is keyed by an arbitrary unique
    name, with ``zone_or_zonelist_or_space_or_spacelist_name`` and the array ``view_factors``
    of ``{from_surface, to_surface, view_factor}``.
    """
    path = os.fspath(path)
    fmt = (format or ("epjson" if path.lower().endswith(".epjson") else "idf")).lower()
    if fmt not in ("idf", "epjson"):
        raise ValueError(f"unknown EnergyPlus format {format!r}; choose idf or epjson")
    if not zones:
        raise ValueError(f"{path}: no zones to write")
    objects = []
    seen = set()
    for zone, matrix, names in zones:
        zone = _check_name(path, zone)
        if zone.lower() in seen:
            raise ValueError(f"{path}: zone {zone!r} is given twice")
        seen.add(zone.lower())
        names = [_check_name(path, s) for s in names]
        objects.append((zone, view_factor_triplets(path, matrix, names, all_pairs=all_pairs)))
    if not any(trip for _, trip in objects):
        raise ValueError(f"{path}: every view factor is zero; nothing to write")
    with _atomic(path, "w") as fh:
        if fmt == "epjson":
            doc = {
                OBJECT: {
                    f"{OBJECT} {k}": {
                        "zone_or_zonelist_or_space_or_spacelist_name": zone,
                        "view_factors": [{"from_surface": a, "to_surface": b, "view_factor": f} for a, b, f in trip],
                    }
                    for k, (zone, trip) in enumerate(objects, start=1)
                }
            }
            json.dump(doc, fh, indent=2)
            fh.write("\n")
            return
        for zone, trip in objects:
            fh.write(f"{OBJECT},\n")
            fh.write(f"    {zone + ',':<30} !- Zone or ZoneList or Space or SpaceList Name\n")
            last = len(trip)
            for k, (a, b, f) in enumerate(trip, start=1):
                end = ";" if k == last else ","
                fh.write(f"    {a + ',':<30} !- From Surface {k}\n")
                fh.write(f"    {b + ',':<30} !- To Surface {k}\n")
                fh.write(f"    {repr(f) + end:<30} !- View Factor {k}\n")
            fh.write("\n")
