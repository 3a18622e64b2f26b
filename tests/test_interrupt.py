"""Ctrl-C keeps every finished block and blocks are sized so the progress bar moves soon
(issue 23 item 9): the run used to wait for a block of the fixed default size (29-56 s; the
progress bar stayed blank for 68 s on a 1 287-patch box) and then discard it (0 blocks kept
without a checkpoint). Where the blocks are cut must change no value, so adaptive sizing
stays resumable."""

import os
import re
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from conftest import cube_faces, write_cube_obj

import nusselt
from nusselt import api, blocks
from nusselt import checkpoint as ck


def _cube(n):
    polys, which = cube_faces(n)
    return nusselt.Scene.from_polygons(polys, surface=[str(w) for w in which])


def _obstructed_room():
    # a 3 x 3 x 3-patch room with a table-like plate in it: the obstructed path
    polys, which = cube_faces(3, size=2.0)
    table = [[(0.6, 0.6, 0.8), (1.4, 0.6, 0.8), (1.4, 1.4, 0.8), (0.6, 1.4, 0.8)]]
    under = [[(0.6, 0.6, 0.79), (0.6, 1.4, 0.79), (1.4, 1.4, 0.79), (1.4, 0.6, 0.79)]]
    return nusselt.Scene.from_polygons(
        [*polys, *np.array(table, dtype=float), *np.array(under, dtype=float)],
        surface=[str(w) for w in which] + ["table", "under"],
    )


class _Bar:
    """Stands in for tqdm: records every update; ``stop_after`` raises KeyboardInterrupt (as
    Ctrl-C does between blocks) once that many blocks are done."""

    def __init__(self, stop_after=None):
        self.updates, self.stop_after = [], stop_after

    def update(self, k):
        self.updates.append(k)
        if self.stop_after is not None and len(self.updates) >= self.stop_after:
            raise KeyboardInterrupt

    def close(self):
        pass


def _same(a, b):
    return (
        np.array_equal(a.matrix.indptr, b.matrix.indptr)
        and np.array_equal(a.matrix.indices, b.matrix.indices)
        and np.array_equal(a.matrix.data, b.matrix.data)
    )


def test_the_first_block_is_small_and_blocks_grow_on_a_mid_size_scene(monkeypatch):
    scene = _cube(12)  # 864 patches: 372 816 pairs, one block of the default size before
    bar = _Bar()
    monkeypatch.setattr(api, "_progress", lambda *a, **k: bar)
    nusselt.form_factors(scene, progress=True)
    n = len(scene.receivers)
    assert sum(bar.updates) == n
    # the first block holds about FIRST_PAIRS pairs: its row, the first, has n - 1 of them
    assert bar.updates[0] <= max(1, blocks.FIRST_PAIRS // (n - 1) + 1)
    assert len(bar.updates) >= 4


def test_the_sizer_aims_at_the_target_grows_boundedly_and_keeps_the_cap():
    n = 1000
    s = blocks.Sizer(n, "pairs", block_size=50_000, target=0.5)
    a = s.stop(0, n)
    assert a == 2  # 999 + 998 pairs reach the first block's 1 024
    s.observe(0, a, 1e-4)  # very fast: growth is bounded, not 5 000-fold
    assert s.work == blocks.GROWTH * (999 + 998)
    for _ in range(10):
        s.observe(0, a, 1e-6)
    assert s.work == 50_000  # never above the cap
    s.observe(0, 100, 10.0)  # slow: the next block aims at half a second of that speed
    done = float(s.cum[100] - s.cum[0])
    assert s.work == pytest.approx(done * 0.05)
    assert s.stop(990, 995) == 995  # never past the limit (the next finished block)
    rows = blocks.Sizer(10, "rows", block_size=10**9, threads=2)
    assert rows.stop(0, 10) == 2  # row methods: one row per core first


@pytest.mark.parametrize(
    "make,kw",
    [
        (_obstructed_room, {"method": "auto"}),
        (lambda: _cube(3), {"method": "montecarlo", "seed": 5, "samples": 2000}),
    ],
)
def test_block_boundaries_change_no_value(make, kw):
    scene = make()
    one = nusselt.form_factors(scene, block_size=1, **kw)  # a block per row
    whole = nusselt.form_factors(scene, block_size=10**12, **kw)
    assert _same(one, whole)


def test_a_resume_with_another_block_size_gives_the_identical_matrix(tmp_path, monkeypatch):
    scene = _obstructed_room()
    ref = nusselt.form_factors(scene)
    monkeypatch.setattr(api, "_progress", lambda *a, **k: _Bar(stop_after=3))
    with pytest.raises(KeyboardInterrupt, match="resume=True"):
        nusselt.form_factors(scene, checkpoint=tmp_path / "ck", block_size=40, progress=True)
    monkeypatch.undo()
    assert len([f for f in os.listdir(tmp_path / "ck") if f.startswith("block_")]) == 3
    again = nusselt.form_factors(scene, checkpoint=tmp_path / "ck", resume=True, block_size=7)
    assert _same(ref, again)


def test_ctrl_c_without_a_checkpoint_saves_the_finished_blocks_and_says_where(monkeypatch):
    scene = _cube(6)
    ref = nusselt.form_factors(scene)
    monkeypatch.setattr(api, "_progress", lambda *a, **k: _Bar(stop_after=4))
    with pytest.raises(KeyboardInterrupt) as e:
        nusselt.form_factors(scene, progress=True)
    monkeypatch.undo()
    msg = str(e.value)
    path = msg.split("saved to checkpoint ")[1].split(";")[0]
    try:
        assert "resume=True" in msg and os.path.isdir(path)
        assert len([f for f in os.listdir(path) if f.startswith("block_")]) == 4
        assert _same(ref, nusselt.form_factors(scene, checkpoint=path, resume=True))
    finally:
        ck.remove_dir(path)


def test_overlapping_blocks_are_refused(tmp_path):
    scene = _cube(3)
    path = tmp_path / "ck"
    nusselt.form_factors(scene, checkpoint=path, block_size=100)
    c = ck.Checkpoint(path, ck.describe_run(scene, "auto", nusselt.methods.resolve("auto", {})[1], "pairs"), True)
    try:
        start, stop, b = c.load(0, scene.receivers)
        c.save(c.next_index(), start, stop, b)  # the same rows twice
        with pytest.raises(ValueError, match="overlaps block 0"):
            c.load_all(scene.receivers)
    finally:
        c.close()


_CLI = [sys.executable, "-c", "import sys; from nusselt.cli import main; sys.exit(main(sys.argv[1:]))", "matrix"]


def test_sigint_to_the_cli_keeps_finished_blocks_and_resume_is_identical(tmp_path):
    """SIGINT to a running ``nusselt matrix`` (as Ctrl-C sends it) while its checkpoint is
    still deferred (nothing on disk yet): exit 130, the finished blocks written to
    OUTPUT.partial, a message naming it and --resume, and the resumed matrix is the
    uninterrupted one."""
    obj = tmp_path / "cube.obj"
    write_cube_obj(obj, 20)  # 2 400 patches: about a second of work on an idle host
    ref, out = tmp_path / "ref.npz", tmp_path / "out.npz"
    subprocess.run([*_CLI, str(obj), "-o", str(ref), "-q"], check=True, capture_output=True)
    partial = str(out) + ".partial"
    # the progress bar (stderr) says when rows are done; nothing is on disk before 10 s
    p = subprocess.Popen([*_CLI, str(obj), "-o", str(out)], stderr=subprocess.PIPE)
    seen, done = b"", []
    try:
        os.set_blocking(p.stderr.fileno(), False)
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and p.poll() is None:
            seen += p.stderr.read() or b""
            done = [int(x) for x in re.findall(rb"\| *([0-9]+)/2400 ", seen)]
            if done and done[-1] == 2400:
                break  # every row is done: too late to interrupt the computation
            if done and done[-1] > 0:
                break
            time.sleep(0.005)
        if p.poll() is not None or (done and done[-1] == 2400):
            pytest.skip("the rows finished before they could be interrupted (a very fast machine)")
        assert not os.path.exists(partial)  # deferred: nothing written yet
        p.send_signal(signal.SIGINT)
        os.set_blocking(p.stderr.fileno(), True)
        err = (seen + p.communicate(timeout=60)[1]).decode()
    finally:
        if p.poll() is None:
            p.kill()
    if p.returncode == 0 or "written in full" in err:
        pytest.skip("the rows finished before SIGINT arrived")
    assert p.returncode == 130, err
    last = err.strip().splitlines()[-1]
    assert partial in last and "--resume" in last and "Traceback" not in err, err
    assert sum(f.startswith("block_") for f in os.listdir(partial)) >= 1
    subprocess.run([*_CLI, str(obj), "-o", str(out), "-q", "--resume"], check=True, capture_output=True)
    a, b = nusselt.io.load_npz(str(ref))["matrix"], nusselt.io.load_npz(str(out))["matrix"]
    assert np.array_equal(a.indptr, b.indptr) and np.array_equal(a.indices, b.indices)
    assert np.array_equal(a.data, b.data)
    assert not os.path.exists(partial)


def _writer_interrupted(monkeypatch, times):
    """nusselt.io.write_result as the CLI calls it, with ``times`` SIGINTs (Ctrl-C) sent to
    this process as it starts writing."""
    real = nusselt.io.write_result

    def write(*args, **kwargs):
        for _ in range(times):
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)  # the handler runs here, between bytecodes
        return real(*args, **kwargs)

    monkeypatch.setattr(nusselt.io, "write_result", write)


def test_ctrl_c_while_the_output_is_written_finishes_it(tmp_path, monkeypatch, capsys):
    """A Ctrl-C after every row is computed, while the rows are held in memory only (the
    deferred checkpoint is not written yet), used to lose them all: the output is now
    finished, and the exit status still says the run was interrupted."""
    from nusselt.cli import main

    obj, out = tmp_path / "cube.obj", tmp_path / "out.npz"
    write_cube_obj(obj, 4)
    _writer_interrupted(monkeypatch, 1)
    assert main(["matrix", str(obj), "-o", str(out), "-q"]) == 130
    err = capsys.readouterr().err
    assert "finishing" in err and "written in full" in err, err
    assert not os.path.exists(str(out) + ".partial")
    ref = nusselt.form_factors(nusselt.Scene.from_file(str(obj)))
    got = nusselt.io.load_npz(str(out))["matrix"]
    assert np.array_equal(got.indptr, ref.matrix.indptr) and np.array_equal(got.data, ref.matrix.data)


def test_a_second_ctrl_c_abandons_the_output_and_keeps_the_checkpoint(tmp_path, monkeypatch, capsys):
    from nusselt.cli import main

    obj, out, part = tmp_path / "cube.obj", tmp_path / "out.npz", tmp_path / "ck"
    write_cube_obj(obj, 4)
    _writer_interrupted(monkeypatch, 2)
    assert main(["matrix", str(obj), "-o", str(out), "-q", "--checkpoint", str(part)]) == 130
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert "not written" in last and str(part) in last and "--resume" in last, last
    assert not os.path.exists(out)
    monkeypatch.undo()
    assert main(["matrix", str(obj), "-o", str(out), "-q", "--checkpoint", str(part), "--resume"]) == 0
    ref = nusselt.form_factors(nusselt.Scene.from_file(str(obj)))
    got = nusselt.io.load_npz(str(out))["matrix"]
    assert np.array_equal(got.indptr, ref.matrix.indptr) and np.array_equal(got.data, ref.matrix.data)


def _assembly_interrupted(monkeypatch):
    """assembly.assemble_pairs as form_factors calls it, with a Ctrl-C (KeyboardInterrupt)
    arriving as it starts: every row is computed, the result not yet made."""
    from nusselt import assembly

    real, calls = assembly.assemble_pairs, []

    def assemble(*args, **kwargs):
        calls.append(1)
        if len(calls) == 1:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(assembly, "assemble_pairs", assemble)


def test_ctrl_c_while_the_finished_rows_are_assembled_saves_them(monkeypatch):
    """A Ctrl-C after the last block but before the result is made (the rows held in memory
    only, no checkpoint asked for) used to lose every row: they are now saved, and the
    resumed matrix (which computes no row) is the uninterrupted one."""
    scene = _cube(4)
    ref = nusselt.form_factors(scene)
    _assembly_interrupted(monkeypatch)
    with pytest.raises(KeyboardInterrupt) as e:
        nusselt.form_factors(scene)
    msg = str(e.value)
    path = msg.split("saved to checkpoint ")[1].split(";")[0]
    try:
        assert "all 96 rows were computed" in msg and "resume=True" in msg
        run = ck.describe_run(scene, "auto", nusselt.methods.resolve("auto", {})[1], "pairs")
        c = ck.Checkpoint(path, run, True)
        try:  # every row is there: the resume computes none
            assert sum(stop - start for start, stop, _ in c.load_all(scene.receivers)) == len(scene.receivers)
        finally:
            c.close()
        assert _same(ref, nusselt.form_factors(scene, checkpoint=path, resume=True))
    finally:
        ck.remove_dir(path)


def test_a_late_ctrl_c_in_the_cli_keeps_the_held_blocks_for_resume(tmp_path, monkeypatch, capsys):
    """The CLI defers its checkpoint (nothing on disk in the first 10 s): a Ctrl-C after the
    last block, before the output phase, writes the held blocks to OUTPUT.partial and says
    --resume, which then writes the uninterrupted matrix."""
    from nusselt.cli import main

    obj, out = tmp_path / "cube.obj", tmp_path / "out.npz"
    partial = str(out) + ".partial"
    write_cube_obj(obj, 4)
    _assembly_interrupted(monkeypatch)
    assert main(["matrix", str(obj), "-o", str(out), "-q"]) == 130
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert partial in last and "--resume" in last, last
    assert not os.path.exists(out) and any(f.startswith("block_") for f in os.listdir(partial))
    assert main(["matrix", str(obj), "-o", str(out), "-q", "--resume"]) == 0
    ref = nusselt.form_factors(nusselt.Scene.from_file(str(obj)))
    got = nusselt.io.load_npz(str(out))["matrix"]
    assert np.array_equal(got.indptr, ref.matrix.indptr) and np.array_equal(got.data, ref.matrix.data)
    assert not os.path.exists(partial)
