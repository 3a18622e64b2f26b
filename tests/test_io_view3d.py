"""View3D .vs3 reader: F 3 and F 3a, sub-surfaces, masks, null and obstruction surfaces,
combine, controls, and one-line errors naming the file and line."""

import math
import pathlib

import numpy as np
import pytest

import nusselt.io as nio

DATA = pathlib.Path(__file__).parent / "data"


def newell(p):
    return 0.5 * np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)


def area(p):
    return float(np.linalg.norm(newell(p)))


def surface_areas(d):
    a = np.zeros(len(d.names))
    for s, p in zip(d.surface, d.polygons):
        a[s] += area(p)
    return dict(zip(d.names, a))


def covers(poly2d, pt):
    """Strictly inside a convex polygon (either orientation)?"""
    q = np.roll(poly2d, -1, axis=0)
    c = (q[:, 0] - poly2d[:, 0]) * (pt[1] - poly2d[:, 1]) - (q[:, 1] - poly2d[:, 1]) * (pt[0] - poly2d[:, 0])
    return bool((c > 0).all() or (c < 0).all())


def coverage(polys, axes, points):
    """How many of the polygons (projected on ``axes``) hold each point."""
    return np.array([sum(covers(p[:, axes], pt) for p in polys) for pt in points])


# --- F 3 with sub-surfaces, a mask, a null surface, combine and an obstruction ----------


def test_room_surfaces_areas_and_flags():
    d = nio.read_scene(DATA / "room_subsurfaces.vs3")
    assert d.names == [
        "floor",
        "ceiling",
        "west",
        "east",
        "south",
        "window",
        "door",
        "north",
        "north_mask",
        "obstruction12",
    ]
    a = surface_areas(d)
    expect = {
        "floor": 30,
        "ceiling": 30,
        "west": 15,
        "east": 15,  # east = 7.5 + combined 7.5
        "south": 18 - 2 - 2,  # minus window and door
        "window": 2,
        "door": 2,
        "north": 18 - 1 - 1.5,  # minus the hole and the mask
        "north_mask": 1.5,
        "obstruction12": 1.5,
    }
    for k, v in expect.items():
        assert a[k] == pytest.approx(v, rel=1e-13, abs=1e-12), k
    obst = [d.names[s] for s, o in zip(d.surface, d.obstruction) if o]
    assert obst == ["obstruction12"]
    np.testing.assert_array_equal(d.emissivity[:-1], [0.9, 0.8, 0.9, 0.7, 0.9, 0.84, 0.6, 0.9, 0.9])
    assert np.isnan(d.emissivity[-1])
    assert d.meta["format"] == "view3d" and d.meta["geometry"] == "3"
    assert d.meta["encl"] == 0 and d.meta["emit"] == 1 and d.meta["eps"] == 1e-5 and d.meta["list"] == 1
    assert d.meta["title"].startswith("wall, the east wall in two parts")  # the last T record
    kinds = [s["kind"] for s in d.meta["surfaces"]]
    assert kinds == list("SSSSSSSSSNMO")
    assert d.meta["surfaces"][4]["cmb"] == 4 and d.meta["surfaces"][6]["base"] == 6
    assert d.meta["surface_numbers"] == [1, 2, 3, 4, 6, 7, 8, 9, 11, 12]
    # The combined surface keeps its own polygon, in the named surface of its target.
    east = [p for s, p in zip(d.surface, d.polygons) if d.names[s] == "east"]
    assert len(east) == 2


def test_room_base_polygons_tile_the_wall_exactly_once():
    d = nio.read_scene(DATA / "room_subsurfaces.vs3")
    by = {n: [p for s, p in zip(d.surface, d.polygons) if d.names[s] == n] for n in d.names}
    # South wall (y = 0): base pieces, window and door cover each point exactly once.
    grid = [(x, z) for x in np.arange(0.05, 6, 0.1) for z in np.arange(0.05, 3, 0.1)]
    for p in by["south"]:
        assert np.allclose(p[:, 1], 0) and newell(p)[1] > 0  # in the plane, facing +y like the base
    cov = coverage(by["south"] + by["window"] + by["door"], [0, 2], grid)
    assert (cov == 1).all()
    in_holes = coverage(by["window"] + by["door"], [0, 2], grid)
    assert (coverage(by["south"], [0, 2], grid) == 1 - in_holes).all()
    # North wall (y = 5): the null surface is a hole (nothing there), the mask is its own surface.
    for p in by["north"]:
        assert np.allclose(p[:, 1], 5) and newell(p)[1] < 0
    (mask,) = by["north_mask"]
    assert newell(mask)[1] > 0  # masks face away from the base's front (View3D convention)
    hole = np.array([[1, 1], [1, 2], [2, 2], [2, 1]], dtype=float)
    for pt, c in zip(grid, coverage(by["north"] + by["north_mask"], [0, 2], grid)):
        assert c == (0 if covers(hole, np.array(pt)) else 1), pt


def test_crlf_and_trailing_comments(tmp_path):
    text = (DATA / "room_subsurfaces.vs3").read_bytes()
    p = tmp_path / "crlf.vs3"
    p.write_bytes(text.replace(b"\n", b"\r\n"))
    a, b = nio.read_scene(DATA / "room_subsurfaces.vs3"), nio.read_scene(p)
    assert a.names == b.names and np.array_equal(a.vertices, b.vertices)
    q = tmp_path / "comments.vs3"
    q.write_text(
        "T title\nc encl=1 ! a comment\nf 3 / comment\nv 1 0 0 0 ! one\nV 2 1 0 0\nV 3 1 1 0\n"
        "s 1 1 2 3 0 0 0 0.5 tri / triangle: v4 = 0\n*\nnot read\n"
    )
    d = nio.read_scene(q)
    assert d.names == ["tri"] and d.faces[0].size == 3 and d.meta["encl"] == 1
    np.testing.assert_array_equal(d.polygons[0], [[0, 0, 0], [1, 0, 0], [1, 1, 0]])


# --- F 3a local shapes --------------------------------------------------------------------


def test_f3a_rectangles_quads_and_triangles_against_hand_computed_vertices():
    d = nio.read_scene(DATA / "shapes_3a.vs3")
    assert d.meta["geometry"] == "3a"
    poly = {}
    for s, p in zip(d.surface, d.polygons):
        poly.setdefault(d.names[s], []).append(p)
    r3 = math.sqrt(3.0)
    # azimuth 0, tilt 90 (facing north, +y); local x runs to -x, local y up:
    # R w=2 h=1 at (-1, 0, 1) -> corners (0,h), (0,0), (w,0), (w,h).
    expect = {
        "window": [(-1, 0, 2), (-1, 0, 1), (-3, 0, 1), (-3, 0, 2)],
        # azimuth 90 (facing east, +x), tilt 90, at (1, 2, 0), w=2 h=1
        "wall_east": [(1, 2, 1), (1, 2, 0), (1, 4, 0), (1, 4, 1)],
        # azimuth 0, tilt 0 (facing up): local x -> -x, local y -> -y; at (0, 0, 2), w=2 h=3
        "floor": [(0, -3, 2), (0, 0, 2), (-2, 0, 2), (-2, -3, 2)],
        # azimuth 180, tilt 180 (facing down): local x -> +x, local y -> -y; at (0, 0, 3), 1 x 1
        "ceiling": [(0, -1, 3), (0, 0, 3), (1, 0, 3), (1, -1, 3)],
        # Q, azimuth 0, tilt 0 at the origin: (0,0) (2,0) (2,1) (0,1)
        "quad": [(0, 0, 0), (-2, 0, 0), (-2, -1, 0), (0, -1, 0)],
        # T, azimuth 90, tilt 90: local x -> +y, local y -> +z
        "tri": [(0, 0, 0), (0, 3, 0), (0, 0, 2)],
        # O, azimuth 0 tilt 90 at (5, 5, 0), 1 x 1
        "obstruction9": [(5, 5, 1), (5, 5, 0), (4, 5, 0), (4, 5, 1)],
    }
    for name, v in expect.items():
        (p,) = poly[name]
        np.testing.assert_allclose(p, np.array(v, dtype=float), atol=1e-15, err_msg=name)
    # azimuth 30, tilt 60 at (1, 2, 3), w=2 h=1, written out by hand with sqrt(3):
    # e_x = (-cos30, sin30, 0) = (-r3/2, 1/2, 0); e_y = (-cos60 sin30, -cos60 cos30, sin60)
    #     = (-1/4, -r3/4, r3/2); corners o + x e_x + y e_y for (0,1), (0,0), (2,0), (2,1).
    o = np.array([1.0, 2.0, 3.0])
    ex, ey = np.array([-r3 / 2, 0.5, 0.0]), np.array([-0.25, -r3 / 4, r3 / 2])
    (p,) = poly["slanted"]
    np.testing.assert_allclose(p, [o + ey, o, o + 2 * ex, o + 2 * ex + ey], atol=1e-14)
    n = newell(p) / area(p)
    # outward normal: horizontal part points to azimuth 30 (clockwise from +y), n_z = cos(tilt)
    np.testing.assert_allclose(
        n, [math.sin(math.radians(60)) * 0.5, math.sin(math.radians(60)) * r3 / 2, 0.5], atol=1e-14
    )
    assert area(p) == pytest.approx(2.0, rel=1e-14)
    # facing directions of the axis-aligned cases
    facing = {"wall_east": [1, 0, 0], "floor": [0, 0, 1], "ceiling": [0, 0, -1], "quad": [0, 0, 1], "tri": [1, 0, 0]}
    for name, f in facing.items():
        (p,) = poly[name]
        np.testing.assert_allclose(newell(p) / area(p), f, atol=1e-15)


def test_f3a_sub_surface_area_is_removed_from_its_base():
    d = nio.read_scene(DATA / "shapes_3a.vs3")
    a = surface_areas(d)
    assert a["wall_north"] == pytest.approx(4 * 3 - 2 * 1, rel=1e-14)
    assert a["window"] == pytest.approx(2.0, rel=1e-14)
    wall = [p for s, p in zip(d.surface, d.polygons) if d.names[s] == "wall_north"]
    win = [p for s, p in zip(d.surface, d.polygons) if d.names[s] == "window"]
    grid = [(x, z) for x in np.arange(-3.95, 0, 0.1) for z in np.arange(0.05, 3, 0.1)]
    assert (coverage(wall + win, [0, 2], grid) == 1).all()
    for p in wall:
        assert newell(p)[1] > 0 and np.allclose(p[:, 1], 0)


def test_f3a_geometry_may_span_several_lines(tmp_path):
    p = tmp_path / "split.vs3"
    p.write_text("F 3a\nS 1 T 0 0 0.9 t\n 0 0 0\n 90\n 90 0 0\n 3 0 0 2\nE\n")
    d = nio.read_scene(p)
    np.testing.assert_allclose(d.polygons[0], [[0, 0, 0], [0, 3, 0], [0, 0, 2]], atol=1e-15)


# --- errors -------------------------------------------------------------------------------

HEAD = "T test\nF 3\nV 1 0 0 0\nV 2 1 0 0\nV 3 1 1 0\nV 4 0 1 0\n"  # lines 1-6
SQ = "S 1 1 2 3 4 0 0 0.9 floor\n"  # line 7

BAD = [
    (HEAD.replace("F 3\n", "") + SQ.replace("S 1", "S 1"), None, "missing F record"),
    (HEAD.replace("F 3", "F 2") + SQ, 2, "unsupported geometry form 'F 2'"),
    (HEAD + "S 1 1 2 3 9 0 0 0.9 floor\n", 7, "surface 1 refers to vertex 9, but only 4 vertices are defined"),
    (HEAD + "S 1 1 0 3 4 0 0 0.9 floor\n", 7, "vertex number 0"),
    (HEAD.replace("V 3 1 1 0", "V 2 1 1 0"), 5, "vertex 2 is defined twice (first on line 4)"),
    (HEAD.replace("V 3 1 1 0", "V 5 1 1 0"), 5, "vertex 5 out of sequence: expected vertex 3"),
    (HEAD.replace("V 3 1 1 0", "V 3 1 x 0"), 5, "coordinate of vertex 3 must be a number, got 'x'"),
    (HEAD.replace("V 3 1 1 0", "V 3 1 inf 0"), 5, "must be finite"),
    (HEAD.replace("V 3 1 1 0", "V 3 1 1"), 5, "a vertex record needs 'V n x y z'"),
    (HEAD + SQ + "Q 2 1 2 3\n", 8, "unknown record 'Q'"),
    (HEAD + SQ + "S 1 1 2 3 4 0 0 0.9 again\n", 8, "surface 1 is defined twice (first on line 7)"),
    (HEAD + SQ + "S 3 1 2 3 4 0 0 0.9 three\n", 8, "surface 3 out of sequence: expected surface 2"),
    (HEAD + "O 1 1 2 3 4\nS 2 1 2 3 4 0 0 0.9 late\n", 8, "comes after obstruction surface 1 (line 7)"),
    (HEAD + "S 1 1 2 3 4 0 0 1.5 floor\n", 7, "emissivity 1.5 is outside [0, 1]"),
    (HEAD + "S 1 1 2 3 4 0 0 high floor\n", 7, "emissivity of surface 1 must be a number"),
    (HEAD + "S 1 1 2 3 4 0 0\n", 7, "expected 'S n v1 v2 v3 v4 base cmb emit name'"),
    (HEAD + SQ + "S 2 1 2 3 4 7 0 0.9 sub\n", 8, "base surface 7 does not exist"),
    (HEAD + "S 1 1 2 3 4 2 0 0.9 a\nS 2 1 2 3 4 0 0 0.9 b\n", 7, "must come after its base surface 2"),
    (HEAD + SQ + "N 2 4 3 2 1 0 0 0.9 hole\n", 8, "null surface 2 needs a base surface"),
    (HEAD + SQ + "S 2 1 2 3 4 0 1 0.9 b\nS 3 1 2 3 4 0 2 0.9 c\n", 9, "itself combined into surface 1"),
    (HEAD + SQ + "S 2 1 2 3 4 0 2 0.9 b\n", 8, "must combine with a previous surface"),
    (HEAD + SQ + "M 2 4 3 2 1 1 1 0.9 m\n", 8, "cannot be combined"),
    (
        HEAD + "V 5 2 0 0\nV 6 2 1 0\n" + "S 1 1 2 3 4 0 0 0.9 floor\nS 2 2 5 6 3 1 0 0.9 out\n",
        10,
        "sub-surface 2 is not inside its base surface 1",
    ),
    (
        HEAD + "V 5 0.2 0.2 0.5\nV 6 0.8 0.2 0.5\nV 7 0.8 0.8 0.5\nV 8 0.2 0.8 0.5\n" + "S 1 1 2 3 4 0 0 0.9 f\n"
        "S 2 5 6 7 8 1 0 0.9 up\n",
        12,
        "not in the plane of its base surface 1",
    ),
    (
        HEAD + "V 5 0.2 0.2 0\nV 6 0.8 0.2 0\nV 7 0.8 0.8 0\nV 8 0.2 0.8 0\n" + "S 1 1 2 3 4 0 0 0.9 f\n"
        "S 2 8 7 6 5 1 0 0.9 w\n",
        12,
        "sub-surface 2 must face the same way as its base 1",
    ),
    (
        HEAD + "V 5 0.2 0.2 0\nV 6 0.8 0.2 0\nV 7 0.8 0.8 0\nV 8 0.2 0.8 0\n" + "S 1 1 2 3 4 0 0 0.9 f\n"
        "M 2 5 6 7 8 1 0 0.9 m\n",
        12,
        "mask surface 2 must face the opposite way",
    ),
    (
        HEAD + "V 5 0.2 0.2 0\nV 6 0.8 0.2 0\nV 7 0.8 0.8 0\nV 8 0.2 0.8 0\n" + "S 1 1 2 3 4 0 0 0.9 f\n"
        "S 2 5 6 7 8 1 0 0.9 a\nS 3 5 6 7 0 1 0 0.9 b\n",
        13,
        "sub-surface 3 overlaps sub-surface 2 on the same base 1",
    ),
    ("C eps\nF 3\n", 1, "control 'eps' has no value"),
    ("C encl=yes\nF 3\n", 1, "control encl must be an integer, got 'yes'"),
    ("F 3a\nV 1 0 0 0\n", 2, "V records are not used with 'F 3a'"),
    ("F 3a\nS 1 X 0 0 0.9 a\n 0 0 0 0 90 1 1\n", 2, "unknown shape 'X'"),
    (
        "F 3a\nS 1 Q 0 0 0.9 a\n 0 0 0 0 90\n 0 0 1 0 1 1\nS 2 R 0 0 0.9 b\n 0 0 0 0 0 1 1\n",
        5,
        "surface 1 (shape Q, line 2) needs 13 numbers",
    ),
    ("F 3a\nS 1 R 0 0 0.9 a\n 0 0 0 0\n", 2, "the file ends first"),
]


@pytest.mark.parametrize("text,line,problem", BAD)
def test_malformed_vs3_names_file_and_line(tmp_path, text, line, problem):
    p = tmp_path / "bad.vs3"
    p.write_text(text)
    with pytest.raises(ValueError) as e:
        nio.read_scene(p)
    msg = str(e.value)
    head = f"{p}, line {line}: " if line else f"{p}: "
    assert msg.startswith(head), msg
    assert problem in msg, msg
    assert "\n" not in msg


def test_file_level_errors(tmp_path):
    for text, problem in [
        ("", "the file is empty"),
        ("! only a comment\n/ and another\n", "no View3D records"),
        ("E\nS 1 1 2 3 4 0 0 0.9 a\n", "no View3D records"),
        ("F 3\nV 1 0 0 0\n", "no surfaces"),
    ]:
        p = tmp_path / "f.vs3"
        p.write_text(text)
        with pytest.raises(ValueError, match=problem) as e:
            nio.read_scene(p)
        assert str(e.value).startswith(f"{p}: ")
    with pytest.raises(OSError, match="nope.vs3: no such file"):
        nio.read_scene(tmp_path / "nope.vs3")


def test_list_control_is_accepted_silently_and_eps_still_warns(tmp_path):
    # `list` only sets the detail of View3D's log (most files EnergyPlus's tools write say
    # list=1): no warning for it, at any level; a control that would change View3D's numbers
    # still says it is ignored.
    import warnings

    body = "F 3\nV 1 0 0 0\nV 2 1 0 0\nV 3 1 1 0\nV 4 0 1 0\nS 1 1 2 3 4 0 0 0.9 floor\nE\n"
    for level in (0, 1, 2):
        p = tmp_path / f"list{level}.vs3"
        p.write_text(f"C encl=0 list={level}\n" + body)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            d = nio.read_scene(p)
        assert d.meta["list"] == level
    p = tmp_path / "eps.vs3"
    p.write_text("C list=1 eps=1e-4\n" + body)
    with pytest.warns(UserWarning) as w:
        nio.read_scene(p)
    assert [str(x.message).split(": ", 1)[1] for x in w][0].startswith("control eps=1e-4 ignored")
    assert len(w) == 1
