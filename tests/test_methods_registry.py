"""The method registry of the core, Python's view of it, budgets and Ctrl-C."""

import _thread
import contextlib
import signal
import threading
import time

import numpy as np
import pytest
from conftest import LONG_CALLS, rect

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


# (blocked, control_variate): an unobstructed pair with the control variate samples nothing
@pytest.mark.parametrize("blocked, control_variate", [(False, False), (True, False), (True, True)])
@pytest.mark.parametrize(
    "method, opts, units", [("montecarlo", {"samples": 4096}, 4096), ("quadrature", {"order": 8}, 64**2)]
)
def test_every_sample_counts_against_the_budget(method, opts, units, blocked, control_variate):
    """One work unit per point pair a sampled method evaluates, whether or not its visibility
    is tested (an unobstructed pair without the control variate samples the whole integral):
    the pair passes at exactly that many units and names the method and pair one below."""
    obs = [BLOCKER] if blocked else []
    o = {**opts, "control_variate": control_variate}
    if method == "quadrature" and blocked:
        o["tol"] = 1e-14  # the blocked pair's order is then `order`
    f = nusselt.view_factor(A, B, obstacles=obs, method=method, budget=units, **o)
    assert f == nusselt.view_factor(A, B, obstacles=obs, method=method, **o)
    with pytest.raises(ValueError, match=rf'method "{method}": pair \(0, 1\) needs more than budget={units - 1}\b'):
        nusselt.view_factor(A, B, obstacles=obs, method=method, budget=units - 1, **o)


def test_a_long_unobstructed_montecarlo_pair_stops_at_its_budget():
    # 2^24 samples (about 4 s of one core; before every sample counted, the budget never
    # stopped them) against a budget of 2^20
    with pytest.raises(ValueError, match=r'method "montecarlo": pair \(0, 1\) needs more than budget=1048576\b'):
        nusselt.view_factor(A, B, method="montecarlo", samples=2**24, control_variate=False, budget=2**20)


@pytest.fixture(scope="module")
def ten_thousand_blockers():
    """10 000 small squares (0.004 wide, a 100 x 100 grid) midway between A and B."""
    w, step = 0.004, 0.01
    return [
        rect(step * a + 0.003, step * a + 0.003 + w, step * b + 0.003, step * b + 0.003 + w, z=0.5)
        for a in range(100)
        for b in range(100)
    ]


#: Methods whose unit is one sample or ray whatever the number of blockers (the BVH answers
#: each): 2^16 units are their default samples, and the pair finishes.
PER_SAMPLE = {"montecarlo", "raytrace"}


@pytest.mark.parametrize("method", list(METHODS))
def test_a_pair_with_ten_thousand_blockers_stops_at_its_budget(method, ten_thousand_blockers):
    """Work that grows with the blockers (shadows per blocker, visible pieces, cells tested
    against candidates) is counted: at a budget of 2^16 units the pair is the budget error,
    not minutes of work; the per-sample methods finish with a value below the free F."""

    def call():
        return nusselt.view_factor(A, B, obstacles=ten_thousand_blockers, method=method, budget=2**16)

    if method in PER_SAMPLE:
        assert 0.0 <= call() < nusselt.view_factor(A, B, method="analytic")
        return
    with pytest.raises(ValueError, match=rf'method "{method}": (pair \(0, 1\)|row 0) needs more than budget=65536\b'):
        call()


def _interrupt_after(seconds):
    t = threading.Timer(seconds, _thread.interrupt_main)
    t.start()
    return t


MANY = [rect(0.1 * k, 0.1 * k + 0.05, 0.2, 0.8, z=0.5) for k in range(10)]


@contextlib.contextmanager
def _python_sigint_handler():
    """Python's own SIGINT handler for the block. `_thread.interrupt_main` (Ctrl-C as these
    tests send it) does nothing while SIGINT is ignored, as it is for a run started in the
    background by a script (`cmd &`, `nohup`): every latency test then ran its 60 s and
    failed, though a real Ctrl-C reaches such a run no more than the test's."""
    previous = signal.getsignal(signal.SIGINT)
    signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)


def _latency_of_ctrl_c(call):
    """Seconds from an interrupt (as Ctrl-C sends it, 0.3 s in) to the KeyboardInterrupt of
    `call`, repeated until the interrupt lands in one."""
    with _python_sigint_handler():
        return _latency_with_handler(call)


def _latency_with_handler(call):
    fired = []

    def fire():
        fired.append(time.perf_counter())
        _thread.interrupt_main()

    timer = threading.Timer(0.3, fire)
    start = time.perf_counter()
    timer.start()
    try:
        try:
            # (bounded: an interrupt that never arrives fails here instead of hanging the run;
            # one full run looped on for minutes, not seen again)
            while time.perf_counter() - start < 60.0:
                call()
        except KeyboardInterrupt:
            return time.perf_counter() - fired[0]
        pytest.fail(
            f"no KeyboardInterrupt within 60 s (interrupt sent: {bool(fired)}); "
            f"SIGINT handler {signal.getsignal(signal.SIGINT)!r}"
        )
    finally:
        timer.cancel()


def _long_calls():
    out = [pytest.param(m, "pair", id=f"{m}-pair") for m in LONG_CALLS]
    out += [pytest.param(m, "point", id=f"{m}-point") for m in LONG_CALLS if METHODS[m].kind == "pairs"]
    return out + [pytest.param(m, "scene", id=f"{m}-scene") for m in ("analytic", "contour", "auto")]


@pytest.fixture(scope="module")
def big_box():
    from conftest import cube_faces

    return nusselt.Scene.from_polygons(cube_faces(20)[0])  # 2 400 patches, 2.9 M pairs


def test_every_method_has_a_long_call():
    assert set(LONG_CALLS) == set(METHODS)
    assert all(m.obstructed for m in METHODS.values())


@pytest.mark.parametrize("method, call", _long_calls())
def test_ctrl_c_stops_a_single_long_call_of_every_method(method, call, request):
    """Ctrl-C reaches every method's inner loop: a call that would run for minutes (extreme
    but allowed options, no budget) raises KeyboardInterrupt soon after the interrupt. The
    bound is generous for a loaded machine (the calls that did not poll took 4 to 17 s);
    `python bench/methods.py interrupt` measures the latency (docs/methods.md)."""
    opts = {**LONG_CALLS.get(method, {}), "budget": 2**62} if call != "scene" else {}
    if call == "pair":
        latency = _latency_of_ctrl_c(lambda: nusselt.view_factor(A, B, obstacles=MANY, method=method, **opts))
    elif call == "point":
        if method == "quadrature":
            opts["panels"] = 64
        p, n = np.array([0.5, 0.5, 0.0]), np.array([0.0, 0.0, 1.0])
        latency = _latency_of_ctrl_c(lambda: nusselt.point_view_factor(p, n, B, obstacles=MANY, method=method, **opts))
    else:
        box = request.getfixturevalue("big_box")
        latency = _latency_of_ctrl_c(lambda: nusselt.form_factors(box, method=method))
    assert latency < 2.0, latency
    # the core is usable again afterwards (the cancellation flag was cleared)
    assert nusselt.view_factor(A, B, method="auto") > 0.19


@pytest.mark.parametrize("method", [n for n, m in METHODS.items() if "budget" in m.options])
def test_every_budget_is_checked_and_named_in_the_error(method):
    """A pair or row that needs more work than its budget is a ValueError naming the budget
    and the option to raise, for every method that has one."""
    with pytest.raises(ValueError, match=r"budget=10\b.*raise the method's `budget` option"):
        nusselt.view_factor(A, B, obstacles=[BLOCKER], method=method, budget=10)


def test_ctrl_c_keeps_finished_blocks_on_disk(tmp_path):
    """An interrupted scene-wide run keeps every finished block in its checkpoint, and the
    resumed run gives the matrix of an uninterrupted one."""
    from conftest import cube_faces

    polys, _ = cube_faces(6)
    polys = list(polys) + [rect(0.4, 0.6, 0.4, 0.6, z=0.5), rect(0.4, 0.6, 0.4, 0.6, z=0.5, flip=True)]
    scene = nusselt.Scene.from_polygons(polys)
    opts = dict(method="raytrace", rays=2**15, block_size=len(polys))  # one row per block
    ckpt = tmp_path / "ck"
    with _python_sigint_handler():
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
