"""Mesh formats through meshio: polygons kept, surface names from physical groups, cell sets,
cell data, STL solids or cell blocks; 3-D cells refused; errors name the file."""

import pathlib

import meshio
import numpy as np
import pytest

import nusselt.io as nio

DATA = pathlib.Path(__file__).parent / "data"

PTS = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 1.5, 0], [2, 0, 0], [2, 1, 0]], dtype=float)


def test_ascii_stl_solid_names():
    d = nio.read_scene(DATA / "two_solids.stl")
    assert d.names == ["floor", "roof"]
    assert d.surface.tolist() == [0, 0, 1]
    assert d.meta["names_from"] == "stl solids"
    np.testing.assert_array_equal(d.polygons[2], [[0, 0, 1], [1, 1, 1], [1, 0, 1]])


def test_binary_stl_is_one_block(tmp_path):
    p = tmp_path / "b.stl"
    meshio.write(p, meshio.Mesh(PTS, [("triangle", np.array([[0, 1, 2], [0, 2, 3]]))]), binary=True)
    d = nio.read_scene(p)
    assert d.names == ["block0"] and len(d.faces) == 2
    np.testing.assert_allclose(d.polygons[1], PTS[[0, 2, 3]])


def test_gmsh_physical_names_quads_kept_lines_and_volumes_skipped():
    d = nio.read_scene(DATA / "physical.msh")
    assert d.names == ["floor", "wall"]
    assert [f.size for f in d.faces] == [3, 3, 4]
    assert d.surface.tolist() == [0, 0, 1]
    np.testing.assert_array_equal(d.polygons[2], [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]])
    assert d.meta["skipped_volume_cells"] == {"tetra": 1}
    assert d.meta["skipped_cells"] == {"line": 1, "vertex": 1}
    # origins count every cell of the file in meshio's block order (ParaView's cell ids)
    assert d.origin[0].startswith("cell ")


def test_abaqus_element_sets_smallest_set_wins():
    d = nio.read_scene(DATA / "elsets.inp")
    assert d.names == ["BOTTOM", "SIDES"]  # the catch-all ALL set does not swallow them
    assert sorted(f.size for f in d.faces) == [3, 3, 4]
    for s, f in zip(d.surface, d.faces):
        assert (f.size == 4) == (d.names[s] == "BOTTOM")


@pytest.mark.parametrize("ext", ["vtu", "vtk"])
def test_vtk_polygons_and_material_ids(tmp_path, ext):
    cells = [
        ("triangle", np.array([[1, 5, 6]])),
        ("quad", np.array([[0, 1, 2, 3]])),
        ("polygon", np.array([[0, 1, 2, 4, 3]])),
        ("line", np.array([[0, 1]])),
    ]
    mat = [np.array([7]), np.array([3]), np.array([7]), np.array([1])]
    p = tmp_path / f"m.{ext}"
    meshio.write(p, meshio.Mesh(PTS, cells, cell_data={"MaterialIds": mat}))
    d = nio.read_scene(p)
    assert [f.size for f in d.faces] == [3, 4, 5]  # the pentagon stays a pentagon
    assert d.names == ["material7", "material3"]
    assert d.surface.tolist() == [0, 1, 0]
    assert d.origin == ["cell 0", "cell 1", "cell 2"]


def test_cell_tags_and_ply(tmp_path):
    p = tmp_path / "t.vtu"
    meshio.write(
        p,
        meshio.Mesh(
            PTS, [("quad", np.array([[0, 1, 2, 3], [1, 5, 6, 2]]))], cell_data={"cell_tags": [np.array([2, 5])]}
        ),
    )
    d = nio.read_scene(p)
    assert d.names == ["tag2", "tag5"]
    q = tmp_path / "q.ply"
    meshio.write(q, meshio.Mesh(PTS, [("quad", np.array([[0, 1, 2, 3], [1, 5, 6, 2]]))]), binary=False)
    d = nio.read_scene(q)
    assert [f.size for f in d.faces] == [4, 4] and d.names == ["block0"]


def test_volume_only_mesh_is_refused(tmp_path):
    p = tmp_path / "tet.vtu"
    pts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    meshio.write(p, meshio.Mesh(pts, [("tetra", np.array([[0, 1, 2, 3]]))]))
    with pytest.raises(ValueError) as e:
        nio.read_scene(p)
    msg = str(e.value)
    assert msg.startswith(f"{p}: ") and "1 tetra" in msg and "boundary surface" in msg and "\n" not in msg


def test_malformed_meshes_name_the_file(tmp_path):
    # out-of-range point index in a legacy VTK file: the cell is named
    p = tmp_path / "bad.vtk"
    p.write_text(
        "# vtk DataFile Version 4.2\nbad\nASCII\nDATASET UNSTRUCTURED_GRID\n"
        "POINTS 3 double\n0 0 0\n1 0 0\n0 1 0\n"
        "CELLS 2 8\n3 0 1 2\n3 0 1 7\nCELL_TYPES 2\n5\n5\n"
    )
    with pytest.raises(ValueError) as e:
        nio.read_scene(p)
    assert str(e.value).startswith(f"{p}, cell 1: refers to point 7, but only 3 points are defined")
    # NaN coordinate
    q = tmp_path / "nan.vtk"
    q.write_text(
        "# vtk DataFile Version 4.2\nbad\nASCII\nDATASET UNSTRUCTURED_GRID\n"
        "POINTS 3 double\n0 0 0\nnan 0 0\n0 1 0\nCELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n"
    )
    with pytest.raises(ValueError, match=r"nan\.vtk, point 1: NaN or infinite"):
        nio.read_scene(q)
    # garbage that meshio cannot parse
    g = tmp_path / "junk.msh"
    g.write_text("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\nthree\n")
    with pytest.raises(ValueError) as e:
        nio.read_scene(g)
    assert str(e.value).startswith(f"{g}: cannot read the mesh") and "\n" not in str(e.value)
    # no surface cells at all
    lines = tmp_path / "lines.vtu"
    meshio.write(lines, meshio.Mesh(PTS, [("line", np.array([[0, 1]]))]))
    with pytest.raises(ValueError, match="no triangles, quads or polygons"):
        nio.read_scene(lines)
    # unknown extension, empty file, missing file
    u = tmp_path / "scene.xyz"
    u.write_text("1 2 3\n")
    with pytest.raises(ValueError, match=r"scene\.xyz: unknown file extension \.xyz"):
        nio.read_scene(u)
    e0 = tmp_path / "empty.ply"
    e0.write_text("")
    with pytest.raises(ValueError, match=r"empty\.ply: the file is empty"):
        nio.read_scene(e0)
    with pytest.raises(OSError, match="gone.stl: no such file"):
        nio.read_scene(tmp_path / "gone.stl")


def test_format_override(tmp_path):
    p = tmp_path / "mesh.dat"
    meshio.write(p, meshio.Mesh(PTS, [("triangle", np.array([[0, 1, 2]]))]), file_format="vtu")
    d = nio.read_scene(p, format="vtu")
    assert len(d.faces) == 1
    o = tmp_path / "obj.txt"
    o.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\no t\nf 1 2 3\n")
    assert nio.read_scene(o, format="obj").names == ["t"]
