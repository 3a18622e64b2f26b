//! Method options from a Python dict (names and types already checked by nusselt.methods;
//! the core re-checks ranges). One key may configure several methods' option structs.
use nusselt_core::hemisphere::SourcePoints;
use nusselt_core::scene::AllOptions;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

fn source(v: &Bound<'_, PyAny>) -> PyResult<(SourcePoints, Option<usize>)> {
    if let Ok(s) = v.cast::<PyString>() {
        return match s.to_str()? {
            "centre" | "center" => Ok((SourcePoints::Centre, Some(0))),
            "auto" | "adaptive" => Ok((SourcePoints::Auto, None)),
            other => Err(PyValueError::new_err(format!("source must be 'centre', 'auto' or an integer k, got {other:?}"))),
        };
    }
    let k: u32 = v.extract()?;
    if k == 0 {
        return Ok((SourcePoints::Centre, Some(0)));
    }
    Ok((SourcePoints::Gauss(k), Some(k as usize)))
}

pub fn options(method: &str, d: &Bound<'_, PyDict>) -> PyResult<AllOptions> {
    let mut o = AllOptions::default();
    for (k, v) in d.iter() {
        let key: String = k.extract()?;
        match key.as_str() {
            "tol" => {
                let t: f64 = v.extract()?;
                match method {
                    "auto" => o.exact.tol = t,
                    _ => o.vis.tol = t,
                }
            }
            "obstructed_tol" => o.vis.tol = v.extract()?,
            "nodes" => o.exact.nodes = v.extract()?,
            "order" => o.vis.order = v.extract()?,
            "panels" => o.vis.panels = v.extract()?,
            "samples" => o.vis.samples = v.extract()?,
            "divisions" => o.vis.divisions = v.extract()?,
            "control_variate" => o.vis.control_variate = v.extract()?,
            "max_depth" => o.vis.max_depth = v.extract()?,
            "seed" => {
                let s: u64 = v.extract()?;
                o.vis.seed = s;
                o.hemicube.seed = s;
                o.single_plane.seed = s;
                o.raytrace.seed = s;
                o.nusselt.seed = s;
            }
            "source" => {
                let (sp, k) = source(&v)?;
                o.hemicube.source = sp;
                o.single_plane.source = sp;
                o.nusselt.source = sp;
                o.vis.source_points = k;
                o.vis.clip_source = k;
            }
            "resolution" => o.hemicube.resolution = v.extract()?,
            "random_rotation" => {
                let r: bool = v.extract()?;
                o.hemicube.random_rotation = r;
                o.single_plane.random_rotation = r;
                o.nusselt.random_rotation = r;
            }
            "half_width" => o.single_plane.half_width = v.extract()?,
            "min_cell" => o.single_plane.min_cell = v.extract()?,
            "rays" => o.raytrace.rays = v.extract()?,
            "cells" => o.nusselt.cells = v.extract()?,
            "jitter" => o.nusselt.jitter = v.extract()?,
            other => return Err(PyTypeError::new_err(format!("unknown option {other:?}"))),
        }
    }
    Ok(o)
}
