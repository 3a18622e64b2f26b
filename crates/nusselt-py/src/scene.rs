//! SceneCore: the validated polygons of a scene and the row-block computations on them.
use crate::convert::polygons_flat;
use crate::errors::guard;
use crate::options::options;
use crate::threads::pool;
use nusselt_core::geometry::{GeometryError, Polygon};
use nusselt_core::matrix::{upper_pair_rows, SparseRow};
use nusselt_core::method::{self, facing, Facing, Method, RuleCache};
use nusselt_core::Error;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::AtomicBool;

#[pyclass(frozen, module = "nusselt._core")]
pub struct SceneCore {
    checked: Vec<Result<Polygon, GeometryError>>,
    polygons: Vec<Polygon>,
    receiver: Vec<bool>,
    rules: RuleCache,
}

#[pymethods]
impl SceneCore {
    #[new]
    fn new(
        coords: PyReadonlyArray2<'_, f64>,
        offsets: PyReadonlyArray1<'_, i64>,
        receiver: PyReadonlyArray1<'_, bool>,
        planarity_tol: f64,
    ) -> PyResult<Self> {
        let checked = polygons_flat(&coords, &offsets, planarity_tol)?;
        let receiver = receiver.as_slice()?.to_vec();
        if receiver.len() != checked.len() {
            return Err(pyo3::exceptions::PyValueError::new_err("receiver mask length differs from polygon count"));
        }
        let polygons: Vec<Polygon> = checked.iter().filter_map(|r| r.as_ref().ok().cloned()).collect();
        let rules = RuleCache::new(polygons.len());
        Ok(SceneCore { checked, polygons, receiver, rules })
    }

    /// Triangles (vertex-index triples) of polygon k (ear clipping, concave outlines too).
    fn triangulate(&self, k: usize) -> PyResult<Vec<[usize; 3]>> {
        self.polygons
            .get(k)
            .map(|p| p.triangulate())
            .ok_or_else(|| pyo3::exceptions::PyIndexError::new_err(format!("no polygon {k}")))
    }

    /// Per polygon: None, or the validation error message.
    fn errors(&self) -> Vec<Option<String>> {
        self.checked.iter().map(|r| r.as_ref().err().map(|e| e.to_string())).collect()
    }

    fn areas<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.polygons.iter().map(|p| p.area()).collect::<Vec<_>>().into_pyarray(py)
    }

    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = self.polygons.iter().map(|p| p.normal().to_array().to_vec()).collect();
        Ok(PyArray2::from_vec2(py, &rows)?)
    }

    fn centroids<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = self.polygons.iter().map(|p| p.centroid().to_array().to_vec()).collect();
        Ok(PyArray2::from_vec2(py, &rows)?)
    }

    /// G_ij = A_i F_ij for the rows given and every receiver j > i, as CSR parts
    /// (indptr, indices, data) over the given rows.
    fn pair_rows<'py>(
        &self,
        py: Python<'py>,
        rows: PyReadonlyArray1<'_, i64>,
        method: &str,
        opts: &Bound<'_, PyDict>,
    ) -> PyResult<(Bound<'py, PyArray1<i64>>, Bound<'py, PyArray1<i64>>, Bound<'py, PyArray1<f64>>)> {
        let rows: Vec<usize> = rows.as_slice()?.iter().map(|&r| r.max(0) as usize).collect();
        let m: Method = method.parse().map_err(crate::errors::to_py)?;
        let o = options(opts)?;
        let out: Vec<SparseRow> = py.detach(|| {
            guard(|| {
                o.check()?;
                if self.polygons.len() != self.checked.len() {
                    return Err(Error::InvalidArgument("the scene has invalid polygons".into()));
                }
                let cancel = AtomicBool::new(false);
                let p = &self.polygons;
                pool().install(|| {
                    upper_pair_rows(
                        p.len(),
                        &rows,
                        &self.receiver,
                        &cancel,
                        |i, j| m == Method::Auto && facing(&p[i], &p[j]) == Facing::None,
                        |i, j| method::area_factor(&p[i], &p[j], m, &o, Some((&self.rules, i, j))),
                    )
                })
            })
        })?;
        let mut indptr = Vec::with_capacity(out.len() + 1);
        indptr.push(0i64);
        let nnz: usize = out.iter().map(|r| r.len()).sum();
        let (mut idx, mut val) = (Vec::with_capacity(nnz), Vec::with_capacity(nnz));
        for r in &out {
            for &(j, g) in r {
                idx.push(j as i64);
                val.push(g);
            }
            indptr.push(idx.len() as i64);
        }
        Ok((indptr.into_pyarray(py), idx.into_pyarray(py), val.into_pyarray(py)))
    }
}
