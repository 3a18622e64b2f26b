"""The method registry of the core, Python's view of it, budgets and Ctrl-C."""

import _thread
import threading
import time

import numpy as np
import pytest
from conftest import rect

import nusselt
from nusselt import _core
from nusselt.methods import METHODS, resolve

A = rect(0, 1, 0, 1)
B = rect(0, 1, 0, 1, z=1.0, flip=True)
BLOCKER = rect(0.3, 0.7, 0.3, 0.7, z=0.5)


def test_python_view_is_the_core_registry():
    core = {m["name"]: m for m in _core.methods()}
    assert list(core) == list(METHODS)
    for name, m in METHODS.items():
        c = core[name]
        assert (m.kind, m.obstructed, m.doc) == (c["kind"], c["obstructed"], c["doc"])
        assert list(m.options) == [o["name"] for o in c["options"]]
        for o in c["options"]:
            mine = m.options[o["name"]]
            assert (mine.default, mine.lo, mine.hi) == (o["default"], o["lo"], o["hi"])


def _outside(o):
    """Values just outside an option's range (none for bool)."""
    if o.kind is bool:
        return []
    lo = o.lo * 0.5 if o.kind is float and o.lo > 0 else o.lo - 1
    hi = o.hi * 2 if o.kind is float else o.hi + 1
    return [v for v in (lo, hi) if not (o.kind is not float and v < 0)]


@pytest.mark.parametrize("name", list(METHODS))
def test_python_and_core_accept_and_refuse_the_same_values(name):
    """Each option's range ends are accepted by both Python's checks and the core (called
    directly, without Python's checks); values just outside are refused by both."""
    m = METHODS[name]
    for k, o in m.options.items():
        inside = [o.default] if o.kind is bool else [o.lo, o.hi]
        for v in inside:
            if (name, k) == ("hemicube", "resolution"):
                v = v - v % 2
            resolve(name, {k: v})
            # a cheap call: the core checks every option before any work
            _check_core(name, {k: v}, ok=True)
        for v in _outside(o):
            with pytest.raises((ValueError, TypeError)):
                resolve(name, {k: v})
            _check_core(name, {k: v}, ok=False)


def _check_core(name, opts, ok):
    """The core's own verdict on an option dict (an empty scene: no work, only the checks)."""
    scene = _core.SceneCore(np.zeros((0, 3)), np.zeros(1, dtype=np.int64), np.zeros(0, dtype=bool), 1e-6)
    call = scene.full_rows if METHODS[name].kind == "rows" else scene.pair_rows
    rows = np.zeros(0, dtype=np.int64)
    if ok:
        call(rows, name, opts)
    else:
        with pytest.raises((ValueError, TypeError, OverflowError)):
            call(rows, name, opts)


@pytest.mark.parametrize("name", [n for n, m in METHODS.items() if m.obstructed])
def test_the_core_default_is_the_listed_default(name):
    """An obstructed pair with no options given to the core equals the pair with every
    option at the default Python lists (so the two cannot disagree on a default)."""
    _, full = resolve(name, {})
    given = _core.view_factor(A, B, [BLOCKER], name, full, 1e-6)
    bare = _core.view_factor(A, B, [BLOCKER], name, {}, 1e-6)
    assert given == bare


def test_tol_is_per_method():
    """`tol` of adaptive is its leaf threshold (it changes the obstructed value); `tol` of
    auto is the unobstructed accuracy (obstructed pairs follow `obstructed_tol`)."""
    loose = nusselt.view_factor(A, B, obstacles=[BLOCKER], method="adaptive", tol=1e-2, max_depth=4)
    tight = nusselt.view_factor(A, B, obstacles=[BLOCKER], method="adaptive", tol=1e-7, max_depth=12)
    assert loose != tight
    exact = nusselt.view_factor(A, B, obstacles=[BLOCKER], method="auto", obstructed_tol=1e-9)
    coarse = nusselt.view_factor(A, B, obstacles=[BLOCKER], method="auto", obstructed_tol=1e-2)
    assert coarse != exact and abs(coarse - exact) <= 1e-2


def test_min_cell_range_is_what_the_core_accepts():
    with pytest.raises(ValueError, match="min_cell"):
        resolve("single-plane", {"min_cell": 1e-5})


def test_budget_exceeded_names_the_budget():
    with pytest.raises(ValueError, match=r"budget=1000 .*raise the method's `budget` option"):
        nusselt.view_factor(A, B, obstacles=[BLOCKER], method="quadrature", budget=1000)
    with pytest.raises(ValueError, match=r"row 0 needs more than budget=10"):
        nusselt.view_factor(A, B, obstacles=[BLOCKER], method="raytrace", budget=10)
    # within the budget: the same value as without one
    assert nusselt.view_factor(A, B, obstacles=[BLOCKER], method="quadrature", budget=10**9) == nusselt.view_factor(
        A, B, obstacles=[BLOCKER], method="quadrature"
    )


def _interrupt_after(seconds):
    t = threading.Timer(seconds, _thread.interrupt_main)
    t.start()
    return t


@pytest.mark.parametrize(
    "method, opts",
    [
        ("adaptive", {"tol": 1e-14, "max_depth": 16, "source": 16, "budget": 2**62}),
        ("nusselt", {"cells": 2**24, "source": 16, "budget": 2**62}),
        ("quadrature", {"order": 32, "control_variate": False, "budget": 2**62}),
    ],
)
def test_ctrl_c_stops_a_single_long_call(method, opts):
    """A call that would run for minutes raises KeyboardInterrupt soon after Ctrl-C (the
    bound is generous: the point is that it stops, not how fast on a loaded machine)."""
    many = [rect(0.1 * k, 0.1 * k + 0.05, 0.2, 0.8, z=0.5) for k in range(10)]
    t0 = time.perf_counter()
    timer = _interrupt_after(0.3)
    try:
        with pytest.raises(KeyboardInterrupt):
            for _ in range(1000):  # a short call repeats until the interrupt lands in one
                nusselt.view_factor(A, B, obstacles=many, method=method, **opts)
    finally:
        timer.cancel()
    assert time.perf_counter() - t0 < 30.0
    # the core is usable again afterwards (the cancellation flag was cleared)
    assert nusselt.view_factor(A, B, method="auto") > 0.19


def test_ctrl_c_keeps_finished_blocks_on_disk(tmp_path):
    """An interrupted scene-wide run keeps every finished block in its checkpoint, and the
    resumed run gives the matrix of an uninterrupted one."""
    from conftest import cube_faces

    polys, _ = cube_faces(6)
    polys = list(polys) + [rect(0.4, 0.6, 0.4, 0.6, z=0.5), rect(0.4, 0.6, 0.4, 0.6, z=0.5, flip=True)]
    scene = nusselt.Scene.from_polygons(polys)
    opts = dict(method="raytrace", rays=2**15, block_size=len(polys))  # one row per block
    ckpt = tmp_path / "ck"
    timer = _interrupt_after(1.0)
    try:
        with pytest.raises(KeyboardInterrupt):
            nusselt.form_factors(scene, checkpoint=ckpt, **opts)
    finally:
        timer.cancel()
    kept = sorted(ckpt.glob("block_*.npz"))
    assert kept, "no finished block was kept"
    resumed = nusselt.form_factors(scene, checkpoint=ckpt, resume=True, **opts)
    whole = nusselt.form_factors(scene, **opts)
    assert abs(resumed.matrix - whole.matrix).max() == 0.0


def test_method_name_type_lists_the_registry():
    from typing import get_args

    from nusselt.methods import MethodName

    assert get_args(MethodName) == tuple(m["name"] for m in _core.methods())
    assert nusselt.MethodName is MethodName
