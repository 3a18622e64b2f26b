"""Property-based tests (hypothesis) of pair and scene invariants: 0 <= F <= 1, rows sum to
at most 1 + tol, reciprocity A_i F_ij = A_j F_ji, an obstacle only takes away (obstructed
<= unobstructed), and F does not change when the geometry is scaled or translated.

Bounds behind obstacles are the accuracy asked for, not measured slack: ``auto`` meets
``obstructed_tol`` relative to each pair's unobstructed F (docs/algorithms.md §6.2), so two
results of one pair (with and without an obstacle, or in two units) differ by at most twice
that.

The default run is derandomized with a small budget; the long run (10 000 cases per test,
``NUSSELT_HYPOTHESIS_EXAMPLES`` to change it; seed 23, ``NUSSELT_HYPOTHESIS_SEED`` to change
it, as the tests pin theirs and ``--hypothesis-seed`` does not reach them):
``NUSSELT_HYPOTHESIS=long python -m pytest -q tests/test_properties.py``.
"""

import os
import warnings

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from conftest import data_literal  # noqa: E402
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from pair_reference import view_factor_mp  # noqa: E402

import nusselt  # noqa: E402

_quiet = [HealthCheck.too_slow, HealthCheck.filter_too_much]
# no example database in either profile: a saved failure replayed in a later run would make
# that run's outcome depend on what ran before
settings.register_profile(
    "default", max_examples=15, derandomize=True, deadline=None, suppress_health_check=_quiet, database=None
)
# the long run: seeded, not derandomized, so that it explores cases the default run does not
settings.register_profile(
    "long",
    max_examples=int(os.environ.get("NUSSELT_HYPOTHESIS_EXAMPLES", "10000")),
    deadline=None,
    suppress_health_check=_quiet,
    database=None,
)
settings.load_profile(os.environ.get("NUSSELT_HYPOTHESIS", "default"))

# the long run's seed (the default profile is derandomized and ignores it)
SEED = int(os.environ.get("NUSSELT_HYPOTHESIS_SEED", "23"))


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


@hypothesis.seed(SEED)
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


@hypothesis.seed(SEED)
@given(st.lists(triangle(), min_size=3, max_size=5), triangle(), scale)
def test_scene_invariants(polys, obstacle, s):
    # exact coordinates on failure: numpy's repr rounds to 8 digits, too few to replay a case
    hypothesis.note(f"exact: polys={[p.tolist() for p in polys]!r} obstacle={obstacle.tolist()!r} s={s!r}")
    try:
        free_scene = nusselt.Scene.from_polygons(polys)
    except ValueError as e:  # overlapping coplanar faces are refused at build (issue 23 item 2)
        hypothesis.assume("lie in one plane" not in str(e))
        raise
    free = nusselt.form_factors(free_scene)
    F, F_err = _with_error(free)
    assert F.min() >= 0.0 and F.max() <= 1.0
    # rows: each F within obstructed_tol x F_free where faces may block each other (seed 36:
    # F[0, 2] 1e-8 high of 1.0, a row 1 + 1e-8), exact to rounding where none can; or within
    # the error estimate the result reports (std_err, with a ToleranceWarning) where an
    # integral ran out of evaluations
    free_f = _free(free_scene.polygons)
    slack = 0.0 if free_scene._core.unobstructed() else DEFAULT_OBSTRUCTED_TOL * free_f.sum(axis=1)
    assert (F.sum(axis=1) <= 1.0 + 1e-9 + slack + F_err.sum(axis=1)).all()
    G = free.areas[:, None] * F
    assert np.allclose(G, G.T, rtol=1e-12, atol=0.0)
    try:
        scene = nusselt.Scene.from_polygons([*polys, obstacle], obstruction=[False] * len(polys) + [True])
    except ValueError as e:
        hypothesis.assume("lie in one plane" not in str(e))
        raise
    blocked, blocked_err = _with_error(nusselt.form_factors(scene))
    assert blocked.min() >= 0.0
    # an obstacle only takes away, up to each result's error: obstructed_tol x F_free each,
    # or the error estimate it reports
    slack = 2 * DEFAULT_OBSTRUCTED_TOL * free_f + F_err + blocked_err + 1e-12
    assert (blocked <= F + slack).all(), np.max((blocked - F) / slack)
    Gb = free.areas[:, None] * blocked
    assert np.allclose(Gb, Gb.T, rtol=1e-12, atol=0.0)
    # scaled and moved: an unobstructed scene to rounding. Where faces may block each other,
    # each F is within obstructed_tol x F_free of the truth (docs/algorithms.md §6.2: the
    # target is relative to the pair's unobstructed F), so two scalings differ by at most
    # twice that; visibility decisions that flip on rounding stay inside it (issue 23 item 6).
    # Plus what the move itself changes of the unobstructed F: the moved coordinates are
    # rounded, and faces 1e-14 out of each other's plane see each other by that much (seed 42:
    # 0.25 -> 0.25000000000000017 and 1e-14 -> 1.0164e-14 changed an unobstructed F by 3e-6)
    moved_polys = [s * p + 7.0 * s for p in polys]
    rounding = np.abs(_free(moved_polys) - free_f)
    for tol in (None, 1e-3):
        kw = {} if tol is None else {"obstructed_tol": tol}
        base, base_err = (F, F_err) if tol is None else _with_error(nusselt.form_factors(free_scene, **kw))
        moved = nusselt.Scene.from_polygons(moved_polys)
        scaled, scaled_err = _with_error(nusselt.form_factors(moved, **kw))
        if free_scene._core.unobstructed():
            assert np.abs(scaled - base).max() <= 1e-9
        else:
            bound = 2 * (tol or DEFAULT_OBSTRUCTED_TOL) * free_f + base_err + scaled_err + rounding + 1e-12
            assert (np.abs(scaled - base) <= bound).all(), np.max(np.abs(scaled - base) / bound)


DEFAULT_OBSTRUCTED_TOL = nusselt.methods.resolve("auto", {})[1]["obstructed_tol"]


def _with_error(result):
    """(F, its error estimate) of a result, dense: the estimate is 0 but where an integral ran
    out of evaluations short of obstructed_tol (and a ToleranceWarning said so)."""
    F = result.matrix.toarray()
    return F, (np.zeros_like(F) if result.std_err is None else result.std_err.toarray())


def _free(polys):
    """F of every pair with nothing in between (the scale of each pair's target)."""
    n = len(polys)
    return np.array([[nusselt.view_factor(polys[i], polys[j]) if i != j else 0.0 for j in range(n)] for i in range(n)])


def _assert_moved_within(polys, tol=None, s=1e-6):
    """Scaling by `s` and moving by 7 s changes no F by more than the two results' errors
    (`tol` x F_free each; `tol` None: auto's default obstructed_tol) and what the move's
    rounding changes of the unobstructed F."""
    kw = {} if tol is None else {"obstructed_tol": tol}
    base, base_err = _with_error(nusselt.form_factors(nusselt.Scene.from_polygons(polys), **kw))
    moved_polys = [s * p + 7 * s for p in polys]
    moved, moved_err = _with_error(nusselt.form_factors(nusselt.Scene.from_polygons(moved_polys), **kw))
    free = _free(polys)
    # (plus the error estimates the results report, and what the move's rounding changes of
    # the unobstructed F, see test_scene_invariants)
    bound = 2 * (tol or DEFAULT_OBSTRUCTED_TOL) * free + base_err + moved_err + np.abs(_free(moved_polys) - free)
    bound += 1e-12
    assert (np.abs(moved - base) <= bound).all(), np.max(np.abs(moved - base) / bound)


def _with_and_without(polys, obstacle):
    """F of the scene of `polys` and of the same scene with `obstacle` added (obstruction only),
    both at the defaults, and the sum of their reported error estimates."""
    F, F_err = _with_error(nusselt.form_factors(nusselt.Scene.from_polygons(polys)))
    scene = nusselt.Scene.from_polygons([*polys, obstacle], obstruction=[False] * len(polys) + [True])
    blocked, blocked_err = _with_error(nusselt.form_factors(scene))
    return F, blocked, F_err + blocked_err


def _assert_obstacle_only_takes_away(polys, obstacle):
    """Adding `obstacle` raises no F by more than the two results' errors (obstructed_tol x
    F_free each, F_free every pair's unobstructed F)."""
    F, blocked, err = _with_and_without(polys, obstacle)
    slack = 2 * DEFAULT_OBSTRUCTED_TOL * _free(polys) + err + 1e-12
    assert (blocked <= F + slack).all(), np.max((blocked - F) / slack)


# Found by the long run (NUSSELT_HYPOTHESIS=long, 10 000 examples).
def test_replay_seed_36_overlap_across_a_thin_gap():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=36 (pair test, after 77 s): a's third
    # vertex is 1e-9 out of b's plane, and the two face each other across at most 7.4e-10 where
    # their outlines overlap (4.2563e-4 of a's area; F is that share). The contour sum cancels
    # 1e4-fold, and the area route's first samples missed the overlap: F 3.5e-16 when scaled
    # by 1e-6 (right only at scale 1). The source is now cut along the target's projected
    # outline first, so the overlap is a piece of its own
    a = np.array([[0.0, 0.0, 0.0], [-0.3125, 0.875, 0.0], [-0.0703125, 0.25, 1e-9]])
    b = np.array([[0.25, 0.0, 0.0], [0.5, 0.0, 0.0], [-0.09765625, 0.3125, 0.0]])
    reference = float(view_factor_mp(a, b))
    assert abs(reference - 4.2563096465e-4) < 1e-14
    for s in (1e-6, 1e-3, 0.1, 1.0, 3.0, 1e3, 1e6):
        for method in ("analytic", "contour", "auto"):
            f = nusselt.view_factor(s * a, s * b, method=method)
            assert abs(f - reference) <= 1e-12, (s, method, f)


def test_replay_nearly_touching_pair_scaled():
    # planes 1e-9 rad apart, piercing each other: the cut was placed by heights rounded to
    # eps of the coordinates (1e-7 of the heights), 1.27e-8 apart at 1e-6
    a = np.array([[0.0, 0.0, 0.0], [0.0, 1e-9, 1.0], [1.0, 1.0, 0.0]])
    b = np.array([[0.0, 0.0, 1.0], [0.0, 1e-9, 0.0], [1.0, 1.0, 0.0]])
    f_ab = nusselt.view_factor(a, b, method="analytic")
    for s in (1e-6, 0.1, 3.0, 1e3):
        moved = nusselt.view_factor(s * a, s * b, method="analytic")
        assert abs(moved - f_ab) <= 1e-14, (s, moved, f_ab)


def test_replay_obstacle_takes_away_in_the_scene_path():
    polys = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
            [[1.0, 1.0, -1.0], [0.0, -1.0, 0.0], [-0.5, 0.0, 0.0]],
            [[0.0, 0.5, -0.5], [-0.6875, 0.4375, 0.0], [1.0, -1.0, 0.375]],
            [[0.0, 0.0, 0.0], [0.0, 0.5, 0.0], [0.5, 0.75, -1.0]],
        )
    ]
    obstacle = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, -1.0], [0.0, 0.0, 0.0]])
    F, blocked, _ = _with_and_without(polys, obstacle)
    free_f = nusselt.view_factor(polys[4], polys[2])
    # F[4, 2] 3.01431e-3 in both the free scene and the pair path (every other face a blocker),
    # 3.01450e-3 in the blocked scene at the default tol (64 x tol F_free above) until a start
    # piece whose samples all missed a shadow next to the obstacle was refined
    assert blocked[4, 2] <= F[4, 2] + 2e-6 * free_f, (blocked[4, 2], F[4, 2])


def test_replay_hidden_obstacle_in_the_scene_path():
    # the obstacle's shadow lies inside face 1's: its kink planes spent the split's budget
    # before the events bounding face 1's shadow, whose samples then all missed a sliver of
    # it (F[4, 2] 9.7 x the bound above the free scene's)
    *polys, obstacle = [np.array(p) for p in data_literal("hidden_obstacle.txt")]
    _assert_obstacle_only_takes_away(polys, obstacle)


# Two faces over one triangle, facing each other 1e-8 apart (face 2 is face 1 with a vertex
# lifted by 1e-8), and face 0 piercing both along y = 0: face 1 sees face 0 only through the
# wedge between them, the triangle V of face 0 below face 2, whatever the point of face 1
# (face 2's plane separates it from the rest), so F[1, 0] = F(T -> V) A_T / A_1 exactly, T
# the part of face 1 in front of face 0 (an unobstructed pair).
WEDGE_FACES = (
    [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 1.0]],
    [[0.0, -1.0, 0.0], [0.0, 0.0, 1e-08], [1.0, 1.0, 0.0]],
)


def test_replay_faces_facing_each_other_across_a_thin_wedge():
    f0, f2 = (np.array(p) for p in WEDGE_FACES)
    f1 = np.array([[0.0, 0.0, 0.0], [0.0, -1.0, 0.0], [1.0, 1.0, 0.0]])
    x = 1e-8 / (1 + 2e-8)
    t = np.array([[0.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.5, 0.0, 0.0]])
    v = np.array([[0.0, 0.0, 0.0], [x, 0.0, x], [0.5, 0.0, 0.0]])
    truth = nusselt.view_factor(t, v, method="analytic") * area(t) / area(f1)
    F = nusselt.form_factors(nusselt.Scene.from_polygons([f0, f1, f2])).matrix.toarray()
    # F[1, 0] was 2.0e-3 (a point F of 0.029 for 5e-16 where face 2 passes 1e-10 above the
    # point, and the integral over face 1 missing the wedge's band); truth 2.5e-9
    free = nusselt.view_factor(f1, f0)
    assert abs(F[1, 0] - truth) <= DEFAULT_OBSTRUCTED_TOL * free, (F[1, 0], truth)
    assert F.sum(axis=1).max() <= 1.0 + 1e-9


def test_replay_thin_wedge_scaled():
    # the same two faces with face 1 turned to meet them along the x axis: F[1, 2] ~ 2.5e-9,
    # 2.086e-9 at 1e-6 x (p + 7) against 2.500e-9 at unit scale (579 x the bound), later
    # 4.268e-9 (the unobstructed F): face 0 crosses both faces' planes, their clearances tied
    # or not by rounding, so the side integrated over depended on where the scene lay (and
    # the other side misses the shadow, which lies within 1e-8 of the common edge)
    f0, f2 = (np.array(p) for p in WEDGE_FACES)
    f1 = np.array([[0.0, 0.0, 0.0], [0.0, -1.0, 1.0], [1.0, 0.0, 0.0]])
    _assert_moved_within([f0, f1, f2])


def test_replay_obstacle_touching_the_source_at_a_vertex():
    # found by the long run: the obstacle lies in face 0's plane x = 0; F[3, 2] is 1.3490973e-8
    # both with and without it at obstructed_tol 1e-10 (F_free 5.6e-8), 1.34909655e-8 in the
    # free scene at the default and was 1.34939386e-8 with the obstacle (error 2.97e-12
    # against a target of 5.6e-14): the obstacle's kinks cut face 3 into start pieces small
    # enough that one held a shadow between all of its samples
    polys = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.25, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.375, 0.0], [1.0, 0.0625, 0.0]],
            [[1.0, 0.0, -0.75], [0.0, 0.0, -1.0], [-1.0, 0.0, 0.0]],
            [[-0.140625, 0.5, 0.3125], [-0.4375, 0.625, 0.59375], [0.0, 0.0, 0.0]],
        )
    ]
    obstacle = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.5], [0.0, 1.0, 0.0]])
    _assert_obstacle_only_takes_away(polys, obstacle)


def test_replay_second_coplanar_blocker_raises_f():
    # found by the long run (seed 23, 10 000 cases): faces 0 and 2 and the obstacle lie in the
    # plane x = 0 (face 2 and the obstacle facing opposite ways, overlapping); F[3, 1] was
    # 1.4055e-6 without the obstacle and 1.4072e-6 with it (83 x the target 2e-11; both
    # 1.40758e-6 now). The free scene's value was the wrong one: face 1 cuts face 3 to a small
    # triangle, and the kink split used the whole face 3, missing the events where the gap
    # between faces 0 and 2 casts onto the cut's vertices
    polys = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.5, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.25], [-0.5, 0.5, 0.5]],
            [[0.0, 1.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0625, 1.0]],
            [[1.0, 0.0, -0.5], [0.0, 0.0, -1.0], [-1.0, 0.0, -1.0]],
        )
    ]
    obstacle = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.5], [0.0, 1.0, 0.0]])
    _assert_obstacle_only_takes_away(polys, obstacle)


def test_replay_loose_tol_moved_scene():
    # found by the long run (seed 23, 10 000 cases): at obstructed_tol 1e-3 F[3, 1] was
    # 0.0659785 at the origin and 0.0657175 at 1e-6 x (p + 7) against 0.0660144 (the default):
    # errors of 0.5 and 4.3 x tol x F_free (F_free 0.0684). A trace parallel to the source's
    # plane cut the source by rounding at the origin only, and the one start piece left when
    # moved had samples 10x apart whose coarse estimate was 8x too small. Now 0.27 x tol both
    polys = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.25, 0.0]],
            [[0.0, 1.0, 0.0], [0.0, 0.375, 0.0], [1.0, 0.0625, 1.0]],
            [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 0.0, 0.0]],
            [[-0.125, 0.5, 0.3125], [-0.4375, 0.5, 0.5625], [0.0, 0.0, 0.0]],
        )
    ]
    _assert_moved_within(polys, tol=1e-3)


# Five faces meeting at the origin (faces 0 and 2 the same triangle facing opposite ways, face 4
# within 0.0039 of face 1's plane); found by the long run once the replays above were fixed
ORIGIN_FACES = (
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
    [[0.00390625, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
)


def test_origin_faces_4_and_2_face_each_other_behind_face_3():
    # the independent reference of the two replays below (F[4, 2] = 0): every segment between
    # random points of faces 4 and 2 leaves the front of one, reaches the front of the other and
    # crosses the plane z = 0 inside face 3 (x, y >= 0, x + y <= 1)
    rng = np.random.default_rng(5)
    a, b = (np.array(ORIGIN_FACES[k]) for k in (4, 2))

    def points(t, n=20_000):
        u = rng.random((n, 2))
        u[u.sum(axis=1) > 1] = 1 - u[u.sum(axis=1) > 1]
        return t[0] + u[:, :1] * (t[1] - t[0]) + u[:, 1:] * (t[2] - t[0])

    p, q = points(a), points(b)
    d = q - p
    na, nb = (np.cross(t[1] - t[0], t[2] - t[0]) for t in (a, b))
    assert ((d @ na) > 0).all() and ((d @ nb) < 0).all()
    x = p + (-p[:, 2] / d[:, 2])[:, None] * d
    assert ((x[:, 0] > 0) & (x[:, 1] >= 0) & (x[:, 0] + x[:, 1] <= 1)).all()


def test_replay_obstacle_raises_a_hidden_pair():
    # F[4, 2] is 0 in the free scene (face 3 hides face 2 from face 4, see the test above); it
    # was 2.0466e-7 with the obstacle at every obstructed_tol (1e-6, 1e-8, 1e-10). The
    # obstacle comes within 0.0052 of face 2's size of its plane, so the integral ran over
    # face 4 instead; there G = free - hidden needed the hidden part (all of the point F,
    # steep towards the vertex (0, 1, 0) the two share) to 1e-4, which the evaluation budget
    # did not reach. Such pieces now integrate the visible part, 0 here. (Since seed 32 the
    # obstacle, crossing face 4's plane beside it, counts as hovering 2^-8 over face 4 too,
    # and the integral runs over face 2; face 4's side is checked in clipping.rs)
    polys = [np.array(p) for p in ORIGIN_FACES]
    obstacle = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.00390625, 1.0, 0.0]])
    _assert_obstacle_only_takes_away(polys, obstacle)


def test_replay_row_of_nearly_coincident_faces():
    # face 0 is face 2 with a vertex lifted by 1e-8 (facing each other): row 2 is F[2, 0] =
    # 1 - 1e-8 (exact, free) and F[2, 4], which face 3 hides whole with face 0 there (the gap
    # between faces 0 and 2 opens onto face 3). It was 1.3888e-8, more than all that leaves
    # face 2 past face 0 (1e-8), at every tol: the integral runs over face 4 (face 0 hovers
    # 1e-8 over face 2), and the hidden part it integrated there is steep towards the vertex
    # the two share; the visible part is 0
    polys = [np.array(p) for p in ORIGIN_FACES]
    polys[0] = np.array([[1e-8, 3.7044103601709316e-230, -3.3149001461721412e-152], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
    F = nusselt.form_factors(nusselt.Scene.from_polygons(polys)).matrix.toarray()
    assert F.sum(axis=1).max() <= 1.0 + 1e-9


def test_replay_obstacle_near_a_corner_of_a_thin_pair():
    # F[4, 3] rose from 0.0626708553 to 0.0626710251 (2.7e-6 of F_free) at every tol: the
    # obstacle's vertex 1e-9 off face 3's corner sent the integral to face 4 (2^-8 thick, an
    # edge in the obstacle's plane), where the evaluation budget ran out 29 x the goal away.
    # A side that runs out is now integrated from the other as well, the better kept
    polys = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
            [[0.0, 0.0, 0.0], [-0.5, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[0.00390625, 0.0, 0.5], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]],
        )
    ]
    obstacle = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [1e-09, 0.0, 0.0]])
    _assert_obstacle_only_takes_away(polys, obstacle)


def test_replay_blockers_close_to_both_faces_of_a_pair():
    # the case above with face 4 1e-6 thick and face 0 shrunk: F[4, 3] rose from 0.0223270116
    # to 0.0223272409 (3.6e-6 of F_free) at every tol. Face 1 lies 1e-6 under face 4 and
    # hides a layer of it as wide, which the integral over face 4 missed whole; both sides
    # are now integrated when blockers come that close to both
    polys = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.125, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [-0.5, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[1e-06, 0.0, 0.5], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]],
        )
    ]
    obstacle = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [1e-09, 0.0, 0.0]])
    _assert_obstacle_only_takes_away(polys, obstacle)


def test_replay_blocker_hinged_on_a_thin_face():
    # F[4, 3] rose from 0.0770910212 to 0.0770913048 (3.7e-6 of F_free) with the obstacle.
    # Face 0 is hinged on an edge of face 4 (1e-6 thick) and hides a layer of it as wide;
    # counted as crossing face 4's plane it tied with face 3, so the pair's order chose the
    # side, and the obstacle broke the tie towards face 4, whose samples miss the layer.
    # A crossing blocker now counts as high as it rises above the plane
    polys = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, -1.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
            [[0.0, 0.0, 0.0], [-1.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[1e-06, 0.0, 0.5], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]],
        )
    ]
    obstacle = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.125, 0.0, 0.0]])
    _assert_obstacle_only_takes_away(polys, obstacle)
    f43, f34 = (nusselt.view_factor(polys[i], polys[j], obstacles=polys[:3]) for i, j in ((4, 3), (3, 4)))
    assert abs(f43 * area(polys[4]) - f34 * area(polys[3])) <= 1e-12 * f34 * area(polys[3])


def test_replay_default_tol_miss_on_a_five_face_pair():
    # found by the long run (seed 23) as "an obstacle raises F[3, 2]" (1.12 x the slack): the
    # obstacle's scene is right and the free one is off. F[3, 2] with faces 0, 1, 4 between:
    # 0.0788412985 at obstructed_tol 1e-6, 0.0788414780 at 1e-8 and 1e-10 (1e-7: 0.0788414779):
    # -2.25 x tol x F_free, the same before this session's changes; 1e-4 and 1e-5 are within
    # 0.12 and 0.41 x tol. The candidates are faces 1 and 4; the integral runs over face 3
    # (33 start pieces) and stops with an error estimate of 3.32e-8 in G (goal 3.36e-8) for
    # an actual 7.6e-8; over face 2 the same budget gets within 2e-10. The miss is one start
    # piece, a sliver 45 times as long as wide whose hidden F peaks within its width of its
    # short end (6e-5 at its apex, 9.2e-3 at 0.98 of its length, 6.7e-3 at the end): its
    # midpoint children are slivers too, sample no nearer the end, and agree with it to 6e-5
    # while both are 4 % off (brute force, 4^5 sub-triangles x Radon 7 per start piece).
    # Cutting slivers (aspect > 4) across by longest-edge bisection fixed this pair (0.05 x
    # tol, 35 % fewer evaluations) but a 10 000-case run (seed 23) then found two scenes 4.1
    # and 4.9 x the invariants' slack off (a pair hidden but for 3e-5 of its F, 17 start
    # pieces of aspect up to 1 100: 8 x tol at 1e-6; a blocker's vertex on the source's edge:
    # 14 x tol); eight children per sliver (halves, each in quarters) fixed this pair too and
    # left those 4.0 and 2.8 x tol off, against 0.49 and 1.05 x with midpoint quarters. Not
    # kept. What the sliver missed was a kink: where a vertex of face 1 lines up with an edge
    # of face 4 seen from the source, the two shadows' outline changes. With those
    # blocker-blocker events among the kink planes the pair is 0.00 x tol off
    polys = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]],
            [[0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.40625, 0.023095109867329322, -0.9296875]],
            [[0.68359375, 1.0, 0.0], [0.0, -0.75, -0.3155923474484793], [-0.4609375, 0.5, -0.5703125]],
            [
                [-0.625, 0.42578125, 0.0],
                [0.3359375, -0.26537515997697614, 0.0],
                [-0.13671875, 0.326171875, -0.6824687435821026],
            ],
            [[0.0, 0.0, -0.4204850217472974], [0.24609375, 0.0, -0.125], [0.140625, -0.28125, 0.0]],
        )
    ]
    others = [polys[k] for k in (0, 1, 4)]
    free = nusselt.view_factor(polys[3], polys[2])
    reference = nusselt.view_factor(polys[3], polys[2], obstacles=others, method="clipping", tol=1e-10)
    f = nusselt.view_factor(polys[3], polys[2], obstacles=others)
    assert abs(f - reference) <= DEFAULT_OBSTRUCTED_TOL * free, (f - reference) / (DEFAULT_OBSTRUCTED_TOL * free)


def test_replay_sliver_start_pieces_meet_tol():
    # found by the long run (seed 23) with slivers cut across (see the five-face pair above).
    # Faces 0 and 2 share an edge; face 0 hides all but 3e-5 of F[1, 2] = 2.2145e-6
    # (obstructed_tol 1e-8 and 1e-10 agree to 2e-16). Integrated over face 2, where face 0
    # stands hinged on its edge, the kink split left 17 start pieces of aspect up to 1 100,
    # and a sliver along the hinge was 0.8 x tol off with an estimate of 0.48 x: at tol 1e-5
    # 1.15 x tol off in all. Face 0 crosses face 1's plane, and a hinged blocker now counts as
    # closer than a crossing one: the integral runs over face 1, exact. The second scene (a
    # blocker's vertex on the source's edge, an obstacle in front of it): 6.5 x tol off at the
    # default, 0.07 x with the blocker-blocker kink events
    a = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 0.365234375], [-1.0, 0.0, 0.0], [-0.90625, -0.9375, 0.0]],
            [[1.0, -1.0, 0.0], [-0.53125, 0.0, 0.4921875], [-0.015625, -0.1640625, 0.265625]],
            [[-1.0, 0.0, -0.5], [-0.90625, -0.9375, 0.0], [0.0, 0.0, 0.365234375]],
        )
    ]
    b = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 0.3671875], [-1.0, 0.0, 0.0], [-0.9375, -1.0, 0.0]],
            [[0.0, 0.0, -1.0], [-0.9375, -0.9375, 0.0], [0.0, 0.0, 1.0]],
            [[0.0, -1.0, 0.0], [-0.5, 0.0, 0.484375], [-0.015625, -0.1640625, 0.265625]],
            [[0.0, 0.0, 0.0], [0.0, -1.0, 0.0], [-1.0, 0.0, 0.0]],
        )
    ]
    misses = []
    for polys, tol in ((a, 1e-5), (a, 1e-6), (b, DEFAULT_OBSTRUCTED_TOL)):
        others = [p for k, p in enumerate(polys) if k not in (1, 2)]
        free = nusselt.view_factor(polys[1], polys[2])
        ref = nusselt.view_factor(polys[1], polys[2], obstacles=others, method="clipping", tol=1e-10)
        f = nusselt.view_factor(polys[1], polys[2], obstacles=others, method="clipping", tol=tol)
        misses.append(abs(f - ref) / (tol * free))
    assert max(misses) <= 1.0, misses


def test_replay_default_tol_miss_found_as_a_scale_change():
    # found by the long run (seed 23, after 4 133 passing cases) as "scaled by 1e-6 and moved
    # changes F[4, 3] by 2.14 x the bound": the moved scene was right (0.15 x tol) and the
    # unit-scale one off. F[3, 4] with faces 0, 1, 2 between: 0.0675359277 at obstructed_tol
    # 1e-6, 0.0675354512 at 1e-7 .. 1e-11 (all equal to 16 digits): +4.43 x tol x F_free.
    # The two placements cut the source into the same pieces but one quad's fan took the
    # other diagonal (the kink split classed a vertex within rounding of a cut plane by that
    # rounding's sign; see `test_replay_scale_flipped_a_start_diagonal`); with that diagonal
    # the estimate misses.
    # Now 0.15 x at scale 1, 1e-3 and 0.1 alike
    polys = [
        np.array(p)
        for p in (
            [[0.0, 0.0, 0.0], [0.6433136330632752, 0.0, 0.0], [0.5832171524012022, 0.9, -0.828138184532504]],
            [
                [0.0, 0.0, -0.1338967507835338],
                [-0.5147964105745512, 0.13880781752124105, 2.415555459061412e-230],
                [1.6647889125163395e-17, 0.7697545535238661, -0.416252236642097],
            ],
            [
                [0.4864707712692875, 0.9999999999999999, -0.15186839279377407],
                [0.31003715205580673, 0.757198728164409, 0.698284156943489],
                [1e-300, 2.2250738585e-313, -0.045130812418270105],
            ],
            [
                [-0.7406896115032957, -0.630184832403041, -0.21875],
                [0.0, -0.875, 0.0],
                [0.2578125, 1.0, -0.4302948521957569],
            ],
            [
                [-4.361026004161372e-209, 1.0, -0.7131574283719972],
                [0.42428285915371355, -0.5736358017532267, 0.0],
                [0.0, 0.7315174795604928, 0.3333333333333333],
            ],
        )
    ]
    free = nusselt.view_factor(polys[3], polys[4])
    reference = nusselt.view_factor(polys[3], polys[4], obstacles=polys[:3], method="clipping", tol=1e-10)
    for s in (1.0, 1e-3, 0.1):
        p = [s * q for q in polys]
        f = nusselt.view_factor(p[3], p[4], obstacles=p[:3])
        assert abs(f - reference) <= DEFAULT_OBSTRUCTED_TOL * free, (
            s,
            (f - reference) / (DEFAULT_OBSTRUCTED_TOL * free),
        )


def test_replay_tiny_coordinates_moved_scene():
    # found by the long run (seed 23). Coordinates down to 1e-311 (subnormal) and 1e-12:
    # F[3, 2] was 0.2298468359 at unit scale, 0.2298461904 scaled by 1e-6 and moved by 7e-6
    # (F_free 0.2469), 1.31 x twice the default tol. Faces 0 and 4 have a vertex within 2e-38 of the
    # line of face 3's edge: the kink planes through them are set by rounding, differ between the two
    # placements, and used up the kink split's 128 pieces before the real kink lines were cut.
    # Planes whose vertex lies within 1e-9 of the size of the edge's line are now skipped:
    # 0.07 x tol from the obstructed_tol 1e-9 result, scaled or not, moved by 0 to 1e-3:
    # 0.17 x tol from the tol-1e-9 result at both placements
    polys = [
        np.array(p)
        for p in (
            [
                [-0.03310078916446524, -2.450946631447523e-190, -0.8299136958843323],
                [2.225073858507e-311, 0.5373825607029095, 8.909372970191636e-262],
                [0.9904448739864447, 0.6070021928899174, 3.91434767552648e-161],
            ],
            [
                [1e-12, -0.6926032373756184, -0.3155923474484793],
                [-0.4598399460155872, 0.8477964728592631, -0.5774565413490861],
                [0.681978386642033, 0.9949591842618455, 0.0],
            ],
            [
                [-0.716263365011006, 0.42460041980364216, -4.899834398234151e-244],
                [0.33604945369658545, -0.26537515997697614, -1.175494351e-38],
                [-0.13815145142740648, 0.3269312364676933, -0.6824687435821026],
            ],
            [
                [-2.225073858507e-311, 1e-12, -1.0517411508943042e-38],
                [-0.9320699816238696, 0.0, 0.023095109867329322],
                [0.0, 0.7175240696685452, 0.0],
            ],
            [
                [0.24608169467869323, 0.0, -0.09426232863453676],
                [0.0, -0.4204850217472974, 0.0],
                [0.1397478196390527, -0.2757841140634921, 0.0],
            ],
        )
    ]
    _assert_moved_within(polys)


@pytest.mark.parametrize("method", ["montecarlo", "quadrature"])
def test_replay_hidden_touching_pair_sampled(method):
    # face 3 hides face 2 from face 4 (see the test above), so F = 0, as clipping gives. The
    # two faces share the vertex (0, 1, 0), where the kernel is singular; the control variate
    # sampled the blocked part, which here is all of it: montecarlo gave 0.00162 +- 0.00020
    # (8 standard errors off), quadrature 0.00183 (the free F is 0.00192). Where the largest
    # kernel sample is blocked they now take the visible part of the same samples
    p = [np.array(v) for v in ORIGIN_FACES]
    for tol in ({"tol": 1e-3}, {"tol": 1e-6}) if method == "quadrature" else ({},):
        f, std = nusselt.view_factor(p[4], p[2], obstacles=[p[3]], method=method, return_std=True, **tol)
        assert 0.0 <= f <= 4 * std + 1e-9


def test_blocker_hovering_over_the_receiver_at_tight_tol():
    # the pair below at tol 1e-9 and 1e-10 gave 7.6e-16: face 4's side ran out of evaluations
    # and face 2's, whose samples all miss the thin wedge, replaced it, claiming the pair
    # hidden whole; the sides disagree beyond both error estimates, so face 4's stays. The
    # reference is the graded Gauss rule's 4.9396e-9 (see below); at 1e-10 the budget ends
    # within 1e-9 x F_free of it
    p = [np.array(v) for v in ORIGIN_FACES]
    lifted = np.array([[1e-8, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
    free = nusselt.view_factor(p[2], p[4])
    for tol in (1e-9, 1e-10):
        f = nusselt.view_factor(p[2], p[4], obstacles=[lifted], method="clipping", tol=tol)
        assert abs(f - 4.9396e-9) <= 1e-9 * free, (tol, f)


def test_blocker_hovering_over_the_receiver_meets_tol():
    # face 0 lifted 1e-8 over face 2 at one vertex, alone between faces 2 and 4: only the thin
    # wedge between them lets light through, F = 4.9410e-9 (clipping at 1e-9 and 1e-10; a
    # graded 80 x 12 x 40 Gauss rule over face 4 of the exact point F gives 4.9396e-9).
    # At tol 1e-6, 1e-7 and 1e-8 the error was 2.1, 2.5 and 2.0 x tol x F_free (a strict xfail
    # until 2026-12). The kink split leaves face 4 one piece (and a sliver): the events of the
    # wedge's edges all lie in the plane z = 0, which holds face 4's edge, so none cuts it; the
    # visible F sits in a strip along that edge as wide as face 4 is thick (2^-8). Leaves along
    # the edge had their rule 18 % off and claimed 20 x less; leaves with an edge on a kink
    # plane that bounds the source now count their whole difference (0.12, 0.52 and 0.71 x
    # tol against a per-leaf brute-force integration)
    p = [np.array(v) for v in ORIGIN_FACES]
    lifted = np.array([[1e-8, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
    free = nusselt.view_factor(p[2], p[4])
    reference = nusselt.view_factor(p[2], p[4], obstacles=[lifted], method="clipping", tol=1e-10)
    assert abs(reference - 4.9396e-9) <= 1e-3 * free * 1e-6
    for tol in (1e-6, 1e-7, 1e-8):
        f = nusselt.view_factor(p[2], p[4], obstacles=[lifted], method="clipping", tol=tol)
        assert abs(f - reference) <= tol * free, (tol, (f - reference) / (tol * free))


# found by the long run (seed 24, after 4 187 passing cases) as "scaled by 1e-6 and moved
# changes F[0, 1] by 1.38 x the bound": face 0 has a vertex 1e-6 above face 1's plane, face 2
# crosses both planes. F[0, 1] = 0.0582488760312 at obstructed_tol 1e-11 and 1e-12, at every
# scale below (equal to 13 digits); F_free 0.05832
NEAR_TOUCHING_PAIR = [
    [[0.0, -0.18359375, 0.09765625], [0.09476491635586348, 0.0, 1e-06], [0.0, -0.9375, -0.5]],
    [[0.0, 0.0, 0.0], [-0.421875, 0.0, 0.0], [0.859375, -0.6015625, 0.0]],
    [[0.0, -0.408203125, 0.5], [0.0, -0.1879407936051012, -0.375], [0.306640625, 0.2265625, 0.9375]],
]


def test_replay_scale_flipped_a_start_diagonal():
    # the kink split clipped its pieces with a tolerance of 0, so a vertex within rounding of
    # a kink plane was classed by that rounding's sign, which changed the pieces' vertex lists
    # and flipped one quad's diagonal with the scale: 0.08 x obstructed_tol off at scale 1,
    # 2.84 x at 0.1, 3e-3, 1e-3 and 1e6. Vertices within the split's tolerance of a plane now
    # count as on it, and every scale gives the unit-scale pieces. The reference is checked
    # against the integral over face 1 (another source, other kink lines) by reciprocity. (At
    # tol 1e-10 the pair is 5e-12 of F_free off, within its target but not the 1e-12 below.)
    a, b, c = (np.array(p) for p in NEAR_TOUCHING_PAIR)
    free = nusselt.view_factor(a, b)
    reference = nusselt.view_factor(a, b, obstacles=[c], method="clipping", tol=1e-11)
    area_a, area_b = nusselt.Scene.from_polygons([a, b]).areas
    other_side = nusselt.view_factor(b, a, obstacles=[c], method="clipping", tol=1e-11) * area_b / area_a
    assert abs(other_side - reference) <= 1e-12 * free, (other_side - reference) / free
    for s in (1e6, 1.0, 0.1, 3e-3, 1e-3, 1e-9):
        tight = nusselt.view_factor(s * a, s * b, obstacles=[s * c], method="clipping", tol=1e-12)
        assert abs(tight - reference) <= 1e-12 * free, s
        f = nusselt.view_factor(s * a, s * b, obstacles=[s * c])
        assert abs(f - reference) <= DEFAULT_OBSTRUCTED_TOL * free, (
            s,
            (f - reference) / (DEFAULT_OBSTRUCTED_TOL * free),
        )


def test_replay_scale_flipped_start_diagonal_from_another_vertex():
    # the same pair with face 0's vertices listed from the second or third: the fan then
    # took the other diagonal of that quad at every scale, and its first samples saw a
    # tenth of the hidden G there (3.1e-9 for 2.9e-8) while the estimate was content
    # (5.9e-9 for a goal of 6.0e-9): 2.86 x tol x F_free. Face 2 crosses both planes; the
    # kink split now takes the events of face 2 as cut to the slab between them (its cut
    # has vertices on the planes), and every listing is 0.78-0.79 x tol off
    a, b, c = (np.array(p) for p in NEAR_TOUCHING_PAIR)
    free = nusselt.view_factor(a, b)
    reference = nusselt.view_factor(a, b, obstacles=[c], method="clipping", tol=1e-10)
    for shift in (1, 2):
        f = nusselt.view_factor(np.roll(a, shift, axis=0), b, obstacles=[c])
        assert abs(f - reference) <= DEFAULT_OBSTRUCTED_TOL * free, (
            shift,
            (f - reference) / (DEFAULT_OBSTRUCTED_TOL * free),
        )


def test_replay_default_tol_misses_of_seeds_24_and_25():
    # found by the long runs after the kink split was made scale-free (seed 24 after 5 688
    # passing cases, seed 25 after 598), both as "an obstacle raises F" and both at every
    # scale alike: the estimate, not a decision that flips (docs/algorithms.md §6.2).
    # Seed 24: F[2, 3] with faces 0 and 1 between, 0.0057084648 at obstructed_tol 1e-7 ..
    # 1e-10 (within 0.2 x tol), -3.42 x tol x F_free at 1e-6 and -1.05 x at 1e-5. Seed 25:
    # F[1, 2] with face 0 and the obstacle between, 0.0151912600 at 1e-7 .. 1e-12, +6.92 x at
    # 1e-6, the same on the build before the kink-split change
    seed24 = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.126953125, -0.71875], [-0.7890625, 0.0, 0.8515625]],
        [[0.5, 0.5, 1.0], [0.546875, -0.5, -0.8125], [-0.9921875, 0.83984375, 0.0]],
        [[0.375, -0.5, 0.0], [0.0, 0.0, 0.0], [0.07421875, 0.0, -0.75]],
    ]
    seed25 = [
        [[0.0, -1.0, 0.0], [0.0, -0.0390625, 0.6953125], [0.390625, 0.90625, -1.0]],
        [[0.84375, 0.3984375, 1.0], [0.4921875, 0.0, 0.0], [0.03125, -0.3984375, 0.0]],
        [[-0.59375, 0.0, 0.375], [0.0, 0.0, -0.78125], [-0.69140625, 1.0, 0.0]],
        [[0.0, 0.0, 1.0], [0.0, 0.0, 0.412109375], [0.0, -1.0, 0.0]],
    ]
    misses = []
    for raw, (i, j), between in ((seed24, (2, 3), (0, 1)), (seed25, (1, 2), (0, 3))):
        p = [np.array(v) for v in raw]
        others = [p[k] for k in between]
        free = nusselt.view_factor(p[i], p[j])
        ref = nusselt.view_factor(p[i], p[j], obstacles=others, method="clipping", tol=1e-10)
        f = nusselt.view_factor(p[i], p[j], obstacles=others)
        misses.append(abs(f - ref) / (DEFAULT_OBSTRUCTED_TOL * free))
    assert max(misses) <= 1.0, misses


def test_replay_default_tol_miss_of_seed_26():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=26 (after the joint hidden test and the
    # casting blockers; the build before them gives the same numbers): in the free scene F[3, 1]
    # with faces 0 and 2 between is computed from face 1's side, 0.0170747514 at the default,
    # against 0.0170758953 at obstructed_tol 1e-8 .. 1e-10 from either side: 64 x tol x F_free,
    # so the obstacle of that case "raised" F by 32 x the slack. Face 3's side at the default is
    # within 0.03 x tol. Face 2 alone is a candidate blocker; it comes close to face 1 beside a
    # start piece across which the shadowed F rises 35-fold, and the rule and its children's
    # were both 0.19 % off there, agreeing to 7e-6. Steep start pieces now count a share of
    # their children's distance from the linear rule as error (STEEP_SHARE in clipping.rs);
    # this pair and both pairs above then meet the default tol
    raw = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]],
        [[0.0, 0.0, -0.75], [-0.9765625, 0.6875, 0.625], [0.0, -0.283203125, 0.0]],
        [[0.0, 0.0, -0.984375], [0.0, -1.0, 0.0], [-0.09436022758029039, -0.1328125, 0.8125]],
        [[0.0, -0.53125, 0.25], [0.7109375, 0.0, 0.8203125], [0.58984375, 0.84375, 0.53125]],
    ]
    p = [np.array(v) for v in raw]
    others = [p[0], p[2]]
    free = nusselt.view_factor(p[1], p[3])
    ref = nusselt.view_factor(p[1], p[3], obstacles=others, method="clipping", tol=1e-10)
    f = nusselt.view_factor(p[1], p[3], obstacles=others)
    assert abs(f - ref) <= DEFAULT_OBSTRUCTED_TOL * free, abs(f - ref) / (DEFAULT_OBSTRUCTED_TOL * free)


def test_replay_seed_27_one_side_converges_off():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=27 (the build before this session gives
    # the same numbers) as "an obstacle raises F[4, 3] by 1.32 x the slack": in the free scene
    # the pair (3, 4) with faces 0-2 between is integrated over face 3, which gives
    # 0.0163889434 x A_4 / A_3 at obstructed_tol 1e-8 .. 1e-11 alike (its estimate content),
    # while face 4's side converges to 0.0163888179 and an independent centroid rule of the
    # exact point F over face 4 (4^6, 4^7 triangles, Richardson) gives 0.016388821. Face 1
    # pierces face 3's edge, and there lines through its edge, one of face 2 and one of face
    # 4 make kinks along curves through the pierce point (edge-edge-edge events) that no
    # planar event cut, in a sector the samples missed at every level. With their tangents
    # and chords cut (`kinks_through_a_pierce_point_are_cut_along_their_tangents`), face 3's
    # side gives 0.0163888185 at the default (0.05 x tol) and 0.0163888179 from 1e-9 on
    raw = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.125, 0.0, -1.0]],
        [[0.0, 0.0, 0.0], [0.0, -1.0, -1.0], [-1.0, 0.0, 0.0]],
        [[0.0, 1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]],
        [[0.0, -0.75, 0.0], [0.0, -1.0, 0.0], [-1.0, 0.0, 0.0]],
    ]
    p = [np.array(v) for v in raw]
    others = p[:3]
    free = nusselt.view_factor(p[4], p[3])
    reference = nusselt.view_factor(p[4], p[3], obstacles=others, method="clipping", tol=1e-10)
    assert abs(reference - 0.016388821) <= 1e-8
    for tol in (DEFAULT_OBSTRUCTED_TOL, 1e-10):
        f = nusselt.view_factor(p[3], p[4], obstacles=others, method="clipping", tol=tol) * area(p[3]) / area(p[4])
        assert abs(f - reference) <= tol * free, (tol, (f - reference) / (tol * free))


@pytest.mark.parametrize("lean", [0.0, 1e-11, 1e-9, 1e-8])
def test_replay_seed_28_face_within_the_band_of_another(lean):
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=28 (after 10 000 clean cases of the
    # pair test) as "scaled and moved changes F[2, 1] by 41 000 x the bound" and "an obstacle
    # raises F". Face 1 leans 1e-9 out of the plane x = 0 of face 3, and the two face each
    # other over a triangle of area 0.25, half of face 1 (so F[1, 3] = 0.5: at no distance all
    # that half sends arrives); face 2 sees face 1 only through that triangle, which face 3
    # covers: F[2, 1] is 0 up to the 1e-9 lean. It came out 0.0320 at the origin and 0.0231
    # moved by 7 or scaled by 1e-6 and moved (montecarlo 0.049; the free F is 0.108): the
    # choice of the side to integrate over counted face 3 as lying in face 1's plane (a band
    # of 1e-9, wider than the pair test's 1e-10), and the point evaluations from face 1 cut
    # blockers within 1e-9 of their height. Leaning 1e-10 or less, the faces are coplanar
    # (F[1, 3] = 0) and face 3 hides nothing: F[2, 1] is the free F, wherever the scene lies
    raw = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [lean, 1.0, -1.0]],
        [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
        [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]],
    ]
    p = [np.array(v) for v in raw]
    free = nusselt.view_factor(p[2], p[1])
    for s, shift in ((1.0, 0.0), (1.0, 7.0), (1e-6, 7e-6)):
        F = nusselt.form_factors(nusselt.Scene.from_polygons([s * q + shift for q in p])).matrix.toarray()
        if lean >= 1e-9:
            assert F[1, 3] == pytest.approx(0.5, abs=1e-6)
            assert F[2, 1] <= DEFAULT_OBSTRUCTED_TOL * free, (s, shift, F[2, 1])
        else:
            assert F[1, 3] == 0.0
            assert F[2, 1] == pytest.approx(free, rel=1e-9), (s, shift, F[2, 1])


def test_replay_seed_29_kinks_of_an_edge_in_the_receivers_plane():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=29 as "scaled and moved changes F[3, 4]
    # by 4.86 x the bound": face 0 is cut to the slab of the pair (3, 4) along face 3's plane,
    # and face 3's vertex (0.1686, 0, 0) lies 2e-8 off face 0's plane, so close to that cut
    # edge's line that the plane through both (face 3's own plane) took its tilt from the
    # rounding: it cut face 4 or not as the scene was moved, and which later events were cut
    # before the split's piece limit followed from it. Moved, a start piece kept an uncut
    # kink, and its estimate (4e-9 of the free F) missed 5.9e-6. Two more events were decided
    # by the rounding: transversals through the point where a cut edge crosses a receiver edge
    polys = [
        [
            [0.0, 0.0, 0.0],
            [0.7400965668255952, 0.0, 0.005768499972629515],
            [0.0, -1.4556360502941236e-05, -0.8220932957095441],
        ],
        [
            [-0.8802780306775775, 0.9048871528122704, -0.5850838786843687],
            [-0.6211757162182429, 0.0, 1.0],
            [0.0, -0.24196735374153922, -0.6161340879345806],
        ],
        [
            [0.0, 0.0, 0.0],
            [0.9360205018919889, 0.3333333333333333, -1.3072089421502345e-101],
            [-0.4017510088515922, -0.2598489043905884, -0.6923567938163759],
        ],
        [
            [-0.4754994838548029, -0.7406146439027537, -0.49981667377081596],
            [-0.2485020253622785, 0.0, 0.009033592887300435],
            [0.16861785760341141, 0.0, 0.0],
        ],
        [
            [0.0, 0.0, -0.355448461648462],
            [-0.8221504539000368, 0.0, 0.0],
            [0.5310796321030398, -0.9091450164818093, 0.6596924425467035],
        ],
    ]
    _assert_moved_within([np.array(q) for q in polys])


def test_replay_seed_29_a_kink_past_the_split_limit():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=29 as "an obstacle raises F[3, 4] by
    # 1.12 x the slack": the obstacle hides nothing of the pair, but its events fill the split
    # of face 4 up to MAX_KINK_PIECES before an event of the others; on the start piece that
    # kink crosses, the samples spread 11-fold and Radon's rule and its children's agreed to
    # 6.5e-5 of the piece with both 4 % off (2.2 x tol of the pair, estimate 3.6e-9)
    polys = [
        [
            [0.0, 0.0, 0.0],
            [0.7400965668255952, 0.0, 0.005768499972629515],
            [0.0, -1.4556360502941236e-05, -0.8220932957095441],
        ],
        [
            [0.0, -0.24196735374153922, -0.6161340879345806],
            [-0.8802780306775775, 0.9048871528122704, -0.5850838786843687],
            [-0.6211757162182429, 0.0, 1.0],
        ],
        [
            [0.0, 0.0, 0.0],
            [0.9360205018919889, 0.3333333333333333, -1.3072089421502345e-101],
            [-0.4017510088515922, -0.2598489043905884, -0.6923567938163759],
        ],
        [
            [-0.7406146439027537, -0.4754994838548029, -0.49981667377081596],
            [-0.2485020253622785, 0.0, 0.009033592887300435],
            [0.16861785760341141, 0.0, 0.0],
        ],
        [
            [0.0, 0.0, -0.355448461648462],
            [-0.8221504539000368, 0.0, 0.0],
            [0.5310796321030398, -0.9091450164818093, 0.6596924425467035],
        ],
    ]
    obstacle = [
        [0.0, 0.9116727647393659, 0.0],
        [-0.6923567938163759, -0.2598489043905884, -0.4017510088515922],
        [-0.5252360993440671, 0.0, -0.6957066428208201],
    ]
    _assert_obstacle_only_takes_away([np.array(q) for q in polys], np.array(obstacle))


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=30 (after 10 000 clean cases of the pair
# test): in both, face 4 leans 2^-24 (6e-8) out of the plane x = 0 that other faces lie in, and
# the part of it in front of its partner is a sliver that wide. The first: see the test. In
# the second, faces 0
# and 1 hide that sliver from face 3 whole (an exact segment test on 40 000 sampled pairs: all
# hidden; every segment from face 3 to it crosses x = 0 at z >= 0, the blockers' edge lying
# on face 3's edge). Scaled by 1e-6 and moved, F[4, 3] was the free 8.729e-9 (the shaft of the
# sliver culled face 0: an edge of it 1e-7 long gave its planes a tolerance of 3e-7 of the
# pair's size), then 3e-15; at the origin it was 8.667e-9, integrated over face 3: from most
# of face 3 the point F to the sliver is 1e-16, its free and hidden values, taken along two
# routes, differed in the last bit (visible +-0.64 ulp, 5-20 % of it), so the start pieces
# along the shared edge failed the test "at most 1 % of every sample's point F visible" and
# integrated the hidden part, the kernel's rise within 6e-8 of the edge, out of evaluations
# with 0.7 % hidden (estimate 0.35 %); that stayed against face 4's side (all but 6.9e-8
# hidden) since the sides disagree by more than their estimates allow. Moved, the two values
# agreed exactly. A visible part within the rounding of the point F now counts as none (see
# VISIBLE_ROUNDING in crates/nusselt-core/src/obstructed/clipping.rs): 2.2e-15 at the origin
SEED_30_OBSTACLE = [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]]


def test_replay_seed_30_obstacle_beside_a_leaning_face():
    # F[4, 2] without the obstacle was 2.953642e-4 at every tol, with it 2.954532e-4, for
    # 2.95451e-4 (graded Gauss over face 4 of the exact point F: 2.954492e-4 / 2.954520e-4 with
    # 6 / 10 points a panel, panels graded by 10 down to 1e-12 towards every line where the
    # point F has a kink or a band). Integrated over face 2 it ran out of evaluations
    # (estimate 12 x the goal) 6e-9 from that; face 4's side, which face 3 covers flat 6e-8
    # above it, claimed 4.3e-9 and was 9e-8 off
    # (a band as wide as that height missed) but replaced face 2's, the two agreeing within
    # SIDES_DISAGREE times their estimates. A side a blocker lies flat over no longer
    # replaces the other (clipping.rs, `lies_flat_over`)
    polys = [
        [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, -1.0, 0.0],
        ],
        [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 0.899647877646554],
            [-0.7902228807353544, 0.0, -0.8915643764209942],
        ],
        [
            [0.0, 0.0, 0.0],
            [0.6750968359876115, 0.6448861784688971, 0.6925955256530236],
            [-0.9109849740018543, 0.0, -1.0],
        ],
        [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 1.0, -1.0],
        ],
        [
            [0.0, 0.0, -0.5],
            [0.0, 1.0, 0.0],
            [-5.960464477539063e-08, 0.0, 0.0],
        ],
    ]
    _assert_obstacle_only_takes_away([np.array(q) for q in polys], np.array(SEED_30_OBSTACLE))
    p = [np.array(q) for q in polys]
    free = nusselt.view_factor(p[4], p[2])
    f = nusselt.view_factor(p[4], p[2], obstacles=[p[0], p[1], p[3]])
    assert abs(f - 2.95451e-4) <= DEFAULT_OBSTRUCTED_TOL * free, (f - 2.95451e-4) / (DEFAULT_OBSTRUCTED_TOL * free)


def test_replay_seed_30_leaning_face_moved():
    # see the comment above SEED_30_OBSTACLE: F[4, 3] is 0 (within rounding) wherever the scene
    # lies
    polys = [
        [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0],
        ],
        [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, -1.0, 0.0],
        ],
        [
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
        ],
        [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
            [0.0, 1.0, 0.0],
        ],
        [
            [0.0, -1.0, -1.0],
            [0.0, 1.0, 0.0],
            [-5.960464477539063e-08, 0.0, 0.0],
        ],
    ]
    polys = [np.array(q) for q in polys]
    _assert_moved_within(polys)
    F = nusselt.form_factors(nusselt.Scene.from_polygons(polys)).matrix.toarray()
    assert F[4, 3] <= DEFAULT_OBSTRUCTED_TOL * _free(polys)[4, 3], F[4, 3]


def test_replay_seed_31_scene_path_at_a_loose_tol():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=31 (scene test, after 37 min) as
    # "scaled and moved changes F[2, 3] by 4.5 x the bound" at obstructed_tol 1e-3. The scene
    # finds face 1 alone a candidate (face 0 hides nothing of the pair); face 1 crosses both
    # faces' planes away from them, the clearances tie, and the integral ran over face 2: a
    # single start piece (no kink crosses it) whose coarse estimate, its rule against its
    # centroid, said 7.0e-4 of F_free for an error of 9.05e-3 (0.0155303 for 0.0157367).
    # A source left whole by the split now starts with its children
    polys = [
        [
            [0.0, 0.0, 1.0],
            [0.0, -0.5, 0.0],
            [-1.0, 0.0, 0.0],
        ],
        [
            [0.0, 0.0, -0.75],
            [0.625, 0.0625, -0.25],
            [-0.75, 0.5, 0.25],
        ],
        [
            [0.0, 0.0, 0.0],
            [0.0, -0.859375, -0.00390625],
            [-0.25, -0.25, 0.0],
        ],
        [
            [0.0, 0.0, 0.0],
            [0.0, 0.96875, -1.0],
            [0.25, -0.125, 0.0],
        ],
    ]
    polys = [np.array(q) for q in polys]
    free = nusselt.view_factor(polys[2], polys[3])
    reference = nusselt.view_factor(polys[2], polys[3], obstacles=polys[:2], method="clipping", tol=1e-9)
    F = nusselt.form_factors(nusselt.Scene.from_polygons(polys), obstructed_tol=1e-3).matrix.toarray()
    assert abs(F[2, 3] - reference) <= 1e-3 * free, (F[2, 3] - reference) / (1e-3 * free)


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=32 (scene test): in both, face 3 leans
# 1e-5 out of the plane x = 0 (its vertex (1e-5, 0, 0)) and the obstacle lies in that plane.
SEED_32_OBSTACLE = [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]


def test_replay_seed_32_steep_piece_at_a_loose_tol():
    # "scaled and moved changes F by 500 x the bound" at obstructed_tol 1e-3: F[0, 3] was
    # 8.74636e-6 at the origin (the unobstructed F is 8.74700e-6) and 0 moved. Face 2 (with face
    # 1) covers every crossing of the plane y = 0 between faces 0 and 3: F[0, 3] = 0 (clipping
    # at tol 1e-9 either way round and placed, and an exact segment test on 20 000 sampled
    # pairs: all blocked). Moved, the joint hidden-whole test found it; at the origin it does
    # not (the crossings' hull lies along face 2's edge, grown by 1e-12 it leaves 1e-12 of it
    # open, right at the threshold) and the integral ran over one start piece, whose samples
    # put its unobstructed G at 1.5e-11 for 5.5e-7 (the point F rises towards the edge the two
    # faces nearly share): below a tenth of the goal, the piece integrated the hidden part,
    # all of which lies along that edge. A piece whose samples' free F spreads now asks for its
    # own G, and integrates the visible part (0)
    polys = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 0.125], [0.0, -1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]],
        [[0.0, 0.0, 0.5], [0.0, 1.0, 0.0], [1e-05, 0.0, 0.0]],
        [[0.0, 1.0, 0.0], [0.0, 1.0, 1.0], [-1.0, 1.0, 0.0]],
    ]
    polys = [np.array(q) for q in polys]
    for tol in (None, 1e-3):
        _assert_moved_within(polys, tol=tol)
    _assert_obstacle_only_takes_away(polys, np.array(SEED_32_OBSTACLE))


def test_replay_seed_32_blocker_crossing_beside_a_leaning_face():
    # "an obstacle raises F[3, 4] by 2.49 x the slack": the obstacle's scene was right and the
    # free one off. F[3, 4] with faces 0-2 between: 0.0676388506 at obstructed_tol 1e-5 .. 1e-7
    # (-4.94 x tol x F_free at the default), 0.0676392496 at 1e-8 .. 1e-10 and with the obstacle
    # (by reciprocity over face 4 alike). Face 2 alone casts; it crosses face 3's plane beside
    # it (the trace touches face 3 at one point of its edge) and its edge from the origin hovers
    # up to 1e-5 over face 3, where the hidden F rises from 0 within 1e-5 of face 2's plane
    # along a start piece whose rule and children's agreed. Counted as crossing (0.1 of face
    # 3's size) it sent the integral over face 3; a blocker whose trace does not run over the
    # face now counts as low as it hovers, and the integral runs over face 4 (0.05 x tol)
    polys = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, 0.5], [0.0, -1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.9375, 1.0], [-1.0, 0.0, 0.0]],
        [[0.0, 0.0, 0.5], [0.0, 1.0, 0.0], [1e-05, 0.0, 0.0]],
        [[0.0, 1.0, 0.0], [0.0, 1.0, 1.0], [-1.0, 1.0, 0.0]],
    ]
    polys = [np.array(q) for q in polys]
    _assert_obstacle_only_takes_away(polys, np.array(SEED_32_OBSTACLE))
    free = nusselt.view_factor(polys[3], polys[4])
    reference = nusselt.view_factor(polys[3], polys[4], obstacles=polys[:3], method="clipping", tol=1e-9)
    f = nusselt.view_factor(polys[3], polys[4], obstacles=polys[:3])
    assert abs(f - reference) <= DEFAULT_OBSTRUCTED_TOL * free, (f - reference) / (DEFAULT_OBSTRUCTED_TOL * free)


def test_replay_seed_33_vertex_a_rounding_behind_a_leaning_face():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=33 (scene test) as "scaled and moved
    # changes F by 1.81 x the bound" at the default obstructed_tol. Face 3 leans 6.1e-5 out of
    # z = 0 over face 4 (both facing +z, open like a book nearly flat along the line from
    # (0, -0.5, 0) to (-1, 0, 0)); they see each other across that line, F[3, 4] = 1.8598638e-9
    # (a 30-digit contour integral: 1.85986384288e-9 at both placements). Face 4's vertex
    # 2.2e-16 above z = 0 puts face 3's vertex (0, -0.5, 0) 1.1e-16 behind face 4's plane: face 3
    # was kept whole (within the plane tolerance) while face 4 was cut where it crosses face 3's
    # plane, 9.1e-13 off that vertex, and the two outlines overlapped by a sliver of 4.5e-13
    # that the contour sum counted whole: F[3, 4] 1.858044836e-9 at the origin (-9.8e-4), the
    # unobstructed kernel alike, and 1.859863839e-9 moved (where the 2.2e-16 rounds away).
    # Faces 0-2 (in x = 0) hide nothing of the pair. Such a vertex is now cut off exactly
    # (geometry::clip_pair): within 2.1e-9 of the reference at every placement tried
    polys = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
        [[0.0, -0.5, 0.0], [0.0, 0.0, 6.103515625e-05], [-1.0, 0.0, 0.0]],
        [[-1.0, 0.0, 0.0], [0.0, -1.0, 2.220446049250313e-16], [0.0, 0.0, 0.0]],
    ]
    polys = [np.array(q) for q in polys]
    for tol in (None, 1e-3):
        _assert_moved_within(polys, tol=tol)
    reference = view_factor_mp(polys[3], polys[4])  # 40 digits, 1.85986384288e-9
    for method in ("analytic", "contour"):
        f = nusselt.view_factor(polys[3], polys[4], method=method)
        assert abs(f - reference) <= 1e-8 * reference, (method, f)


SEED_33_LEANING = [
    [[0.0, 0.0, 0.0], [0.0, 0.0, -0.25], [0.8448319428180837, 0.5, 0.0]],
    [[0.0, 0.0, -0.25], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
    [[0.0, -0.5, -0.25], [0.82421875, 0.0, -0.9375], [1e-05, 0.0, -0.25]],
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]],
    [[2.220446049250313e-16, -0.5, -0.9375], [0.0, 0.53125, -0.375], [0.0, 0.0, 0.0]],
]


def test_replay_seed_33_leaning_face_at_a_loose_tol():
    # found by the same long run (seed 33) after the case above was fixed, after 18 min: "scaled
    # and moved changes F by 16.1 x the bound" at obstructed_tol 1e-3 (0.04 x at the default).
    # Face 2 leans 1e-5 (its vertex (1e-5, 0, -0.25)). F[2, 4] was 6.9369208e-3 at the origin and
    # 7.2667229e-3 moved; clipping at tol 1e-9 (every other face an obstacle) gives 7.2664159e-3
    # at both placements (F_free 1.0265e-2): the origin was 32 x tol x F_free low. Faces 0 and 1
    # cross face 2's plane 6.4e-6 deep, 3e-6 beside its corner, where the point F over face 2
    # is steep: the start pieces there count their children's whole difference as error. Their
    # traces were looked for in the plane of the first start piece, a sliver (2.6e-12 of the
    # area) whose normal rounding tilted by 1.8e-5 rad, so that both blockers lay on one side:
    # no trace, a quarter of the difference, and the corner piece (its rule 10 % off) kept.
    # The traces are now taken in the source's own plane (clipping.rs,
    # `the_traces_lie_in_the_plane_of_the_source`): 7.2667576e-3 at the origin (0.03 x tol)
    _assert_moved_within([np.array(q) for q in SEED_33_LEANING], tol=1e-3)


def test_seed_33_leaning_face_against_the_reference():
    # The case above, against the reference rather than moved: with the traces found, the start
    # piece over face 2 at the corner near the blockers (its point F steep, samples 5.3e-4 ..
    # 7.8e-3, rising towards the corner over decades of distance) has its rule 9.1e-5 of G
    # off and its children's rule 8.8e-5 (the corner child carries the same error), so their
    # difference, 3.1e-6, was all its estimate said; it met the goal at 1e-2 and 3e-3 (2.75e-5
    # and 8.3e-6) and F was 3.2 and 10.7 x tol low at both placements. The steep-leaf share of
    # the rule's gap to equal weights (STEEP_SHARE) says nothing for the equal-weight rule of
    # targets from 1e-4 on. There a steep leaf now counts its children's difference without
    # their cancellation (clipping.rs, `uncancelled_difference`): each child's departure from
    # the parent's samples' linear model, less what a quadratic gives, root-sum-squared; the
    # corner child departs by 8.2e-5, the others by -6.8e-5 .. 3e-6, 7.6e-5 in all. F is now
    # within 0.07 x tol at 1e-2 and 0.05 x at 3e-3, at both placements
    polys = [np.array(q) for q in SEED_33_LEANING]
    s = 1e-6
    for q in (polys, [s * p + 7 * s for p in polys]):
        free = nusselt.view_factor(q[2], q[4])
        obstacles = [q[0], q[1], q[3]]
        reference = nusselt.view_factor(q[2], q[4], obstacles=obstacles, method="clipping", tol=1e-9)
        for tol in (1e-2, 3e-3):
            f = nusselt.view_factor(q[2], q[4], obstacles=obstacles, obstructed_tol=tol)
            assert abs(f - reference) <= tol * free, (tol, (f - reference) / (tol * free))


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=34 (scene test): face 0 leans 1e-8 and
# face 2 1e-6 out of the plane x = 0, so face 0 lies in front of face 2 (seen from face 1)
# on one side of the line where their planes cross (0.99 y + 1.5 z < 0.5) and hides that
# sliver S of face 2's part in front of face 1. Hidden F[1, 2] = F(face 1 -> S): S
# (orthogonal projection) and the exact central projection of face 0 from each source point
# differ by < 1e-28 in the point F wherever the point sees face 2; F(1 -> S) = 1.5513255768e-4
# by the closed form and by the contour integral (1e-17 apart), and by 30-digit Lambert
# quadrature on graded panels 1.539e-4 / 1.55125e-4 (4 / 8 points a panel, the exact hidden
# part within 1e-11 of F(1 -> S) at both): F[1, 2] = 5.7404901161e-4 - 1.5513255768e-4 =
# 4.1891645392e-4.
SEED_34_F12 = 4.1891645392e-4


def test_replay_seed_34_blocker_hovering_over_the_other_side():
    # "scaled and moved changes F[1, 2] by 164 x the bound" at the default obstructed_tol.
    # Integrated over face 2, a point of S at distance d from the crossing line has face 0 only
    # ~1.8e-6 d above it. The exact point visibility cut the blocker a little below p's height
    # over face 1 (2.2e-13 of p's coordinates, 7.7 x wider relative to the scene when moved) to
    # keep the central projection finite; that strip covered a wide cone from p and light
    # leaked (d = 1e-6: hidden point F 0.4175 at the origin, 0.1164 moved, for ~0.5262):
    # F[1, 2] 4.1891646e-4 / 4.1910469e-4 (moved, 328 x the goal off). A blocker near p's
    # height now casts the exact cone from p over it, cut by half-planes on the receiver
    polys = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1e-08, 1.0, 0.0]],
        [[0.0, 0.0, 0.0625], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
        [[0.0, -1.0, 1.0], [0.0, 0.5, 0.0], [1e-06, 0.0, 1.0]],
    ]
    polys = [np.array(q) for q in polys]
    free = nusselt.view_factor(polys[1], polys[2])
    s = 1e-6
    moved = [s * q + 7 * s for q in polys]
    for q in (polys, moved):
        f = nusselt.view_factor(q[1], q[2], obstacles=[q[0]])
        assert abs(f - SEED_34_F12) <= DEFAULT_OBSTRUCTED_TOL * free, (f - SEED_34_F12) / (
            DEFAULT_OBSTRUCTED_TOL * free
        )
    _assert_moved_within(polys)


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=35 (scene test, after 9 min), not yet
# diagnosed: an obstacle raises some F by 1.45 x the slack, and scaling by 1e-6 and moving
# changes some F by 1.44 x the bound, both at the default obstructed_tol (1e-3 is within).
# Face 1 has a coordinate of 1e-60 (a rounding-scale y).
SEED_35 = [
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[0.0, 0.0, 0.671875], [0.96875, 0.0, -0.828125], [-0.84375, 1e-60, -0.04296875]],
    [[0.0, 0.0, -0.98046875], [0.0, -0.93359375, -0.6796875], [-0.13671875, 0.07095695185751683, 0.0]],
    [[0.0, 0.06411104616764818, 0.0], [0.015625, -0.634765625, -0.40625], [-0.44257406402799526, 0.0, 0.0]],
]


# Both failed on F[1, 2] of the scene without the obstacle: 8.4536329e-3 for 8.45365862264e-3
# (independent reference: 40-digit unobstructed F less the hidden part, Lambert's formula on the
# receiver clipped to the blocker's projection, Gauss rules on the kink-cut source), 2.9 x
# obstructed_tol off with the error estimate under its goal; with the obstacle and moved it was
# right. Integrated over face 2, face 3 close beside its edge, a leaf two levels below a start
# piece had samples spread 27-fold, its rule and its children's 0.07 % off and agreeing to 7e-11;
# only start pieces that steep were held to a share of their children's linear gap (clipping.rs,
# STEEP_SHARE), now every leaf is. Face 1's 1e-60 only decided where that leaf fell: it tilts the
# plane so that face 2's vertex on it lies behind, and the part of face 2 starts at another vertex.
def test_replay_seed_35_obstacle_raises_f():
    obstacle = np.array([[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 1.0, -1.0]])
    _assert_obstacle_only_takes_away([np.array(q) for q in SEED_35], obstacle)


def test_replay_seed_35_moved():
    _assert_moved_within([np.array(q) for q in SEED_35])


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=36 (scene test, after 10 000 clean cases of
# the pair test and 22 min): face 0 leans 1e-8 out of the plane y = 0 beside face 2 (in y = 0),
# the two sharing the line y = z = 0, and face 1 lies in z = 0, standing on that line between
# them. Every ray from face 0 to face 2 crosses z = 0 within the 1e-8 gap, where face 1 is
# (except beyond x = 0), and the unobstructed F (1.0e-8, 40 digits) comes from a band about
# 1e-8 wide along the common line. F[0, 2] is 3.46e-15 (a tensor Gauss rule over face 0 of
# the visible point F, graded by 4 towards both edges at the origin down to 1e-18: 3.4631e-15,
# graded by 2 3.4653e-15; the same rules give the unobstructed F within 4e-7;
# `samples_that_miss_where_the_unobstructed_f_gathers_say_so` in clipping.rs). It was 1.0e-8
# at every obstructed_tol and placement, claiming the goal met when moved, for two reasons:
# - over face 2 no sample comes near the band (the start pieces' unobstructed G by their
#   samples is 1e-7 of the exact one), and the hidden part follows the samples. Such an
#   integral now checks at its end that its leaves see the unobstructed G (`missed` in
#   clipping.rs) and counts what they do not as error;
# - over face 0 the kink split cuts a sliver 2.5e-9 high along the band, and its pieces within
#   1e-10 of face 1's plane were taken as hidden from nothing: the shaft test counted a
#   blocker plane within 1e-10 of the pair's size of the piece as touching it (7 % of the
#   sliver's hidden G). That test now takes rounding only (`Shaft::may_meet_triangle`).
# Where the scene lies at the origin, F is now right at the default and at 1e-3. Scaled and
# moved, the default's integrals see the band no better, but the pair says so (std_err 1e-8,
# a ToleranceWarning).
SEED_36_SHARED_LINE = [
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.5], [-1.0, 1e-08, 0.0]],
    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
    [[0.0, 0.0, 0.0], [1.0, 0.0, -1.0], [-1.0, 0.0, 0.0]],
]


def test_replay_seed_36_blocker_on_the_shared_line():
    p = [np.array(q) for q in SEED_36_SHARED_LINE]
    free = nusselt.view_factor(p[0], p[2])
    # 40-digit contour integral; 1.6e-10 off, where a coordinate of size 1 moved by its last
    # bit moves the 1e-8 tilt by 1e-8 of itself (docs/guide.md, analytic's rounding)
    assert abs(free - 9.99999450531876e-9) <= 1e-9 * free
    for q in (p, [1e-6 * x + 7e-6 for x in p]):
        for tol in (DEFAULT_OBSTRUCTED_TOL, 1e-3):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", nusselt.ToleranceWarning)
                F, err = _with_error(nusselt.form_factors(nusselt.Scene.from_polygons(q), obstructed_tol=tol))
            assert abs(F[0, 2] - 3.46e-15) <= max(tol * free, err[0, 2]), (tol, F[0, 2] / free, err[0, 2] / free)
    F, err = _with_error(nusselt.form_factors(nusselt.Scene.from_polygons(p)))
    assert err[0, 2] == 0.0 and abs(F[0, 2] - 3.46e-15) <= DEFAULT_OBSTRUCTED_TOL * free


def test_replay_seed_36_row_sum_past_the_shared_line():
    # the same faces 0 and 1, face 2 now covering face 0 (z from -1 to 1): F[0, 2] = 1.0 and
    # F[0, 1] = 1.0e-8 (the sliver of face 1 in front of face 0), row sum 1 + 1e-8: F[0, 2]
    # keeps the part of face 2 below z = 0, which face 1 hides but for that band. That is
    # within obstructed_tol x F_free (1e-6 x 1.0), the accuracy promised, so the row may
    # exceed 1 by that much (the scene test held rows to 1 + 1e-9 until seed 36)
    p = [np.array(q) for q in SEED_36_SHARED_LINE[:2]]
    p.append(np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [-1.0, 0.0, 0.0]]))
    F = nusselt.form_factors(nusselt.Scene.from_polygons(p)).matrix.toarray()
    bound = 1.0 + DEFAULT_OBSTRUCTED_TOL * _free(p).sum(axis=1)
    assert (F.sum(axis=1) <= bound).all(), F.sum(axis=1) - 1.0


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=37 (scene test, after 10 000 clean cases
# of the pair test and 15 min): the obstacle raised F[4, 1] by 3.8 x the slack at the default
# obstructed_tol. The pair was integrated over face 1, where an edge of face 3 pierces face 1's
# plane: a sliver start piece cornered at that point had all its samples beyond the rise of the
# hidden F there (up to 0.6 within 0.007) and claimed its goal, 2.8e-7 off in G. A leaf with
# such a point now counts its area times the hidden F's limit there (`clipping::pierce_limit`)
SEED_37 = [
    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.25, 1.0, 0.0]],
    [[0.0, 0.0, 0.576171875], [0.9375, 0.0, 0.0], [-0.328125, 0.904296875, -1.0]],
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, -0.5]],
    [[0.0, 0.0, 1.0], [0.0, 0.13620460344004104, 0.0], [0.8125, 0.05790897567968201, 0.9453125]],
    [[-0.66796875, 0.0, 0.9296875], [0.44902525456830156, 0.25390625, 0.0], [0.0, -0.21875, 0.443359375]],
]


def test_replay_seed_37_obstacle_raises_f():
    obstacle = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -0.25], [0.0, 1.0, 0.0]])
    _assert_obstacle_only_takes_away([np.array(q) for q in SEED_37], obstacle)


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=38 (scene test, after 10 000 clean cases of
# the pair test and 50 min, on d9c8dd0): F[0, 2] differed between placements by 1 100 x the
# bound and an obstacle raised it by 38 x the slack. Faces 1 and 2 share a vertex V on face 0's
# edge; only a triangle of face 0 about 6e-5 across lies in front of face 2, and face 1 stands
# on face 0 along a line through V that halves that triangle. The pair was integrated over
# face 2 (face 1 crosses its plane: clearance 0.1 against face 0's 0.05), where the kernel lies
# within about 1e-4 of V. Far from V the point F is ~2e-14 and its visible part fell under the
# rounding allowance of the visible-part switch, so the start pieces integrated the visible
# part from samples far from V and counted their exact G, mass near V included, as hidden: F
# 2.8e-13 at obstructed_tol 1e-3, and 1.39e-9 at the default, where that side ran out of
# evaluations. Over face 0's small part every target is met, and a pair whose parts in front
# differ in radius by more than 100 is now integrated over the smaller (`clipping::SMALL_SIDE`).
# Reference: graded tensor Gauss (6 points a panel, panels graded by 10 towards every vertex)
# of the exact point F over face 0's front triangle cut along face 1's trace: 1.0960495670e-9
# at 3 and 5 levels (the free F the same way 1.74442551e-9, exact 1.7444255010e-9)
SEED_38 = [
    [[0.0, 0.0, 0.0], [-1.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
    [[0.0, 0.0, 1.0], [1.0, 1.0, 0.0], [-6.103515625e-05, 0.0, 0.0]],
    [[0.0, 1.0, 0.0], [0.0, -1.0, 1.0], [-6.103515625e-05, 0.0, 0.0]],
]


def test_replay_seed_38_kernel_at_a_vertex():
    p = [np.array(q) for q in SEED_38]
    free = nusselt.view_factor(p[0], p[2])
    assert abs(free - 1.7444255010e-9) <= 1e-8 * free
    for q in (p, [1e-6 * x + 7e-6 for x in p]):
        for tol in (None, 1e-3):
            kw = {} if tol is None else {"obstructed_tol": tol}
            f = nusselt.form_factors(nusselt.Scene.from_polygons(q), **kw).matrix.toarray()[0, 2]
            assert abs(f - 1.0960495670e-9) <= (tol or DEFAULT_OBSTRUCTED_TOL) * free, (tol, f)


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=39 (scene test), both on F[3, 4]: faces 0-2
# each have an edge in y = 0, within 4e-8 of face 4's plane (face 4 leans 6e-8 out of it), and
# face 3 crosses that plane. A blocker's edge and a vertex of face 3's part in front of face 4
# span a kink plane 4e-8 rad off face 4's plane; over face 4 it lies within the kink split's
# tolerance along a band 0.04 wide, and a start piece with vertices on both sides of the band
# was cut into two halves that overlapped (0.0532 of area into 0.0560), so part of face 4
# counted twice. The split now leaves such a piece whole (`geometry::cuts_in_two`).
# "An obstacle raises F[3, 4] by 19.9 x the slack" (2031 x on the build with the kink cuts
# ordered by reach): the free scene was wrong, 3.3042e-5 at every obstructed_tol for 6.506920e-5
# (nested adaptive Gauss-Kronrod over face 3 of the exact point F, to 1e-11 of F: 6.5069200e-5 /
# 6.5069254e-5 from two of its vertices); with the obstacle, which hides nothing of the pair,
# 6.5068898e-5. Now 6.5068833e-5 without it
SEED_39 = [
    [[0.0, 0.0, 0.4643752850792635], [0.0, 0.0, -0.30993796626476466], [0.0, 0.4959378708484483, 0.4916379264466204]],
    [[0.0, 0.0, -0.9213925681584167], [0.0, 0.0, -0.3036873413796738], [0.0, 0.4083555728127941, -0.7256366774880623]],
    [
        [0.0, 0.0, 0.9999999999999999],
        [0.43926912210183633, 0.0, -0.6206510770004806],
        [-0.9474149672713192, 0.5263460985521964, 0.5],
    ],
    [
        [0.0, -0.035490666954058225, 0.0],
        [0.0, -0.029731871631357043, -0.2424826093484571],
        [-0.5155422402224391, 0.3119631603455597, 0.9548792880155585],
    ],
    [
        [0.15058686561303403, 0.0, 0.27732066287958834],
        [0.6820315858517412, 5.960464477539063e-08, -0.8556063093113888],
        [-0.24309367533859905, 0.0, -1.0],
    ],
]
# "scaled by 3 and moved by 21 changes F[3, 4] by 32 x the bound" at the default obstructed_tol
# (1e-3 was within): the same faces rounded, face 2 moved. Scaled, a plane of the same kind split
# a piece of 0.2933 into 0.3062, and F[3, 4] was 3.1607e-5 for 3.2836996e-5 (nested
# Gauss-Kronrod over face 3 as above; F_free 0.0191: 64 x tol x F_free); at the origin, where
# the plane's rounding differs, 3.2836752e-5. Now 3.2837015e-5 scaled
SEED_39_ROUNDED = [
    [[0.0, 0.0, 0.4643752850792635], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
    [[0.0, 0.0, -0.9375], [0.0, 0.0, 0.0], [0.0, 1.0, -1.0]],
    [[0.0, 1.0, 0.0], [0.5, 0.0, 1.0], [-0.5, 0.5263460985521964, 0.5]],
    [[0.0, -0.03125, 0.0], [0.0, -0.03125, -0.125], [-0.515625, 0.5, 0.75]],
    [
        [0.15058686561303403, 0.0, 0.28125],
        [0.6820315858517412, 5.960464477539063e-08, -0.8556063093113888],
        [-0.244140625, 0.0, -1.0],
    ],
]


def test_replay_seed_39_obstacle_raises_f():
    obstacle = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.6763535932682863], [0.0, -0.790768822880823, 0.0]])
    _assert_obstacle_only_takes_away([np.array(q) for q in SEED_39], obstacle)


def test_replay_seed_39_moved():
    for tol in (None, 1e-3):
        _assert_moved_within([np.array(q) for q in SEED_39_ROUNDED], tol=tol, s=3.0)


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=41 (scene test, 10 min, on ece3b20): start
# pieces whose samples were all 0 while a steep hidden F lay along one of their edges.
def test_replay_seed_41_moved():
    # F[2, 3] 4.0 x tol x F_free high at the default (it met the tol where moved)
    polys = [
        [
            [-0.8730321434529524, -2.225073858507e-311, 0.1669194989722238],
            [-2.2250738585072014e-308, -9.844898802101006e-78, 0.0],
            [-0.6179240651941543, -0.7562221966110352, -0.9274688690658568],
        ],
        [
            [-0.4472043649612977, -0.5702831701882579, -0.5629253366088668],
            [0.3241339112698245, -0.08988404864817734, 0.052234655406105945],
            [0.558944636848056, 0.7921606187462218, 0.14259677932698245],
        ],
        [
            [0.0, -0.774317764458075, -0.8869390887928565],
            [-4.172141648151047e-228, -1.0, -1.6483082360298924e-194],
            [0.2665827028332137, -0.37408989876157317, 0.6493375136306505],
        ],
        [
            [-0.4116674657516811, 0.8879729346947487, -0.6675667991867944],
            [-0.4158922440508891, -1.6508794878190337e-87, 1.0],
            [0.1745165074236652, -0.8698120397686897, -0.7016997321854022],
        ],
        [
            [0.0, 0.0, 0.0],
            [-0.6149165243927265, 0.0, 0.0],
            [-0.807227615196977, -0.39660830628184296, -0.5103047371426096],
        ],
    ]
    _assert_moved_within([np.array(p) for p in polys])


def test_replay_seed_41_obstacle_raises_f():
    # the obstacle hides nothing of the pair (3, 4), but raised F[3, 4] by 2.5 x the slack
    polys = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 0.3241339112698245], [-0.4472043649612977, 0.0, -0.5629253366088668]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, -0.8869390887928565], [0.0, -1.0, 0.0]],
        [
            [0.0, 0.0, 0.0],
            [0.0, -0.9274688690658568, -0.7562221966110352],
            [-0.8730321434529524, 0.0, 0.1669194989722238],
        ],
        [[0.0, 1.0, 0.0], [-0.6149165243927265, 0.0, 0.0], [-0.807227615196977, -0.5, -0.5]],
        [[0.1875, -1.0, -0.75], [-0.5, 1.0, -0.5], [-0.375, 0.0, 1.0]],
    ]
    obstacle = np.array([[0.0, -1.0, -0.25], [0.0, -0.25, 0.0], [-1.0, 0.0, 0.0]])
    _assert_obstacle_only_takes_away([np.array(p) for p in polys], obstacle)


def test_replay_seed_42_moved_at_a_loose_tol():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=42 (scene test, 6 min, on 0e76d7f):
    # face 2 crosses face 0's plane along a line through it, only a wedge 2.2e-10 thick in
    # front; F[0, 2] was 0 for 7.52e-11 at obstructed_tol 1e-3 (samples' free F at rounding
    # took the visible part), 7.52e-11 where moved: 65 x the bound
    polys = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.75, 0.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, -1.0, 0.0], [1.0, 0.5, 0.0]],
        [[0.0, 0.0, -1.0], [0.0, -1.0, 0.0], [0.5, 2.226117160647273e-10, 1.0]],
    ]
    _assert_moved_within([np.array(p) for p in polys], tol=1e-3)


def test_replay_seed_42_moved_nearly_coplanar():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=42 (scene test, 10 min, on 8d6ef5c):
    # faces 1 and 2 lie 1e-14 and 1e-8 out of one plane; moving the scene rounds those offsets
    # (1e-14 -> 1.0164e-14) and changes their unobstructed F by 3.0e-6 of it, nothing to do with
    # the obstruction (face 0 hides nothing of the pair): the bound now carries that change
    polys = [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.25, 0.0, 1.0], [0.0, 1e-14, -0.4375]],
        [[0.0, 0.0, -0.375], [1.0, 1e-08, -1.0], [1.0, 0.0, 0.0]],
    ]
    polys = [np.array(p) for p in polys]
    moved = [1e-6 * p + 7e-6 for p in polys]
    blocked = nusselt.form_factors(nusselt.Scene.from_polygons(polys)).matrix.toarray()
    assert blocked[1, 2] == pytest.approx(nusselt.view_factor(polys[1], polys[2]), rel=1e-6)
    blocked_moved = nusselt.form_factors(nusselt.Scene.from_polygons(moved)).matrix.toarray()
    assert blocked_moved[1, 2] == pytest.approx(nusselt.view_factor(moved[1], moved[2]), rel=1e-6)
    _assert_moved_within(polys)


def test_replay_seed_41_obstacle_raises_f_next_to_a_pierce_point():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=41 (scene test, 15 min, on 95fa932):
    # the obstacle raised F[3, 4] by 1.36 x the slack at every tol; over face 3 a start piece
    # next to where face 1 pierces it held a rise along its edge that its one leaf missed
    *polys, obstacle = [np.array(p) for p in data_literal("seed_41_pierce_point.txt")]
    _assert_obstacle_only_takes_away(polys, obstacle)


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=40 (scene test, 6 min, on b72dcb6): the
# obstacle raised F[2, 3] by 1.32 x the slack (2 x obstructed_tol x F_free, F_free 0.10449).
# Without it F[2, 3] was 4.5 x tol x F_free low at the default (0.1042956679 for 0.1042961424):
# an edge of face 3 lies in the blockers' plane 1.6e-3 rad off their common edge, and along the
# kink plane through both the hidden F's slope grows without bound, next to a start piece's
# edge where no sample reached (clipping.rs, EDGE_SHARE)
SEED_40 = data_literal("seed_40_edge_in_the_blockers_plane.txt")


def test_replay_seed_40_obstacle_raises_f():
    obstacle = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]])
    _assert_obstacle_only_takes_away([np.array(q) for q in SEED_40], obstacle)


def test_replay_seed_43_moved_sliver_in_front():
    # found by the long run with NUSSELT_HYPOTHESIS_SEED=43 (scene test, 19 min, on 7d6ef69):
    # faces 0 and 2 meet at an edge nearly back to back and see each other only within 1e-7
    # of it; face 1 lies between them in the plane through that edge and hides 42 % of their
    # unobstructed F. The integral ran over face 2, far from that layer, and missed 4 % of the
    # unobstructed F there (both scalings alike, 1.1 x the bound apart); face 0's part in front
    # is a sliver and is integrated now (clipping.rs: `far_smaller`; the Rust test
    # `a_sliver_in_front_is_integrated_though_a_blocker_comes_close_to_it` has the reference)
    polys = [np.array(p) for p in data_literal("seed_43_sliver_in_front.txt")]
    _assert_moved_within(polys)
    # the long run's second case (on 0f6e4c5, 16 min): face 4's third vertex elsewhere; moved,
    # the sliver's integral ran out short of its goal and face 2's replaced it (9.05 x the
    # bound); a side chosen as far the smaller is kept now
    other = [*polys[:4], polys[4].copy()]
    other[4][2] = [-0.7131272104126429, 0.0, 0.11025108287547725]
    _assert_moved_within(other)
    # the pair against the unobstructed F: 0.577 of it is visible (the Rust test's reference,
    # an independent tensor rule over face 0, to 1e-5)
    blocked = nusselt.form_factors(nusselt.Scene.from_polygons(polys)).matrix.toarray()
    assert blocked[0, 2] / nusselt.view_factor(polys[0], polys[2]) == pytest.approx(0.57704, abs=1e-4)


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=44 (scene test, 7.5 min, on 34d16ce): the
# obstacle raised F[4, 2] by 21 x the slack. Not the obstacle: without it F[4, 2] was
# 3.5298731e-5 at the default, 4.4e-5 of the unobstructed F (3.8104e-5) low. Face 2 pierces
# face 4's plane and only a needle of it, 6.1e-5 high, lies in front; the integral runs over the
# needle, whose start pieces are slivers cornered where face 4's edge meets it: each child a
# sliver like its parent, they missed the point F's rise towards that corner, every target
# claimed met. Slivers near the receiver are now cut across in graded pieces (kinks.rs:
# `grade_slivers`)
SEED_44 = data_literal("seed_44_needle_in_front.txt")
# F[4, 2] by the independent integration of `test_seed_44_reference`
SEED_44_F42 = 3.530038657707e-5


def test_replay_seed_44_obstacle_raises_f():
    polys = [np.array(p) for p in SEED_44]
    obstacle = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    _assert_obstacle_only_takes_away(polys, obstacle)
    free = nusselt.view_factor(polys[4], polys[2])
    F = nusselt.form_factors(nusselt.Scene.from_polygons(polys)).matrix.toarray()
    assert abs(F[4, 2] - SEED_44_F42) <= DEFAULT_OBSTRUCTED_TOL * free, (F[4, 2] - SEED_44_F42) / free


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=45 (scene test, 18 min, on e1dcf4a), two
# scenes that differ in face 3: the obstacle raised F[1, 3] by 8.5 x the slack, and moved, F[1, 3]
# and F[2, 3] changed by 9.8 and 18.7 x the bound. Face 3's start pieces next to face 1 are
# slivers; as such they ran out of evaluations 1.8e-4 of the unobstructed F off, and the other
# side, as good as exact, did not replace them (a blocker lies flat over face 1). Graded
# (kinks.rs: `grade_slivers`), they meet the target
SEED_45 = [
    [
        [0.0, 0.0, -0.24744465236508684],
        [0.5903381776736629, 0.9999999999999999, 0.0],
        [0.08770598414037267, -0.3690238402672511, 0.6909264336819767],
    ],
    [[0.0, 1.192092896e-07, 0.0], [0.3125, 0.0, 0.796875], [-0.5266979727804068, -1e-05, 0.0]],
    [[0.3125, 0.0, 0.796875], [0.3285057996265788, 1e-09, 0.0], [-0.29360651598524334, 0.0, 0.0]],
    [
        [-0.9204673787980422, -0.5992865861061504, 0.0],
        [0.8309006712806828, 0.0, 0.99999],
        [0.0, 0.5700511995139705, 0.9423479652050015],
    ],
]
SEED_45_FACE_3 = [[-0.9204673787980422, -0.5992865861061504, 0.0], [0.8125, 0.0, 1.0], [0.0, 0.5625, 0.9375]]


def test_replay_seed_45_obstacle_raises_f():
    polys = [np.array(p) for p in SEED_45]
    _assert_obstacle_only_takes_away(polys, np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]]))
    _assert_moved_within(polys)


def test_replay_seed_45_moved():
    _assert_moved_within([np.array(p) for p in [*SEED_45[:3], SEED_45_FACE_3]])


# Found by the same long run on ac1ee3a (seed 45 again, scene test, 42 min): the obstacle raised
# F[1, 4] by 1.37 x the slack. Not the obstacle: without it F[1, 4] is 2.2897854e-3 at the
# default, 2.7e-6 of the unobstructed F (3.5247e-3) below the 2.2897949e-3 that both sides give
# at obstructed_tol 1e-8 and 1e-10 (over face 1 within 1.6e-7 at the default), the goal
# claimed met. Over face 4, one start piece under the coarse start (COARSE_START_TOL, which the
# default reaches) had its rule 1.6e-4 off and 3e-7 from its centroid value (its estimate 1.4e-11
# for an error of 3.9e-9), its samples falling 2.5-fold towards a corner. Its corners' departure
# from the samples' quadratic now counts too (DEPARTURE_SHARE): 0.01 x tol
SEED_45_THIRD = [
    [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]],
    [
        [0.0, 1.0, 0.05977671361710102],
        [0.0, 0.6186375174692582, 0.683122959190301],
        [-0.09993839983683261, 0.33501723155085394, -0.9733139018287171],
    ],
    [
        [0.0, -0.20326763832084072, 0.10632651596078335],
        [0.46875, 0.0, 0.0],
        [0.06299767811831303, 0.4427793657128054, 0.8766341686788581],
    ],
    [
        [0.638671875, 0.7993437120978211, 0.04248816441465508],
        [-0.7582202342443249, 0.0, -0.5621064531278795],
        [-0.15890910981662576, 0.060114020170549454, -0.14029518611141456],
    ],
    [
        [0.8728051321147716, 0.6811541323941599, 0.0],
        [-0.3147727875888958, -0.4733073001111733, 0.9941554061686784],
        [0.0, 0.382202328696702, 0.0],
    ],
]


def test_replay_seed_45_coarse_start_misses_at_the_default():
    polys = [np.array(p) for p in SEED_45_THIRD]
    free = nusselt.view_factor(polys[1], polys[4])
    F = nusselt.form_factors(nusselt.Scene.from_polygons(polys)).matrix.toarray()
    tight = nusselt.form_factors(nusselt.Scene.from_polygons(polys), obstructed_tol=1e-10).matrix.toarray()
    assert abs(F[1, 4] - tight[1, 4]) <= DEFAULT_OBSTRUCTED_TOL * free, (F[1, 4] - tight[1, 4]) / free


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=46 (scene test, 55 min, on ac1ee3a), two
# cases: the obstacle raised an F by 2.4 x the slack, and scaled and moved an F changed by
# 6.8 x the bound. Faces 1-3 share points and edges at the 1e-5 scale; the pairs' integrals
# (both sides) run out of evaluations at every obstructed_tol <= 1e-6 and end 1e-5 to 5e-5 of
# the unobstructed F short. Not fixed: since they say so (std_err, ToleranceWarning), each
# number is within the error it reports
SEED_46_OBSTACLE = (
    [
        [
            [-0.6233694235534352, 0.6476495781538127, 0.006149633826857626],
            [0.2717755251377747, -0.009992905402322672, -0.5611149971877353],
            [-0.007252104071939991, 0.5806002394843013, -0.8809526687897717],
        ],
        [
            [1.2386696854266587e-26, -0.6835962516113461, 0.4268177842681846],
            [-1e-05, -8.053799262279076e-46, -0.7106241819083445],
            [-1e-05, 0.0, 0.1287220021944917],
        ],
        [
            [1.0658373575676088e-159, -0.35714100174443597, 6.16940949236213e-195],
            [-0.25763258128355593, 6.516806370874048e-134, -2.8032614522907233e-145],
            [-1e-05, 0.0, 0.1287220021944917],
        ],
        [
            [-1.2646461832314758e-107, 0.6818299453430288, -6.103515625e-05],
            [0.0, 0.6827344399572888, -0.6521134484161446],
            [1.0658373575676088e-159, -0.35714100174443597, 6.16940949236213e-195],
        ],
        [
            [-0.471987928581738, 0.0, -0.3145438682428686],
            [-0.3538884664354879, -0.6393771594592677, -0.20053403890421095],
            [0.8014897183821876, 0.41559934700948564, 0.22561034977406602],
        ],
    ],
    [[-1e-05, -8.053799262279076e-46, -0.7106241819083445], [0.0, 0.0, 0.0], [0.8908955397065785, 0.0, 0.0]],
)
SEED_46_MOVED = [
    [[-0.6233694235534352, 0.6476495781538127, 0.0], [0.0, 0.0, -0.5611149971877353], [0.0, 0.0, 0.0]],
    [[0.0, -0.6835962516113461, 0.4268177842681846], [-1e-05, 0.0, -0.7106241819083445], [-1e-05, 0.0, 0.0]],
    [[0.0, -0.35714100174443597, 0.0], [0.0, 0.0, 0.0], [-1e-05, 0.0, 0.1287220021944917]],
    [
        [0.0, 0.0, 0.0],
        [0.0, 0.6827344399572888, -0.6521134484161446],
        [1.0658373575676088e-159, -0.35714100174443597, 6.16940949236213e-195],
    ],
    [
        [-0.471987928581738, 0.0, -0.3145438682428686],
        [-0.3538884664354879, -0.6393771594592677, -0.20053403890421095],
        [0.8014897183821876, 0.41559934700948564, 0.22561034977406602],
    ],
]


def test_replay_seed_46_obstacle_raises_f():
    polys, obstacle = SEED_46_OBSTACLE
    with pytest.warns(nusselt.ToleranceWarning):
        _assert_obstacle_only_takes_away([np.array(p) for p in polys], np.array(obstacle))


def test_replay_seed_46_moved():
    with pytest.warns(nusselt.ToleranceWarning):
        _assert_moved_within([np.array(p) for p in SEED_46_MOVED])


def test_an_integral_out_of_evaluations_reports_its_error():
    """Pairs whose integral ends short of obstructed_tol carry its error estimate in std_err
    (reciprocal: A_i s_ij = A_j s_ji) and a ToleranceWarning names the worst; every other entry's
    std_err is 0, and a single view_factor reports the same estimate."""
    polys = [np.array(p) for p in SEED_46_MOVED]
    with pytest.warns(nusselt.ToleranceWarning, match=r"\d+ entries of F did not reach obstructed_tol=1e-06"):
        r = nusselt.form_factors(nusselt.Scene.from_polygons(polys))
    S = r.std_err.toarray()
    i, j = np.unravel_index(np.argmax(S), S.shape)
    assert S[i, j] > DEFAULT_OBSTRUCTED_TOL * nusselt.view_factor(polys[i], polys[j])
    assert np.allclose(r.areas[:, None] * S, (r.areas[:, None] * S).T, rtol=1e-12, atol=0.0)
    assert 0 < np.count_nonzero(S) < S.size - len(S)
    others = [polys[k] for k in range(len(polys)) if k not in (i, j)]
    with pytest.warns(nusselt.ToleranceWarning, match="its error estimate"):
        f, s = nusselt.view_factor(polys[i], polys[j], obstacles=others, return_std=True)
    assert f == pytest.approx(r.matrix.toarray()[i, j], rel=1e-12) and s == pytest.approx(S[i, j], rel=1e-12)
    # a pair that meets its target reports nothing
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert nusselt.view_factor(polys[0], polys[4], obstacles=polys[1:4], return_std=True)[1] == 0.0


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=47 (scene test, 34 min, on ac1ee3a): the
# obstacle raised an F by 1.35 x the slack. Without the obstacle F[3, 1] was 2.7 x tol low at
# the default, claimed met: over face 1, whose part in front of face 3 ends at face 3's plane,
# leaves along that edge counted a quarter of their rule's difference while the rule there was
# 9e-4 off (the point F falls to 0 like the height over that plane, with shadows of blockers
# touching face 3 turning with it). Such leaves count all of it now
SEED_47 = [
    [[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [-0.40625, 0.0, 0.0]],
    [[0.0, 1.0, 0.0], [1.0, 0.0, 0.5], [-0.5, 1.0, 0.125]],
    [[0.0, 0.40625, -0.875], [0.0, 0.03125, 0.75], [0.0, -1.0, 0.0]],
    [[0.375, 0.0, -0.5], [0.0, -1.0, 0.0], [0.0, 0.0, 0.0]],
]


def test_replay_seed_47_obstacle_raises_f():
    obstacle = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 1.0]])
    _assert_obstacle_only_takes_away([np.array(p) for p in SEED_47], obstacle)


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=48 (scene test, 12 min, on a8a0817):
# scaled by 0.1 and moved by 0.7, F[0, 3] changed by 20 x the bound, claimed met. Face 2 (a
# blocker of the pair) shares a vertex with face 3; moved, that vertex lay within rounding
# behind face 3's plane, and cutting the blocker to the pair's slab left a quad with an edge
# 1.3e-13 long, whose cone plane from each source point lay where rounding put it (point F
# 1.9e-3 off; the pair 4e-5 of its F). The same scene given that quad is fixed too.
SEED_48 = [
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
    [[0.0, 0.0, 0.0], [0.0, 0.4375, 0.80859375], [-0.125, 0.0, 0.25]],
    [[0.0, 0.6875, 0.8414733953056248], [0.0, 0.0, 0.7578125], [-0.125, 0.0, 0.25]],
]


def test_replay_seed_48_moved():
    _assert_moved_within([np.array(p) for p in SEED_48], s=0.1)


def test_replay_seed_48_blocker_with_an_edge_of_rounding_length():
    """Face 2 given as the quad the cut made of it (a vertex doubled 1.3e-13 away)."""
    polys = [0.1 * np.array(p) + 0.7 for p in SEED_48]
    quad = [polys[2][0], polys[2][1], [0.687500000000023, 0.7000000000000802, 0.7250000000001025], polys[2][2]]
    plain = nusselt.form_factors(nusselt.Scene.from_polygons(polys)).matrix.toarray()
    doubled = nusselt.form_factors(nusselt.Scene.from_polygons([*polys[:2], np.array(quad), polys[3]])).matrix.toarray()
    free = nusselt.view_factor(polys[0], polys[3])
    assert abs(doubled[0, 3] - plain[0, 3]) <= 1e-8 * free, (doubled[0, 3] - plain[0, 3]) / free


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=48 again (scene test, 45 min, on 5f2680c):
# face 3 lies 1e-8 .. 6e-8 out of face 2's plane; scaled by 1e-6 and moved by 7e-6 the scene was
# refused as overlapping coplanar faces (plane offsets measured from the origin)
SEED_48_NEARLY_COPLANAR = [
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    [[0.0, -0.3125, 1e-08], [1.0, 0.5, 0.0], [-0.5, 0.0, 5.960464477539063e-08]],
]


def test_replay_seed_48_nearly_coplanar_faces_moved():
    _assert_moved_within([np.array(p) for p in SEED_48_NEARLY_COPLANAR])


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=49 (scene test, 50 min, on 638195b; both
# fail on 591ae49 too), two cases:
# - with the obstacle F[3, 4] is 1.24238e-3 at the default, 2.2e-5 of the unobstructed F
#   (0.01693) above the 1.242011e-3 of obstructed_tol 1e-10; without it 2.8e-6 low; both
#   claimed met (no std_err). The integral runs over face 4 (clearance 0.71 against 0.05),
#   which ends 2.2e-5 off claiming 9.3e-7; over face 3 it is 7e-9 off. The pair with subsets
#   of its blockers (clipping at 1e-6 against 1e-10, x tol): faces 0, 1, 2 and the obstacle
#   +21.8; 0, 1, 2 -2.8; 1, 2 and the obstacle +5.5; 0, 1 and it 0.00; 0, 2 and it 0.02; the
#   obstacle moved 1e-3 off face 0's plane +2.9. So it takes faces 1 and 2 together, which
#   share the segment from (0, 0, 0) up the z axis (a hinge between two blockers). A brute
#   force over face 4's final leaves at 1e-6 (each split 4^4 times, Radon's rule on each)
#   puts 3.5e-8 of the 4.6e-8 in G in one start piece (area 0.084, hidden G 3.1e-4, off by
#   1.1e-4 of itself) refined once, whose rule and children agree to 9e-11: within about 1 %
#   of its size of its corner (2/7, -5/7, 5/7) the visible F drops from 8.8e-4 to 7.2e-4 (the
#   hidden F there 4.8e-3), a departure of 4 % of the integrand, under EDGE_SHARE's 10 %.
#   No event passes near that corner but the blocker-blocker one the piece is cut along (face
#   2's vertex (0, -1, 0), which is face 4's, and face 1's edge from (0, 0, 1)); the point F
#   there agrees with a ray-cast grid over face 3 to the grid's 0.1 %, and along face 4's edge
#   the visible F bends smoothly but sharply (its slope falls 4-fold within 0.05 of the
#   corner). At 1e-10 the pair converges right. Counting 1 % of a refined start piece's area
#   times its corners' departure (DEPARTURE_SHARE, which fixed seed 51) left it at 12.3 x the
#   bound; EDGE_SHARE (clipping.rs) at 3 % instead of 10 % fixes it, and the seed-34 replay,
#   which then ran out of evaluations and took the other side (4.1 x tol off), meets its goal
#   since MAX_SOURCE_EVALS is 250 000 instead of 60 000;
# - scaled by 1e-6 and moved, an F changes by 1.6 x the bound: F[4, 0] by 3.3e-6 of the
#   unobstructed F at obstructed_tol 1e-8 and 1e-10 alike. The hidden part over face 4 is
#   0.65712224510 of the free F in both placements and over face 0 0.65712224518 unmoved,
#   but 0.65712554164 moved (claiming 3e-10): face 0's integral, the side taken on a
#   clearance tie (0.05 each), misses a feature in the moved placement only. Face 0 lies
#   in face 1's plane, back to back with it and inside it. Brute force over its final leaves
#   at 1e-8 (each split 4^4 times): all of it in one start piece integrating the visible F,
#   never split, with a corner at the origin where faces 0-3 meet; 1.6e-4 of itself off.
#   Fixed with seed 53's case below: such a piece now asks the limits at its corners.
SEED_49_OBSTACLE = (
    [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.5, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, 0.875], [0.0, -1.0, 0.0]],
        [[0.0, 0.75, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
        [[0.0, -1.0, 0.0], [0.0, -1.0, 1.0], [1.0, 0.0, 0.0]],
    ],
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.25], [0.0, 1.0, 0.0]],
)
SEED_49_MOVED = [
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.125, 0.0]],
    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    [[0.0, 0.0, 0.0], [0.0, -1.0, 1.0], [-0.125, 0.25, 0.0]],
    [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [-1.0, 0.5, 0.0]],
    [[0.0, 0.5, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
]


def test_replay_seed_49_obstacle_raises_f():
    polys, obstacle = SEED_49_OBSTACLE
    _assert_obstacle_only_takes_away([np.array(p) for p in polys], np.array(obstacle))


def test_replay_seed_49_moved():
    _assert_moved_within([np.array(p) for p in SEED_49_MOVED])


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=56 (scene test, 12 min, on 8ea334b; the
# same on a1c4ab5): scaled by 1e-3 and moved, F[1, 2] changed by 2.2 x the bound at
# obstructed_tol 1e-3 (0.409227 unmoved, 0.407436 moved, 0.4069384 at 1e-9), neither
# reporting an error. Faces 1 and 2 share a vertex, face 0 hides 0.8 % of their unobstructed F.
# Over face 1 a thin start piece under the 3-point rule, its children's samples spread
# 340-fold (9.7e-5 .. 3.3e-2), went from 3.67e-5 to 5.29e-5 with one level and counted that
# difference as its error while about 1e-4 of its hidden G was missing: 5.6 x tol off. Such a
# leaf now counts twice its estimate (`VERY_STEEP` in clipping.rs).
SEED_56 = [
    [[0.0, 0.0, -0.5], [0.0, -1.0, 1.0], [1.0, -0.5, 0.0]],
    [[0.5, -1.0, 0.25], [0.0, 0.0, 0.0], [0.0, 0.25, 0.0]],
    [[0.5, -1.0, 0.25], [1.0, 0.0, 0.0], [0.0, 0.125, 0.0]],
]


def _assert_f12_meets_clipping(polys, placements, tols):
    """F[1, 2] of the scene (face 0 the obstacle) at each placement and `obstructed_tol` within
    tol of the unobstructed F from `clipping` at 1e-10 on the original."""
    free = _free(polys)[1, 2]
    reference = nusselt.view_factor(polys[1], polys[2], obstacles=[polys[0]], method="clipping", tol=1e-10)
    for q in placements:
        for tol in tols:
            f = nusselt.form_factors(nusselt.Scene.from_polygons(q), obstructed_tol=tol).matrix[1, 2]
            assert abs(f - reference) <= tol * free, (tol, (f - reference) / (tol * free))


def test_replay_seed_56_moved_at_a_loose_tol():
    polys = [np.array(p) for p in SEED_56]
    _assert_moved_within(polys, tol=1e-3, s=1e-3)
    # (that the reference is right, against the integral over face 2: the Rust test
    # `a_very_steep_leaf_is_not_trusted_on_one_level`)
    _assert_f12_meets_clipping(polys, [polys], (1e-2, 1e-3))


# The same seed rerun on 455b7ac (with the fix above) found a sibling after 12 min: scaled by
# 1e-6 and moved, F[1, 2] changed by 1.33 x the bound at obstructed_tol 1e-3. Faces 1 and 2
# share a vertex again and face 0 hides 0.5 % of their unobstructed F (0.41675); F[1, 2] is
# 0.4146892 (clipping at 1e-10), at 1e-3 1.27 x tol off at the origin and 3.92 x moved, at 1e-4
# within tol (0.68 and 0.86 x), at the default 0.05 x. Face 1's edge from the shared vertex lies
# in face 2, and about the point where face 0's plane meets it the hidden F depends on the
# direction alone: 0.34 along the edge of a start piece of face 1, below 1e-5 at every sample of
# the 3-point rule there. Start pieces whose samples spread now compare their corners with
# their samples' plane (LINEAR_EDGE_SHARE in clipping.rs): 0.006 and 0.035 x tol.
SEED_56_SIBLING = [
    [[0.0, 0.0, -0.5], [1.0, -0.625, 0.0], [0.5, -1.0, 0.75]],
    [[0.75, -0.875, 0.375], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    [[0.75, -0.875, 0.375], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]],
]


def test_replay_seed_56_sibling_at_a_loose_tol():
    polys = [np.array(p) for p in SEED_56_SIBLING]
    # (the reference against the integral over face 2: the Rust test
    # `a_layer_along_a_piece_touching_the_receiver_is_found_under_the_3_point_rule`)
    _assert_f12_meets_clipping(polys, [polys, [1e-6 * p + 7e-6 for p in polys]], (1e-3,))


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=53 (scene test, 19 min, on 2a94463).
# Scaled by 1e-6 and moved, F[2, 4] changed by 19.8 x the bound (4.2e-6 for an unobstructed F
# of 0.105), neither result reporting an error; at obstructed_tol 1e-8 the pair gave 4-5
# different values 5e-6 apart under other moves and scales. Moved, its integral over face 4
# ended 1.6e-6 of the hidden part high, claiming its goal; over face 2 it was right. Brute
# force over face 4's final leaves (each split 4^4 times): all of it in one start piece
# integrating the visible F, whose 35 samples (its own and its children's) were all dark but
# one at a rounding's level, so it counted as lit and never asked its corners: within 1.5 %
# of its size of one corner light came through (visible F 2.4e-5 of a free 0.43 there). A
# blind piece of the visible part now asks the limits at its corners and edge midpoints
# whether or not a sample is lit (`edge_limit` in clipping.rs).
SEED_53_MOVED = [
    [
        [-0.10350397387358767, 0.22835200066614303, 0.2866102548821374],
        [-0.9254391898634236, -0.671848094848646, 0.6127099241171754],
        [0.0, 0.0, 0.0],
    ],
    [[0.0, 0.0, 0.0], [0.0, -0.07623504706479278, 1.192092896e-07], [0.5408160591488071, 0.0, 0.0]],
    [
        [-0.3683917949011163, -1.0, 1.0],
        [0.0, 0.9605739764364145, 0.0],
        [0.2822196134563566, 0.9902202982144721, -0.2968398605951331],
    ],
    [[0.0, 0.0, 0.0], [0.0, -0.6304333271530407, 0.0], [-0.522431152032011, 0.0, 0.0]],
    [
        [-0.4291861703172336, -0.8191345641214327, -0.37863943259746324],
        [0.9999999999999999, 0.0, -0.8681595630072216],
        [0.0, 1.0, 0.9999999999999999],
    ],
]


def test_replay_seed_53_moved():
    _assert_moved_within([np.array(p) for p in SEED_53_MOVED])


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=51 (scene test, 42 min, on 34a1e4a; fails
# on ada6fc6 too). With the obstacle F[4, 3] is 3.7e-6 of the unobstructed F (0.0668)
# high at the default; at obstructed_tol 1e-8 and 1e-10 the two agree within 6e-11: an
# integral claims its goal at the default while 3.7 x off (the pair (3, 4) over its side:
# 3.84 x). A corner departure share of 5 % instead of 10 % fixes it (see seed 49 above).
# Fixed instead by counting 1 % of a refined start piece's area times its corners' departure
# as its error at least, as coarse start pieces did (DEPARTURE_SHARE in clipping.rs).
SEED_51_OBSTACLE = (
    [
        [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]],
        [[0.0, 0.0, -0.03125], [0.8125, 0.03125, 0.0], [-0.5, -0.875, 0.0]],
        [[0.8125, 0.03125, 0.0], [0.625, 0.875, 0.53125], [-0.625, -0.3125, 0.0]],
        [[0.90625, -0.875, 0.0], [-0.46875, 0.8125, -0.0546875], [-0.75, 1.0, 0.5]],
    ],
    [[0.0, 0.0, 0.0], [1.0, 0.0, -1.0], [-0.5, -0.875, 0.0]],
)


def test_replay_seed_51_obstacle_raises_f():
    polys, obstacle = SEED_51_OBSTACLE
    _assert_obstacle_only_takes_away([np.array(p) for p in polys], np.array(obstacle))


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=48 a third time (scene test, 44 min, on
# 4ab0138): the obstacle raised an F by 1.79 x the slack. Passes since the gaps between two
# blockers' shadows are cut along their edge-edge-edge events (see seed 50 below)
SEED_48_OBSTACLE = (
    [
        [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
        [[0.0, 0.0, 0.0], [0.0, 0.0, -0.125], [-0.375, 0.0, -0.875]],
        [[0.0, 0.0, 0.0], [0.201171875, 0.48942078605245753, 0.0], [-0.75, -0.15625, -0.5]],
        [[0.0, 0.0, 1.0], [0.0, -0.02734375, 0.0], [-0.484375, 0.7578125, -0.2890625]],
        [[0.0, 0.5, 0.0], [-0.96875, -1.0, 0.0], [-0.1640625, 0.3984375, 1.0]],
    ],
    [[0.0, 0.0, 0.0], [0.0, 0.25, 0.0], [-1.0, 0.0, 0.0]],
)


def test_replay_seed_48_obstacle_raises_f():
    polys, obstacle = SEED_48_OBSTACLE
    _assert_obstacle_only_takes_away([np.array(p) for p in polys], np.array(obstacle))


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=50 (scene test, 10 min, on 2d2fead), two
# cases; both failed until the gaps between two blockers' shadows were cut along their
# edge-edge-edge events (`gap_chords` in crates/nusselt-core/src/obstructed/kinks.rs):
# - the obstacle raises F[3, 4] by 1.67 x the slack: 3.3e-6 of the unobstructed F at every
#   obstructed_tol from 1e-6 to 1e-12. The obstacle hides nothing of the pair (with faces 0
#   and 1 alone the same F as with 0, 1 and 2; 60 000 random source points give the same
#   point F with and without it). It is the F without it that is wrong: G = A F of the pair
#   over face 3 is 8.1895198e-4, over face 4 8.1895504e-4 (both claiming 9e-13), and with
#   the obstacle both sides give 8.1895504e-4. Face 3's final leaves each agree with a
#   1e-14 integral of themselves, its start pieces tile its part exactly, and neither the
#   blockers' cut to the slab, the shaft culling nor the pieces' own G change it. A brute
#   force (each leaf split 4^3 and 4^5 times, Radon's rule on each) finds it all in one
#   start piece integrating the visible F, 3.0e-9 of G off: its 7 samples and its
#   children's 28 are all in shadow, but within a tenth of its size of a corner (not at the
#   corner) up to 1 % of the free F comes through a gap between the shadows of faces 0 and
#   1. No kink cut bounded that gap (two blockers' shadows meet along edge-edge-edge events,
#   which were cut only at pierce points); the obstacle's kink cuts happened to reach it;
# - scaled by 1e-6 and moved, F[2, 3] changes by 1.08 x the bound: 1.89e-6 of the
#   unobstructed F at obstructed_tol 1e-8 and 1e-10 alike: the same kind of miss.
SEED_50_OBSTACLE = (
    [
        [
            [0.5834344732009976, 0.0, 0.0],
            [0.3333333333333333, 0.8134613990200181, 0.2676669448118274],
            [0.14437714378005073, -0.3115530688414284, 0.0],
        ],
        [
            [-0.05551362362587198, -0.11230303670122699, 0.0],
            [0.0, -0.25120451086312146, -0.42556938510445386],
            [0.5057808230093057, 0.24216463717099068, 0.0],
        ],
        [
            [0.0, 0.0, 0.5062371311345761],
            [0.0, 0.0, 0.0],
            [0.0, -0.03687067840895408, 0.628772856072159],
        ],
        [
            [0.5661550787254854, -0.5259756847622777, 0.9],
            [-2.612168588997259e-16, 0.0, -0.12338351339437925],
            [1e-14, 0.4693412878996772, -0.5736047901251212],
        ],
        [
            [-0.2831793327881308, 0.30925921026087466, -0.6077014464345906],
            [0.6490271984464662, 0.33673889207489016, -0.6895780414664165],
            [0.0, 0.0, 0.0],
        ],
    ],
    [[0.0, -0.6841299346898944, 0.0], [0.0, 0.0, 0.9999768754759102], [0.0, 0.0, 0.0]],
)
SEED_50_MOVED = [
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
    [[1.0, 0.0, 0.0], [0.5, 1.0, 0.0], [0.25, -0.25, 0.0]],
    [[0.75, -0.5, 0.875], [0.0, 0.0, -0.125], [0.0, 0.5, -0.5]],
    [[0.0, 0.0, 0.0], [0.0, 0.375, -0.75], [0.75, 0.25, -0.5]],
    [[0.0, 0.0, 0.125], [0.0, -0.25, -0.375], [0.5, 0.1875, 0.0]],
]


def test_replay_seed_50_obstacle_raises_f():
    polys, obstacle = SEED_50_OBSTACLE
    _assert_obstacle_only_takes_away([np.array(p) for p in polys], np.array(obstacle))


def test_replay_seed_50_moved():
    _assert_moved_within([np.array(p) for p in SEED_50_MOVED])


@pytest.mark.slow  # about 5 min
def test_seed_44_reference():
    """F[4, 2] of SEED_44 by an integration that shares nothing with nusselt's obstructed
    path: over the needle of face 2 in front of face 4 (z >= 0), per point the part of face 4
    in front of face 2 less the shadow cone of face 3 (the only face that hides anything of
    the pair), both by half-plane clipping, then Lambert's contour sum; nested adaptive
    Gauss-Kronrod over the needle, with breakpoints where the pierce segment ends and where
    face 3's trace crosses it."""
    from scipy.integrate import quad

    polys = [np.array(p) for p in SEED_44]
    f2, f3, f4 = polys[2], polys[3], polys[4]
    n2 = np.cross(f2[1] - f2[0], f2[2] - f2[0])
    n2 /= np.linalg.norm(n2)
    area4 = 0.5 * np.linalg.norm(np.cross(f4[1] - f4[0], f4[2] - f4[0]))

    def clip(poly, a, b):
        """The part of the convex polygon with a . y <= b."""
        out = []
        for k in range(len(poly)):
            p, q = poly[k], poly[(k + 1) % len(poly)]
            fp, fq = a @ p - b, a @ q - b
            if fp <= 0:
                out.append(p)
            if (fp < 0 < fq) or (fq < 0 < fp):
                out.append(p + (q - p) * (fp / (fp - fq)))
        return out

    def lambert(x, poly):
        total = 0.0
        for k in range(len(poly)):
            a, b = poly[k] - x, poly[(k + 1) % len(poly)] - x
            c = np.cross(a, b)
            if np.linalg.norm(c) > 0:
                total += np.arctan2(np.linalg.norm(c), a @ b) * (n2 @ c) / np.linalg.norm(c)
        return abs(total) / (2 * np.pi)

    up = np.array([0.0, 0.0, 1.0])
    front = [p[:2] for p in clip(list(f4), -n2, -n2 @ f2[0])]
    needle = clip(list(f2), -up, 0.0)  # (base end, apex, base end)
    caster = clip(list(f3), -up, 0.0)

    def visible(x, blocked):
        """Lambert's sum over the front part less face 3's shadow from x: the shadow is the
        cone from x over face 3's part between the planes z = 0 and z = x_z, and the front
        part outside it is the disjoint union of its pieces outside each of the cone's
        half-planes in turn."""
        cone = clip(caster, up, x[2]) if blocked else []
        pieces, rest = [], front
        if len(cone) >= 3:
            c = np.mean(cone, axis=0)
            for k in range(len(cone)):
                m = np.cross(cone[k] - x, cone[(k + 1) % len(cone)] - x)
                m = m if m @ (c - x) >= 0 else -m
                # in the shadow: m . (y - x) >= 0, with y = (y0, y1, 0)
                outside = clip(rest, m[:2], m @ x)
                pieces += [outside] if len(outside) >= 3 else []
                rest = clip(rest, -m[:2], -(m @ x))
                if len(rest) < 3:
                    break
        else:
            pieces = [front]
        return sum(lambert(x, [np.array([*p, 0.0]) for p in piece]) for piece in pieces)

    a, apex, c = needle[0], needle[1], needle[2]
    d = c - a
    jac = np.linalg.norm(np.cross(d, apex - c))

    def along(p):
        return ((p[:2] - a[:2]) @ d[:2]) / (d[:2] @ d[:2])

    trace = [p[:2] for p in caster if abs(p[2]) == 0.0]
    s_trace = np.linalg.solve(np.array([d[:2], trace[0] - trace[1]]).T, trace[0] - a[:2])[0]
    breaks = sorted([along(np.array([*front[1], 0.0])), along(np.array([*front[2], 0.0])), s_trace])

    def f42(blocked):
        def across(s):
            g = lambda t: visible(a + s * (d + t * (apex - c)), blocked)  # noqa: E731
            return quad(g, 0.0, 1.0, epsabs=0, epsrel=1e-7, limit=200)[0] * jac * s

        v, err = quad(across, 0.0, 1.0, points=breaks, epsabs=0, epsrel=1e-7, limit=400)
        assert err / area4 < 1e-11
        return v / area4

    # the rule on the unobstructed F, against the exact kernel
    assert abs(f42(False) - nusselt.view_factor(f4, f2)) <= 1e-14
    assert abs(f42(True) - SEED_44_F42) <= 1e-11

    # the hidden F over the start piece of obstructed/clipping.rs's
    # `a_visible_piece_compares_its_corners_with_its_samples` (the needle beyond the pierce
    # segment's end p, as the kink split leaves it), from p, where it gathers
    p = np.array([-0.18948271022069518, -0.26810338777587256, 0.0])
    top = np.array([-0.18911304644732252, -0.2682762589384444, 2.927897029611217e-5])
    jac = np.linalg.norm(np.cross(a - p, top - a))

    def hidden(x):
        return visible(x, False) - visible(x, True)

    def outward(u):
        g = lambda w: hidden(p + u * (a - p) + u * w * (top - a))  # noqa: E731
        return quad(g, 0.0, 1.0, epsabs=0, epsrel=1e-9, limit=200)[0] * u * jac

    piece = quad(outward, 0.0, 1.0, points=[1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 0.1], epsabs=0, epsrel=1e-9, limit=400)[0]
    assert abs(piece / area4 - 1.50565e-8) <= 1e-13, piece / area4


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=61 (scene test, after 49 min, on 515d94a).
# Faces 0 and 2 meet along the z axis (face 2's edge starts 1e-8 off the origin), and face 1 lies
# in the plane x = 0 through that edge, tilted 1e-12 out of it; F[0, 2] is 8.8e-9. Over face 2's
# needle in front of face 0, 1e-8 wide, face 1 hides most of the point F in the layer x < 1e-12 z.
# Face 1's plane is a kink plane, but it lay within the kink split's tolerance (1e-9 of the pair's
# size) of the needle's edge and was not cut: the integral ran out of evaluations with face 1
# alone (F 8.826057e-9) and claimed almost nothing hidden once a second obstacle through the
# origin was added (8.827821e-9, 2.0e-4 of the unobstructed F higher), and the scaled and moved
# scene differed by 1.006 x the bound. The tolerance is now also 1e-9 of the source's width
# (KINK_TOL in obstructed/kinks.rs).
SEED_61_POLYS = [
    [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.5, 0.0, 0.0]],
    [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1e-12, -1.0, 1.0]],
    [[0.0, 1e-08, 0.0], [0.0, 0.0, 1.0], [0.125, -1.0, 0.0]],
]


def test_replay_seed_61_obstacle_through_a_hinge_raises_f():
    polys = [np.array(p) for p in SEED_61_POLYS]
    _assert_obstacle_only_takes_away(polys, np.array([[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 1.0]]))


def test_replay_seed_61_hinge_scaled_and_moved():
    _assert_moved_within([np.array(p) for p in SEED_61_POLYS])


# Found by the long run with NUSSELT_HYPOTHESIS_SEED=63 (scene test, after 36 min, on 9109f8c and
# as far back as e8a613f). At obstructed_tol 1e-3, F[0, 4] was 3.4097e-5 for 3.5495e-5, 2.5 x the
# target low, while the scene scaled by 1e-6 and moved met it: over face 0, a start piece hidden
# whole from face 4, its three samples 2.7-fold apart, kept the coarse estimate of its hidden part
# (12 % high). See VISIBLE_SPREAD_LINEAR in obstructed/clipping.rs.
SEED_63_POLYS = [
    [
        [0.0, 0.0, 0.0],
        [0.4963909986989725, 0.0, 0.48916857966083893],
        [-0.4462023292954477, -0.9685899589081393, 0.49090201057060523],
    ],
    [
        [0.0, 0.8323927916661442, -0.6794596292833313],
        [0.0, -0.6828418250427766, -0.605756203842032],
        [-0.12234379998886546, 1e-12, 0.7266535689310558],
    ],
    [
        [0.5412756564101509, 0.4970412022116013, 5e-324],
        [0.5680459082084659, -0.9999999999999999, -0.4404649102103292],
        [-0.12565265960291794, -1.2598012284350193e-118, -0.17194676756353],
    ],
    [
        [0.07454692760374626, 0.0, -0.380977129367538],
        [6.190028139677765e-96, 5.960464477539063e-08, 0.9375],
        [-0.4462023292954477, -0.9685899589081393, 0.49090201057060523],
    ],
    [
        [-0.216234854666985, -0.3333333333333333, -0.25903958579530284],
        [-0.31758478202177665, -0.23655274232290657, 0.0],
        [0.0, 5.960464477539063e-08, 0.9375],
    ],
]


def test_replay_seed_63_piece_hidden_whole_at_a_loose_target():
    polys = [np.array(p) for p in SEED_63_POLYS]
    _assert_moved_within(polys, tol=1e-3)
    # against the default target, 1000 x tighter
    scene = nusselt.Scene.from_polygons(polys)
    loose = nusselt.form_factors(scene, obstructed_tol=1e-3).matrix
    tight = nusselt.form_factors(scene).matrix
    loose, tight = (m.toarray() if hasattr(m, "toarray") else np.asarray(m) for m in (loose, tight))
    assert (np.abs(loose - tight) <= 1e-3 * _free(polys) + 1e-15).all()
