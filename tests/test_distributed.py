"""Distributed runs on a dask.distributed LocalCluster: the same matrix as a local run, the
scene built once per worker, and no finished block lost when a worker is killed mid-run."""

import json
import logging
import os

import numpy as np
import pytest
from conftest import cube_faces, write_cube_obj

import nusselt
import nusselt.blocks
from nusselt import checkpoint as ck

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def client():
    c = distributed.Client(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None, silence_logs=logging.ERROR
    )
    yield c
    c.close()


def _scene():
    polys, which = cube_faces(3)
    return nusselt.Scene.from_polygons(polys, surface=[str(w) for w in which])


def _same(a, b):
    a, b = a.matrix, b.matrix
    assert a.shape == b.shape and a.nnz == b.nnz
    assert np.array_equal(a.indptr, b.indptr) and np.array_equal(a.indices, b.indices)
    assert np.array_equal(a.data, b.data)  # bit for bit


@pytest.mark.parametrize("method,opts", [("auto", {}), ("raytrace", {"rays": 64})])
def test_cluster_gives_the_identical_matrix_and_ships_the_scene_once(client, tmp_path, method, opts):
    scene = _scene()
    local = nusselt.form_factors(scene, method=method, block_size=400, **opts)
    far = nusselt.form_factors(scene, method=method, block_size=400, client=client, checkpoint=tmp_path / "ck", **opts)
    _same(local, far)
    if local.std_err is not None:
        assert np.array_equal(local.std_err.data, far.std_err.data)
    # several blocks, each in the checkpoint; the scene built at most once per worker process
    assert len(os.listdir(tmp_path / "ck")) > 4
    builds = client.run(lambda: __import__("nusselt.distributed").distributed.scene_builds())
    assert all(v <= 1 for per_worker in builds.values() for v in per_worker.values())
    assert sum(len(v) for v in builds.values()) >= 1


class KillOnce(distributed.WorkerPlugin):
    """Kills its worker process (os._exit, as a crash or the OOM killer would) once, when the
    ``after``-th block task of the run finishes on any worker: the block just computed is lost
    with the process (the client has not fetched it) and must be rerun elsewhere."""

    def __init__(self, workdir, after):
        self.workdir, self.after = str(workdir), after

    def transition(self, key, start, finish, **kw):
        if finish == "memory" and "nusselt-block" in str(key):
            open(os.path.join(self.workdir, f"done-{os.getpid()}-{abs(hash(str(key)))}"), "w").close()
            marker = os.path.join(self.workdir, "killed")
            if len(os.listdir(self.workdir)) >= self.after and not os.path.exists(marker):
                open(marker, "w").close()
                os._exit(1)


def test_killing_a_worker_loses_no_finished_block(client, tmp_path):
    scene = _scene()
    local = nusselt.form_factors(scene, block_size=100)
    work, ckdir = tmp_path / "work", tmp_path / "ck"
    work.mkdir()
    client.register_plugin(KillOnce(work, after=4), name="kill-once")
    saved = []
    orig = ck.Checkpoint.save

    def spy(self, k, start, stop, b):
        saved.append((start, stop))
        orig(self, k, start, stop, b)

    try:
        ck.Checkpoint.save = spy
        far = nusselt.form_factors(scene, block_size=100, client=client, checkpoint=ckdir)
    finally:
        ck.Checkpoint.save = orig
        client.unregister_worker_plugin("kill-once")
    assert (work / "killed").exists()  # a worker did die mid-run
    _same(local, far)
    plan = nusselt.blocks.plan_range(len(scene.receivers), "pairs", 100)
    assert sorted(saved) == plan  # every block written exactly once
    client.wait_for_workers(2, timeout=30)


class _CancelsFirstBlock:
    """A client whose first block task is cancelled as soon as it is submitted, as the
    scheduler does with a task it forgot when a worker died handing over its result."""

    def __init__(self, client):
        self._client, self.cancelled = client, []

    def submit(self, *args, **kwargs):
        f = self._client.submit(*args, **kwargs)
        if not self.cancelled and "nusselt-block" in str(kwargs.get("key")):
            self._client.cancel([f])
            self.cancelled.append(kwargs["key"])
        return f

    def __getattr__(self, name):
        return getattr(self._client, name)


def test_a_block_the_scheduler_cancels_is_computed_again(client):
    scene = _scene()
    local = nusselt.form_factors(scene, block_size=100)
    flaky = _CancelsFirstBlock(client)
    far = nusselt.form_factors(scene, block_size=100, client=flaky)
    assert len(flaky.cancelled) == 1  # one block was lost and had to be resubmitted
    _same(local, far)


def test_cli_dask_local(tmp_path):
    from nusselt.cli import main

    obj = tmp_path / "cube.obj"
    write_cube_obj(obj, 2)
    out_local, out_far = tmp_path / "a.npz", tmp_path / "b.npz"
    assert main(["matrix", str(obj), "-o", str(out_local), "-q", "--block-size", "50"]) == 0
    assert main(["matrix", str(obj), "-o", str(out_far), "-q", "--block-size", "50", "--dask", "local:1"]) == 0
    a, b = nusselt.io.load_npz(out_local), nusselt.io.load_npz(out_far)
    assert np.array_equal(a["matrix"].toarray(), b["matrix"].toarray())


def test_a_distributed_run_resumes_from_its_checkpoint(client, tmp_path):
    scene = _scene()
    ckdir = tmp_path / "ck"
    first = nusselt.form_factors(scene, block_size=150, client=client, checkpoint=ckdir)
    blocks = sorted(ckdir.glob("block_*.npz"))
    gone = []
    for p in blocks[::2]:
        with np.load(p) as z:
            meta = json.loads(str(z["meta"]))
        gone.append((meta["start"], meta["stop"]))
        p.unlink()  # as a client killed mid-run leaves it
    saved = []
    orig = ck.Checkpoint.save

    def spy(self, k, start, stop, b):
        saved.append((start, stop))
        orig(self, k, start, stop, b)

    try:
        ck.Checkpoint.save = spy
        again = nusselt.form_factors(scene, block_size=150, client=client, checkpoint=ckdir, resume=True)
    finally:
        ck.Checkpoint.save = orig
    _same(first, again)
    assert sorted(saved) == sorted(gone)  # only the missing blocks were computed
