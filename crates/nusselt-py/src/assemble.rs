//! Assembly of the full F from the upper-triangle blocks of a pair-method run, in one pass
//! (numpy/scipy would concatenate, transpose and merge: several copies of every entry).
use crate::errors::guard;
use numpy::{Element, IntoPyArray, PyArray1, PyArrayMethods, PyReadonlyArray1};
use nusselt_core::matrix::{mirror_into, mirror_layout, upper_reciprocity, MirrorLayout, Stored, UpperRow};
use pyo3::prelude::*;
use std::borrow::Cow;

type Block<'py> = (
    PyReadonlyArray1<'py, i64>,
    PyReadonlyArray1<'py, i64>,
    PyReadonlyArray1<'py, i32>,
    PyReadonlyArray1<'py, f64>,
    Option<PyReadonlyArray1<'py, f64>>,
);
type Out<'py> = (Bound<'py, PyArray1<i64>>, Bound<'py, PyArray1<i32>>, Bound<'py, PyAny>, Option<Bound<'py, PyAny>>);

/// (indptr, indices, F, standard errors of F or None) over receiver indices, from blocks of
/// (rows, indptr, columns, G, std of G) in scene indices; `col_of` maps scene index to
/// receiver index (-1: not a receiver). Standard errors are kept only when some are nonzero.
/// F (and its errors) are float32 when `float32`: written so, never held as float64 too.
/// The output arrays come from `alloc(count, dtype name)` (1-d, writable, contiguous), so the
/// caller picks their memory.
#[pyfunction]
pub fn mirror_pairs<'py>(
    py: Python<'py>,
    areas: PyReadonlyArray1<'py, f64>,
    col_of: PyReadonlyArray1<'py, i64>,
    blocks: Vec<Block<'py>>,
    float32: bool,
    alloc: Bound<'py, PyAny>,
) -> PyResult<Out<'py>> {
    let areas = areas.as_slice()?;
    let col_of = col_of.as_slice()?;
    // every polygon a receiver (the usual case): indices need no mapping and no copy
    let identity = col_of.iter().enumerate().all(|(k, &c)| c == k as i64);
    let mut mapped: Vec<(usize, Cow<[i32]>, usize, usize, usize)> = Vec::new(); // row, cols, block, start, end
    let mut with_std = false;
    for (b, (rows, indptr, indices, data, std)) in blocks.iter().enumerate() {
        let (rows, indptr, indices, data) =
            (rows.as_slice()?, indptr.as_slice()?, indices.as_slice()?, data.as_slice()?);
        if indptr.len() != rows.len() + 1
            || indices.len() != data.len()
            || std.as_ref().is_some_and(|s| s.len().ok() != Some(data.len()))
        {
            return Err(pyo3::exceptions::PyValueError::new_err(format!("block {b}: inconsistent CSR parts")));
        }
        if let Some(s) = std {
            with_std |= s.as_slice()?.iter().any(|&v| v != 0.0);
        }
        let map = |k: i64| -> PyResult<i64> {
            usize::try_from(k)
                .ok()
                .and_then(|k| col_of.get(k))
                .copied()
                .filter(|&c| (0..=i32::MAX as i64).contains(&c))
                .ok_or_else(|| {
                    pyo3::exceptions::PyValueError::new_err(format!("block {b}: index {k} is not a receiver"))
                })
        };
        for (r, &row) in rows.iter().enumerate() {
            let (s, e) = (indptr[r] as usize, indptr[r + 1] as usize);
            if s > e || e > indices.len() {
                return Err(pyo3::exceptions::PyValueError::new_err(format!("block {b}: bad indptr")));
            }
            let cols = if identity {
                Cow::Borrowed(&indices[s..e]) // mirror_upper checks the range
            } else {
                Cow::Owned(
                    indices[s..e].iter().map(|&j| map(j as i64).map(|c| c as i32)).collect::<PyResult<Vec<i32>>>()?,
                )
            };
            mapped.push((map(row)? as usize, cols, b, s, e));
        }
    }
    let slices: Vec<(&[f64], Option<&[f64]>)> = blocks
        .iter()
        .map(|(_, _, _, d, s)| Ok((d.as_slice()?, s.as_ref().map(|s| s.as_slice()).transpose()?)))
        .collect::<PyResult<_>>()?;
    let rows: Vec<UpperRow> = mapped
        .iter()
        .map(|(row, cols, b, s, e)| UpperRow {
            row: *row,
            cols,
            g: &slices[*b].0[*s..*e],
            std: slices[*b].1.map(|sd| &sd[*s..*e]),
        })
        .collect();
    let layout = guard(|| mirror_layout(areas.len(), &rows))?;
    let indices = fresh::<i32>(&alloc, layout.nnz(), "int32")?;
    let (f, sd) = if float32 {
        fill::<f32>(py, &alloc, areas, &rows, &layout, with_std, &indices, "float32")?
    } else {
        fill::<f64>(py, &alloc, areas, &rows, &layout, with_std, &indices, "float64")?
    };
    Ok((layout.indptr().to_vec().into_pyarray(py), indices, f, sd))
}

/// A 1-d array of `count` entries of type T from the caller's `alloc`.
fn fresh<'py, T: Element>(alloc: &Bound<'py, PyAny>, count: usize, dtype: &str) -> PyResult<Bound<'py, PyArray1<T>>> {
    let a = alloc.call1((count, dtype))?;
    let a = a
        .cast_into::<PyArray1<T>>()
        .map_err(|_| pyo3::exceptions::PyTypeError::new_err(format!("alloc must return a 1-d {dtype} array")))?;
    if a.len()? != count {
        return Err(pyo3::exceptions::PyValueError::new_err(format!("alloc returned the wrong length for {count}")));
    }
    Ok(a)
}

/// Fills the caller's arrays with F (and its standard errors) as V, the GIL released.
fn fill<'py, V: Stored + Element>(
    py: Python<'py>,
    alloc: &Bound<'py, PyAny>,
    areas: &[f64],
    rows: &[UpperRow<'_>],
    layout: &MirrorLayout,
    with_std: bool,
    indices: &Bound<'py, PyArray1<i32>>,
    dtype: &str,
) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>)> {
    let nnz = layout.nnz();
    let data = fresh::<V>(alloc, nnz, dtype)?;
    let sd = if with_std { Some(fresh::<V>(alloc, nnz, dtype)?) } else { None };
    {
        let mut iw = indices.try_readwrite()?;
        let mut dw = data.try_readwrite()?;
        let mut sw = sd.as_ref().map(|s| s.try_readwrite()).transpose()?;
        let not_contiguous = |_| pyo3::exceptions::PyValueError::new_err("alloc must return contiguous arrays");
        let is = iw.as_slice_mut().map_err(not_contiguous)?;
        let ds = dw.as_slice_mut().map_err(not_contiguous)?;
        let ss: &mut [V] = match sw.as_mut() {
            Some(w) => w.as_slice_mut().map_err(not_contiguous)?,
            None => &mut [],
        };
        let pool = crate::threads::pool();
        py.detach(|| guard(|| pool.install(|| mirror_into(areas, rows, layout, is, ds, ss))))?;
    }
    Ok((data.into_any(), sd.map(|s| s.into_any())))
}

type Upper<'py> =
    (PyReadonlyArray1<'py, i64>, PyReadonlyArray1<'py, i64>, PyReadonlyArray1<'py, i32>, PyReadonlyArray1<'py, f64>);

/// The reciprocity error of the F that `mirror_pairs` builds from these blocks of (rows,
/// indptr, columns, G), rounded to float32 first when `float32`; `areas` and the blocks' rows
/// and columns by scene index.
#[pyfunction]
pub fn pair_reciprocity(
    py: Python<'_>,
    areas: PyReadonlyArray1<'_, f64>,
    blocks: Vec<Upper<'_>>,
    float32: bool,
) -> PyResult<f64> {
    let areas = areas.as_slice()?;
    let mut rows: Vec<UpperRow> = Vec::new();
    for (b, (r, indptr, indices, data)) in blocks.iter().enumerate() {
        let (r, indptr, indices, data) = (r.as_slice()?, indptr.as_slice()?, indices.as_slice()?, data.as_slice()?);
        let bad = || pyo3::exceptions::PyValueError::new_err(format!("block {b}: inconsistent CSR parts"));
        if indptr.len() != r.len() + 1 || indices.len() != data.len() {
            return Err(bad());
        }
        for (k, &row) in r.iter().enumerate() {
            let (s, e) = (indptr[k], indptr[k + 1]);
            if s < 0 || s > e || e as usize > indices.len() || row < 0 {
                return Err(bad());
            }
            let (s, e) = (s as usize, e as usize);
            rows.push(UpperRow { row: row as usize, cols: &indices[s..e], g: &data[s..e], std: None });
        }
    }
    let pool = crate::threads::pool();
    py.detach(|| guard(|| pool.install(|| upper_reciprocity(areas, &rows, float32))))
}
