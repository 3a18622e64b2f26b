"""Every hand-written text reader reads through one line reader (``scenedata.text_lines``): a
line longer than the cap is refused naming the file and line, before it is held. The cap is
made small here so that a line just over it is cheap; the real 16 MiB cap is exercised under an
address-space limit in test_memory_limits.py. epJSON is parsed whole, so it has a size cap."""

import shutil
from pathlib import Path

import numpy as np
import pytest

import nusselt
from nusselt import sensors
from nusselt.cli import main
from nusselt.io import energyplus, scenedata, view3d

DATA = Path(__file__).parent / "data"
CAP = 200  # bytes, in place of 16 MiB


@pytest.fixture
def small_cap(monkeypatch):
    monkeypatch.setattr(scenedata, "MAX_LINE_BYTES", CAP)


def long_line_after(path: Path, keep: int, line: str) -> int:
    """Rewrite ``path`` with ``line`` (just over the cap) after its first ``keep`` lines; its number."""
    lines = path.read_text().splitlines()
    path.write_text("\n".join(lines[:keep] + [line] + lines[keep:]) + "\n")
    return keep + 1


def test_the_line_reader_refuses_a_line_just_over_the_cap_and_not_one_at_it(tmp_path, small_cap):
    f = tmp_path / "a.txt"
    f.write_bytes(b"x\n" + b"y" * CAP + b"\n" + b"z" * (CAP + 1) + b"\n")
    got = scenedata.text_lines(str(f), "test")
    assert next(got) == (1, "x") and next(got) == (2, "y" * CAP)
    with pytest.raises(ValueError, match=r"a\.txt, line 3: longer than 0 MiB: damaged, or not a test file"):
        next(got)


def test_the_line_reader_drops_a_byte_order_mark(tmp_path):
    f = tmp_path / "bom.txt"
    f.write_bytes(b"\xef\xbb\xbfa,b\r\nc\n")
    assert list(scenedata.text_lines(str(f), "test")) == [(1, "a,b"), (2, "c")]


def test_vs3_long_line_is_refused_naming_file_and_line(tmp_path, small_cap):
    f = tmp_path / "room.vs3"
    shutil.copy(DATA / "room_subsurfaces.vs3", f)
    before = nusselt.Scene.from_file(str(f))  # the file itself reads under the small cap
    assert len(before) > 0
    no = long_line_after(f, 3, "! " + "c" * CAP)  # even a comment: the cap comes before parsing
    with pytest.raises(ValueError, match=rf"room\.vs3, line {no}: longer than"):
        nusselt.Scene.from_file(str(f))


def test_view3d_output_long_line_is_refused_and_line_numbers_count_blank_lines(tmp_path, small_cap):
    f = tmp_path / "F.txt"
    f.write_text("View3D 3.2 0 1 0 2\n\n1 1\n0 1\n" + "1 " * CAP + "\n1 1\n")
    with pytest.raises(ValueError, match=r"F\.txt, line 5: longer than"):
        view3d.read_view3d_output(str(f))
    f.write_text("View3D 3.2 0 1 0 2\n\n1 1\n0 1\n1 x\n1 1\n")  # the blank line 2 still counts
    with pytest.raises(ValueError, match=r"F\.txt, line 5: bad number"):
        view3d.read_view3d_output(str(f))
    f.write_text("View3D 3.2 0 1 0 2\n\n1 1\n0 1\n1 0\n1 1\n")
    out = view3d.read_view3d_output(str(f))
    assert np.array_equal(out["matrix"], [[0, 1], [1, 0]]) and np.array_equal(out["areas"], [1, 1])


def test_idf_long_line_is_refused_naming_file_and_line(tmp_path):
    f = tmp_path / "zones.idf"
    shutil.copy(DATA / "4ZoneWithShading_Simple_1_geometry.idf", f)
    n = len(nusselt.Scene.from_file(str(f)))
    longest = max(len(ln.encode()) for ln in f.read_text().splitlines())
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(scenedata, "MAX_LINE_BYTES", longest)
        assert len(nusselt.Scene.from_file(str(f))) == n  # unchanged at a cap it just fits
        no = long_line_after(f, 10, "! " + "c" * longest)
        with pytest.raises(ValueError, match=rf"zones\.idf, line {no}: longer than .* not a IDF file"):
            nusselt.Scene.from_file(str(f))
        with pytest.raises(ValueError, match=rf"zones\.idf, line {no}: longer than"):
            energyplus.read_user_view_factors(str(f))


def test_epjson_over_the_size_cap_is_refused_before_it_is_read(tmp_path, monkeypatch):
    from test_io_energyplus import cube_epjson

    f = tmp_path / "cube.epJSON"
    cube_epjson(f)
    size = f.stat().st_size
    monkeypatch.setattr(scenedata, "MAX_JSON_BYTES", size)
    assert len(nusselt.Scene.from_file(str(f))) > 0  # at the cap: read
    monkeypatch.setattr(scenedata, "MAX_JSON_BYTES", size - 1)
    with pytest.raises(ValueError, match=r"cube\.epJSON: .* larger than .* epJSON file may have .* convert it to IDF"):
        nusselt.Scene.from_file(str(f))
    with pytest.raises(ValueError, match=r"cube\.epJSON: .* larger than"):
        energyplus.read_user_view_factors(str(f))


def test_json_content_is_found_past_leading_blank_space(tmp_path):
    from test_io_energyplus import cube_epjson

    f = tmp_path / "cube.txt"  # no .epJSON name: the content says JSON
    cube_epjson(f)
    f.write_bytes(b"\xef\xbb\xbf" + b" \n" * 70000 + f.read_bytes())
    assert len(nusselt.Scene.from_file(str(f), format="energyplus")) > 0


def test_points_csv_long_line_and_bad_csv_are_refused_naming_file_and_line(tmp_path, small_cap):
    f = tmp_path / "p.csv"
    f.write_text("x,y,z,nx,ny,nz\n0,0,0,0,0,1\n" + "1," * CAP + "\n")
    with pytest.raises(ValueError, match=r"p\.csv, line 3: longer than"):
        sensors.read_points_csv(f)
    # a quoted field that never closes runs past csv's field limit (128 Ki characters)
    f.write_text('x,y,z,nx,ny,nz\n\n0,0,0,0,0,1\n"1' + ("c" * 190 + "\n") * 700)
    with pytest.raises(ValueError, match=r"p\.csv, line \d+: bad CSV: field larger than field limit"):
        sensors.read_points_csv(f)
    f.write_text("\ufeffx,y,z,nx,ny,nz\n\n0,0,0,0,0,1\n0,0,q,0,0,1\n")  # BOM header; line 4 after a blank
    with pytest.raises(ValueError, match=r"p\.csv:4: not a number"):
        sensors.read_points_csv(f)


def test_exchange_values_long_line_is_refused_naming_file_and_line(tmp_path, capsys, small_cap):
    room = str(DATA / "cube_room.obj")
    v = tmp_path / "v.csv"
    v.write_text("surface,emissivity,temperature,flux\n\n" + "x" * (CAP + 1) + "\n")
    assert main(["exchange", room, "--values", str(v)]) == 2
    assert "v.csv, line 3: longer than" in capsys.readouterr().err
