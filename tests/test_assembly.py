"""Lean assembly and trust measures: the same numbers as the straightforward dense formulas,
float32 and compressed output, and refusal of runs that cannot fit (issue 21 item 1)."""

import numpy as np
import pytest
import scipy.sparse as sp
from conftest import cube_faces

import nusselt
from nusselt import assembly, budget, trust


def _cube(n=4):
    polys, which = cube_faces(n)
    return nusselt.Scene.from_polygons(polys, surface=[str(w) for w in which])


def _dense_reciprocity(f, a):
    g = f * a[:, None]
    den = np.maximum(np.abs(g), np.abs(g.T))
    ok = den > 0
    return float(np.max(np.abs(g - g.T)[ok] / den[ok])) if ok.any() else 0.0


def test_banded_reciprocity_equals_the_dense_formula(monkeypatch):
    rng = np.random.default_rng(3)
    n = 40
    f = rng.random((n, n)) * (rng.random((n, n)) < 0.3)
    f[3, 7], f[7, 3] = 0.2, 0.0  # an entry present in one direction only: error 1
    a = rng.random(n) + 0.5
    monkeypatch.setattr(trust, "BAND_ENTRIES", 37)  # many bands, of a few rows each
    assert trust.reciprocity_error(sp.csr_array(f), a) == _dense_reciprocity(f, a) == 1.0
    f[3, 7] = 0.0
    sym = (f + f.T) / a[:, None]  # A_i F_ij symmetric up to rounding: a symmetric pattern
    assert trust.reciprocity_error(sp.csr_array(sym), a) == pytest.approx(_dense_reciprocity(sym, a), abs=0)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_pair_reciprocity_from_blocks_equals_the_measure_of_the_matrix(dtype):
    polys, _ = cube_faces(3)
    scene = nusselt.Scene.from_polygons([p * [1.0, 1.7, 0.6] for p in polys])  # unequal areas
    res = nusselt.form_factors(scene, block_size=100, dtype=dtype)
    seeded = res.reciprocity_error  # from the blocks
    fresh = trust.reciprocity_error(res.matrix, res.areas)
    assert seeded == fresh == _dense_reciprocity(res.dense().astype(np.float64), res.areas)
    assert res.matrix.dtype == dtype


def test_float32_values_are_the_float64_ones_rounded():
    scene = _cube(3)
    a = nusselt.form_factors(scene)
    b = nusselt.form_factors(scene, dtype=np.float32)
    assert b.matrix.dtype == np.float32
    assert np.array_equal(a.matrix.indices, b.matrix.indices)
    assert np.array_equal(a.matrix.data.astype(np.float32), b.matrix.data)
    with pytest.raises(ValueError, match="dtype"):
        nusselt.form_factors(scene, dtype=np.int32)


def test_streamed_threshold_equals_thresholding_the_full_matrix():
    scene = _cube(4)
    t = 0.004
    full = nusselt.form_factors(scene).dense()
    res = nusselt.form_factors(scene, threshold=t, block_size=500)
    small = (full < t) & (full.T < t)
    assert np.array_equal(res.dense(), np.where(small, 0.0, full))
    assert res.info["dropped"] == pytest.approx(np.max((full * small).sum(axis=1)), rel=1e-12)


def test_row_blocks_assemble_to_the_same_matrix_whatever_the_block_size():
    scene = _cube(3)
    a = nusselt.form_factors(scene, method="hemicube", block_size=10**9)
    b = nusselt.form_factors(scene, method="hemicube", block_size=60)
    assert np.array_equal(a.matrix.indptr, b.matrix.indptr) and np.array_equal(a.matrix.data, b.matrix.data)
    assert a.matrix.indices.dtype == np.int32


def test_compressed_npz_reads_back_identical_and_smaller(tmp_path):
    res = nusselt.form_factors(_cube(4))
    nusselt.io.write_result(tmp_path / "a.npz", res)
    nusselt.io.write_result(tmp_path / "b.npz", res, compress=True)
    a, b = nusselt.io.load_npz(tmp_path / "a.npz"), nusselt.io.load_npz(tmp_path / "b.npz")
    assert (a["matrix"] != b["matrix"]).nnz == 0 and np.array_equal(a["matrix"].data, res.matrix.data)
    assert (tmp_path / "b.npz").stat().st_size < 0.8 * (tmp_path / "a.npz").stat().st_size


@pytest.mark.filterwarnings("ignore:.*rows are 0")  # a large threshold empties rows, as asked
def test_threshold_bounds_the_entries_it_keeps():
    """At most 2.2 n / t entries survive a threshold t (row sums <= 1): the bound the memory
    check relies on, checked on a scene where every pair sees the other."""
    scene = _cube(4)
    for t in (0.002, 0.01, 0.05):
        res = nusselt.form_factors(scene, threshold=t)
        assert res.matrix.nnz <= budget.max_entries(len(res), t)


def test_a_run_that_cannot_fit_is_refused_before_any_work(monkeypatch):
    scene = _cube(2)  # 24 x 20 facing pairs: 480 entries, 9 kB at the peak
    monkeypatch.setattr(budget, "available_memory", lambda: 5_000)
    calls = []
    with monkeypatch.context() as m:
        m.setattr(assembly, "assemble_pairs", lambda *a, **k: calls.append(1))
        with pytest.raises(MemoryError) as e:
            nusselt.form_factors(scene, progress=False)
    msg = str(e.value)
    assert "24 receivers" in msg and "threshold" in msg and "float32" in msg and not calls
    nusselt.form_factors(scene, check_memory=False)  # the caller knows better: runs


def test_cli_refuses_a_run_that_cannot_fit_with_exit_2(tmp_path, monkeypatch, capsys):
    from nusselt.cli import main

    obj = tmp_path / "sq.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 0 1 1\nv 1 1 1\nv 1 0 1\nf 1 2 3 4\nf 5 6 7 8\n")
    monkeypatch.setattr(budget, "available_memory", lambda: 1)
    assert main(["matrix", str(obj), "-o", str(tmp_path / "x.npz"), "-q"]) == 2
    err = capsys.readouterr().err
    assert "threshold" in err and "float32" in err and "Traceback" not in err
    assert not (tmp_path / "x.npz.partial").exists()


def test_assembled_csr_is_the_scipy_matrix_without_scipy_parts():
    """A pair method's result holds the scipy-free Csr until ``matrix`` is read; its row sums,
    entry count and dense form are scipy's, and ``matrix`` wraps the same arrays."""
    from nusselt._sparse import Csr

    scene = _cube(3)
    res = nusselt.form_factors(scene)
    held = res._stored_matrix()
    assert isinstance(held, Csr)
    f = held.toarray()
    assert res.closure_error == pytest.approx(float(np.max(np.abs(f.sum(axis=1) - 1))), abs=1e-15)
    np.testing.assert_allclose(held.row_sums(), f.sum(axis=1), rtol=0, atol=1e-15)
    m = res.matrix
    assert sp.issparse(m) and m.has_canonical_format and m.nnz == held.nnz == np.count_nonzero(f)
    assert np.shares_memory(m.data, held.data) and np.shares_memory(m.indices, held.indices)
    np.testing.assert_array_equal(m.toarray(), f)
    assert res._stored_matrix() is m  # from now on the scipy array, and its measures stand
    assert res.__dict__["_measures_cache"][0] is m


def test_a_pair_run_written_to_npz_loads_no_scipy(tmp_path):
    """``nusselt matrix scene.obj -o out.npz`` of a pair method never imports scipy (0.2 s of
    CPU, docs/scale.md), and the file holds the matrix form_factors computes."""
    import subprocess
    import sys

    from conftest import write_cube_obj

    obj, out = tmp_path / "cube.obj", tmp_path / "cube.npz"
    write_cube_obj(str(obj), 3)
    code = (
        "import sys\nfrom nusselt.cli import main\n"
        f"assert main(['matrix', {str(obj)!r}, '-o', {str(out)!r}, '-q']) == 0\n"
        "print(sorted(m for m in sys.modules if m.startswith('scipy')))\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert run.stdout.strip().splitlines()[-1] == "[]"
    got = nusselt.io.load_npz(out)
    want = nusselt.form_factors(nusselt.Scene.from_file(obj))
    np.testing.assert_array_equal(got["matrix"].toarray(), want.dense())
    np.testing.assert_array_equal(got["row_sums"], want.row_sums)


def _cube_and_plate():
    """The closed 2 x 2 cube and, below it, a 10 x 10 plate facing away: 124 receivers, but
    only the cube's 24 x 20 non-coplanar pairs exchange radiation."""
    from conftest import rect

    polys, _ = cube_faces(2)
    plate = [rect(x, x + 0.1, y, y + 0.1, z=-1.0, flip=True) for x in np.arange(10) / 10 for y in np.arange(10) / 10]
    return nusselt.Scene.from_polygons(list(polys) + plate)


def test_the_estimated_entries_are_the_facing_pairs():
    """Every row counted (small scenes): the nonzero count exactly; sampled rows (the
    384-patch cube): above it by at most the margin."""
    scene = _cube_and_plate()
    res = nusselt.form_factors(scene)
    assert budget.estimated_entries(scene) == res.matrix.nnz == 24 * 20
    big = _cube(8)
    nnz = nusselt.form_factors(big).matrix.nnz  # 384 x 320
    assert nnz <= budget.estimated_entries(big) <= 1.5 * nnz


def test_memory_check_accepts_a_run_whose_worst_case_alone_would_not_fit(monkeypatch):
    """The plate below the cube faces away: its 100 rows are empty. The worst case (every pair
    seeing each other) does not fit in 50 kB, the expected result does: the run goes ahead;
    in 5 kB it is refused, with the estimate and the hints in the message."""
    scene = _cube_and_plate()
    sizes = {"kind": "pairs", "threshold": 0.0, "dtype": np.float64, "with_std": False}
    expect = budget.estimated_entries(scene)
    assert budget.peak_bytes(len(scene), entries=expect, **sizes) < 50_000 < budget.peak_bytes(len(scene), **sizes)
    monkeypatch.setattr(budget, "available_memory", lambda: 50_000)
    res = nusselt.form_factors(scene)  # the plate's rows are 0, as they should be
    assert res.matrix.nnz == expect
    monkeypatch.setattr(budget, "available_memory", lambda: 5_000)
    with pytest.raises(MemoryError) as e:
        nusselt.form_factors(scene)
    msg = str(e.value)
    assert "124 receivers" in msg and f"about {expect:,} entries" in msg and "threshold" in msg and "float32" in msg


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_mirror_into_mapped_memory_gives_the_same_matrix(monkeypatch, dtype):
    """The mirror's arrays from populated mappings (big results) hold what np.zeros-backed
    ones do; float32 is the float64 result rounded once."""
    scene = _cube(3)
    plain = nusselt.form_factors(scene, dtype=dtype)
    monkeypatch.setattr(assembly, "MAPPED_BYTES", 0)
    mapped = nusselt.form_factors(scene, dtype=dtype)
    assert not mapped.matrix.data.flags.owndata  # a view of the mapping
    assert mapped.matrix.dtype == dtype
    np.testing.assert_array_equal(mapped.dense(), plain.dense())
    wide = nusselt.form_factors(scene).dense()
    np.testing.assert_array_equal(mapped.dense(), wide.astype(dtype))
