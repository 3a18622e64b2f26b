"""The fixed cost a short run pays: a fresh process that imports nusselt and reads a scene.

Each case runs ``--repeat`` times as a fresh child under ``/usr/bin/time``; the table shows
the median and least wall seconds and one core's CPU (user + sys) of the whole process. The
scene is the closed unit cube with 8 x 8 quads per face (384 patches, bench/cube.py), written
as OBJ and as View3D ``.vs3``. The floor is a Python that does nothing and one that imports
numpy; the ``nusselt methods`` command shows what the command line adds.

numpy's OpenBLAS starts a pool of worker threads that busy-wait for about 2^28 cycles before
they sleep; on a 2-core host that is ~0.07 s of CPU on the other core, spent whether or not
BLAS is ever called. The `nusselt` command sets ``OPENBLAS_THREAD_TIMEOUT=4`` before numpy
loads (a user's own setting wins); a program that imports nusselt keeps its environment, so
the API cases are shown both ways.

    python bench/startup.py              # 21 runs of each case
    python bench/startup.py --repeat 5

Measure an installed package (``pip install .``, bytecode compiled at install): with
``PYTHONDONTWRITEBYTECODE=1`` and an editable install every start compiles the sources again.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from cube import cube_faces, write_cube_obj  # noqa: E402


def write_vs3(path: pathlib.Path, polys) -> None:
    lines = ["T unit cube, 8 x 8 quads per face", "C encl=1 list=0 eps=1.0e-6", "F 3"]
    k = 1
    for q in polys:
        lines += [f"V {k + i} {x:.17g} {y:.17g} {z:.17g}" for i, (x, y, z) in enumerate(q)]
        k += len(q)
    for s, q in enumerate(polys):
        first = 1 + len(q) * s
        verts = " ".join(str(first + i) for i in range(len(q)))
        lines.append(f"S {s + 1} {verts} 0 0 0.9 p{s + 1}")
    lines.append("End of data")
    path.write_text("\n".join(lines) + "\n")


def measure(cmd: list[str], repeat: int, env: dict) -> tuple[float, float, float, float]:
    walls, cpus = [], []
    for _ in range(repeat):
        r = subprocess.run(
            ["/usr/bin/time", "-f", "%e %U %S", *cmd], env=env, capture_output=True, text=True, check=True
        )
        wall, user, system = map(float, r.stderr.strip().splitlines()[-1].split())
        walls.append(wall)
        cpus.append(user + system)
    return statistics.median(walls), min(walls), statistics.median(cpus), min(cpus)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=21)
    args = ap.parse_args()

    polys, _ = cube_faces(8)
    with tempfile.TemporaryDirectory() as tmp:
        obj, vs3 = pathlib.Path(tmp, "cube384.obj"), pathlib.Path(tmp, "cube384.vs3")
        write_cube_obj(str(obj), 8)
        write_vs3(vs3, polys)
        env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_THREAD_TIMEOUT"}
        py = sys.executable
        read = "import nusselt; s = nusselt.Scene.from_file({!r}); assert len(s) == 384"
        command = str(pathlib.Path(py).with_name("nusselt"))
        cases = [
            ("python -c pass", [py, "-c", "pass"], {}),
            ("import numpy", [py, "-c", "import numpy"], {}),
            ("import nusselt + read OBJ", [py, "-c", read.format(str(obj))], {}),
            ("import nusselt + read .vs3", [py, "-c", read.format(str(vs3))], {}),
            (
                "  the same, OPENBLAS_THREAD_TIMEOUT=4",
                [py, "-c", read.format(str(vs3))],
                {"OPENBLAS_THREAD_TIMEOUT": "4"},
            ),
            ("nusselt methods (the command)", [command, "methods"], {}),
        ]
        print(f"{'case':40s} {'wall med':>9s} {'min':>6s} {'CPU med':>8s} {'min':>6s}   ({args.repeat} runs)")
        for label, cmd, extra in cases:
            wm, wl, cm, cl = measure(cmd, args.repeat, {**env, **extra})
            print(f"{label:40s} {wm:9.3f} {wl:6.3f} {cm:8.3f} {cl:6.3f}")


if __name__ == "__main__":
    main()
