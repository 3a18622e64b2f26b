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
    /// A result array could not be allocated (refused instead of aborting the process).
    #[error("cannot allocate {what}: {count} entries ({bytes} bytes); use a sparse threshold (threshold=) or fewer rows per block")]
    OutOfMemory { what: &'static str, count: usize, bytes: usize },
    /// One pair or row needed more work units than its budget (see [`crate::work`]).
    #[error(
        "{what} needs more than budget={budget} work units (visibility tests, cells or rays); raise the \
             method's `budget` option, or choose cheaper options (a looser tol, a smaller max_depth, fewer cells)"
    )]
    Budget { what: String, budget: u64 },
    /// The caller asked to stop (Ctrl-C).
    #[error("interrupted")]
    Cancelled,
}

pub type Result<T> = std::result::Result<T, Error>;

/// `vec![value; count]`, or [`Error::OutOfMemory`] naming `what` when it cannot be allocated
/// (`vec!` would abort the whole process, Python and all).
pub fn try_filled<T: Clone>(what: &'static str, count: usize, value: T) -> Result<Vec<T>> {
    let mut v = Vec::new();
    let bytes = count.saturating_mul(std::mem::size_of::<T>());
    v.try_reserve_exact(count).map_err(|_| Error::OutOfMemory { what, count, bytes })?;
    v.resize(count, value);
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_allocation_that_cannot_fit_is_an_error() {
        // 2^60 f64 entries (8 EiB): more than any machine has, refused instead of aborting
        let err = try_filled("the entries of F", 1usize << 60, 0.0f64).unwrap_err();
        assert_eq!(err, Error::OutOfMemory { what: "the entries of F", count: 1 << 60, bytes: 1 << 63 });
        assert!(err.to_string().contains("the entries of F"));
        assert_eq!(try_filled("x", 3, 1u8).unwrap(), vec![1, 1, 1]);
    }
}
