"""Files cut short are refused, skipped cells are counted (issue 23, item 7)."""

from pathlib import Path

import meshio
import numpy as np
import pytest
from conftest import cube_faces

import nusselt
from nusselt.io.scenedata import SkippedCellsWarning

DATA = Path(__file__).parent / "data"


def cube_mesh():
    polys, _ = cube_faces(1)
    tris = []
    for p in polys:
        tris += [p[[0, 1, 2]], p[[0, 2, 3]]]
    pts = np.concatenate(tris)
    return meshio.Mesh(pts, [("triangle", np.arange(len(pts)).reshape(-1, 3))])


def test_ascii_stl_cut_after_a_facet_is_refused(tmp_path):
    full = tmp_path / "cube.stl"
    meshio.write(full, cube_mesh(), binary=False)
    assert len(nusselt.Scene.from_file(full)) == 12
    text = full.read_text()
    cut = tmp_path / "cut.stl"
    at = [i for i in range(len(text)) if text.startswith("endfacet\n", i)][6] + len("endfacet\n")
    cut.write_text(text[:at])  # 7 whole facets, no endsolid: meshio reads 7 of 12
    with pytest.raises(ValueError, match=r"cut.stl: truncated: the ASCII STL file does not end with 'endsolid'"):
        nusselt.io.read_scene(cut)
    ok = tmp_path / "ok.stl"
    ok.write_text(text.rstrip("\n"))  # no final newline is not a cut
    assert len(nusselt.io.read_scene(ok).faces) == 12


def test_binary_stl_cut_is_refused_with_counts(tmp_path):
    full = tmp_path / "cube.stl"
    meshio.write(full, cube_mesh(), binary=True)
    raw = full.read_bytes()
    cut = tmp_path / "cutb.stl"
    cut.write_bytes(raw[: 84 + 50 * 7 + 20])
    with pytest.raises(
        ValueError,
        match=r"cutb.stl: truncated: the binary STL header declares 12 triangles "
        r"\(684 bytes\), the file has 454 bytes \(7 whole triangles\)",
    ):
        nusselt.io.read_scene(cut)


def test_vs3_cut_at_a_record_is_refused(tmp_path):
    text = (DATA / "room_subsurfaces.vs3").read_text().splitlines()
    end = next(i for i, t in enumerate(text) if t.strip().upper().startswith("E"))
    first_s = next(i for i, t in enumerate(text) if t.startswith("S "))
    cut = tmp_path / "cut.vs3"
    cut.write_text("\n".join(text[: first_s + 5]) + "\n")  # 5 surfaces, then nothing
    with pytest.raises(
        ValueError,
        match=r"cut.vs3: the file ends without its end-of-data record .* after 5 "
        r"surfaces .* it looks truncated",
    ):
        nusselt.io.read_scene(cut)
    assert end > first_s + 5


def test_skipped_cells_are_counted_in_a_warning(tmp_path):
    m = cube_mesh()
    lines = np.array([[0, 1], [1, 2]])
    tet = np.array([[0, 1, 2, 4]])
    mesh = meshio.Mesh(m.points, [("triangle", m.cells[0].data), ("line", lines), ("tetra", tet)])
    p = tmp_path / "mixed.vtu"
    meshio.write(p, mesh)
    with pytest.warns(
        SkippedCellsWarning,
        match=r"mixed.vtu: skipped 3 cells that are not surfaces "
        r"\(2 line, 1 tetra\); read 12 surface cells",
    ):
        d = nusselt.io.read_scene(p)
    assert len(d.faces) == 12 and d.meta["skipped_cells"] == {"line": 2}
