//! numpy arrays <-> core polygons.
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use nusselt_core::geometry::{GeometryError, Polygon, Vec3};
use nusselt_core::Error;
use pyo3::exceptions::PyValueError;
use pyo3::PyResult;

/// One polygon from an (n, 3) array; `what` names it in error messages ("pj", "obstacle 3").
pub fn polygon(arr: &PyReadonlyArray2<'_, f64>, what: &str, tol: f64) -> PyResult<Polygon> {
    let a = arr.as_array();
    if a.ncols() != 3 {
        return Err(PyValueError::new_err(format!(
            "{what}: expected an (n, 3) array of vertices, got shape {:?}",
            a.shape()
        )));
    }
    let v: Vec<Vec3> = a.rows().into_iter().map(|r| Vec3::new(r[0], r[1], r[2])).collect();
    Polygon::with_tolerance(v, tol).map_err(|e| PyValueError::new_err(format!("{what} {e}")))
}

/// Polygons from flat vertex rows and offsets (polygon k = rows offsets[k]..offsets[k+1]).
/// Returns every polygon's error, so the caller can name faces with their file origin.
pub fn polygons_flat(
    coords: &PyReadonlyArray2<'_, f64>,
    offsets: &PyReadonlyArray1<'_, i64>,
    tol: f64,
) -> PyResult<Vec<Result<Polygon, GeometryError>>> {
    let c = coords.as_array();
    let o = offsets.as_array();
    if c.ncols() != 3 {
        return Err(PyValueError::new_err("coordinates must have shape (m, 3)"));
    }
    let mut out = Vec::with_capacity(o.len().saturating_sub(1));
    for k in 0..o.len().saturating_sub(1) {
        let (s, e) = (o[k], o[k + 1]);
        if s < 0 || e < s || e as usize > c.nrows() {
            return Err(PyValueError::new_err(format!("invalid polygon offsets at polygon {k}")));
        }
        let v = (s as usize..e as usize).map(|r| Vec3::new(c[[r, 0]], c[[r, 1]], c[[r, 2]])).collect();
        out.push(Polygon::with_tolerance(v, tol));
    }
    Ok(out)
}

pub fn vec3(x: &[f64], what: &str) -> Result<Vec3, Error> {
    if x.len() != 3 || x.iter().any(|v| !v.is_finite()) {
        return Err(Error::InvalidArgument(format!("{what} must be 3 finite numbers, got {x:?}")));
    }
    Ok(Vec3::new(x[0], x[1], x[2]))
}
