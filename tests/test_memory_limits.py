"""Real allocation failures under an address-space limit (RLIMIT_AS) in a child process: a
result block that cannot fit, and a file with an absurdly long line, end in a clear error and
an ordinary exit, never in an abort (SIGABRT, exit 134) or a kill.

POSIX only (``resource``); each child imports numpy, scipy and nusselt (about 0.6 GB of address
space before any work), so the limits leave that much room.
"""

import os
import subprocess
import sys
import textwrap

import pytest

resource = pytest.importorskip("resource")

#: The child's address-space limit: room for the interpreter and libraries, not for the work.
LIMIT = 1536 << 20


def _run_limited(code: str, *args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (LIMIT, LIMIT))

    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code), *args],
        preexec_fn=limit,
        capture_output=True,
        text=True,
        timeout=timeout,
        env={**os.environ, "RAYON_NUM_THREADS": "2"},
    )


PLATES = """
import sys
import nusselt

def plates(k):
    # two parallel k x k plates facing each other: nothing blocks, 2 k^2 patches
    out = []
    for z, flip in ((0.0, False), (1.0, True)):
        for i in range(k):
            for j in range(k):
                q = [(i / k, j / k, z), ((i + 1) / k, j / k, z), ((i + 1) / k, (j + 1) / k, z), (i / k, (j + 1) / k, z)]
                out.append(q[::-1] if flip else q)
    return out
"""


@pytest.mark.slow
def test_a_block_that_cannot_fit_is_a_memory_error_not_an_abort():
    # 28 800 patches in one block: room for 4.1e8 pairs (5 GB) in the unobstructed row
    # kernel, under a 1.5 GiB limit: the core itself must refuse (vec! aborted the process)
    code = (
        PLATES
        + """
import numpy as np
from nusselt.methods import resolve

scene = nusselt.Scene.from_polygons(plates(120))
assert scene._core.unobstructed()
try:  # one block of every row, as the core receives it (form_factors grows blocks up to it)
    scene._core.pair_rows(np.arange(len(scene), dtype=np.int64), "auto", resolve("auto", {})[1])
except MemoryError as e:
    print("refused:", e)
    sys.exit(3)
sys.exit(0)
"""
    )
    r = _run_limited(code)
    assert r.returncode == 3, (r.returncode, r.stderr[-2000:])
    assert "cannot allocate a block's column indices: 414705600 entries" in r.stdout, r.stdout


@pytest.mark.slow
def test_the_cli_refuses_a_run_that_cannot_fit_before_any_work(tmp_path):
    # the same scene through the CLI: the memory check sees the address-space limit and refuses
    obj = tmp_path / "plates.obj"
    code = (
        PLATES
        + """
with open(sys.argv[1], "w") as fh:
    for poly in plates(120):
        for p in poly:
            fh.write("v %r %r %r\\n" % p)
    for k in range(2 * 120 * 120):
        fh.write("f %d %d %d %d\\n" % (4 * k + 1, 4 * k + 2, 4 * k + 3, 4 * k + 4))
"""
    )
    subprocess.run([sys.executable, "-c", code, str(obj)], check=True, timeout=120)
    run = "import sys; from nusselt.cli import main; sys.exit(main(sys.argv[1:]))"
    r = _run_limited(run, "matrix", str(obj), "-o", str(tmp_path / "F.npz"), "-q")
    assert r.returncode == 2, (r.returncode, r.stderr[-2000:])
    assert "nusselt: error:" in r.stderr and "memory" in r.stderr, r.stderr
    assert not (tmp_path / "F.npz").exists()


_LONG_LINES = {
    # a 24 MB face line (the reproducer, 100 MB, aborted under 4 GiB)
    "long.obj": (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf", b" 1 2 3", b"\n", 4),
    # the IDF reader streams through the same line reader: a 24 MB field list on line 2
    "long.idf": (b"Version,9.4;\nZone,Z", b",0", b";\n", 2),
}


@pytest.mark.parametrize("name", sorted(_LONG_LINES))
def test_an_absurdly_long_line_is_refused_without_reading_it_whole(tmp_path, name):
    # refused when the reader has read 16 MiB of the line, never held whole or split into
    # Python objects, under the address-space limit
    head, unit, tail, line = _LONG_LINES[name]
    path = tmp_path / name
    with open(path, "wb") as fh:
        fh.write(head)
        chunk = unit * (1 << 16)
        for _ in range(24 * (1 << 20) // len(chunk)):
            fh.write(chunk)
        fh.write(tail)
    code = """
    import sys
    import nusselt
    try:
        nusselt.Scene.from_file(sys.argv[1])
    except ValueError as e:
        print("refused:", e)
        sys.exit(3)
    """
    r = _run_limited(code, str(path))
    assert r.returncode == 3, (r.returncode, r.stderr[-2000:])
    assert f"{name}, line {line}: longer than 16 MiB" in r.stdout, r.stdout


@pytest.mark.slow
def test_a_100_000_patch_scene_is_refused_up_front_with_the_numbers(monkeypatch):
    """Issue 21's 1e5-patch criterion: the closed cube of 99 846 patches faces 83 % of its pairs
    (167 GiB at the peak): refused before any block is computed, with the estimate, the
    threshold and float32 hints (given 64 GiB: any machine of this size refuses it too)."""
    from conftest import cube_faces

    import nusselt
    from nusselt import blocks, budget

    polys, _ = cube_faces(129)
    scene = nusselt.Scene.from_polygons(polys)
    monkeypatch.setattr(budget, "available_memory", lambda: 64 << 30)
    monkeypatch.setattr(blocks, "run_blocks", lambda *a, **k: pytest.fail("computed"))
    with pytest.raises(MemoryError) as e:
        nusselt.form_factors(scene)
    msg = str(e.value)
    assert "99846 receivers" in msg and "expected to hold" in msg and "GiB" in msg
    assert "threshold" in msg and "float32" in msg
