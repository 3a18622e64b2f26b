//! view_factor / point_view_factor for single pairs and points.
use crate::convert::{polygon, vec3};
use crate::options::options;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use nusselt_core::scene;
use pyo3::prelude::*;
use pyo3::types::PyDict;

fn obstacles(obs: &[PyReadonlyArray2<'_, f64>], tol: f64) -> PyResult<Vec<nusselt_core::Polygon>> {
    obs.iter().enumerate().map(|(k, o)| polygon(o, &format!("obstacle {k}"), tol)).collect()
}

/// (F_ab, standard error) for two polygons, with optional obstacles.
#[pyfunction]
pub fn view_factor(
    py: Python<'_>,
    a: PyReadonlyArray2<'_, f64>,
    b: PyReadonlyArray2<'_, f64>,
    obstacles_: Vec<PyReadonlyArray2<'_, f64>>,
    method: &str,
    opts: &Bound<'_, PyDict>,
    planarity_tol: f64,
) -> PyResult<(f64, f64)> {
    let pa = polygon(&a, "pi", planarity_tol)?;
    let pb = polygon(&b, "pj", planarity_tol)?;
    let obs = obstacles(&obstacles_, planarity_tol)?;
    let (m, o) = options(method, opts)?;
    let pool = crate::threads::pool();
    let e = crate::interrupt::run(py, || pool.install(|| scene::pair_view_factor(pa, pb, obs, m, &o)))?;
    Ok((e.value, e.std_err))
}

/// (F, standard error) from a differential area at `p` with unit normal `n` to polygon `b`.
#[pyfunction]
pub fn point_view_factor(
    py: Python<'_>,
    p: PyReadonlyArray1<'_, f64>,
    n: PyReadonlyArray1<'_, f64>,
    b: PyReadonlyArray2<'_, f64>,
    obstacles_: Vec<PyReadonlyArray2<'_, f64>>,
    method: &str,
    opts: &Bound<'_, PyDict>,
    planarity_tol: f64,
) -> PyResult<(f64, f64)> {
    let pb = polygon(&b, "pj", planarity_tol)?;
    let obs = obstacles(&obstacles_, planarity_tol)?;
    let (m, o) = options(method, opts)?;
    let (p, n) = (p.as_slice()?.to_vec(), n.as_slice()?.to_vec());
    let e = crate::interrupt::run(py, || {
        let (p, n) = (vec3(&p, "point")?, vec3(&n, "normal")?);
        scene::point_view_factor(p, n, pb, obs, m, &o)
    })?;
    Ok((e.value, e.std_err))
}
