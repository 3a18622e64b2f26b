//! Visibility: which polygon a ray hits first, whether a segment is blocked, and which
//! polygons can block a pair at all. Every method with visibility goes through [`Visibility`].
//! Obstacles are opaque from both sides.

use crate::geometry::{Polygon, Vec3};

pub mod bvh;
pub mod occluders;
pub mod shadow;

pub use bvh::Bvh;
pub use occluders::Occluders;

/// Ids are indices into the scene's polygon list.
pub trait Visibility: Sync {
    /// First polygon hit by `origin + t * dir` for t in (tmin, tmax), skipping the ids in
    /// `ignore`. Returns the id, the ray parameter t and whether the front side was hit
    /// (dir . normal < 0).
    fn first_hit(&self, origin: Vec3, dir: Vec3, tmin: f64, tmax: f64, ignore: &[u32]) -> Option<Hit>;

    /// True if any polygon other than those in `ignore` blocks the open segment a -> b.
    fn occluded(&self, a: Vec3, b: Vec3, ignore: &[u32]) -> bool;

    /// Ids of polygons (other than `ignore`) that may intersect the region between the two
    /// polygons (a conservative shaft test): the candidate blockers of the pair.
    fn candidates_between(&self, a: &Polygon, b: &Polygon, ignore: &[u32], out: &mut Vec<u32>);

    /// Ids of polygons (other than `ignore`) that may meet the convex hull of `a` and the box
    /// [lo, hi]: a superset of the candidates of every pair (a' in a, b in the box). One such
    /// query serves a whole cluster of receivers of a row; where it is empty, none of them
    /// needs a query of its own. With `among` (sorted ids, a superset of the answer, e.g. the
    /// answer for a bigger box), only those polygons are tested.
    fn candidates_toward_box(
        &self,
        a: &Polygon,
        lo: Vec3,
        hi: Vec3,
        ignore: &[u32],
        among: Option<&[u32]>,
        out: &mut Vec<u32>,
    );

    /// [`Visibility::candidates_between`] for a pair whose blockers are known to lie in the
    /// sorted id list `among` (from [`Visibility::candidates_toward_box`]), without searching
    /// the scene: the polygons of `among` the pair's shaft test keeps. Every polygon that can
    /// block the pair is kept; one that merely passes both conservative tests may be left out.
    fn candidates_among(&self, a: &Polygon, b: &Polygon, ignore: &[u32], among: &[u32], out: &mut Vec<u32>);
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub id: u32,
    pub t: f64,
    pub front: bool,
}
