"""Bad input gets a clear exception naming the problem; never a crash or a Rust panic."""

import numpy as np
import pytest
from conftest import rect

import nusselt
from nusselt import _core

GOOD = rect(0, 1, 0, 1)
FACING = rect(0, 1, 0, 1, z=1, flip=True)


@pytest.mark.parametrize(
    "poly, message",
    [
        (np.array([[0, 0, 0], [1, 0, np.nan], [1, 1, 0], [0, 1, 0]]), "NaN or infinite"),
        (np.array([[0, 0, 0], [1, 0, np.inf], [1, 1, 0]]), "NaN or infinite"),
        (np.zeros((4, 2)), "(n, 3)"),
        (np.zeros(12), "(n, 3)"),
        (np.array([[0, 0, 0], [1, 0, 0], [1, 0, 0]]), "at least 3 distinct"),
        (np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]]), "zero area"),
        (np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.01], [0, 1, 0]]), "not planar"),
        (np.array([[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0]]), "self-intersecting"),
        (np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [-1, 0.5, 0], [0, 2, 0]]), "self-intersecting"),
    ],
)
def test_bad_polygons(poly, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        nusselt.view_factor(poly, FACING)
    with pytest.raises(ValueError, match="pj"):
        nusselt.view_factor(GOOD, poly)


def test_geometry_errors_name_the_polygon_as_the_caller_named_it():
    line = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]], dtype=float)
    obstacle = rect(0.2, 0.8, 0.2, 0.8, z=0.5)
    with pytest.raises(ValueError, match=r"^obstacle 1 has zero area"):
        nusselt.view_factor(GOOD, FACING, obstacles=[obstacle, line])
    with pytest.raises(ValueError, match=r"^pj has zero area"):
        nusselt.point_view_factor([0.5, 0.5, 0], [0, 0, 1], line)
    with pytest.raises(ValueError, match=r"^obstacle 0 has zero area"):
        nusselt.point_view_factor([0.5, 0.5, 0], [0, 0, 1], FACING, obstacles=[line])
    # the core reports the position in its list; the binding's exception carries it
    with pytest.raises(_core.GeometryError) as info:
        _core.view_factor(GOOD, FACING, [obstacle, line], "clipping", {}, 1e-6)
    assert isinstance(info.value, ValueError)
    message, index, kind, reason, degenerate = info.value.args
    assert (index, kind, degenerate) == (3, "zero_area", True) and message == f"polygon 3 {reason}"
    # a scene names its face by where it came from
    bent = np.vstack([GOOD, [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0.0, 1, 1.3]]])
    with pytest.raises(ValueError, match=r"face 1 \(room\.obj:7\) is not planar"):
        nusselt.Scene(bent, [np.arange(4), np.arange(4, 8)], origin=["room.obj:3", "room.obj:7"])


def test_bad_methods_and_options():
    with pytest.raises(ValueError, match="unknown method"):
        nusselt.view_factor(GOOD, FACING, method="magic")
    with pytest.raises(TypeError, match="no option"):
        nusselt.view_factor(GOOD, FACING, method="analytic", nodes=4)
    with pytest.raises(ValueError, match="outside"):
        nusselt.view_factor(GOOD, FACING, method="contour", nodes=0)
    with pytest.raises(ValueError, match="outside"):
        nusselt.view_factor(GOOD, FACING, method="contour", nodes=10**9)
    with pytest.raises(TypeError, match="integer"):
        nusselt.view_factor(GOOD, FACING, method="contour", nodes=2.5)
    with pytest.raises(ValueError):
        nusselt.view_factor(GOOD, FACING, tol=float("nan"))


def test_bad_points():
    with pytest.raises(ValueError, match="point"):
        nusselt.point_view_factor([0, 0], [0, 0, 1], FACING)
    with pytest.raises(ValueError, match="normal"):
        nusselt.point_view_factor([0, 0, 0], [0, 0, 0], FACING)
    with pytest.raises(ValueError, match="point"):
        nusselt.point_view_factor([0, np.nan, 0], [0, 0, 1], FACING)


def test_panics_never_cross_into_python():
    # the guard every binding call runs in turns a panic into a RuntimeError
    with pytest.raises(RuntimeError, match="internal error"):
        _core._panic_guard_selftest()


def test_random_garbage_gives_only_clean_errors():
    rng = np.random.default_rng(7)
    for _ in range(300):
        k = int(rng.integers(1, 7))
        p = rng.normal(size=(k, 3)) * 10.0 ** rng.integers(-8, 8)
        if rng.random() < 0.2:
            p[rng.integers(k)] = rng.choice([np.nan, np.inf, 1e308])
        q = rng.normal(size=(int(rng.integers(3, 6)), 3))
        for m in ("auto", "analytic", "contour"):
            try:
                f = nusselt.view_factor(p, q, method=m)
            except ValueError:
                continue
            assert np.isfinite(f) and 0.0 <= f <= 1.0 + 1e-12


def test_result_assembly_rejects_malformed_blocks():
    """The one-pass assembly of pair blocks checks what it is given (a corrupt checkpoint
    block must be an error, not a crash or a wrong matrix)."""
    areas = np.ones(3)
    col_of = np.arange(3, dtype=np.int64)
    i64 = lambda *v: np.array(v, dtype=np.int64)
    i32 = lambda *v: np.array(v, dtype=np.int32)
    good = (i64(0), i64(0, 2), i32(1, 2), np.array([0.2, 0.3]), None)
    indptr, idx, f, sd = _core.mirror_pairs(areas, col_of, [good], False, np.zeros)
    assert sd is None
    dense = np.zeros((3, 3))
    for r in range(3):
        dense[r, idx[indptr[r] : indptr[r + 1]]] = f[indptr[r] : indptr[r + 1]]
    assert np.array_equal(dense, [[0, 0.2, 0.3], [0.2, 0, 0], [0.3, 0, 0]])
    bad = [
        (i64(0), i64(0, 3), i32(1, 2), np.array([0.2, 0.3]), None),  # indptr beyond the entries
        (i64(0), i64(0, 2), i32(1), np.array([0.2, 0.3]), None),  # fewer columns than values
        (i64(1), i64(0, 1), i32(0), np.array([0.2]), None),  # below the diagonal
        (i64(0), i64(0, 1), i32(5), np.array([0.2]), None),  # not a polygon
        (i64(0), i64(0, 2), i32(2, 1), np.array([0.2, 0.3]), None),  # columns not ascending
    ]
    for block in bad:
        with pytest.raises(ValueError):
            _core.mirror_pairs(areas, col_of, [block], False, np.zeros)
    with pytest.raises(ValueError, match="twice"):
        _core.mirror_pairs(areas, col_of, [good, good], False, np.zeros)
    # arrays from the caller's alloc that do not fit are refused before any write
    with pytest.raises(ValueError, match="wrong length"):
        _core.mirror_pairs(areas, col_of, [good], False, lambda n, t: np.zeros(n + 1, dtype=t))
    with pytest.raises(TypeError, match="int32 array"):
        _core.mirror_pairs(areas, col_of, [good], False, lambda n, t: np.zeros(n))
