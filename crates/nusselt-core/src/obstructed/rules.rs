//! Triangle rules and source point sets shared by the point-evaluation methods.

use crate::geometry::{Polygon, Vec3};
use crate::quadrature::AreaRule;

/// Source points and weights (summing to the polygon's area): the centroid alone, or a
/// k x k Gauss rule.
pub(super) fn source_points(a: &Polygon, k: usize) -> Vec<(Vec3, f64)> {
    if k == 0 {
        return vec![(a.centroid(), a.area())];
    }
    let r = AreaRule::new(a, k);
    r.points.into_iter().zip(r.weights).collect()
}

pub(super) fn centroid3(t: &[Vec3; 3]) -> Vec3 {
    (t[0] + t[1] + t[2]) / 3.0
}

pub(super) fn area3(t: &[Vec3; 3]) -> f64 {
    0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()
}

/// Radon's 7-point degree-5 rule on a triangle (barycentric points, weights summing to 1).
pub(super) fn radon7() -> [([f64; 3], f64); 7] {
    let s15 = 15f64.sqrt();
    let (a1, a2) = ((6.0 - s15) / 21.0, (6.0 + s15) / 21.0);
    let (w1, w2) = ((155.0 - s15) / 1200.0, (155.0 + s15) / 1200.0);
    let (b1, b2) = (1.0 - 2.0 * a1, 1.0 - 2.0 * a2);
    [
        ([1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0], 9.0 / 40.0),
        ([a1, a1, b1], w1),
        ([a1, b1, a1], w1),
        ([b1, a1, a1], w1),
        ([a2, a2, b2], w2),
        ([a2, b2, a2], w2),
        ([b2, a2, a2], w2),
    ]
}

/// A triangle rule (barycentric points, weights summing to 1) mapped onto `t`: points and
/// weights summing to its area.
pub(super) fn rule_points<'r>(rule: &'r [([f64; 3], f64)], t: &[Vec3; 3]) -> impl Iterator<Item = (Vec3, f64)> + 'r {
    let (t, area) = (*t, area3(t));
    rule.iter().map(move |(b, w)| (t[0] * b[0] + t[1] * b[1] + t[2] * b[2], area * w))
}

pub(super) fn rule_integral(rule: &[([f64; 3], f64)], t: &[Vec3; 3], f: &dyn Fn(Vec3) -> f64) -> f64 {
    rule_points(rule, t).map(|(x, w)| w * f(x)).sum()
}
