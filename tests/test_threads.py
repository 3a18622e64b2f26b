"""The core's worker pool: its size follows NUSSELT_NUM_THREADS, else RAYON_NUM_THREADS (what
benchmarks and rayon users set), else the CPUs; and every result is the same whatever it is."""

import os
import subprocess
import sys

import numpy as np

import nusselt
from nusselt.data import cornell_box

PROBE = "import nusselt._core as c; print(c.num_threads())"


def _clean_env() -> dict[str, str]:
    """This environment without the pool-size variables."""
    return {k: v for k, v in os.environ.items() if k not in ("NUSSELT_NUM_THREADS", "RAYON_NUM_THREADS")}


def _pool_size(**env):
    clean = _clean_env()
    out = subprocess.run(
        [sys.executable, "-c", PROBE], env={**clean, **env}, capture_output=True, text=True, check=True
    )
    return int(out.stdout)


def test_the_pool_size_follows_the_environment():
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    # the default: the CPUs this process may use (Rust also honours a cgroup CPU quota, which
    # Python's affinity mask does not see, so at most the affinity count)
    default = _pool_size()
    assert 1 <= default <= cpus
    assert _pool_size(RAYON_NUM_THREADS="1") == 1
    assert _pool_size(RAYON_NUM_THREADS="3") == 3
    # ours wins over rayon's; unset, empty or nonsense values fall through to the next
    assert _pool_size(NUSSELT_NUM_THREADS="2", RAYON_NUM_THREADS="1") == 2
    assert _pool_size(NUSSELT_NUM_THREADS="x", RAYON_NUM_THREADS="1") == 1
    assert _pool_size(NUSSELT_NUM_THREADS="0") == default


def test_results_do_not_depend_on_the_pool_size(tmp_path):
    # the Cornell box (obstructed: two blocks inside), computed in processes with 1 and 3
    # threads, is bit for bit the result of this process
    here = nusselt.form_factors(cornell_box()).dense()
    script = "import sys, numpy as np, nusselt; from nusselt.data import cornell_box\n" + (
        "np.save(sys.argv[1], nusselt.form_factors(cornell_box()).dense())"
    )
    env = {k: v for k, v in os.environ.items() if k != "NUSSELT_NUM_THREADS"}
    for n in ("1", "3"):
        path = tmp_path / f"f{n}.npy"
        subprocess.run([sys.executable, "-c", script, str(path)], env={**env, "RAYON_NUM_THREADS": n}, check=True)
        assert np.array_equal(np.load(path), here), n


WORK = """
import nusselt
def sq(z, s, up):
    v = [[0.5 - s, 0.5 - s, z], [0.5 + s, 0.5 - s, z], [0.5 + s, 0.5 + s, z], [0.5 - s, 0.5 + s, z]]
    return v if up else v[::-1]
polys = [sq(0, 0.5, True), sq(1, 0.5, False), sq(0.5, 0.2, True)]
scene = nusselt.Scene.from_polygons(polys, obstruction=[False, False, True])
u = nusselt._core.work_units(); nusselt.form_factors(scene)
v = nusselt._core.work_units(); nusselt.form_factors(scene)
print(v - u, nusselt._core.work_units() - v)
"""


def test_work_units_count_the_same_work_alike():
    # the counter benchmarks use instead of noisy CPU times: the same computation spends the
    # same units, again and on one thread or two, and plates with a blocker between spend some
    clean = _clean_env()
    counts = []
    for n in ("1", "2"):
        env = {**clean, "RAYON_NUM_THREADS": n}
        out = subprocess.run([sys.executable, "-c", WORK], env=env, capture_output=True, text=True, check=True)
        counts.extend(int(x) for x in out.stdout.split())
    assert counts[0] > 0
    assert len(set(counts)) == 1, counts
