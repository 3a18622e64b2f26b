//! SceneCore: the validated polygons of a scene and the row-block computations on them.
use crate::convert::polygons_flat;
use crate::options::options;
use crate::threads::pool;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2};
use nusselt_core::geometry::Polygon;
use nusselt_core::matrix::PairBlock;
use nusselt_core::scene::Scene;
use nusselt_core::work::CANCEL;
use nusselt_core::Error;
use pyo3::prelude::*;
use pyo3::types::PyDict;

type Csr<'py> = (
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i32>>,
    Bound<'py, PyArray1<f64>>,
    Option<Bound<'py, PyArray1<f64>>>,
);

#[pyclass(frozen, module = "nusselt._core")]
pub struct SceneCore {
    /// Per polygon: None, or its [`Error::Geometry`].
    errors: Vec<Option<Error>>,
    scene: Scene,
}

impl SceneCore {
    fn valid(&self) -> Result<(), Error> {
        match self.errors.iter().flatten().next() {
            Some(e) => Err(e.clone()),
            None => Ok(()),
        }
    }

    /// A heavy call on the scene: off the GIL on the thread pool, interruptible by Ctrl-C.
    fn run<T: Send>(&self, py: Python<'_>, f: impl FnOnce(&Scene) -> Result<T, Error> + Send) -> PyResult<T> {
        let pool = pool();
        crate::interrupt::run(py, || {
            self.valid()?;
            pool.install(|| f(&self.scene))
        })
    }
}

/// A block's CSR parts as numpy arrays.
fn csr(py: Python<'_>, b: PairBlock) -> Csr<'_> {
    (b.indptr.into_pyarray(py), b.cols.into_pyarray(py), b.g.into_pyarray(py), b.std.map(|s| s.into_pyarray(py)))
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
        let checked: Vec<Result<Polygon, Error>> = polygons_flat(&coords, &offsets, planarity_tol)?;
        let receiver = receiver.as_slice()?.to_vec();
        let errors = checked.iter().map(|r| r.as_ref().err().cloned()).collect();
        let polygons: Vec<Polygon> = checked.into_iter().filter_map(|r| r.ok()).collect();
        let receiver = if polygons.len() == receiver.len() { receiver } else { vec![false; polygons.len()] };
        let scene = Scene::new(polygons, receiver).map_err(crate::errors::to_py)?;
        Ok(SceneCore { errors, scene })
    }

    /// Per polygon: None, or its validation error as a (not raised) GeometryError.
    fn errors(&self, py: Python<'_>) -> Vec<Option<Py<pyo3::exceptions::PyBaseException>>> {
        self.errors.iter().map(|e| e.clone().map(|e| crate::errors::to_py(e).into_value(py))).collect()
    }

    fn areas<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scene.polygons().iter().map(|p| p.area()).collect::<Vec<_>>().into_pyarray(py)
    }

    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = self.scene.polygons().iter().map(|p| p.normal().to_array().to_vec()).collect();
        Ok(PyArray2::from_vec2(py, &rows)?)
    }

    fn centroids<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = self.scene.polygons().iter().map(|p| p.centroid().to_array().to_vec()).collect();
        Ok(PyArray2::from_vec2(py, &rows)?)
    }

    /// Triangles (vertex-index triples) of polygon k (ear clipping, concave outlines too).
    fn triangulate(&self, k: usize) -> PyResult<Vec<[usize; 3]>> {
        self.scene
            .polygons()
            .get(k)
            .map(|p| p.triangulate())
            .ok_or_else(|| pyo3::exceptions::PyIndexError::new_err(format!("no polygon {k}")))
    }

    /// Whether polygon k is strictly convex ([`Polygon::is_strictly_convex`], the core's one
    /// convexity test).
    fn strictly_convex(&self, k: usize) -> PyResult<bool> {
        self.scene
            .polygons()
            .get(k)
            .map(|p| p.is_strictly_convex())
            .ok_or_else(|| pyo3::exceptions::PyIndexError::new_err(format!("no polygon {k}")))
    }

    /// True when no polygon of the scene can block another pair.
    fn unobstructed(&self, py: Python<'_>) -> bool {
        let pool = pool();
        py.detach(|| pool.install(|| self.scene.unobstructed()))
    }

    /// Pair methods: G_ij = A_i F_ij for the given rows and every receiver j > i, as CSR
    /// parts over those rows (indptr, indices, G, standard error of G).
    fn pair_rows<'py>(
        &self,
        py: Python<'py>,
        rows: PyReadonlyArray1<'_, i64>,
        method: &str,
        opts: &Bound<'_, PyDict>,
    ) -> PyResult<Csr<'py>> {
        let rows = to_rows(&rows)?;
        let m = options(method, opts)?;
        let b = self.run(py, |scene| scene.pair_block(&rows, &m, &CANCEL))?;
        Ok(csr(py, b))
    }

    /// Row methods: F_ij for the given rows, as CSR parts plus standard errors (NaN where the
    /// method has none) and the lost hemisphere fraction per row.
    fn full_rows<'py>(
        &self,
        py: Python<'py>,
        rows: PyReadonlyArray1<'_, i64>,
        method: &str,
        opts: &Bound<'_, PyDict>,
    ) -> PyResult<(
        Bound<'py, PyArray1<i64>>,
        Bound<'py, PyArray1<i64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
    )> {
        let rows = to_rows(&rows)?;
        let m = options(method, opts)?;
        if !m.is_row() {
            return Err(pyo3::exceptions::PyValueError::new_err(format!("{method:?} is not a row method")));
        }
        let out = self.run(py, |scene| scene.full_rows(&rows, &m, &CANCEL))?;
        let (mut indptr, mut idx, mut val, mut std, mut lost) =
            (vec![0i64], Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for r in &out {
            for (k, &(j, f)) in r.entries.iter().enumerate() {
                idx.push(j as i64);
                val.push(f);
                std.push(r.std_err.as_ref().map_or(f64::NAN, |s| s[k]));
            }
            indptr.push(idx.len() as i64);
            lost.push(r.lost);
        }
        Ok((
            indptr.into_pyarray(py),
            idx.into_pyarray(py),
            val.into_pyarray(py),
            std.into_pyarray(py),
            lost.into_pyarray(py),
        ))
    }

    /// F from each point (unit normal) to every receiver, as CSR parts (indptr, receiver
    /// polygon ids, F, standard error or None); `obstructed`: every polygon blocks.
    fn point_rows<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'_, f64>,
        normals: PyReadonlyArray2<'_, f64>,
        method: &str,
        opts: &Bound<'_, PyDict>,
        obstructed: bool,
    ) -> PyResult<Csr<'py>> {
        let (p, n) = (vec3_rows(&points, "points")?, vec3_rows(&normals, "normals")?);
        let m = options(method, opts)?;
        let b = self.run(py, |scene| scene.point_rows(&p, &n, &m, obstructed, &CANCEL))?;
        Ok(csr(py, b))
    }

    /// F from a small sphere at each point to every receiver (visible solid angle / 4 pi),
    /// as CSR parts (indptr, receiver polygon ids, F, None).
    fn point_sphere_rows<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'_, f64>,
        obstructed: bool,
    ) -> PyResult<Csr<'py>> {
        let p = vec3_rows(&points, "points")?;
        let b = self.run(py, |scene| scene.point_sphere_rows(&p, obstructed, &CANCEL))?;
        Ok(csr(py, b))
    }

    /// Sky view factor of each point (unit normal): 1 - the fraction the scene intercepts.
    fn point_sky<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'_, f64>,
        normals: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (p, n) = (vec3_rows(&points, "points")?, vec3_rows(&normals, "normals")?);
        let out = self.run(py, |scene| scene.point_sky(&p, &n, &CANCEL))?;
        Ok(out.into_pyarray(py))
    }

    /// Sky view factor of each polygon in `rows` (Gauss rule of `order` over the polygon).
    fn patch_sky<'py>(
        &self,
        py: Python<'py>,
        rows: PyReadonlyArray1<'_, i64>,
        order: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let rows = to_rows(&rows)?;
        let out = self.run(py, |scene| scene.patch_sky(&rows, order, &CANCEL))?;
        Ok(out.into_pyarray(py))
    }

    /// Whether each ray (origin, direction) to infinity meets a polygon of the scene.
    fn rays_blocked<'py>(
        &self,
        py: Python<'py>,
        origins: PyReadonlyArray2<'_, f64>,
        dirs: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let (o, d) = (vec3_rows(&origins, "origins")?, vec3_rows(&dirs, "directions")?);
        let out = self.run(py, |scene| scene.rays_blocked(&o, &d, &CANCEL))?;
        Ok(out.into_pyarray(py))
    }
}

/// Rows of an (m, 3) array as vectors.
fn vec3_rows(a: &PyReadonlyArray2<'_, f64>, what: &str) -> PyResult<Vec<nusselt_core::Vec3>> {
    let a = a.as_array();
    if a.ncols() != 3 {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "{what}: expected an (m, 3) array, got shape {:?}",
            a.shape()
        )));
    }
    Ok(a.rows().into_iter().map(|r| nusselt_core::Vec3::new(r[0], r[1], r[2])).collect())
}

fn to_rows(rows: &PyReadonlyArray1<'_, i64>) -> PyResult<Vec<usize>> {
    rows.as_slice()?
        .iter()
        .map(|&r| usize::try_from(r).map_err(|_| pyo3::exceptions::PyValueError::new_err(format!("negative row {r}"))))
        .collect()
}
