//! Quadrature rules: 1-D Gauss tables ([`gauss`]), area rules on polygons ([`area_rules`],
//! also the normalised source points of the row methods) and adaptive refinement
//! ([`adaptive`]: the triangle split and the local refinement loop).
//! The kernels that use them live with their methods (`unobstructed::far_field`,
//! `obstructed::rules`, `hemisphere`).

pub mod adaptive;
pub mod area_rules;
pub mod gauss;

pub(crate) use area_rules::triangle_rule;
pub use area_rules::{polygon_gauss_points, AreaRule};
pub use gauss::{gauss_legendre, try_gauss_legendre, MAX_ORDER};
