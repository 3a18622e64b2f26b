"""The command line: the demo, the main job's options, one-line errors, kill and resume."""

import os
import re
import signal
import struct
import subprocess
import sys
import time
import zlib

import numpy as np
import pytest
from conftest import cube_faces

import nusselt
import nusselt.data
import nusselt.io as nio
from nusselt.cli import main
from nusselt.render import Camera, colormap, render, value_range, write_png


def read_png(path):
    """Minimal PNG decoder for what write_png writes (8-bit RGB, filter 0 rows)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, w = 8, b"", None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos : pos + 4])
        tag, body = data[pos + 4 : pos + 8], data[pos + 8 : pos + 8 + n]
        (crc,) = struct.unpack(">I", data[pos + 8 + n : pos + 12 + n])
        assert crc == zlib.crc32(tag + body) & 0xFFFFFFFF
        if tag == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            assert (depth, ctype) == (8, 2)
        elif tag == b"IDAT":
            idat += body
        pos += 12 + n
    raw = np.frombuffer(zlib.decompress(idat), dtype=np.uint8).reshape(h, 1 + 3 * w)
    assert np.all(raw[:, 0] == 0)
    return raw[:, 1:].reshape(h, w, 3)


# --- rendering ------------------------------------------------------------------------------


def square(cx, cy, z, half):
    """A square facing -z (towards a camera at the origin looking +z), CCW seen from it."""
    return np.array(
        [[cx - half, cy - half, z], [cx - half, cy + half, z], [cx + half, cy + half, z], [cx + half, cy - half, z]]
    )


def test_render_colours_depth_and_png_roundtrip(tmp_path):
    far = square(0, 0, 10, 8)  # fills the view behind
    near = square(0, 0, 5, 0.5)  # small, in front, at the centre
    camera = Camera(eye=(0, 0, 0), look=(0, 0, 1), up=(0, 1, 0), fov_deg=60, size=64)
    img = render([far, near], [1e-2, 1.0], camera)
    assert img.shape[0] == 64 and img.shape[1] > 64 + 32  # picture, then the colour bar and its labels
    assert (img[:, 64 + 32 :] == 255).all(axis=2).sum() > 20  # white tick labels drawn beside the bar
    to8 = lambda c: np.round(np.clip(c, 0, 1) * 255).astype(int)
    centre, corner = img[32, 32].astype(int), img[4, 4].astype(int)
    assert np.abs(centre - to8(colormap(1.0))).max() <= 1  # near square: top of the scale
    assert np.abs(corner - to8(colormap(0.0))).max() <= 1  # far square: 2 decades down = bottom
    # z-buffer: drawing order does not matter
    img2 = render([near, far], [1.0, 1e-2], camera)
    np.testing.assert_array_equal(img, img2)
    path = tmp_path / "x.png"
    write_png(path, img)
    np.testing.assert_array_equal(read_png(path), img)


def test_value_range_clamps_decades_and_ignores_nan():
    v = np.array([0.0, 1e-9, 1e-3, 1e-1, np.nan])
    lo, hi = value_range(v, decades=3)
    assert hi == pytest.approx(-1) and lo == pytest.approx(-4)
    lo, hi = value_range(v, decades=20)
    assert lo == pytest.approx(-9)
    assert value_range([0.0, np.nan]) == (0.0, 1.0)
    assert value_range([2.0, 5.0], log=False) == (2.0, 5.0)


# --- the demo --------------------------------------------------------------------------------


def test_demo_prints_the_box_and_writes_a_png(tmp_path, capsys):
    png = tmp_path / "box.png"
    rc = main(["demo", "-o", str(png), "--refine", "150", "--tol", "1e-3", "--size", "96"])
    out = capsys.readouterr().out
    assert rc == 0
    assert "short block" in out and "tall block" in out and "light" in out
    # the light's row on the fine mesh adds up to its surface row (additivity), to the tolerance
    diff = float(re.search(r"differs from the surface row by ([0-9.e+-]+)", out).group(1))
    assert diff < 1e-3
    img = read_png(png)
    assert img.shape[0] == 96 and img.shape[1] > 96 + 32
    assert len(np.unique(img.reshape(-1, 3), axis=0)) > 20  # a picture, not a flat image


# --- errors: one line, exit 2, no traceback ----------------------------------------------

BAD_FILES = {
    "bad.obj": "v 0 0 0\nv 1 0 0\nf 1 2\n",
    "bad.vs3": "T broken\nC encl=0\nF 3\nV 1 0 0 0\nS 1 1 2 9 0 0 0 0.9 x\nEnd of data\n",
    "bad.stl": "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 nan\n",
    "bad.ply": "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n0 0 0\n",
    "bad.vtu": "<VTKFile type='UnstructuredGrid'><UnstructuredGrid><Piece",
    "bad.msh": "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\ngarbage\n",
    "empty.obj": "# nothing here\n",
}


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_malformed_files_give_one_line_errors(tmp_path, capsys, name):
    path = tmp_path / name
    path.write_text(BAD_FILES[name])
    rc = main(["matrix", str(path), "-o", str(tmp_path / "out.npz"), "-q"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2
    assert err[-1].startswith("nusselt: error: ") and name in err[-1], err
    assert not any("Traceback" in line for line in err)
    with pytest.raises((ValueError, OSError), match=re.escape(name)):
        nusselt.Scene.from_file(path)


@pytest.mark.parametrize(
    "args, what",
    [
        (["matrix", "{missing}", "-o", "{out}.npz"], "no such file"),
        (["matrix", "{good}", "-o", "{out}.xyz"], "output format"),
        (["matrix", "{good}", "-o", "{out}.npz", "--method", "nope"], "unknown method"),
        (["matrix", "{good}", "-o", "{out}.npz", "--option", "order"], "NAME=VALUE"),
        (["matrix", "{good}", "-o", "{out}.npz", "--option", "tol=-1"], "tol"),
        (["matrix", "{good}", "-o", "{out}.npz", "--threshold", "2"], "threshold"),
    ],
)
def test_bad_arguments_give_one_line_errors(tmp_path, capsys, args, what):
    good = tmp_path / "box.obj"
    good.write_text(open(nusselt.data.bundled("cornell_empty.obj")).read())
    subs = {"missing": str(tmp_path / "missing.obj"), "out": str(tmp_path / "out"), "good": str(good)}
    rc = main([a.format(**subs) for a in args])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and err[-1].startswith("nusselt: error: ") and what in err[-1], err


def test_error_through_a_real_process_has_no_traceback(tmp_path):
    path = tmp_path / "bad.obj"
    path.write_text(BAD_FILES["bad.obj"])
    p = subprocess.run(
        [sys.executable, "-m", "nusselt.cli", "matrix", str(path), "-o", str(tmp_path / "o.npz")],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 2
    assert p.stderr.strip().count("\n") == 0 and "bad.obj, line 3" in p.stderr and "Traceback" not in p.stderr


# --- the main job's options --------------------------------------------------------------


def test_matrix_npz_stores_trust_measures_and_threshold(tmp_path, capsys):
    out = tmp_path / "f.npz"
    assert (
        main(
            [
                "matrix",
                nusselt.data.bundled("cornell_empty.obj"),
                "-o",
                str(out),
                "-q",
                "--refine",
                "200",
                "--threshold",
                "0.02",
            ]
        )
        == 0
    )
    r = nio.load_npz(out)
    f = r["matrix"]
    info = r["info"]
    np.testing.assert_allclose(r["row_sums"], f.sum(axis=1), rtol=0, atol=1e-15)
    assert info["closure_error"] == pytest.approx(np.abs(r["row_sums"] - 1).max())
    assert info["reciprocity_error"] < 1e-12  # pairs dropped in both directions only
    assert info["threshold"] == 0.02 and info["dropped"] > 0
    # every pair dropped had both entries below the threshold; the full run tells which
    full = nusselt.form_factors(nusselt.Scene.from_file(nusselt.data.bundled("cornell_empty.obj")).refined(200))
    g = full.matrix.toarray()
    kept = f.toarray() != 0
    small = (g < 0.02) & (g.T < 0.02)
    assert np.array_equal(kept, (g != 0) & ~small)
    assert info["dropped"] == pytest.approx(np.max((g * small).sum(axis=1)))
    assert "memory: about" in capsys.readouterr().err


def test_correct_option_fixes_sampled_rows_and_refuses_open_scenes(tmp_path, capsys):
    out = tmp_path / "f.npz"
    cube = tmp_path / "cube.obj"
    write_cube_obj(cube, 3)
    assert (
        main(
            [
                "matrix",
                str(cube),
                "-o",
                str(out),
                "-q",
                "--method",
                "raytrace",
                "--option",
                "rays=256",
                "--correct",
                "closure",
            ]
        )
        == 0
    )
    r = nio.load_npz(out)
    assert r["info"]["corrected"] == "closure"
    assert r["info"]["closure_error"] < 1e-9 and r["info"]["reciprocity_error"] < 1e-9
    exact = nusselt.form_factors(nusselt.Scene.from_file(cube)).matrix.toarray()
    # the correction moves the estimate towards the exact matrix
    raw = nusselt.form_factors(nusselt.Scene.from_file(cube), method="raytrace", rays=256).matrix.toarray()
    assert np.abs(r["matrix"].toarray() - exact).sum() < np.abs(raw - exact).sum()
    rc = main(
        [
            "matrix",
            nusselt.data.bundled("cornell_empty.obj"),
            "-o",
            str(out),
            "-q",
            "--method",
            "raytrace",
            "--option",
            "rays=64",
            "--correct",
            "closure",
        ]
    )
    assert rc == 2 and "closed enclosure" in capsys.readouterr().err


def write_cube_obj(path, n):
    """Closed unit cube, n x n quads per face, fronts facing in, one object per face."""
    polys, face = cube_faces(n)
    lines = []
    for k, (p, f) in enumerate(zip(polys, face)):
        if k == 0 or f != face[k - 1]:
            lines.append(f"o face{f}")
        lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in p.tolist()]
        lines.append("f " + " ".join(str(4 * k + i) for i in range(1, 5)))
    path.write_text("\n".join(lines) + "\n")


# --- kill -9 halfway and resume ------------------------------------------------------------


def test_sigkill_halfway_then_resume_gives_the_identical_matrix(tmp_path):
    scene = tmp_path / "cube.obj"
    write_cube_obj(scene, 18)  # 1944 patches, 1.9 M pairs
    cmd = [
        sys.executable,
        "-m",
        "nusselt.cli",
        "matrix",
        str(scene),
        "-q",
        "--block-size",
        "40000",
        "--option",
        "tol=1e-6",
    ]
    ref = tmp_path / "ref.npz"
    subprocess.run(cmd + ["-o", str(ref)], check=True, capture_output=True)

    out = tmp_path / "out.npz"
    partial = tmp_path / "out.npz.partial"
    cmd += ["--checkpoint", str(partial)]  # from the first block: a short run is killed here
    p = subprocess.Popen(cmd + ["-o", str(out)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.time() + 300
        while time.time() < deadline and p.poll() is None:
            if partial.is_dir():
                done = [f for f in os.listdir(partial) if f.startswith("block_") and f.endswith(".npz")]
                if len(done) >= 3:  # blocks grow: the third ends well before half of the run
                    break
            time.sleep(0.05)
        assert p.poll() is None, "the run finished before it could be killed"
        os.kill(p.pid, signal.SIGKILL)
    finally:
        p.wait()
    assert not out.exists()
    kept = sorted(f for f in os.listdir(partial) if f.startswith("block_"))
    rows = 0
    for f in kept:
        with np.load(partial / f) as z:
            meta = __import__("json").loads(str(z["meta"]))
        rows += meta["stop"] - meta["start"]
    assert 0 < rows < 1944  # some rows finished, not all

    # without --resume the interrupted run is not silently overwritten
    again = subprocess.run(cmd + ["-o", str(out)], capture_output=True, text=True)
    assert again.returncode == 2 and "--resume" in again.stderr

    subprocess.run(cmd + ["-o", str(out), "--resume"], check=True, capture_output=True)
    assert not partial.exists()
    a, b = nio.load_npz(ref), nio.load_npz(out)
    for key in ("indptr", "indices", "data"):
        np.testing.assert_array_equal(getattr(a["matrix"], key), getattr(b["matrix"], key))
    np.testing.assert_array_equal(a["areas"], b["areas"])


_CTRL_C_ON_IMPORT = """
import sys
class CtrlC:  # Ctrl-C arrives while nusselt's modules load, before the command's main() runs
    def find_spec(self, name, path=None, target=None):
        if name == "nusselt.api":  # one of the modules `import nusselt` loads
            raise KeyboardInterrupt
sys.meta_path.insert(0, CtrlC())
sys.argv[0] = ARGV0
from nusselt.cli import main
sys.exit(main(["methods"]))
"""


def test_ctrl_c_while_the_command_starts_is_a_quiet_exit_130():
    def run(argv0):
        code = _CTRL_C_ON_IMPORT.replace("ARGV0", repr(argv0))
        return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)

    r = run(os.path.join("venv", "bin", "nusselt"))  # as the console script runs
    assert r.returncode == 130
    assert r.stderr == "nusselt: interrupted\n"
    # a program that imports nusselt gets its KeyboardInterrupt as usual
    r = run("analysis.py")
    assert r.returncode != 0 and "KeyboardInterrupt" in r.stderr and "Traceback" in r.stderr


_BLAS_TIMEOUT_SEEN = """
import os, sys
sys.argv[0] = ARGV0
import nusselt
print(os.environ.get("OPENBLAS_THREAD_TIMEOUT"))
"""


def test_the_command_lets_idle_blas_threads_sleep_and_leaves_programs_alone():
    def seen(argv0, **env):
        code = _BLAS_TIMEOUT_SEEN.replace("ARGV0", repr(argv0))
        base = {k: v for k, v in os.environ.items() if k != "OPENBLAS_THREAD_TIMEOUT"}
        r = subprocess.run(
            [sys.executable, "-c", code], env={**base, **env}, capture_output=True, text=True, timeout=120
        )
        assert r.returncode == 0, r.stderr
        return r.stdout.strip()

    command = os.path.join("venv", "bin", "nusselt")
    assert seen(command) == "4"  # set before numpy (and its OpenBLAS) load
    assert seen(command, OPENBLAS_THREAD_TIMEOUT="28") == "28"  # the user's setting wins
    assert seen("analysis.py") == "None"  # a program importing nusselt keeps its environment
