//! The one error type of the core; the binding maps each variant to a Python exception.

use crate::geometry::GeometryError;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// A polygon failed validation; `index` is its position in the caller's list.
    #[error("polygon {index} {source}")]
    Geometry { index: usize, source: GeometryError },
    /// An option is out of its valid range or a method cannot do what was asked.
    #[error("{0}")]
    InvalidArgument(String),
    /// One pair or row needed more work units than its budget (see [`crate::work`]).
    #[error("{what} needs more than budget={budget} work units (visibility tests, cells or rays); raise the \
             method's `budget` option, or choose cheaper options (a looser tol, a smaller max_depth, fewer cells)")]
    Budget { what: String, budget: u64 },
    /// The caller asked to stop (Ctrl-C).
    #[error("interrupted")]
    Cancelled,
}

pub type Result<T> = std::result::Result<T, Error>;
