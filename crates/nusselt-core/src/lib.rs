//! nusselt-core: form factors (view factors) between planar polygons.
//!
//! Pure Rust, no Python and no file I/O: flat arrays and [`geometry::Polygon`]s in, numbers
//! and sparse rows out. The Python package `nusselt` wraps this crate (`crates/nusselt-py`).
//!
//! # From a scene to a CSR block
//!
//! 1. **Scene.** [`geometry::Polygon::new`] validates one polygon (finite, planar, simple,
//!    positive area) and computes its normal, area and centroid; [`scene::Scene::new`] takes
//!    the polygons and which of them are receivers (the others only block).
//! 2. **Method and options.** [`registry::configure`] turns a method name and the user's
//!    options into a [`scene::AnyMethod`]: one variant per method, each carrying its own
//!    options type, named as users see them ([`obstructed::ClippingOptions`],
//!    [`hemisphere::HemicubeOptions`], ...; declared by `registry::method_options!`), checked
//!    against the names, defaults and ranges in [`registry::METHODS`], the one table of them
//!    (the Python package builds its own table from it).
//! 3. **Visibility, once per scene.** [`scene::Scene::unobstructed`] decides whether anything
//!    can block at all (a convex enclosure cannot). If it can, the scene lazily builds the
//!    joined occluders and their BVH ([`visibility::Occluders`], [`visibility::Bvh`]) the
//!    first time a method needs them; the row methods use a BVH of the polygons themselves.
//! 4. **Per pair, per method family.**
//!    * [`unobstructed`]: the exact unobstructed G_ij = A_i F_ij of every pair, by `auto`'s
//!      plan ([`unobstructed::far_field::FarPlan`]: moment or Gauss rules far away, the
//!      analytic or contour kernels close by), in the vectorised rows of
//!      [`unobstructed::rows`].
//!    * [`obstructed`]: only pairs whose shaft keeps a candidate blocker get a visibility
//!      estimator (quadrature, Monte Carlo, subdivision, adaptive, or the exact visible region
//!      of `clipping` from [`visibility::shadow`]) that scales the unobstructed value.
//!    * [`hemisphere`]: the row methods (hemicube, single plane, raytrace, Nusselt analog)
//!      compute a whole row of F from points on the source polygon.
//! 5. **Sparse rows.** [`matrix`] runs the rows of a block in parallel (rayon), one pair
//!    once (the upper triangle of the symmetric G) for pair methods, whole rows of F for row
//!    methods, and returns a [`matrix::PairBlock`]: CSR parts (offsets, columns, values and
//!    standard errors). [`matrix::mirror_upper`] completes the symmetric matrix at the end.
//! 6. **Back to Python, block by block.** A call computes only the rows it is given
//!    ([`scene::Scene::pair_block`], [`scene::Scene::full_rows`]). Between blocks the Python
//!    layer reports progress, writes the block to a checkpoint (a killed run resumes to the
//!    identical matrix and loses nothing finished), and hands blocks to a cluster as tasks.
//!    Cancellation reaches inside a block too: every loop polls the `cancel` flag and the
//!    work budget of [`work`], and returns [`Error`] rather than panicking.
//!
//! Supporting layers: [`quadrature`] (1-D Gauss tables and area rules on polygons),
//! [`sampling`] (low-discrepancy points, area-uniform polygon sampling), [`special`]
//! (dilogarithm and friends), [`error`]. The mathematics of every method is in
//! `docs/algorithms.md`.

pub mod error;
pub mod geometry;
pub mod hemisphere;
pub mod matrix;
pub mod obstructed;
pub mod quadrature;
pub mod registry;
pub mod sampling;
pub mod scene;
pub mod special;
pub mod unobstructed;
pub mod visibility;
pub mod work;

pub use error::Error;
pub use geometry::{Polygon, Vec3};
