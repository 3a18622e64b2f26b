"""EnergyPlus geometry in (IDF, epJSON), UserViewFactors out; View3D emit=1 (script-F)."""

import json
from pathlib import Path

import numpy as np
import pytest

import nusselt
import nusselt.cli
from nusselt.io import read_energyplus, read_user_view_factors, read_view3d_output
from nusselt.zones import zone_form_factors

DATA = Path(__file__).parent / "data"
# Unit cube, exact (Howell's catalogue, C-11 / C-14): opposite faces, adjacent faces.
F_OPP, F_ADJ = 0.19982489569838736, 0.20004377607540316


def cube_epjson(path, rel_north=0.0, origin=(0.0, 0.0, 0.0), clockwise=False):
    """A unit-cube zone of BuildingSurface:Detailed, vertices counter-clockwise seen from
    outside (EnergyPlus's default), a 0.5 x 0.5 window on the south wall."""
    faces = {  # outward-facing CCW seen from outside
        "South": [(0, 0, 1), (0, 0, 0), (1, 0, 0), (1, 0, 1)],
        "North": [(1, 1, 1), (1, 1, 0), (0, 1, 0), (0, 1, 1)],
        "East": [(1, 0, 1), (1, 0, 0), (1, 1, 0), (1, 1, 1)],
        "West": [(0, 1, 1), (0, 1, 0), (0, 0, 0), (0, 0, 1)],
        "Floor": [(0, 1, 0), (1, 1, 0), (1, 0, 0), (0, 0, 0)],
        "Ceiling": [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)],
    }
    win = [(0.25, 0, 0.75), (0.25, 0, 0.25), (0.75, 0, 0.25), (0.75, 0, 0.75)]
    flip = (lambda v: v[::-1]) if clockwise else (lambda v: v)
    vx = lambda vs: [
        {"vertex_x_coordinate": x, "vertex_y_coordinate": y, "vertex_z_coordinate": z} for x, y, z in flip(vs)
    ]
    doc = {
        "GlobalGeometryRules": {
            "GlobalGeometryRules 1": {
                "starting_vertex_position": "UpperLeftCorner",
                "vertex_entry_direction": "Clockwise" if clockwise else "Counterclockwise",
                "coordinate_system": "Relative",
            }
        },
        "Zone": {
            "Cube": {
                "direction_of_relative_north": rel_north,
                "x_origin": origin[0],
                "y_origin": origin[1],
                "z_origin": origin[2],
            }
        },
        "BuildingSurface:Detailed": {
            n: {
                "surface_type": "Wall",
                "construction_name": "C",
                "zone_name": "Cube",
                "outside_boundary_condition": "Outdoors",
                "vertices": vx(v),
            }
            for n, v in faces.items()
        },
        "FenestrationSurface:Detailed": {
            "Win": dict(
                {"surface_type": "Window", "construction_name": "G", "building_surface_name": "South"},
                **{
                    f"vertex_{k + 1}_{c}_coordinate": p[i] for k, p in enumerate(flip(win)) for i, c in enumerate("xyz")
                },
            )
        },
        "InternalMass": {"Furniture": {"construction_name": "C", "zone_or_zonelist_name": "Cube", "surface_area": 5}},
    }
    Path(path).write_text(json.dumps(doc))


@pytest.mark.parametrize("kw", [{}, {"rel_north": 30.0, "origin": (5.0, -2.0, 1.0)}, {"clockwise": True}])
def test_cube_zone_exact(tmp_path, kw):
    p = tmp_path / "cube.epJSON"
    cube_epjson(p, **kw)
    with pytest.warns(UserWarning, match="InternalMass 'Furniture' has no geometry"):
        scene = nusselt.Scene.from_file(p)
    assert scene.meta["zones"] == ["Cube"] and scene.meta["internal_mass"] == ["Furniture"]
    r = zone_form_factors(scene).by_surface()
    a = dict(zip(r.names, r.areas))
    assert a["Win"] == pytest.approx(0.25, abs=1e-14) and a["South"] == pytest.approx(0.75, abs=1e-14)
    f = r.dense()
    i = r.names.index
    np.testing.assert_allclose(r.row_sums, 1.0, atol=1e-12)
    assert r.reciprocity_error < 1e-12
    # additivity: window + rest of the wall sees the north wall as the whole south face does
    g = a["South"] * f[i("South"), i("North")] + a["Win"] * f[i("Win"), i("North")]
    assert g == pytest.approx(F_OPP, abs=1e-12)
    assert f[i("Floor"), i("Ceiling")] == pytest.approx(F_OPP, abs=1e-12)
    assert f[i("Floor"), i("East")] == pytest.approx(F_ADJ, abs=1e-12)
    assert f[i("Win"), i("South")] == 0.0


def test_relative_coordinates_move_the_zone(tmp_path):
    cube_epjson(tmp_path / "a.epJSON", rel_north=90.0, origin=(10.0, 0.0, 2.0))
    with pytest.warns(UserWarning):
        d = read_energyplus(tmp_path / "a.epJSON")
    # rotated clockwise by 90 degrees: (x, y) -> (y, -x), then shifted by the origin
    lo, hi = d.vertices.min(axis=0), d.vertices.max(axis=0)
    np.testing.assert_allclose(lo, [10.0, -1.0, 2.0], atol=1e-12)
    np.testing.assert_allclose(hi, [11.0, 0.0, 3.0], atol=1e-12)


def test_energyplus_example_four_zones_close():
    """EnergyPlus's own 4ZoneWithShading_Simple_1 (rectangular forms, World coordinates for
    detailed surfaces, relative rectangular surfaces): every zone closes and the interzone
    windows of zones 3 and 4 coincide, which checks the azimuth/tilt/lower-left-corner frame."""
    scene = nusselt.Scene.from_file(DATA / "4ZoneWithShading_Simple_1_geometry.idf")
    assert scene.meta["zones"] == ["ZONE 1", "ZONE 2", "ZONE 3", "ZONE 4"]
    r = zone_form_factors(scene).by_surface()
    np.testing.assert_allclose(r.row_sums, 1.0, atol=1e-12)
    a = dict(zip(r.names, r.areas))
    assert a["Zn001:Wall001"] == pytest.approx(200 - 15 - 15, abs=1e-9)  # window and door cut out
    assert a["Zn002:Wall001:Win002"] == pytest.approx(15, abs=1e-12)
    d = read_energyplus(DATA / "4ZoneWithShading_Simple_1_geometry.idf")
    polys = {d.names[s]: d.vertices[f] for f, s in zip(d.faces, d.surface)}
    w3, w4 = polys["Zn003:Wall004:Win001"], polys["Zn004:Wall004:Win001"]
    assert sorted(map(tuple, np.round(w3, 12))) == sorted(map(tuple, np.round(w4, 12)))
    n3 = np.cross(w3[1] - w3[0], w3[2] - w3[1])
    n4 = np.cross(w4[1] - w4[0], w4[2] - w4[1])
    assert n3 @ n4 < 0  # each faces into its own zone
    assert n3[0] < 0  # zone 3 lies at x < 26: its window faces -x


@pytest.mark.parametrize("ext", ["idf", "epJSON"])
def test_cli_writes_all_pairs_per_zone(tmp_path, ext):
    out = tmp_path / f"vf.{ext}"
    rc = nusselt.cli.main(["matrix", str(DATA / "4ZoneWithShading_Simple_1_geometry.idf"), "-o", str(out), "-q"])
    assert rc == 0
    got = read_user_view_factors(out)
    assert list(got) == ["ZONE 1", "ZONE 2", "ZONE 3", "ZONE 4"]
    z1 = got["ZONE 1"]
    names = {a for a, _ in z1}
    assert len(names) == 8 and len(z1) == 64  # 6 walls/floor/ceiling + window + door, zeros included
    for s in names:
        assert sum(z1[(s, t)] for t in names) == pytest.approx(1.0, abs=1e-12)
    if ext == "epJSON":
        schema = json.loads((DATA / "energyplus_userviewfactors_schema.json").read_text())
        jsonschema = pytest.importorskip("jsonschema")
        jsonschema.validate(json.loads(out.read_text()), schema)
    rc = nusselt.cli.main(
        ["matrix", str(DATA / "4ZoneWithShading_Simple_1_geometry.idf"), "-o", str(out), "-q", "--zone-name", "zone 3"]
    )
    assert rc == 0 and list(read_user_view_factors(out)) == ["ZONE 3"]


def test_bad_inputs(tmp_path):
    p = tmp_path / "bad.idf"
    p.write_text("Zone, Z;\nWall:Exterior, W, C, Nowhere, 180, 90, 0, 0, 0, 2, 1;\n")
    with pytest.raises(ValueError, match=r"bad.idf, line 2: Wall:Exterior 'W': zone 'Nowhere' is not defined"):
        read_energyplus(p)
    p.write_text("Zone, Z;\nWall:Exterior, W, C, Z, 180, 90, 0, 0, 0, 2, 1;\nWindow, G, C, W, , 1, 1.5, 0.2, 1, 0.5;\n")
    with pytest.raises(ValueError, match=r"line 3: Window 'G' \(on Wall:Exterior 'W'\) is not inside its base"):
        read_energyplus(p)


def test_emit1_script_f_two_surface_enclosure(tmp_path):
    """A cube: surface A the floor, B the five other faces (combined). Net exchange between
    two grey surfaces of an enclosure (textbook two-surface formula):
    Q = A_A sigma dT4 / ((1 - eA)/eA + 1/F_AB + A_A (1 - eB)/(A_B eB)), F_AB = 1,
    so script-F_AB = 1 / ((1 - eA)/eA + 1 + (1 - eB)/(5 eB))."""
    eA, eB = 0.6, 0.8
    v = "\n".join(
        f"V {k + 1} {x} {y} {z}"
        for k, (x, y, z) in enumerate(
            [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
        )
    )
    text = f"""T cube
C encl=1 emit=1
F 3
{v}
S 1 1 2 3 4 0 0 {eA} floor
S 2 5 8 7 6 0 0 {eB} top
S 3 1 5 6 2 0 2 {eB} s
S 4 2 6 7 3 0 2 {eB} e
S 5 3 7 8 4 0 2 {eB} n
S 6 4 8 5 1 0 2 {eB} w
End
"""
    p = tmp_path / "cube.vs3"
    p.write_text(text)
    out = tmp_path / "cube.txt"
    assert nusselt.cli.main(["matrix", str(p), "-o", str(out), "-q"]) == 0
    r = read_view3d_output(out)
    assert r["emit"] == 1
    sf_ab = 1.0 / ((1 - eA) / eA + 1 + (1 - eB) / (5 * eB))
    assert r["matrix"][0, 1] == pytest.approx(sf_ab, abs=5e-7)
    np.testing.assert_allclose(r["matrix"].sum(axis=1), [eA, eB], atol=2e-6)  # rows sum to eps_i
    assert r["areas"][0] * r["matrix"][0, 1] == pytest.approx(r["areas"][1] * r["matrix"][1, 0], abs=5e-6)


def test_view3d_controls_warn_and_null_orientation(tmp_path):
    p = tmp_path / "c.vs3"
    p.write_text(
        "C maxU=8 bogus=3\nF 3\nV 1 0 0 0\nV 2 1 0 0\nV 3 1 1 0\nV 4 0 1 0\n"
        "V 5 .2 .2 0\nV 6 .4 .2 0\nV 7 .4 .4 0\nV 8 .2 .4 0\n"
        "S 1 1 2 3 4 0 0 0.9 plate\nN 2 5 6 7 8 1 0 0.9 hole\nEnd\n"
    )
    with pytest.warns(UserWarning) as w:
        with pytest.raises(ValueError, match="null surface 2 must face the opposite way to its base surface 1"):
            nusselt.io.read_view3d(p)
    msgs = " ".join(str(x.message) for x in w)
    assert "maxU=8 ignored" in msgs and "bogus=3 is not a View3D 3.2 control" in msgs
