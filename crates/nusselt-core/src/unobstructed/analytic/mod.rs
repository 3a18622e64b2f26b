//! Exact (closed-form) kernels: differential area to polygon (Lambert), polygon to polygon
//! (Narayanaswamy's edge-pair formula) and named catalogue configurations.

pub mod area_routes;
pub mod closed_forms;
pub mod lambert;
pub mod polygon_pair;

pub use lambert::{point_contour, point_polygon, point_polygon_unrouted};
pub use polygon_pair::{edge_pair_log_integral, polygon_pair, polygon_pair_within};
