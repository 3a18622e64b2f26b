//! Thin PyO3 binding of nusselt-core: array conversion, error mapping (errors.rs), GIL
//! release around every heavy call, a fork-safe worker pool (threads.rs). No numerics here.
use pyo3::prelude::*;

mod assemble;
mod convert;
mod errors;
mod interrupt;
mod options;
mod pair;
mod scene;
mod threads;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::SceneCore>()?;
    m.add("GeometryError", m.py().get_type::<errors::GeometryError>())?;
    m.add_function(wrap_pyfunction!(assemble::mirror_pairs, m)?)?;
    m.add_function(wrap_pyfunction!(assemble::pair_reciprocity, m)?)?;
    m.add_function(wrap_pyfunction!(options::methods, m)?)?;
    m.add_function(wrap_pyfunction!(pair::view_factor, m)?)?;
    m.add_function(wrap_pyfunction!(pair::point_view_factor, m)?)?;
    m.add_function(wrap_pyfunction!(threads::num_threads, m)?)?;
    m.add_function(wrap_pyfunction!(threads::work_units, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_guard_selftest, m)?)?;
    Ok(())
}

/// Deliberately panics inside the guard every binding call uses; the test suite calls it to
/// prove that a panic reaches Python as a RuntimeError, never as an abort.
#[pyfunction]
fn _panic_guard_selftest() -> PyResult<()> {
    errors::guard(|| -> Result<(), nusselt_core::Error> { panic!("self-test panic") })
}
