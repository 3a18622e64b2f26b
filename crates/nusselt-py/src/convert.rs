//! numpy arrays <-> core polygons.
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use nusselt_core::geometry::{validate_all, Polygon, Vec3};
use nusselt_core::Error;
use pyo3::exceptions::PyValueError;
use pyo3::PyResult;

/// Vertex rows of an (n, 3) array; `index` names the polygon (callers check shapes first).
fn vertices(arr: &PyReadonlyArray2<'_, f64>, index: usize) -> PyResult<Vec<Vec3>> {
    let a = arr.as_array();
    if a.ncols() != 3 {
        return Err(PyValueError::new_err(format!(
            "polygon {index}: expected an (n, 3) array of vertices, got shape {:?}",
            a.shape()
        )));
    }
    Ok(a.rows().into_iter().map(|r| Vec3::new(r[0], r[1], r[2])).collect())
}

/// Polygons from (n, 3) arrays; a polygon that fails validation is [`Error::Geometry`] with
/// its position in `arrays`, for the caller to name.
pub fn polygons(arrays: &[&PyReadonlyArray2<'_, f64>], tol: f64) -> PyResult<Vec<Polygon>> {
    let outlines = arrays.iter().enumerate().map(|(k, a)| vertices(a, k)).collect::<PyResult<Vec<_>>>()?;
    validate_all(outlines, tol).into_iter().collect::<Result<_, _>>().map_err(crate::errors::to_py)
}

/// Polygons from flat vertex rows and offsets (polygon k = rows offsets[k]..offsets[k+1]).
/// Returns every polygon's error, so the caller can name faces with their file origin.
pub fn polygons_flat(
    coords: &PyReadonlyArray2<'_, f64>,
    offsets: &PyReadonlyArray1<'_, i64>,
    tol: f64,
) -> PyResult<Vec<Result<Polygon, Error>>> {
    let c = coords.as_array();
    let o = offsets.as_array();
    if c.ncols() != 3 {
        return Err(PyValueError::new_err("coordinates must have shape (m, 3)"));
    }
    let mut outlines = Vec::with_capacity(o.len().saturating_sub(1));
    for k in 0..o.len().saturating_sub(1) {
        let (s, e) = (o[k], o[k + 1]);
        if s < 0 || e < s || e as usize > c.nrows() {
            return Err(PyValueError::new_err(format!("invalid polygon offsets at polygon {k}")));
        }
        outlines.push((s as usize..e as usize).map(|r| Vec3::new(c[[r, 0]], c[[r, 1]], c[[r, 2]])).collect());
    }
    Ok(validate_all(outlines, tol))
}

pub fn vec3(x: &[f64], what: &str) -> Result<Vec3, Error> {
    if x.len() != 3 || x.iter().any(|v| !v.is_finite()) {
        return Err(Error::InvalidArgument(format!("{what} must be 3 finite numbers, got {x:?}")));
    }
    Ok(Vec3::new(x[0], x[1], x[2]))
}
