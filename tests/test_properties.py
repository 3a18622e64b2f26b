"""Property-based tests (hypothesis) of pair and scene invariants: 0 <= F <= 1, rows sum to
at most 1 + tol, reciprocity A_i F_ij = A_j F_ji, an obstacle only takes away (obstructed
<= unobstructed), and F does not change when the geometry is scaled or translated.

The default run is derandomized with a small budget; the long run (10 000 cases per test):
``NUSSELT_HYPOTHESIS=long python -m pytest -q tests/test_properties.py``.
"""

import os

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import nusselt  # noqa: E402

_quiet = [HealthCheck.too_slow, HealthCheck.filter_too_much]
settings.register_profile("default", max_examples=15, derandomize=True, deadline=None, suppress_health_check=_quiet)
# the long run: seeded, not derandomized, so that it explores cases the default run does not
settings.register_profile(
    "long",
    max_examples=int(os.environ.get("NUSSELT_HYPOTHESIS_EXAMPLES", "10000")),
    deadline=None,
    suppress_health_check=_quiet,
    database=None,
)
settings.load_profile(os.environ.get("NUSSELT_HYPOTHESIS", "default"))

coord = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
point = st.tuples(coord, coord, coord)


def area(p):
    return 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))


@st.composite
def triangle(draw):
    """A triangle in [-1, 1]^3 that is not a needle (area above 1e-3 of its squared size)."""
    p = np.array(draw(st.tuples(point, point, point)), dtype=float)
    size = max(np.linalg.norm(p[i] - p[j]) for i in range(3) for j in range(i))
    hypothesis.assume(size > 1e-3 and area(p) > 1e-3 * size * size)
    return p


scale = st.sampled_from([1e-6, 1e-3, 0.1, 3.0, 1e3, 1e6])
shift = st.tuples(*[st.floats(-100.0, 100.0)] * 3)


@hypothesis.seed(23)
@given(triangle(), triangle(), scale, shift)
def test_pair_invariants(a, b, s, t):
    f_ab = nusselt.view_factor(a, b, method="analytic")
    f_ba = nusselt.view_factor(b, a, method="analytic")
    assert 0.0 <= f_ab <= 1.0 and 0.0 <= f_ba <= 1.0
    assert abs(area(a) * f_ab - area(b) * f_ba) <= 1e-9 * max(area(a), area(b))
    # moved by t in units of the triangles' size: a shift much larger than the shape rounds
    # its coordinates themselves (98 + 1e-6 x keeps x to 1e-8), which no method can undo
    t = np.array(t)
    moved = nusselt.view_factor(s * (a + t), s * (b + t), method="analytic")
    assert abs(moved - f_ab) <= 1e-8, (moved, f_ab)


@hypothesis.seed(23)
@given(st.lists(triangle(), min_size=3, max_size=5), triangle(), scale)
def test_scene_invariants(polys, obstacle, s):
    try:
        free_scene = nusselt.Scene.from_polygons(polys)
    except ValueError as e:  # overlapping coplanar faces are refused at build (issue 23 item 2)
        hypothesis.assume("lie in one plane" not in str(e))
        raise
    free = nusselt.form_factors(free_scene)
    F = free.matrix.toarray()
    assert F.min() >= 0.0 and F.max() <= 1.0
    assert F.sum(axis=1).max() <= 1.0 + 1e-9
    G = free.areas[:, None] * F
    assert np.allclose(G, G.T, rtol=1e-12, atol=0.0)
    try:
        scene = nusselt.Scene.from_polygons([*polys, obstacle], obstruction=[False] * len(polys) + [True])
    except ValueError as e:
        hypothesis.assume("lie in one plane" not in str(e))
        raise
    blocked = nusselt.form_factors(scene).matrix.toarray()
    assert blocked.min() >= 0.0
    assert (blocked <= F + 1e-6).all(), np.max(blocked - F)
    Gb = free.areas[:, None] * blocked
    assert np.allclose(Gb, Gb.T, rtol=1e-12, atol=0.0)
    # scaled and moved: an unobstructed scene to rounding; where faces may block each other,
    # visibility decisions flip on rounding: the 10 000-case run measured up to 1.8e-6
    # (2e-3 of one entry, two triangles sharing an edge at 0.45 degrees) - issue 23 item 6,
    # not fixed; the bound asserted here is that measured one, not auto's obstructed_tol
    scaled = nusselt.form_factors(nusselt.Scene.from_polygons([s * p + 7.0 * s for p in polys])).matrix.toarray()
    bound = 1e-9 if free_scene._core.unobstructed() else 1e-5
    assert np.abs(scaled - F).max() <= bound
