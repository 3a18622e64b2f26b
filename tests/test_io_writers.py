"""Result writers: npz round trip, CSV, View3D text, EnergyPlus IDF, VTU, dispatch."""

import csv
import pathlib
import types

import meshio
import numpy as np
import pytest
import scipy.sparse as sp

import nusselt.io as nio
from nusselt.result import FormFactors

DATA = pathlib.Path(__file__).parent / "data"


def sample(n=4, seed=1):
    """A reciprocal matrix: G symmetric, F = G / A (row = source), with some exact zeros."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.5, 2.0, n)
    g = rng.uniform(0, 0.1, (n, n))
    g = g + g.T
    np.fill_diagonal(g, 0)
    g[0, n - 1] = g[n - 1, 0] = 0
    g *= 0.9 / (g / a[:, None]).sum(axis=1).max()  # rows sum to at most 0.9
    return g / a[:, None], a


def test_npz_round_trip_sparse_dense_and_extras(tmp_path):
    f, a = sample(5)
    names = ["floor", "ceiling", "wall, east", "wäll", "x"]
    std = sp.csr_array(f * 1e-3)
    p = tmp_path / "r.npz"
    nio.write_npz(
        p,
        sp.csr_array(f),
        a,
        names,
        std_err=std,
        faces=np.arange(5),
        method=np.array("auto"),
        info={"options": {"n": 3}},
    )
    r = nio.load_npz(p)
    assert isinstance(r["matrix"], sp.csr_array)
    np.testing.assert_array_equal(r["matrix"].toarray(), f)
    assert r["matrix"].nnz == np.count_nonzero(f)
    np.testing.assert_array_equal(r["areas"], a)
    assert r["names"] == names
    assert isinstance(r["std_err"], sp.csr_array)
    np.testing.assert_array_equal(r["std_err"].toarray(), f * 1e-3)
    np.testing.assert_array_equal(r["faces"], np.arange(5))
    assert str(r["method"]) == "auto" and r["info"] == {"options": {"n": 3}}
    assert r["version"] == 1
    # dense input gives the same file content
    q = tmp_path / "d.npz"
    nio.write_npz(q, f, a, names)
    np.testing.assert_array_equal(nio.load_npz(q)["matrix"].toarray(), f)
    # a path without the .npz extension is written as given (np.savez would append .npz)
    s = tmp_path / "out.data"
    nio.write_npz(s, f, a, names)
    assert s.exists() and not (tmp_path / "out.data.npz").exists()
    assert not list(tmp_path.glob(".nusselt-*"))  # no temporary files left


@pytest.mark.parametrize("compress", [False, True])
@pytest.mark.parametrize("past_the_cache", [False, True])
def test_npz_holds_what_np_savez_writes(tmp_path, monkeypatch, compress, past_the_cache):
    """The writer streams each array into the zip itself (np.savez copied every 16 MiB) and a
    big file past the page cache: the arrays read back are np.savez's, dtype and shape too."""
    from nusselt.io import direct
    from nusselt.io.writers import npz

    monkeypatch.setattr(npz, "MIN_BYTES", 0 if past_the_cache else 1 << 60)
    monkeypatch.setattr(npz, "CHUNK", 4096)  # arrays in several pieces
    monkeypatch.setattr(direct, "CHUNK", 8192)
    rng = np.random.default_rng(3)
    m = sp.random_array((300, 300), density=0.2, format="csr", rng=rng)
    p = tmp_path / "r.npz"
    nio.write_npz(p, m, rng.uniform(1, 2, 300), [f"p{k}" for k in range(300)], compress=compress, info={"a": 1})
    np.savez(tmp_path / "ref.npz", **dict(np.load(p)))
    with np.load(p) as ours, np.load(tmp_path / "ref.npz") as ref:
        assert ours.files == ref.files
        for k in ref.files:
            assert ours[k].dtype == ref[k].dtype and ours[k].shape == ref[k].shape, k
            np.testing.assert_array_equal(ours[k], ref[k])
    r = nio.load_npz(p)
    assert (r["matrix"] != m).nnz == 0 and r["info"] == {"a": 1}
    assert __import__("zipfile").ZipFile(p).testzip() is None  # every CRC right


@pytest.mark.parametrize("way", ["direct", "no O_DIRECT", "refused at write"])
@pytest.mark.parametrize("size", [0, 1, 4095, 8192, 8193, 3 * 8192 + 5])
def test_direct_writer_writes_the_bytes_given(tmp_path, monkeypatch, way, size):
    import errno
    import os

    from nusselt.io import direct

    monkeypatch.setattr(direct, "CHUNK", 8192)
    if way == "no O_DIRECT":
        monkeypatch.delattr(os, "O_DIRECT", raising=False)
    elif way == "refused at write":
        real, calls = os.write, []

        def write(fd, data):
            calls.append(1)
            if len(calls) == 1:
                raise OSError(errno.EINVAL, "Invalid argument")
            return real(fd, data)

        monkeypatch.setattr(direct.os, "write", write)
    data = np.random.default_rng(size).integers(0, 256, size, dtype=np.uint8).tobytes()
    p = tmp_path / "f.bin"
    p.write_bytes(b"old content, longer than some of the sizes" * 500)
    w = direct.DirectWriter(p)
    for s in range(0, size, 3000):  # pieces of another size than the chunks
        assert w.write(data[s : s + 3000]) == len(data[s : s + 3000])
        assert w.tell() == min(s + 3000, size)
    w.close()
    w.close()
    assert p.read_bytes() == data


def test_npz_errors(tmp_path):
    f, a = sample(3)
    with pytest.raises(ValueError, match="2 names for 3 rows"):
        nio.write_npz(tmp_path / "x.npz", f, a, ["a", "b"])
    with pytest.raises(ValueError, match="square"):
        nio.write_npz(tmp_path / "x.npz", f[:2], a, ["a", "b", "c"])
    other = tmp_path / "other.npz"
    np.savez(other, x=np.arange(3))
    with pytest.raises(ValueError, match=r"other\.npz: not a nusselt form-factor file"):
        nio.load_npz(other)
    junk = tmp_path / "junk.npz"
    junk.write_text("not a zip")
    with pytest.raises(ValueError, match=r"junk\.npz: not a readable \.npz file"):
        nio.load_npz(junk)


def test_csv_exact_values_header_and_quoting(tmp_path):
    f, a = sample(4)
    names = ["floor", "wall, east", 'say "hi"', "x"]
    p = tmp_path / "f.csv"
    nio.write_csv(p, sp.csr_array(f), names)
    rows = list(csv.reader(p.open()))
    assert rows[0] == ["from \\ to"] + names
    assert [r[0] for r in rows[1:]] == names
    np.testing.assert_array_equal(np.array([[float(x) for x in r[1:]] for r in rows[1:]]), f)  # exact
    nio.write_csv(p, f, names, precision=3)
    rows = list(csv.reader(p.open()))
    np.testing.assert_allclose(np.array([[float(x) for x in r[1:]] for r in rows[1:]]), f, rtol=5e-3)
    with pytest.raises(ValueError) as e:
        nio.write_csv(tmp_path / "big.csv", f, names, max_rows=3)
    assert "too large" in str(e.value) and ".npz" in str(e.value)
    assert not (tmp_path / "big.csv").exists()


def test_view3d_output_layout_and_round_trip(tmp_path):
    f, a = sample(3)
    p = tmp_path / "vf.txt"
    nio.write_view3d(p, sp.csr_array(f), a, emissivity=[0.9, 0.5, 0.123456], encl=1)
    lines = p.read_text().splitlines()
    assert lines[0] == "View3D 3.2 0 1 0 3".ljust(30)  # header padded like View3D's
    assert lines[1] == " ".join(f"{x:g}" for x in a)
    assert lines[2] == " ".join(f"{x:.6f}" for x in f[0])
    assert lines[5] == "0.900 0.500 0.123"
    r = nio.read_view3d_output(p)
    assert r["encl"] == 1 and r["emit"] == 0 and r["out"] == 0 and r["version"] == "3.2"
    np.testing.assert_allclose(r["matrix"], f, atol=5e-7)
    # full precision: exact round trip
    nio.write_view3d(p, f, a, precision=None)
    r = nio.read_view3d_output(p)
    np.testing.assert_array_equal(r["matrix"], f)
    np.testing.assert_array_equal(r["areas"], a)
    np.testing.assert_array_equal(r["emissivity"], [1.0, 1.0, 1.0])  # unknown: written as black


def parse_idf(text):
    """Fields of one IDF object: strip '!' comments, split on commas, drop the ';'."""
    body = " ".join(line.split("!", 1)[0] for line in text.splitlines())
    assert body.rstrip().endswith(";")
    return [s.strip() for s in body.rstrip()[:-1].split(",")]


def test_energyplus_object(tmp_path):
    f, a = sample(4)
    names = ["Floor", "Ceiling", "Wall 1", "Wall 2"]
    p = tmp_path / "vf.idf"
    nio.write_energyplus(p, sp.csr_array(f), names, "Zone One")
    text = p.read_text()
    assert "!- Zone or ZoneList or Space or SpaceList Name" in text
    assert "!- From Surface 1" in text and "!- To Surface 1" in text and "!- View Factor 1" in text
    fields = parse_idf(text)
    assert fields[0] == "ZoneProperty:UserViewFactors:BySurfaceName" and fields[1] == "Zone One"
    trip = fields[2:]
    assert len(trip) % 3 == 0
    got = np.zeros_like(f)
    for i in range(0, len(trip), 3):
        got[names.index(trip[i]), names.index(trip[i + 1])] = float(trip[i + 2])
    np.testing.assert_array_equal(got, f)  # values exact, row = "From Surface"
    assert len(trip) // 3 == np.count_nonzero(f)  # omitted pairs are zero
    nio.write_energyplus(p, f, names, "Zone One", all_pairs=True)
    assert len(parse_idf(p.read_text())[2:]) == 3 * 16
    with pytest.raises(ValueError, match="cannot be an EnergyPlus name"):
        nio.write_energyplus(p, f, ["a,b", "c", "d", "e"], "Z")
    g = f.copy()
    g[1, 2] = 1.2
    with pytest.raises(ValueError, match=r"F\[Ceiling -> Wall 1\] = 1.2 is not a view factor"):
        nio.write_energyplus(p, g, names, "Z")


def test_vtu_keeps_polygons_order_and_cell_data(tmp_path):
    pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 1.5, 0], [2, 0, 0], [2, 1, 0]], float)
    faces = [[0, 1, 2], [0, 1, 2, 3], [0, 1, 2, 4, 3], [1, 5, 6, 2], [1, 5, 6], [0, 1, 2, 4, 3]]
    data = {"area": np.arange(6.0), "vec": np.arange(12.0).reshape(6, 2), "flag": np.array([1, 0, 1, 0, 1, 0], bool)}
    p = tmp_path / "s.vtu"
    nio.write_vtu(p, pts, faces, data)
    m = meshio.read(p)
    got = [list(c) for block in m.cells for c in block.data]
    assert got == faces  # cell k of the file is faces[k]
    for k in ("area", "vec"):
        np.testing.assert_array_equal(np.concatenate(m.cell_data[k]), data[k])
    np.testing.assert_array_equal(np.concatenate(m.cell_data["flag"]), data["flag"].astype(int))
    with pytest.raises(ValueError, match="has 2 entries for 6 faces"):
        nio.write_vtu(p, pts, faces, {"bad": np.zeros(2)})


def scene_from(path):
    """A Scene-like namespace from a SceneData (areas by Newell's formula)."""
    d = nio.read_scene(path)
    areas = np.array([np.linalg.norm(0.5 * np.cross(p, np.roll(p, -1, 0)).sum(0)) for p in d.polygons])
    return types.SimpleNamespace(
        vertices=d.vertices,
        faces=d.faces,
        surface=d.surface,
        surface_names=d.names,
        obstruction=d.obstruction,
        areas=areas,
        meta=d.meta,
        source=d.source,
        emissivity=d.emissivity,
    )


def patch_result(scene, seed=3):
    recv = np.flatnonzero(~scene.obstruction)
    f, _ = sample(len(recv), seed)
    return FormFactors(
        sp.csr_array(f),
        scene.areas[recv],
        [f"{scene.surface_names[scene.surface[k]]}[{k}]" for k in recv],
        recv,
        "test",
        surface=scene.surface[recv],
        surface_names=scene.surface_names,
    )


def test_write_result_dispatch(tmp_path):
    scene = scene_from(DATA / "room_subsurfaces.vs3")
    res = patch_result(scene)
    n = len(res.areas)
    # npz keeps everything
    nio.write_result(tmp_path / "r.npz", res, scene=scene)
    r = nio.load_npz(tmp_path / "r.npz")
    np.testing.assert_array_equal(r["matrix"].toarray(), res.matrix.toarray())
    np.testing.assert_array_equal(r["faces"], res.faces)
    assert list(r["surface_names"]) == scene.surface_names and str(r["method"]) == "test"
    # csv as given (patch level)
    nio.write_result(tmp_path / "r.csv", res)
    assert len(list(csv.reader((tmp_path / "r.csv").open()))) == n + 1
    # View3D text from a .vs3 scene: per surface, with the file's emissivities
    nio.write_result(tmp_path / "r.txt", res, scene=scene)
    v = nio.read_view3d_output(tmp_path / "r.txt")
    s = res.by_surface()
    assert v["matrix"].shape == (9, 9)  # 10 surfaces minus the obstruction
    # the file says emit=1: View3D then writes script-F of the emissivities
    em = np.array([0.9, 0.8, 0.9, 0.7, 0.9, 0.84, 0.6, 0.9, 0.9])
    assert v["emit"] == 1
    from nusselt.exchange import script_f

    np.testing.assert_allclose(v["matrix"], script_f(s.dense(), em), atol=5e-7)
    np.testing.assert_allclose(v["emissivity"], em)
    # EnergyPlus: always per surface, zone named after the scene file
    nio.write_result(tmp_path / "r.idf", res, scene=scene)
    fields = parse_idf((tmp_path / "r.idf").read_text())
    assert fields[1] == "room_subsurfaces" and set(fields[2::3]) <= set(s.names)
    nio.write_result(tmp_path / "z.idf", res, scene=scene, zone_name="Z1")
    assert parse_idf((tmp_path / "z.idf").read_text())[1] == "Z1"
    # a plain dict result (as load_npz returns) works for npz/csv/txt
    nio.write_result(tmp_path / "d.txt", {"matrix": res.matrix, "areas": res.areas, "names": res.names})
    assert nio.read_view3d_output(tmp_path / "d.txt")["matrix"].shape == (n, n)
    with pytest.raises(ValueError, match="cannot tell the output format"):
        nio.write_result(tmp_path / "r.xlsx", res)
    with pytest.raises(ValueError, match="needs the scene geometry"):
        nio.write_result(tmp_path / "r.vtu", res)


@pytest.mark.parametrize("level", ["patch", "surface"])
def test_write_result_vtu_cell_data(tmp_path, level):
    scene = scene_from(DATA / "room_subsurfaces.vs3")
    res = patch_result(scene)
    if level == "surface":
        res = res.by_surface()
    p = tmp_path / "r.vtu"
    nio.write_result(p, res, scene=scene, to_surface="window")
    m = meshio.read(p)
    cd = {k: np.concatenate(v) for k, v in m.cell_data.items()}
    nf = len(scene.faces)
    assert sum(len(b.data) for b in m.cells) == nf
    np.testing.assert_allclose(cd["area"], scene.areas)
    np.testing.assert_array_equal(cd["obstruction"], scene.obstruction.astype(int))
    dense = res.dense()
    for k in range(nf):
        r = cd["row"][k]
        if scene.obstruction[k]:
            assert r == -1 and np.isnan(cd["row_sum"][k]) and np.isnan(cd["F_to_window"][k])
            continue
        assert cd["row_sum"][k] == pytest.approx(dense[r].sum(), rel=1e-14)
        if level == "patch":
            cols = [j for j in range(len(res.areas)) if scene.surface_names[res.surface[j]] == "window"]
            assert res.faces[r] == k
        else:
            cols = [res.names.index("window")]
            assert res.faces[r] == scene.surface[k]
        assert cd["F_to_window"][k] == pytest.approx(dense[r, cols].sum(), rel=1e-14)
    with pytest.raises(ValueError, match="no surface named 'nope'"):
        nio.write_result(p, res, scene=scene, to_surface="nope")
