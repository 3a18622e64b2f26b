"""`nusselt exchange` and `nusselt render` on the command line."""

import numpy as np
from test_cli import read_png

from nusselt.cli import main

ROOM = "tests/data/cube_room.obj"
SIGMA = 5.670374419e-8


def test_exchange_mixed_conditions_and_csv(tmp_path, capsys):
    out = tmp_path / "q.csv"
    rc = main(
        [
            "exchange",
            ROOM,
            "--emissivity",
            "0.9",
            "--emissivity",
            "floor=0.3",
            "--temperature",
            "293.15",
            "--temperature",
            "floor=300",
            "--flux",
            "ceiling=0",
            "-o",
            str(out),
        ]
    )
    assert rc == 0
    text = capsys.readouterr().out
    assert "floor" in text and "sum of Q" in text
    rows = np.genfromtxt(out, delimiter=",", names=True, dtype=None, encoding=None)
    heat = dict(zip(rows["surface"], rows["heat_W"]))
    assert abs(sum(heat.values())) < 1e-10 * abs(heat["floor"])  # closed room: energy conserved
    assert heat["ceiling"] == 0.0 and heat["floor"] > 0
    t = dict(zip(rows["surface"], rows["temperature_K"]))
    assert 293.15 < t["ceiling"] < 300.0  # a zero-flux surface settles between its neighbours


def test_exchange_values_csv(tmp_path, capsys):
    v = tmp_path / "v.csv"
    v.write_text(
        "surface,emissivity,temperature,flux\n"
        + "".join(
            f"{n},0.8,{300 if n == 'floor' else 280},\n" for n in ["floor", "ceiling", "south", "east", "north", "west"]
        )
    )
    assert main(["exchange", ROOM, "--values", str(v)]) == 0
    v.write_text("surface,emissivity,temperature,flux\nfloor,0.8,abc,\n")
    assert main(["exchange", ROOM, "--values", str(v)]) == 2
    assert "line 2" in capsys.readouterr().err


def test_exchange_bad_input_exits_2(capsys):
    assert main(["exchange", ROOM, "--temperature", "flor=300"]) == 2
    assert "no surface 'flor'" in capsys.readouterr().err
    assert main(["exchange", ROOM]) == 2
    assert "exactly one of temperature and flux" in capsys.readouterr().err
    assert main(["exchange", ROOM, "--temperature", "300", "--emissivity", "1.2"]) == 2
    assert "emissivity" in capsys.readouterr().err


def test_render_writes_an_rgb_picture(tmp_path, capsys):
    png = tmp_path / "r.png"
    rc = main(
        [
            "render",
            ROOM,
            "-o",
            str(png),
            "--refine",
            "0.34",
            "--resolution",
            "32",
            "--size",
            "48",
            "--emission",
            "ceiling=5,5,5",
            "--reflectance",
            "west=0.7,0.1,0.1",
            "--eye",
            "0.5,0.5,-0.6",
        ]
    )
    assert rc == 0
    img = read_png(png)
    assert img.shape == (48, 48, 3)
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > 20
    assert main(["render", ROOM, "-o", str(png)]) == 2
    assert "nothing emits" in capsys.readouterr().err
