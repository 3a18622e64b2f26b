"""The numpy graph routines behind shells and orientation, against plain Python references,
and the promise that reading a scene does not load scipy."""

import subprocess
import sys
from collections import deque

import numpy as np
import pytest

from nusselt.io.topology import _components, _two_colour


def _bfs_components(n, u, v):
    adj = [[] for _ in range(n)]
    for a, b in zip(u, v):
        adj[a].append(b)
        adj[b].append(a)
    lab = [-1] * n
    for root in range(n):
        if lab[root] >= 0:
            continue
        lab[root] = root
        todo = deque([root])
        while todo:
            x = todo.popleft()
            for y in adj[x]:
                if lab[y] < 0:
                    lab[y] = root
                    todo.append(y)
    return np.array(lab)


@pytest.mark.parametrize("seed", range(20))
def test_components_match_breadth_first_search(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 300))
    m = int(rng.integers(0, 2 * n))
    u, v = rng.integers(0, n, m), rng.integers(0, n, m)
    # labels are each component's smallest node, as the reference's roots are
    np.testing.assert_array_equal(_components(n, u, v), _bfs_components(n, u, v))


def test_components_of_a_long_path_in_shuffled_order():
    rng = np.random.default_rng(1)
    perm = rng.permutation(5000)
    lab = _components(5000, perm[:-1], perm[1:])
    assert np.all(lab == 0)


@pytest.mark.parametrize("seed", range(10))
def test_two_colour_satisfies_every_edge_of_a_consistent_graph(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 200))
    truth = rng.random(n) < 0.5
    u, v = rng.integers(0, n, 3 * n), rng.integers(0, n, 3 * n)
    flip = _two_colour(n, u, v, truth[u] ^ truth[v])
    assert np.all(flip[u] ^ flip[v] == truth[u] ^ truth[v])
    # the first node of each component keeps its orientation
    lab = _components(n, u, v)
    assert not flip[np.unique(lab)].any()


def test_reading_a_scene_does_not_import_scipy(tmp_path):
    path = tmp_path / "box.obj"
    pts = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(1, 3, 4, 2), (5, 6, 8, 7), (1, 2, 6, 5), (3, 7, 8, 4), (1, 5, 7, 3), (2, 4, 8, 6)]
    path.write_text(
        "".join(f"v {x} {y} {z}\n" for x, y, z in pts) + "".join(f"f {a} {b} {c} {d}\n" for a, b, c, d in quads)
    )
    code = (
        "import sys, nusselt\n"
        f"s = nusselt.Scene.from_file({str(path)!r})\n"
        "assert len(s) == 6\n"
        "print(sorted(m for m in sys.modules if m.startswith('scipy')))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
