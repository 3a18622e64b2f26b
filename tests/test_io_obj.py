"""OBJ reader: objects/groups as surfaces, face forms, negative indices, errors."""

import pathlib

import numpy as np
import pytest

import nusselt.io as nio

DATA = pathlib.Path(__file__).parent / "data"


def newell(p):
    return 0.5 * np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)


def test_cube_room_names_and_faces():
    d = nio.read_scene(DATA / "cube_room.obj")
    assert d.names == ["floor", "ceiling", "south", "east", "north", "west"]
    assert d.surface.tolist() == [0, 1, 2, 3, 4, 5]
    assert all(f.size == 4 for f in d.faces)  # quads stay quads
    assert not d.obstruction.any() and d.emissivity is None
    # v/vt/vn, v//vn, v/vt, plain v with a continuation line, and negative indices.
    expect = {
        "floor": [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)],
        "ceiling": [(0, 0, 1), (0, 1, 1), (1, 1, 1), (1, 0, 1)],
        "south": [(0, 0, 0), (0, 0, 1), (1, 0, 1), (1, 0, 0)],
        "east": [(1, 0, 0), (1, 0, 1), (1, 1, 1), (1, 1, 0)],
        "north": [(1, 1, 0), (1, 1, 1), (0, 1, 1), (0, 1, 0)],
        "west": [(0, 0, 0), (0, 1, 0), (0, 1, 1), (0, 0, 1)],
    }
    for name, poly in zip(d.names, d.polygons):
        np.testing.assert_array_equal(poly, np.array(expect[name], dtype=float))
        # every front faces the room's centre: the vertex order was kept
        assert newell(poly) @ (np.full(3, 0.5) - poly.mean(axis=0)) > 0
    lines = (DATA / "cube_room.obj").read_text().splitlines()
    assert d.origin[3] == f"line {lines.index('g east') + 2}"  # first line of the continued face
    assert d.meta["format"] == "obj" and d.source.endswith("cube_room.obj")


def test_crlf_and_lf_give_the_same_scene(tmp_path):
    text = (DATA / "cube_room.obj").read_bytes()
    p = tmp_path / "crlf.obj"
    p.write_bytes(text.replace(b"\n", b"\r\n"))
    a, b = nio.read_scene(DATA / "cube_room.obj"), nio.read_scene(p)
    assert a.names == b.names
    np.testing.assert_array_equal(a.vertices, b.vertices)
    assert all((fa == fb).all() for fa, fb in zip(a.faces, b.faces))


def test_default_surface_groups_and_usemtl(tmp_path):
    p = tmp_path / "g.obj"
    p.write_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
        "f 1 2 3\n"  # before any name
        "usemtl red\nf 1 3 4\n"  # usemtl is not a surface
        "g wall left\nf -4 -2 -1\n"
        "o box\ng\nf 2 3 4\n"  # a bare g: back to default
        "o wall left\nf 4 3 2\n"
    )
    d = nio.read_scene(p)
    assert d.names == ["default", "wall left"]
    assert d.surface.tolist() == [0, 0, 1, 0, 1]
    np.testing.assert_array_equal(d.faces[2], [0, 2, 3])


def test_negative_indices_are_relative_to_the_vertices_read_so_far(tmp_path):
    p = tmp_path / "neg.obj"
    p.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nv 6 5 5\nf -5 -2 -1\n")
    d = nio.read_scene(p)
    np.testing.assert_array_equal(d.faces[0], [0, 1, 2])
    np.testing.assert_array_equal(d.faces[1], [0, 3, 4])


def test_polygons_with_many_vertices_are_kept(tmp_path):
    ang = np.linspace(0, 2 * np.pi, 7)[:-1]
    p = tmp_path / "hex.obj"
    p.write_text(
        "".join(f"v {float(np.cos(a))!r} {float(np.sin(a))!r} 0\n" for a in ang) + "o hexagon\nf 1 2 3 4 5 6\n"
    )
    d = nio.read_scene(p)
    assert d.faces[0].tolist() == list(range(6)) and d.names == ["hexagon"]


BAD = [
    ("v 0 0\n", 1, "a vertex needs x y z"),
    ("v 0 0 0\nv 0 1.5.2 0\n", 2, "bad number in vertex"),
    ("v 0 0 nan\n", 1, "NaN or infinite"),
    ("v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "at least 3 vertices"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", 4, "refers to vertex 9, but only 3 vertices are defined"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -5\n", 4, "refers to vertex -5 (relative), but only 3 vertices"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "vertex index 0"),
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 a 2\n", 4, "bad vertex index 'a'"),
    ("v 0 0 0\nvx 1 2 3\n", 2, "unknown OBJ statement 'vx'"),
    ("v 0 0 0\ncurv 0 1 1 2\n", 2, "free-form geometry"),
]


@pytest.mark.parametrize("text,line,problem", BAD)
def test_malformed_obj_names_file_and_line(tmp_path, text, line, problem):
    p = tmp_path / "bad.obj"
    p.write_text(text)
    with pytest.raises(ValueError) as e:
        nio.read_scene(p)
    msg = str(e.value)
    assert msg.startswith(f"{p}, line {line}: "), msg
    assert problem in msg and "\n" not in msg


def test_file_level_errors(tmp_path):
    empty = tmp_path / "empty.obj"
    empty.write_text("")
    with pytest.raises(ValueError, match=r"empty\.obj: the file is empty"):
        nio.read_scene(empty)
    only_v = tmp_path / "v.obj"
    only_v.write_text("# just points\nv 0 0 0\nv 1 0 0\n")
    with pytest.raises(ValueError, match=r"v\.obj: no faces"):
        nio.read_scene(only_v)
    binary = tmp_path / "bin.obj"
    binary.write_bytes(b"\x00\x01\x02" * 40)
    with pytest.raises(ValueError, match="binary"):
        nio.read_scene(binary)
    missing = tmp_path / "missing.obj"
    with pytest.raises(OSError, match="missing.obj: no such file"):
        nio.read_scene(missing)
    with pytest.raises(OSError, match="is a directory"):
        nio.read_obj(tmp_path)
