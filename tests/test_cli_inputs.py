"""Command-line input options and checks before work (issue 23, items 1, 2, 12)."""

import numpy as np
import pytest
from conftest import cube_faces

import nusselt
from nusselt.cli import main
from nusselt.data import bundled


def write_obj(path, polys, names=None):
    lines, k = [], 1
    for i, p in enumerate(polys):
        if names:
            lines.append(f"o {names[i]}")
        lines += [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in p]
        lines.append("f " + " ".join(str(k + j) for j in range(len(p))))
        k += len(p)
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_no_arguments_prints_help(capsys):
    assert main([]) == 2
    out = capsys.readouterr()
    assert "usage: nusselt" in out.out and "matrix" in out.out and "error" not in out.err


def test_refine_zero_is_an_error(tmp_path, capsys):
    assert main(["matrix", bundled("cornell_box.obj"), "-o", str(tmp_path / "x.npz"), "--refine", "0", "-q"]) == 2
    assert "max_edge must be positive, got 0" in capsys.readouterr().err


@pytest.mark.parametrize("ext", [".npz", ".csv"])
def test_to_surface_needs_vtu(tmp_path, capsys, ext):
    out = tmp_path / f"x{ext}"
    assert main(["matrix", bundled("cornell_box.obj"), "-o", str(out), "--to-surface", "light", "-q"]) == 2
    assert "--to-surface is for .vtu output" in capsys.readouterr().err
    assert not out.exists()


def test_to_surface_typo_fails_before_any_work(tmp_path, capsys):
    out = tmp_path / "x.vtu"
    assert main(["matrix", bundled("cornell_box.obj"), "-o", str(out), "--to-surface", "ligth", "-q"]) == 2
    err = capsys.readouterr().err
    assert "--to-surface: " in err and "no surface named 'ligth' (surfaces: " in err and "light" in err
    assert "memory:" not in err  # refused before the run started
    assert not out.exists() and not (tmp_path / "x.vtu.partial").exists()


def test_orient_options_on_an_outward_box(tmp_path, capsys):
    polys, face = cube_faces(1)
    path = write_obj(tmp_path / "box.obj", [p[::-1] for p in polys], [f"side{k}" for k in face])
    assert main(["matrix", path, "-o", str(tmp_path / "a.npz"), "-q"]) == 0
    err = capsys.readouterr().err
    assert "turned 6 faces of a closed shell facing outward to face inward" in err
    r = nusselt.load_npz(tmp_path / "a.npz")
    assert np.allclose(r["matrix"].sum(axis=1), 1.0, atol=1e-12)
    assert main(["matrix", path, "-o", str(tmp_path / "b.npz"), "-q", "--orient", "as-is"]) == 0
    err = capsys.readouterr().err
    assert "nusselt: warning: " in err and "fronts face outward" in err and "whole result is 0" in err
    assert nusselt.load_npz(tmp_path / "b.npz")["matrix"].nnz == 0


def test_repair_and_two_sided_options(tmp_path, capsys):
    polys, face = cube_faces(1)
    names = [f"side{k}" for k in face]
    path = write_obj(tmp_path / "doubled.obj", polys + polys, names + names)
    assert main(["matrix", path, "-o", str(tmp_path / "a.npz"), "-q"]) == 2
    assert "lie in one plane, face the same way and overlap" in capsys.readouterr().err
    assert main(["matrix", path, "-o", str(tmp_path / "a.npz"), "-q", "--repair"]) == 0
    assert "nusselt: warning: " in capsys.readouterr().err
    r = nusselt.load_npz(tmp_path / "a.npz")
    assert r["matrix"].shape == (6, 6) and np.allclose(r["matrix"].sum(axis=1), 1.0, atol=1e-12)
    plate = np.array([[0.1, 0.1, 0.5], [0.9, 0.1, 0.5], [0.9, 0.9, 0.5], [0.1, 0.9, 0.5]])
    path = write_obj(tmp_path / "fin.obj", polys + [plate], names + ["plate"])
    assert (
        main(
            [
                "matrix",
                path,
                "-o",
                str(tmp_path / "f.npz"),
                "-q",
                "--two-sided",
                "plate",
                "--option",
                "obstructed_tol=1e-8",
            ]
        )
        == 0
    )
    r = nusselt.load_npz(tmp_path / "f.npz")
    assert r["areas"][-1] == pytest.approx(2 * 0.64, rel=1e-14)
    assert np.allclose(r["matrix"].sum(axis=1), 1.0, atol=1e-7)
    assert main(["matrix", path, "-o", str(tmp_path / "g.npz"), "-q", "--two-sided", "plat"]) == 2
    assert "--two-sided: " in capsys.readouterr().err


def test_memory_error_while_reading_names_the_file(tmp_path, monkeypatch, capsys):
    import nusselt.io as nio

    def no_memory(path, format=None):
        raise MemoryError()

    monkeypatch.setattr(nio, "_read_by_format", no_memory)
    with pytest.raises(MemoryError, match=r"room.obj: not enough memory to read this"):
        nio.read_scene(tmp_path / "room.obj")
    (tmp_path / "room.obj").write_text("v 0 0 0\n")
    assert main(["matrix", str(tmp_path / "room.obj"), "-o", str(tmp_path / "x.npz"), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("nusselt: error: out of memory") and "room.obj: not enough memory" in err


def test_read_scene_orients_on_request(tmp_path):
    polys, _ = cube_faces(1)
    path = write_obj(tmp_path / "box.obj", [p[::-1] for p in polys])
    assert nusselt.io.read_scene(path).faces[0].tolist() == [0, 1, 2, 3]
    d = nusselt.io.read_scene(path, orient="inward")
    assert d.meta["orient"]["flipped"] == list(range(6)) and d.faces[0].tolist() == [3, 2, 1, 0]


def test_empty_stl_solid_is_a_clear_error(tmp_path):
    p = tmp_path / "blank.stl"
    p.write_text("solid\nendsolid\n")
    with pytest.raises(ValueError, match="blank.stl: the mesh has no points"):
        nusselt.io.read_scene(p)
