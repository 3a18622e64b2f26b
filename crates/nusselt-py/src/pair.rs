//! view_factor / point_view_factor for single pairs and points.
use crate::convert::{polygons, vec3};
use crate::options::options;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use nusselt_core::scene::{self, AnyMethod};
use nusselt_core::Polygon;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The polygons (`first`, then the obstacles; a geometry error carries the position in that
/// list) and the configured method of one call.
fn prepare(
    first: &[&PyReadonlyArray2<'_, f64>],
    obstacles: &[PyReadonlyArray2<'_, f64>],
    method: &str,
    opts: &Bound<'_, PyDict>,
    tol: f64,
) -> PyResult<(Vec<Polygon>, AnyMethod)> {
    let all: Vec<&PyReadonlyArray2<'_, f64>> = first.iter().copied().chain(obstacles).collect();
    let polys = polygons(&all, tol)?;
    Ok((polys, options(method, opts)?))
}

/// (F_ab, standard error) for two polygons, with optional obstacles. Polygon indices in
/// errors: a = 0, b = 1, obstacle k = 2 + k.
#[pyfunction]
pub fn view_factor(
    py: Python<'_>,
    a: PyReadonlyArray2<'_, f64>,
    b: PyReadonlyArray2<'_, f64>,
    obstacles: Vec<PyReadonlyArray2<'_, f64>>,
    method: &str,
    opts: &Bound<'_, PyDict>,
    planarity_tol: f64,
) -> PyResult<(f64, f64)> {
    let (mut polys, m) = prepare(&[&a, &b], &obstacles, method, opts, planarity_tol)?;
    let obs = polys.split_off(2);
    let pb = polys.pop().expect("b");
    let pa = polys.pop().expect("a");
    let pool = crate::threads::pool();
    let e = crate::interrupt::run(py, || pool.install(|| scene::pair_view_factor(pa, pb, obs, &m)))?;
    Ok((e.value, e.std_err))
}

/// (F, standard error) from a differential area at `p` with unit normal `n` to polygon `b`.
/// Polygon indices in errors: b = 0, obstacle k = 1 + k.
#[pyfunction]
pub fn point_view_factor(
    py: Python<'_>,
    p: PyReadonlyArray1<'_, f64>,
    n: PyReadonlyArray1<'_, f64>,
    b: PyReadonlyArray2<'_, f64>,
    obstacles: Vec<PyReadonlyArray2<'_, f64>>,
    method: &str,
    opts: &Bound<'_, PyDict>,
    planarity_tol: f64,
) -> PyResult<(f64, f64)> {
    let (mut polys, m) = prepare(&[&b], &obstacles, method, opts, planarity_tol)?;
    let obs = polys.split_off(1);
    let pb = polys.pop().expect("b");
    let (p, n) = (p.as_slice()?.to_vec(), n.as_slice()?.to_vec());
    let e = crate::interrupt::run(py, || {
        let (p, n) = (vec3(&p, "point")?, vec3(&n, "normal")?);
        scene::point_view_factor(p, n, pb, obs, &m)
    })?;
    Ok((e.value, e.std_err))
}
