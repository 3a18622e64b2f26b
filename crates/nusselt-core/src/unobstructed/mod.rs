//! Unobstructed pairs: the exact form factor of two polygons that see each other wholly, and of
//! a point and a polygon. [`method`] chooses the kernel (`auto`'s plan, or one named by the
//! user); [`rows`] is the same choice as a hot loop over a block of rows.

pub mod analytic;
pub mod contour;
pub mod far_field;
pub mod method;
pub mod moments;
pub mod rows;
