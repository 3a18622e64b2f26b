//! nusselt-core: form factors (view factors) between planar polygons.
//!
//! Pure Rust, no Python and no file I/O: flat arrays and [`geometry::Polygon`]s in, numbers
//! and sparse rows out. The Python package `nusselt` wraps this crate.

pub mod analytic;
pub mod contour;
pub mod error;
pub mod geometry;
pub mod hemisphere;
pub mod matrix;
pub mod method;
pub mod moments;
pub mod obstructed;
pub mod quadrature;
pub mod registry;
pub mod sampling;
pub mod scene;
pub mod special;
pub mod unobstructed_rows;
pub mod visibility;
pub mod work;

pub use error::Error;
pub use geometry::{Polygon, Vec3};
