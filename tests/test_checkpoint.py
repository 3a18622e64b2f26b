"""Checkpoints refuse what they cannot trust (issue 23 item 10) and files are written
durably with the umask's mode and no stray temporaries (item 12). Each test reproduces a
failure of the checkpoint or writer code as it was: a traceback (EOFError, BadZipFile,
KeyError, AttributeError), a resume that trusted another scene's blocks, no fsync, files
of mode 0600, and a temporary left behind by a killed write."""

import json
import os
import signal
import subprocess
import sys

import numpy as np
import pytest
from conftest import cube_faces, write_cube_obj

import nusselt
from nusselt import checkpoint as ck
from nusselt.cli import main
from nusselt.io import atomic


def _scene(n=3):
    polys, which = cube_faces(n)
    return nusselt.Scene.from_polygons(polys, surface=[str(w) for w in which])


def _run(scene, path, **kw):
    return nusselt.form_factors(scene, checkpoint=path, block_size=200, **kw)


def _interrupted(tmp_path, scene=None, **kw):
    """A checkpoint directory as a killed run leaves it: manifest and some finished blocks."""
    scene = scene or _scene()
    path = tmp_path / "ck"
    _run(scene, path, **kw)  # a finished run's checkpoint holds every block
    blocks = sorted(p for p in path.iterdir() if p.name.startswith("block_"))
    for p in blocks[len(blocks) // 2 :]:
        p.unlink()
    return scene, path, blocks[: len(blocks) // 2]


def test_resume_of_an_intact_checkpoint_gives_the_identical_matrix(tmp_path):
    scene, path, kept = _interrupted(tmp_path)
    ref = nusselt.form_factors(scene, block_size=200)
    again = _run(scene, path, resume=True)
    assert len(kept) >= 2
    assert np.array_equal(ref.matrix.data, again.matrix.data)
    assert np.array_equal(ref.matrix.indices, again.matrix.indices)


@pytest.mark.parametrize("damage", ["truncate", "garbage", "empty", "bitflip", "drop_key", "foreign_meta"])
def test_a_damaged_block_is_refused_naming_the_directory_and_block(tmp_path, damage):
    scene, path, kept = _interrupted(tmp_path)
    victim = kept[1]
    raw = victim.read_bytes()
    if damage == "truncate":  # was EOFError / BadZipFile
        victim.write_bytes(raw[: len(raw) // 2])
    elif damage == "garbage":
        victim.write_bytes(os.urandom(len(raw)))
    elif damage == "empty":
        victim.write_bytes(b"")
    elif damage in ("bitflip", "drop_key", "foreign_meta"):
        with np.load(victim) as z:
            arrays = {k: z[k] for k in z.files}
        if damage == "bitflip":  # a whole zip with one value changed: only the content hash sees it
            arrays["data"] = arrays["data"].copy()
            arrays["data"][0] = np.nextafter(arrays["data"][0], 1.0)
        elif damage == "drop_key":  # was KeyError
            del arrays["indptr"]
        else:
            meta = json.loads(str(arrays["meta"]))
            meta["digest"] = "0" * 64
            arrays["meta"] = np.array(json.dumps(meta))
        with open(victim, "wb") as fh:
            np.savez(fh, **arrays)
    with pytest.raises(ValueError) as e:
        _run(scene, path, resume=True)
    msg = str(e.value)
    assert str(path) in msg and victim.name in msg
    # deleting the damaged block recomputes just it: the identical matrix
    victim.unlink()
    ref = nusselt.form_factors(scene, block_size=200)
    assert np.array_equal(_run(scene, path, resume=True).matrix.data, ref.matrix.data)


def test_a_block_moved_to_another_index_is_refused(tmp_path):
    scene, path, kept = _interrupted(tmp_path)
    kept[1].unlink()
    os.link(kept[0], kept[1])  # block 0 under block 1's name
    with pytest.raises(ValueError, match="holds block 0, not 1"):
        _run(scene, path, resume=True)


@pytest.mark.parametrize("text", ["", "{", "[1, 2]", '{"format": "nusselt-checkpoint"}', "\x00\xff"])
def test_a_damaged_manifest_is_refused(tmp_path, text):
    scene, path, _ = _interrupted(tmp_path)
    (path / "manifest.json").write_bytes(text.encode("latin-1"))  # "[1, 2]" was AttributeError
    with pytest.raises(ValueError, match="manifest.json is damaged"):
        _run(scene, path, resume=True)


def test_blocks_without_a_manifest_are_never_trusted(tmp_path):
    """Stray blocks of another scene in a directory without manifest (the resume used to
    take them: exit 0, F off by 0.19) are refused."""
    polys, which = cube_faces(3, size=2.0)
    other = nusselt.Scene.from_polygons(polys, surface=[str(w) for w in which])
    _, path, _ = _interrupted(tmp_path, scene=other)
    (path / "manifest.json").unlink()
    with pytest.raises(ValueError, match="no manifest.json"):
        _run(_scene(3), path, resume=True)


def test_a_block_of_another_scene_is_refused_even_with_a_manifest(tmp_path):
    a = _scene(3)
    polys, which = cube_faces(3, size=2.0)
    b = nusselt.Scene.from_polygons(polys, surface=[str(w) for w in which])
    _, _, kept_a = _interrupted(tmp_path / "a", scene=a)
    _, pb, kept_b = _interrupted(tmp_path / "b", scene=b)
    kept_b[0].unlink()
    os.link(kept_a[0], kept_b[0])
    with pytest.raises(ValueError, match="belongs to another run"):
        _run(b, pb, resume=True)


@pytest.mark.parametrize(
    "change,expect",
    [
        ({"method": "analytic"}, "the method ('auto' then, 'analytic' now)"),
        ({"tol": 1e-6}, "the options (tol="),
        ({"scene": "bigger"}, "the scene geometry"),
    ],
)
def test_a_refused_resume_says_what_changed(tmp_path, change, expect):
    scene, path, _ = _interrupted(tmp_path)
    kw = {"checkpoint": path, "resume": True, "block_size": 200}
    if change.pop("scene", None):
        polys, which = cube_faces(3, size=1.5)
        scene = nusselt.Scene.from_polygons(polys, surface=[str(w) for w in which])
    with pytest.raises(ValueError) as e:
        nusselt.form_factors(scene, **kw, **change)
    assert expect in str(e.value), str(e.value)


def test_cli_refuses_a_damaged_checkpoint_with_exit_2_and_one_line(tmp_path, capsys):
    obj = tmp_path / "cube.obj"
    write_cube_obj(obj, 3)
    out = tmp_path / "f.npz"
    partial = tmp_path / "f.npz.partial"
    # a checkpoint as a killed run leaves it: made by the library with the CLI's settings
    nusselt.form_factors(nusselt.Scene.from_file(obj), checkpoint=partial, block_size=200)
    blocks = sorted(partial.glob("block_*.npz"))
    blocks[0].write_bytes(blocks[0].read_bytes()[:100])
    assert main(["matrix", str(obj), "-o", str(out), "-q", "--block-size", "200", "--resume"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and blocks[0].name in err and str(partial) in err
    assert not out.exists()


def test_blocks_and_manifest_are_fsynced_before_rename(tmp_path, monkeypatch):
    events = []
    real_fsync, real_replace = os.fsync, os.replace
    monkeypatch.setattr(os, "fsync", lambda fd: (events.append("fsync"), real_fsync(fd))[1])
    monkeypatch.setattr(
        os, "replace", lambda a, b: (events.append(("replace", os.path.basename(b))), real_replace(a, b))[1]
    )
    _run(_scene(2), tmp_path / "ck")
    renames = [i for i, e in enumerate(events) if isinstance(e, tuple)]
    assert renames and any(events[i][1] == "manifest.json" for i in renames)
    for i in renames:  # the file before its rename, the directory after it
        assert events[i - 1] == "fsync" and events[i + 1] == "fsync"


# --- atomic writes (issue 23 item 12) --------------------------------------------------------


@pytest.mark.parametrize("umask", [0o022, 0o002, 0o077])
def test_outputs_honour_the_umask(tmp_path, umask):
    old = os.umask(umask)
    try:
        res = nusselt.form_factors(_scene(1))
        for name in ("f.npz", "f.csv", "f.txt"):
            nusselt.io.write_result(tmp_path / name, res)
            assert (os.stat(tmp_path / name).st_mode & 0o777) == 0o666 & ~umask, name
    finally:
        os.umask(old)


def test_an_exception_while_writing_leaves_neither_file_nor_temporary(tmp_path):
    target = tmp_path / "x.txt"
    with pytest.raises(RuntimeError), atomic.atomic_open(target, "w") as fh:
        fh.write("half")
        raise RuntimeError("disk gone")
    assert os.listdir(tmp_path) == []


def test_a_temporary_left_by_a_killed_write_is_recognisable_and_removed_next_time(tmp_path):
    target = tmp_path / "big.npz"
    code = (
        "import sys, time; from nusselt.io.atomic import atomic_open\n"
        "with atomic_open(sys.argv[1], 'wb') as fh:\n"
        "    fh.write(b'x' * 1000); fh.flush(); print('writing', flush=True); time.sleep(60)\n"
    )
    p = subprocess.Popen([sys.executable, "-c", code, str(target)], stdout=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "writing"
        os.kill(p.pid, signal.SIGKILL)
    finally:
        p.wait()
    left = os.listdir(tmp_path)
    assert len(left) == 1 and left[0].startswith(".big.npz.nusselt-") and left[0].endswith(".tmp")
    # a temporary of a running writer is left alone
    live = tmp_path / f".big.npz.nusselt-{os.getpid()}-abcd.tmp"
    live.write_bytes(b"")
    nusselt.io.write_result(target, nusselt.form_factors(_scene(1)))
    assert sorted(os.listdir(tmp_path)) == sorted(["big.npz", live.name])
    assert nusselt.io.load_npz(target)["matrix"].shape == (6, 6)


def test_a_removal_stopped_half_way_leaves_a_checkpoint_that_resumes(tmp_path, monkeypatch):
    """Ctrl-C during the removal of a finished run's checkpoint (after the output is written)
    used to leave blocks without their manifest, which every later --resume refused."""
    scene = _scene()
    path = tmp_path / "ck"
    ref = _run(scene, path)
    real_unlink, calls = os.unlink, []

    def unlink(p, *a, **k):
        calls.append(p)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real_unlink(p, *a, **k)

    monkeypatch.setattr(os, "unlink", unlink)
    with pytest.raises(KeyboardInterrupt):
        ck.remove_dir(path)
    monkeypatch.setattr(os, "unlink", real_unlink)
    assert (path / "manifest.json").exists()
    assert np.array_equal(_run(scene, path, resume=True).matrix.data, ref.matrix.data)


def test_a_checkpoint_in_use_by_another_run_is_refused(tmp_path):
    scene = _scene(2)
    run = ck.describe_run(scene, "auto", {}, "pairs")
    first = ck.Checkpoint(tmp_path / "ck", run, resume=False)
    try:
        code = (
            "import fcntl, os, sys\nfd = os.open(sys.argv[1], os.O_RDWR)\n"
            "try:\n    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)\nexcept BlockingIOError:\n    sys.exit(3)\n"
        )
        p = subprocess.run([sys.executable, "-c", code, str(tmp_path / "ck" / "lock")], check=False)
        assert p.returncode == 3  # another process cannot take it
        with pytest.raises(ValueError, match="in use by another running nusselt"):
            ck.Checkpoint(tmp_path / "ck", run, resume=True)  # flock: per open file, so here too
    finally:
        first.close()


# --- when the checkpoint is written (deferral) -----------------------------------------------


class _Clock:
    """Stands in for time.perf_counter in nusselt.blocks: every reading is ``step`` s later."""

    def __init__(self, step):
        self.now, self.step = 0.0, step

    def __call__(self):
        self.now += self.step
        return self.now


def _block_files(path):
    return sorted(p.name for p in path.glob("block_*.npz")) if path.is_dir() else []


def _same(a, b):
    return all(np.array_equal(getattr(a.matrix, k), getattr(b.matrix, k)) for k in ("indptr", "indices", "data"))


def test_a_run_shorter_than_checkpoint_after_writes_no_checkpoint(tmp_path, monkeypatch):
    scene = _scene(4)
    ref = nusselt.form_factors(scene, block_size=200)
    monkeypatch.setattr(ck.Checkpoint, "save", lambda *a: pytest.fail("a block was written"))
    res = _run(scene, tmp_path / "ck", checkpoint_after=1e9)
    assert not (tmp_path / "ck").exists() and _same(ref, res)


def test_the_held_blocks_are_written_once_checkpoint_after_has_passed(tmp_path, monkeypatch):
    """Each clock reading is 1 s later: a block's compute ends 2k s in; with a deferral of
    5.5 s the first two blocks are held, written with the third, later ones as they finish,
    and the checkpoint resumes to the identical matrix."""
    scene = _scene(4)
    ref = nusselt.form_factors(scene, block_size=200)
    writes = []
    save = ck.Checkpoint.save

    def record(self, k, start, stop, b):
        writes.append((k, len(clock_readings)))
        save(self, k, start, stop, b)

    clock = _Clock(1.0)
    clock_readings = []
    monkeypatch.setattr(nusselt.blocks.time, "perf_counter", lambda: clock_readings.append(0) or clock())
    monkeypatch.setattr(ck.Checkpoint, "save", record)
    res = _run(scene, tmp_path / "ck", checkpoint_after=5.5)
    monkeypatch.undo()
    assert _same(ref, res)
    assert [k for k, _ in writes] == list(range(len(writes))) and len(writes) >= 4
    at = [r for _, r in writes]
    assert at[0] == at[1] == at[2] == 7  # the first three together, after the third block (reading 7)
    assert all(b > a for a, b in zip(at[2:], at[3:]))  # then one by one
    path = tmp_path / "ck"
    assert len(_block_files(path)) == len(writes)
    files = _block_files(path)
    for f in files[len(files) // 2 :]:
        (path / f).unlink()
    assert _same(ref, _run(scene, path, resume=True))


def test_ctrl_c_while_the_checkpoint_is_deferred_writes_the_finished_blocks_there(tmp_path, monkeypatch):
    from test_interrupt import _Bar

    scene = _scene(4)
    ref = nusselt.form_factors(scene, block_size=200)
    monkeypatch.setattr(nusselt.api, "_progress", lambda *a, **k: _Bar(stop_after=3))
    with pytest.raises(KeyboardInterrupt, match="resume=True") as e:
        _run(scene, tmp_path / "ck", checkpoint_after=1e9, progress=True)
    monkeypatch.undo()
    assert str(tmp_path / "ck") in str(e.value)
    assert len(_block_files(tmp_path / "ck")) == 3
    assert _same(ref, _run(scene, tmp_path / "ck", resume=True, checkpoint_after=1e9))


def test_a_threshold_that_drops_pairs_ends_the_deferral_at_once(tmp_path, monkeypatch):
    scene = _scene(4)
    ref = nusselt.form_factors(scene, block_size=200, threshold=0.02)
    res = _run(scene, tmp_path / "ck", checkpoint_after=1e9, threshold=0.02)
    assert res.info["dropped"] > 0 and _same(ref, res)
    assert len(_block_files(tmp_path / "ck")) >= 2  # held blocks would double the memory


def test_a_directory_that_holds_a_run_is_checked_before_any_work_even_when_deferred(tmp_path, monkeypatch):
    scene, path, _ = _interrupted(tmp_path)
    monkeypatch.setattr(nusselt.blocks, "run_blocks", lambda *a, **k: pytest.fail("computed"))
    with pytest.raises(ValueError, match="already holds a run"):
        nusselt.form_factors(scene, checkpoint=path, checkpoint_after=1e9)
    (path / "manifest.json").unlink()
    with pytest.raises(ValueError, match="no manifest.json"):
        nusselt.form_factors(scene, checkpoint=path, checkpoint_after=1e9)


def test_the_cli_writes_no_checkpoint_for_a_short_run_and_from_the_start_with_checkpoint(tmp_path, monkeypatch):
    obj = tmp_path / "cube.obj"
    write_cube_obj(obj, 4)
    saved = []
    save = ck.Checkpoint.save
    monkeypatch.setattr(ck.Checkpoint, "save", lambda self, *a: saved.append(self.path) or save(self, *a))
    assert main(["matrix", str(obj), "-o", str(tmp_path / "a.npz"), "-q", "--block-size", "200"]) == 0
    assert saved == [] and not (tmp_path / "a.npz.partial").exists()
    d = tmp_path / "ck"
    assert (
        main(["matrix", str(obj), "-o", str(tmp_path / "b.npz"), "-q", "--block-size", "200", "--checkpoint", str(d)])
        == 0
    )
    assert len(saved) >= 2 and set(saved) == {str(d)} and not d.exists()  # removed once the output is written
    a, b = (nusselt.io.load_npz(tmp_path / f)["matrix"] for f in ("a.npz", "b.npz"))
    assert np.array_equal(a.data, b.data) and np.array_equal(a.indices, b.indices)


def test_holds_run_sees_a_manifest_blocks_or_a_zone_checkpoint_inside(tmp_path):
    assert not ck.holds_run(tmp_path / "none")
    (tmp_path / "empty").mkdir()
    assert not ck.holds_run(tmp_path / "empty")
    _run(_scene(3), tmp_path / "zones" / "zone0")  # as nusselt.zones lays out a building's run
    assert ck.holds_run(tmp_path / "zones") and ck.holds_run(tmp_path / "zones" / "zone0")
    (tmp_path / "zones" / "zone0" / "manifest.json").unlink()
    assert ck.holds_run(tmp_path / "zones")  # stray blocks: refused when opened, before any work
