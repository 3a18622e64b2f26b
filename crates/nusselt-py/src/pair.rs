//! view_factor / point_view_factor for single pairs.
use crate::convert::{polygon, vec3};
use crate::errors::guard;
use crate::options::options;
use nusselt_core::method::{self, Method};
use nusselt_core::Error;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// F_ab for two polygons; `obstacles` must be empty for the unobstructed methods.
#[pyfunction]
pub fn view_factor(
    py: Python<'_>,
    a: PyReadonlyArray2<'_, f64>,
    b: PyReadonlyArray2<'_, f64>,
    obstacles: Vec<PyReadonlyArray2<'_, f64>>,
    method: &str,
    opts: &Bound<'_, PyDict>,
    planarity_tol: f64,
) -> PyResult<f64> {
    let pa = polygon(&a, "pi", planarity_tol)?;
    let pb = polygon(&b, "pj", planarity_tol)?;
    let obs = obstacles
        .iter()
        .enumerate()
        .map(|(k, o)| polygon(o, &format!("obstacle {k}"), planarity_tol))
        .collect::<PyResult<Vec<_>>>()?;
    let m: Method = method.parse().map_err(crate::errors::to_py)?;
    let o = options(opts)?;
    py.detach(|| {
        guard(|| {
            o.check()?;
            if !obs.is_empty() {
                return Err(Error::InvalidArgument(format!("method {method:?} does not handle obstacles")));
            }
            Ok(method::area_factor(&pa, &pb, m, &o, None)? / pa.area())
        })
    })
}

/// F from a differential area at `p` with unit normal `n` to polygon `b`.
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
) -> PyResult<f64> {
    let pb = polygon(&b, "pj", planarity_tol)?;
    let m: Method = method.parse().map_err(crate::errors::to_py)?;
    let o = options(opts)?;
    let (p, n) = (p.as_slice()?.to_vec(), n.as_slice()?.to_vec());
    let n_obs = obstacles.len();
    py.detach(|| {
        guard(|| {
            let (p, n) = (vec3(&p, "point")?, vec3(&n, "normal")?);
            if n_obs > 0 {
                return Err(Error::InvalidArgument(format!("method {method:?} does not handle obstacles")));
            }
            method::point_factor(p, n, &pb, m, &o)
        })
    })
}
