"""EnergyPlus geometry (IDF and epJSON) in, ``ZoneProperty:UserViewFactors:BySurfaceName`` out.

Reading (``read_energyplus``, ``Scene.from_file("x.idf")`` / ``("x.epJSON")``):

* zones: ``Zone`` (name, direction of relative north, origin) and ``Building`` (north axis);
* base surfaces: ``BuildingSurface:Detailed``, ``Wall:Detailed``, ``RoofCeiling:Detailed``,
  ``Floor:Detailed`` and the rectangular forms ``Wall:Exterior``, ``Wall:Adiabatic``,
  ``Wall:Underground``, ``Wall:Interzone``, ``Roof``, ``Ceiling:Adiabatic``,
  ``Ceiling:Interzone``, ``Floor:GroundContact``, ``Floor:Adiabatic``, ``Floor:Interzone``;
* fenestration: ``FenestrationSurface:Detailed``, ``Window``, ``Door``, ``GlazedDoor`` and
  their ``:Interzone`` forms, cut out of their base surface;
* ``GlobalGeometryRules``: vertex entry direction, coordinate system of detailed surfaces
  (Relative to the zone, or World/Absolute), of rectangular surfaces, starting vertex position.

Conventions. EnergyPlus lists a surface's vertices counter-clockwise seen from OUTSIDE the zone
(``Counterclockwise`` entry; ``Clockwise`` the other way round); nusselt wants them
counter-clockwise seen from the front, the side facing the zone interior, so they are
reversed (or kept, for clockwise entry). Relative coordinates are rotated clockwise by the
zone's direction of relative north, shifted by the zone origin, then rotated clockwise by the
building's north axis (EnergyPlus's transformation; for view factors only the shape of each
zone matters, but subsurfaces and mixed coordinate systems need it right).

A rectangular surface with azimuth a (clockwise from north) and tilt t (0 faces up, 90 is
vertical, 180 faces down) has the outward normal n = (sin t sin a, sin t cos a, cos t); its
starting point is the lower left corner seen from outside, its length runs along
e_x = (-cos a, sin a, 0) (to the right of a viewer outside) and its height or width along
e_y = n x e_x. A ``Window``/``Door``/``GlazedDoor`` starts at (Starting X, Starting Z) in the
same frame of its base surface, measured from the base's lower left corner (the corner of the
base's bounding rectangle in that frame: the corner itself for rectangular bases). A
horizontal base uses its own azimuth when it came from a rectangular form, else 180.

Each base surface minus its windows and doors becomes several polygons of the base's named
surface (the core takes simple polygons): convex bases are cut by half-plane clipping, other
bases are triangulated first and each triangle is cut. A window's area is thus removed from
its wall exactly, and the form-factor algebra over the pieces gives the wall's F.

``InternalMass`` has no geometry: it is left out with a warning naming it (EnergyPlus then
treats every pair with it as zero, i.e. no long-wave exchange with it); the geometric
surfaces of its zone still form a closed enclosure. ``Shading:*`` surfaces are outside every
zone and are ignored. Window multipliers above 1 cannot be drawn: a warning names them.

Each zone is its own enclosure: ``meta["surface_zone"]`` gives the zone of every named
surface, and :func:`nusselt.zones.zone_form_factors` computes zone by zone.

Writing: :func:`nusselt.io.writers.energyplus.write_user_view_factors` writes one object per
zone with all N^2 pairs (zeros included: EnergyPlus warns when pairs are missing), as IDF text
or epJSON; :func:`read_user_view_factors` here reads them back.
"""

from __future__ import annotations

import math
import os
import re
import warnings

import numpy as np

from . import _planar
from .scenedata import SceneData, check_readable, parse_error, read_json, starts_with, text_lines
from .view3d import local_plane_axes

OBJECT = "ZoneProperty:UserViewFactors:BySurfaceName"

_GEOMETRY_RULE_FIELDS = [
    "starting_vertex_position",
    "vertex_entry_direction",
    "coordinate_system",
    "daylighting_reference_point_coordinate_system",
    "rectangular_surface_coordinate_system",
]
_RULE_CHOICES = {
    "starting_vertex_position": ("upperleftcorner", "lowerleftcorner", "upperrightcorner", "lowerrightcorner"),
    "vertex_entry_direction": ("counterclockwise", "clockwise"),
    "coordinate_system": ("relative", "world", "absolute"),
    "daylighting_reference_point_coordinate_system": ("relative", "world", "absolute"),
    "rectangular_surface_coordinate_system": ("relative", "world", "absolute"),
}
_RULE_DEFAULTS = {
    "starting_vertex_position": "upperleftcorner",
    "vertex_entry_direction": "counterclockwise",
    "coordinate_system": "relative",
    "daylighting_reference_point_coordinate_system": "relative",
    "rectangular_surface_coordinate_system": "relative",
}

_DETAILED_TAIL = [
    "outside_boundary_condition",
    "outside_boundary_condition_object",
    "sun_exposure",
    "wind_exposure",
    "view_factor_to_ground",
    "number_of_vertices",
]
_RECT = [
    "azimuth_angle",
    "tilt_angle",
    "starting_x_coordinate",
    "starting_y_coordinate",
    "starting_z_coordinate",
    "length",
]

# Base surfaces: IDF field layout after (name, construction, zone[, space]) and the surface type.
_BASE = {
    "BuildingSurface:Detailed": ("detailed", None, None),
    "Wall:Detailed": ("detailed", "Wall", None),
    "RoofCeiling:Detailed": ("detailed", "Roof", None),
    "Floor:Detailed": ("detailed", "Floor", None),
    "Wall:Exterior": ("rect", "Wall", 90.0),
    "Wall:Adiabatic": ("rect", "Wall", 90.0),
    "Wall:Underground": ("rect", "Wall", 90.0),
    "Wall:Interzone": ("rect_iz", "Wall", 90.0),
    "Roof": ("rect", "Roof", 0.0),
    "Ceiling:Adiabatic": ("rect", "Ceiling", 0.0),
    "Ceiling:Interzone": ("rect_iz", "Ceiling", 0.0),
    "Floor:GroundContact": ("rect", "Floor", 180.0),
    "Floor:Adiabatic": ("rect", "Floor", 180.0),
    "Floor:Interzone": ("rect_iz", "Floor", 180.0),
}
_SUB = {
    "FenestrationSurface:Detailed": ("detailed", None),
    "Window": ("window", "Window"),
    "GlazedDoor": ("window", "GlassDoor"),
    "Door": ("door", "Door"),
    "Window:Interzone": ("interzone", "Window"),
    "GlazedDoor:Interzone": ("interzone", "GlassDoor"),
    "Door:Interzone": ("interzone", "Door"),
}
_KNOWN = {k.lower(): k for k in [*_BASE, *_SUB, "Zone", "Building", "GlobalGeometryRules", "Version", "InternalMass"]}


def _idf_layouts(kind: str, version: tuple[int, int] | None) -> list[list[str]]:
    """Candidate IDF field layouts of an object, most likely first (by the Version object).

    EnergyPlus 9.6 added ``Space Name`` after ``Zone Name`` of every base surface and of
    ``InternalMass``; 9.0 removed ``Shading Control Name`` from the fenestration objects."""
    space_first = version is None or version >= (9, 6)
    shading_first = version is not None and version < (9, 0)
    head = ["name", "construction_name", "zone_name"]

    def with_space(rest, before=head):
        a = before + ["space_name"] + rest
        b = before + rest
        return [a, b] if space_first else [b, a]

    if kind in _BASE:
        form = _BASE[kind][0]
        if kind == "BuildingSurface:Detailed":
            return with_space(_DETAILED_TAIL, ["name", "surface_type", "construction_name", "zone_name"])
        if form == "detailed":
            return with_space(_DETAILED_TAIL)
        last = "height" if _BASE[kind][1] == "Wall" else "width"
        iz = ["outside_boundary_condition_object"] if form == "rect_iz" else []
        return with_space(iz + _RECT + [last])
    if kind == "InternalMass":
        return with_space(["surface_area"], ["name", "construction_name", "zone_name"])
    if kind == "FenestrationSurface:Detailed":
        a = [
            "name",
            "surface_type",
            "construction_name",
            "building_surface_name",
            "outside_boundary_condition_object",
            "view_factor_to_ground",
        ]
        b = ["frame_and_divider_name", "multiplier", "number_of_vertices"]
        old, new = a + ["shading_control_name"] + b, a + b
        return [old, new] if shading_first else [new, old]
    tail = ["multiplier", "starting_x_coordinate", "starting_z_coordinate", "length", "height"]
    form = _SUB[kind][0]
    if form == "window":
        a = ["name", "construction_name", "building_surface_name"]
        old, new = a + ["shading_control_name", "frame_and_divider_name"] + tail, a + ["frame_and_divider_name"] + tail
        return [old, new] if shading_first else [new, old]
    if form == "door":
        return [["name", "construction_name", "building_surface_name"] + tail]
    return [["name", "construction_name", "building_surface_name", "outside_boundary_condition_object"] + tail]


class _Obj:
    """One geometry object with named fields (snake_case, as epJSON names them)."""

    __slots__ = ("kind", "name", "fields", "vertices", "where")

    def __init__(self, kind, name, fields, vertices, where):
        self.kind, self.name, self.fields, self.vertices, self.where = kind, name, fields, vertices, where

    def label(self) -> str:
        return f"{self.kind} {self.name!r}" if self.name else self.kind


# --- IDF text ------------------------------------------------------------------------------


def _idf_objects(path: str) -> list[tuple[int, list[str]]]:
    """(first line, fields) of every IDF object, read line by line; ``!`` starts a comment,
    ``,`` separates fields, ``;`` ends an object."""
    out: list[tuple[int, list[str]]] = []
    fields: list[str] = []
    cur: list[str] = []
    start = None
    for no, line in text_lines(path, "IDF"):
        line = line.split("!", 1)[0]
        for piece in re.split(r"([,;])", line):
            if piece == ",":
                fields.append("".join(cur).strip())
                cur = []
            elif piece == ";":
                fields.append("".join(cur).strip())
                out.append((start or no, fields))
                fields, cur, start = [], [], None
            else:
                if piece.strip() and start is None:
                    start = no
                cur.append(piece)
    if "".join(cur).strip() or fields:
        raise parse_error(
            path,
            f"line {start}",
            f"object {(fields or [''.join(cur).strip()])[0]!r} is not terminated by ';' before the end of the file",
        )
    return out


def _version(values: list[str]) -> tuple[int, int] | None:
    m = re.match(r"\s*(\d+)\.(\d+)", values[0]) if values else None
    return (int(m.group(1)), int(m.group(2))) if m else None


def _fits(kind: str, layout: list[str], values: list[str]) -> bool:
    n = len(layout)
    vals = list(values)
    while vals and vals[-1] == "":
        vals.pop()
    if kind in _BASE and _BASE[kind][0] == "detailed" or kind == "FenestrationSurface:Detailed":
        rest = len(vals) - n
        if rest < 9 or rest % 3:
            return False
        nv = vals[n - 1].strip().lower()
        try:
            return nv in ("", "autocalculate") or int(float(nv)) == rest // 3
        except ValueError:
            return False
    if kind == "InternalMass":
        return len(vals) <= n
    return len(vals) == n  # the last fields (length, height or width) are required


def _from_idf(path: str) -> list[_Obj]:
    raw = _idf_objects(path)
    version = None
    for _, vals in raw:
        if vals[0].strip().lower() == "version":
            version = _version(vals[1:])
    objs = []
    for line, vals in raw:
        kind = _KNOWN.get(vals[0].strip().lower())
        if kind is None:
            continue
        values = vals[1:]
        where = f"line {line}"
        if kind in ("Version",):
            continue
        if kind == "Zone":
            names = ["name", "direction_of_relative_north", "x_origin", "y_origin", "z_origin"]
        elif kind == "Building":
            names = ["name", "north_axis"]
        elif kind == "GlobalGeometryRules":
            names = _GEOMETRY_RULE_FIELDS
        else:
            layouts = _idf_layouts(kind, version)
            layout = next((lay for lay in layouts if _fits(kind, lay, values)), None)
            if layout is None:
                lens = " or ".join(str(len(lay)) for lay in layouts)
                raise parse_error(
                    path,
                    where,
                    f"{kind} {values[0] if values else ''!r}: {len(values)} fields do not "
                    f"match its layout ({lens} fields before the vertices, or in all, "
                    f"for EnergyPlus {'{}.{}'.format(*version) if version else 'without a Version object'})",
                )
            names = layout
        fields = {k: v for k, v in zip(names, values)}
        verts = None
        if (kind in _BASE and _BASE[kind][0] == "detailed") or kind == "FenestrationSurface:Detailed":
            rest = [v for v in values[len(names) :]]
            while rest and rest[-1] == "":
                rest.pop()
            verts = [rest[k : k + 3] for k in range(0, len(rest), 3)]
        objs.append(_Obj(kind, fields.get("name", ""), fields, verts, where))
    return objs


# --- epJSON --------------------------------------------------------------------------------


def _is_epjson(path: str) -> bool:
    return path.lower().endswith(".epjson") or starts_with(path, b"{")


def _read_epjson(path: str):
    # JSON is parsed whole: a file too large for that is refused, with the way out
    return read_json(path, "epJSON", "convert it to IDF (EnergyPlus ConvertInputFormat), which is read line by line")


def _from_epjson(path: str) -> list[_Obj]:
    doc = _read_epjson(path)
    if not isinstance(doc, dict):
        raise parse_error(path, None, "an epJSON file is a JSON object of object types")
    lower = {k.lower(): k for k in doc}
    objs = []
    for low, kind in _KNOWN.items():
        if low not in lower or kind == "Version":
            continue
        group = doc[lower[low]]
        if not isinstance(group, dict):
            raise parse_error(path, kind, "must map object names to their fields")
        for name, fields in group.items():
            where = f"{kind} {name!r}"
            if not isinstance(fields, dict):
                raise parse_error(path, where, "fields must be a JSON object")
            fields = {k: ("" if v is None else v) for k, v in fields.items()}
            fields.setdefault("name", name)
            if kind == "InternalMass" and "zone_or_zonelist_name" in fields:
                fields.setdefault("zone_name", fields["zone_or_zonelist_name"])
            verts = None
            if kind in _BASE and _BASE[kind][0] == "detailed":
                vl = fields.get("vertices")
                if not isinstance(vl, list):
                    raise parse_error(path, where, "needs a 'vertices' array of {vertex_x_coordinate, ...}")
                verts = []
                for k, v in enumerate(vl):
                    try:
                        verts.append([v["vertex_x_coordinate"], v["vertex_y_coordinate"], v["vertex_z_coordinate"]])
                    except (KeyError, TypeError):
                        raise parse_error(
                            path,
                            where,
                            f"vertex {k + 1} needs vertex_x_coordinate, vertex_y_coordinate and vertex_z_coordinate",
                        ) from None
            elif kind == "FenestrationSurface:Detailed":
                verts = []
                for k in range(1, 5):
                    keys = [f"vertex_{k}_{c}_coordinate" for c in "xyz"]
                    if all(key in fields and fields[key] != "" for key in keys):
                        verts.append([fields[key] for key in keys])
                    elif k <= 3:
                        raise parse_error(path, where, f"needs vertex_{k}_x/y/z_coordinate")
            objs.append(_Obj(kind, str(name), fields, verts, where))
    return objs


# --- geometry ------------------------------------------------------------------------------


def _num(path, obj: _Obj, key: str, default: float | None = None) -> float:
    v = obj.fields.get(key, "")
    if v == "" or (isinstance(v, str) and v.strip().lower() in ("", "autocalculate", "autosize")):
        if default is None:
            raise parse_error(path, obj.where, f"{obj.label()}: field {key.replace('_', ' ')} is required")
        return float(default)
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise parse_error(
            path, obj.where, f"{obj.label()}: {key.replace('_', ' ')} must be a number, got {v!r}"
        ) from None
    if not math.isfinite(x):
        raise parse_error(path, obj.where, f"{obj.label()}: {key.replace('_', ' ')} is not finite")
    return x


def _rot_z(p: np.ndarray, deg: float) -> np.ndarray:
    """Rotate points clockwise (seen from above) by ``deg`` about the z axis."""
    if deg == 0.0:
        return p
    c, s = _planar.cos_sin_deg(-deg)
    x, y = p[:, 0], p[:, 1]
    return np.column_stack([x * c - y * s, x * s + y * c, p[:, 2]])


class _Zone:
    __slots__ = ("name", "north", "origin", "where")

    def __init__(self, name, north, origin, where):
        self.name, self.north, self.origin, self.where = name, north, origin, where

    def to_world(self, p: np.ndarray, building_north: float) -> np.ndarray:
        q = _rot_z(p, self.north) + self.origin
        return _rot_z(q, building_north)


def _rectangle(p0, azimuth, tilt, length, height) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Corners counter-clockwise seen from OUTSIDE (upper left first) and the frame (e_x, e_y)."""
    ex, ey, _ = local_plane_axes(azimuth, tilt)
    p0 = np.asarray(p0, dtype=np.float64)
    corners = np.array([p0 + height * ey, p0, p0 + length * ex, p0 + length * ex + height * ey])
    return corners, ex, ey


def _outside_frame(poly_out: np.ndarray, azimuth_hint: float | None) -> tuple[np.ndarray, np.ndarray]:
    """(e_x, e_y) of a base surface given counter-clockwise seen from outside."""
    n = _planar.newell_normal(poly_out)
    n = n / np.linalg.norm(n)
    st = math.hypot(n[0], n[1])
    if st < 1e-9:
        az = 180.0 if azimuth_hint is None else azimuth_hint
        ex, ey, _ = local_plane_axes(az, 0.0 if n[2] > 0 else 180.0)
        return ex, ey
    ex = np.array([-n[1], n[0], 0.0]) / st
    return ex, np.cross(n, ex)


#: EnergyPlus's rules for windows and doors: convex, facing as their base, which may be concave.
_CUT_RULES = _planar.CutRules(
    plane_tol=1e-4,
    concave_base=True,
    messages={
        "zero_base": "{base} has zero area but has windows or doors",
        "not_simple": "{base} is not a simple polygon",
        "off_plane": "{what} is not in the plane of its base surface (a vertex is {dist:.3g} m from it)",
        "zero_area": "{what} has zero area",
        "wrong_way": "{what} faces the opposite way to its base surface "
        "(its vertices must go round in the same sense as the base's)",
        "not_convex": "{what} is not convex",
        "outside": "{what} is not inside its base surface ({pct:.3g}% of it lies outside)",
        "overlap": "{what} overlaps {other}",
    },
)


def _cut(path, base: dict, subs: list[dict]) -> list[np.ndarray]:
    """The base polygon (nusselt orientation) minus its subsurfaces, as convex polygons."""
    holes = [_planar.Hole(s["poly"], s["where"], f"{s['label']} (on {base['label']})", s["label"]) for s in subs]
    return _planar.cut_holes(
        base["poly"],
        holes,
        _CUT_RULES,
        where=base["where"],
        label=base["label"],
        fail=lambda where, problem: parse_error(path, where, problem),
    )


def read_energyplus(path) -> SceneData:
    """Read the zone geometry of an EnergyPlus ``.idf`` or ``.epJSON`` file.

    Returns a :class:`SceneData` with one named surface per EnergyPlus heat-transfer surface
    and subsurface (names as in the file), polygons counter-clockwise seen from inside the
    zone, and ``meta``: ``format="energyplus"``, ``zones`` (names in file order),
    ``surface_zone`` / ``surface_type`` / ``base_surface`` (per named surface),
    ``geometry_rules``, ``internal_mass`` (names left out), ``version``.
    """
    path = os.fspath(path)
    check_readable(path)
    is_json = _is_epjson(path)
    objs = _from_epjson(path) if is_json else _from_idf(path)
    return _build(path, objs, "epJSON" if is_json else "IDF")


def _choice(path, obj, key, value) -> str:
    v = str(value).strip().lower().replace(" ", "").replace("-", "")
    if v == "":
        return _RULE_DEFAULTS[key]
    if v not in _RULE_CHOICES[key]:
        raise parse_error(
            path,
            obj.where,
            f"GlobalGeometryRules: {key.replace('_', ' ')} {value!r} is not one of {', '.join(_RULE_CHOICES[key])}",
        )
    return "world" if v == "absolute" else v


def _build(path: str, objs: list[_Obj], dialect: str) -> SceneData:
    rules = dict(_RULE_DEFAULTS)
    building_north = 0.0
    zones: dict[str, _Zone] = {}
    for o in objs:
        if o.kind == "GlobalGeometryRules":
            for rule in _GEOMETRY_RULE_FIELDS:
                rules[rule] = _choice(path, o, rule, o.fields.get(rule, ""))
        elif o.kind == "Building":
            building_north = _num(path, o, "north_axis", 0.0)
        elif o.kind == "Zone":
            key = o.name.lower()
            if not o.name:
                raise parse_error(path, o.where, "Zone without a name")
            if key in zones:
                raise parse_error(path, o.where, f"zone {o.name!r} is defined twice (first at {zones[key].where})")
            zone_origin = np.array([_num(path, o, f"{c}_origin", 0.0) for c in "xyz"])
            zones[key] = _Zone(o.name, _num(path, o, "direction_of_relative_north", 0.0), zone_origin, o.where)
    ccw = rules["vertex_entry_direction"] == "counterclockwise"
    detailed_relative = rules["coordinate_system"] == "relative"
    rect_relative = rules["rectangular_surface_coordinate_system"] == "relative"

    def zone_of(o, key="zone_name") -> _Zone:
        z = str(o.fields.get(key, "")).strip()
        if not z:
            raise parse_error(path, o.where, f"{o.label()} names no zone")
        if z.lower() not in zones:
            shown = ", ".join(v.name for v in list(zones.values())[:10]) or "none"
            raise parse_error(path, o.where, f"{o.label()}: zone {z!r} is not defined (zones: {shown})")
        return zones[z.lower()]

    def coords(o) -> np.ndarray:
        try:
            p = np.array([[float(c) for c in v] for v in o.vertices], dtype=np.float64)
        except (TypeError, ValueError):
            raise parse_error(path, o.where, f"{o.label()}: vertex coordinates must be numbers") from None
        if len(p) < 3 or p.shape[1] != 3:
            raise parse_error(path, o.where, f"{o.label()}: a surface needs at least 3 vertices (x, y, z each)")
        if not np.isfinite(p).all():
            raise parse_error(path, o.where, f"{o.label()}: vertex coordinates must be finite")
        return p

    surfaces: dict[str, dict] = {}  # lower-case name -> record
    order: list[str] = []
    internal_mass: list[str] = []

    def add(rec):
        key = rec["name"].lower()
        if not rec["name"]:
            raise parse_error(path, rec["where"], f"{rec['label']} has no name")
        if key in surfaces:
            raise parse_error(
                path,
                rec["where"],
                f"surface name {rec['name']!r} is used twice "
                f"(first at {surfaces[key]['where']}); EnergyPlus names are unique",
            )
        surfaces[key] = rec
        order.append(key)

    for o in objs:
        if o.kind == "InternalMass":
            internal_mass.append(o.name)
            continue
        if o.kind not in _BASE:
            continue
        form, stype, tilt_default = _BASE[o.kind]
        z = zone_of(o)
        if form == "detailed":
            p = coords(o)
            if detailed_relative:
                p = z.to_world(p, building_north)
            outside = p if ccw else p[::-1]
            az_hint = None
            stype = stype or str(o.fields.get("surface_type", "")).strip() or "Wall"
        else:
            az = _num(path, o, "azimuth_angle")
            tilt = _num(path, o, "tilt_angle", tilt_default)
            p0 = [_num(path, o, f"starting_{c}_coordinate", 0.0) for c in "xyz"]
            length = _num(path, o, "length")
            other = _num(path, o, "height" if stype == "Wall" else "width")
            outside, _, _ = _rectangle(p0, az, tilt, length, other)
            if rect_relative:
                outside = z.to_world(outside, building_north)
                az = az + z.north + building_north
            az_hint = az
        if _planar.polygon_area_3d(outside) == 0:
            raise parse_error(path, o.where, f"{o.label()} has zero area")
        add(
            {
                "name": o.name,
                "label": o.label(),
                "where": o.where,
                "zone": z.name,
                "type": stype,
                "outside": outside,
                "poly": outside[::-1].copy(),
                "az_hint": az_hint,
                "subs": [],
                "base": None,
            }
        )

    for o in objs:
        if o.kind not in _SUB:
            continue
        form, stype = _SUB[o.kind]
        bname = str(o.fields.get("building_surface_name", "")).strip()
        base = surfaces.get(bname.lower())
        if base is None or base["base"] is not None:
            raise parse_error(
                path, o.where, f"{o.label()}: base surface {bname!r} is not a building surface of this file"
            )
        mult = _num(path, o, "multiplier", 1.0)
        if mult > 1:
            warnings.warn(
                f"{path}: {o.label()} has multiplier {mult:g}; nusselt draws it once (its geometry), "
                "so its view factors are those of one window",
                stacklevel=3,
            )
        if form == "detailed":
            p = coords(o)
            if detailed_relative:
                p = zones[base["zone"].lower()].to_world(p, building_north)
            outside = p if ccw else p[::-1]
            stype = str(o.fields.get("surface_type", "")).strip() or "Window"
        else:
            ex, ey = _outside_frame(base["outside"], base["az_hint"])
            local = (base["outside"] - base["outside"][0]) @ np.column_stack([ex, ey])
            llc = base["outside"][0] + local[:, 0].min() * ex + local[:, 1].min() * ey
            x0, z0 = _num(path, o, "starting_x_coordinate", 0.0), _num(path, o, "starting_z_coordinate", 0.0)
            length, height = _num(path, o, "length"), _num(path, o, "height")
            p0 = llc + x0 * ex + z0 * ey
            outside = np.array([p0 + height * ey, p0, p0 + length * ex, p0 + length * ex + height * ey])
        rec = {
            "name": o.name,
            "label": o.label(),
            "where": o.where,
            "zone": base["zone"],
            "type": stype,
            "outside": outside,
            "poly": outside[::-1].copy(),
            "az_hint": None,
            "subs": [],
            "base": base["name"],
        }
        add(rec)
        base["subs"].append(rec)

    if not order:
        raise parse_error(path, None, "no heat-transfer surfaces (BuildingSurface:Detailed, Wall:Exterior, ...) found")
    if internal_mass:
        shown = ", ".join(repr(n) for n in internal_mass[:5]) + (" ..." if len(internal_mass) > 5 else "")
        warnings.warn(
            f"{path}: InternalMass {shown} has no geometry and is left out of the view factors "
            "(EnergyPlus takes the omitted pairs as zero: no long-wave exchange with it)",
            stacklevel=3,
        )

    names: list[str] = []
    surface_zone: list[str] = []
    surface_type: list[str] = []
    base_of: list[str | None] = []
    verts: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    surface: list[int] = []
    origin: list[str] = []
    nverts = 0
    for key in order:
        rec = surfaces[key]
        k = len(names)
        names.append(rec["name"])
        surface_zone.append(rec["zone"])
        surface_type.append(rec["type"])
        base_of.append(rec["base"])
        polys = _cut(path, rec, rec["subs"]) if rec["subs"] else [rec["poly"]]
        for j, p in enumerate(polys):
            verts.append(p)
            faces.append(np.arange(nverts, nverts + len(p)))
            nverts += len(p)
            surface.append(k)
            origin.append(
                f"{rec['where']} ({rec['label']}" + (f", part {j + 1} of {len(polys)})" if len(polys) > 1 else ")")
            )
    used = []
    for z in zones.values():
        if z.name in surface_zone:
            used.append(z.name)
    meta = {
        "format": "energyplus",
        "dialect": dialect,
        "zones": used,
        "surface_zone": surface_zone,
        "surface_type": surface_type,
        "base_surface": base_of,
        "geometry_rules": rules,
        "building_north_axis": building_north,
        "internal_mass": internal_mass,
    }
    return SceneData(
        vertices=np.concatenate(verts),
        faces=faces,
        surface=np.array(surface, dtype=np.int64),
        names=names,
        origin=origin,
        source=path,
        meta=meta,
    )


def read_user_view_factors(path) -> dict[str, dict[tuple[str, str], float]]:
    """Read ``ZoneProperty:UserViewFactors:BySurfaceName`` objects back (IDF or epJSON):
    ``{zone: {(from, to): F}}``."""
    path = os.fspath(path)
    check_readable(path)
    out: dict[str, dict[tuple[str, str], float]] = {}
    if _is_epjson(path):
        doc = _read_epjson(path)
        group: dict[str, dict] = next((v for k, v in doc.items() if k.lower() == OBJECT.lower()), {})
        for obj in group.values():
            z = obj["zone_or_zonelist_or_space_or_spacelist_name"]
            out[z] = {(e["from_surface"], e["to_surface"]): float(e["view_factor"]) for e in obj["view_factors"]}
        return out
    for line, vals in _idf_objects(path):
        if vals[0].strip().lower() != OBJECT.lower():
            continue
        rest = vals[2:]
        if len(rest) % 3:
            raise parse_error(
                path,
                f"line {line}",
                f"{OBJECT}: {len(rest)} fields after the zone name are not (from, to, view factor) triplets",
            )
        out[vals[1]] = {(rest[k], rest[k + 1]): float(rest[k + 2]) for k in range(0, len(rest), 3)}
    return out
