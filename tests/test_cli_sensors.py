"""`nusselt sensors`: CSV in, CSV out; errors name the file and line."""

from __future__ import annotations

import csv

import pytest
from test_sensors import box, corner

from nusselt.cli import main


def write_obj(path, polys, names):
    lines, k = [], 1
    for poly, name in zip(polys, names):
        lines.append(f"o {name}")
        lines += [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in poly]
        lines.append("f " + " ".join(str(k + i) for i in range(len(poly))))
        k += len(poly)
    path.write_text("\n".join(lines) + "\n")


def test_sensors_command_writes_view_factors_and_temperatures(tmp_path, capsys):
    scene = tmp_path / "cube.obj"
    write_obj(scene, box((0, 0, 0), (1, 1, 1)), ["floor", "ceiling", "south", "north", "west", "east"])
    pts = tmp_path / "pts.csv"
    pts.write_text("x,y,z,nx,ny,nz\n0.5,0.5,0.5,0,0,2\n0.3,0.6,0.2,1,0,0\n")
    out = tmp_path / "out.csv"
    args = [str(scene), str(pts), "-o", str(out)]
    temps = ["--temperature", "floor=290", "--temperature", "ceiling=310"] + sum(
        (["--temperature", f"{w}=300"] for w in ["south", "north", "west", "east"]), []
    )
    assert main(["sensors", *args, *temps]) == 0
    rows = list(csv.DictReader(out.open()))
    assert rows[0]["nz"] == "1.0"
    assert float(rows[0]["F_ceiling"]) == pytest.approx(4 * corner(0.5, 0.5, 0.5), rel=1e-13)
    assert float(rows[0]["F_floor"]) == 0.0
    assert abs(float(rows[1]["F_uncovered"])) < 1e-12
    f_c = float(rows[0]["F_ceiling"])
    assert float(rows[0]["t_plane"]) == pytest.approx((f_c * 310.0**4 + (1 - f_c) * 300.0**4) ** 0.25, rel=1e-12)
    # at the centre a sphere sees each face 1/6
    assert float(rows[0]["t_mrt_sphere"]) == pytest.approx(
        ((290.0**4 + 310.0**4 + 4 * 300.0**4) / 6) ** 0.25, rel=1e-12
    )
    # a surface without a temperature, a bad line in the points file
    assert main(["sensors", *args, "--temperature", "floor=290"]) == 2
    assert "has no temperature" in capsys.readouterr().err
    pts.write_text("x,y,z,nx,ny,nz\n0.5,0.5,0.5,0,0,1\n0.5,0.5,oops,0,0,1\n")
    assert main(["sensors", *args]) == 2
    assert "pts.csv:3: not a number" in capsys.readouterr().err
    assert main(["sensors", *args[:3], str(out), "--temperature", "floor"]) == 2
    assert "SURFACE=KELVIN" in capsys.readouterr().err
