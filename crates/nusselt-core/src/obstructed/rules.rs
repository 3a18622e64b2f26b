//! Triangle rules and source point sets shared by the point-evaluation methods.

use super::kinks::split_at_kinks;
use crate::geometry::{Polygon, Vec3};
use crate::quadrature::AreaRule;

/// Most points of the kink-split source rule (`source='auto'` of `subdivision` and
/// `adaptive`) beyond one per piece: each point costs one whole receiver evaluation, so the
/// rule's cost is bounded here, whatever the number of blockers (docs/algorithms.md §6.1).
pub(super) const MAX_SOURCE_POINTS: usize = 64;

/// Pieces that get Radon's rule even when the pieces alone exceed [`MAX_SOURCE_POINTS`]: the
/// largest pieces of a split that hit its cap carry most of the error of a centroid rule
/// (wall to wall past a crate: 1.8e-3 with centroids only, 1.2e-3 with these; bench/methods.py).
const MIN_UPGRADED: usize = 8;

/// Source points of `subdivision` and `adaptive` on `a` (the part of the source in front of
/// the receiver `b`), weights summing to its area. `Some(k)`: [`source_points`]. `None`
/// ('auto'): `a` cut along the kink lines of the visible F ([`split_at_kinks`]), so that each
/// piece's integrand is smooth; every piece gets its centroid, and the largest pieces
/// Radon's 7-point rule instead while the count stays within [`MAX_SOURCE_POINTS`] (at least
/// [`MIN_UPGRADED`] of them): a small piece's error is small whatever its rule. The count is
/// at most max(64, pieces + 48), pieces <= 4 x 64 triangles. Before the cap, every piece got
/// Radon's rule: up to 448 points, 6.9 s for one obstructed pair at 48 divisions.
pub(super) fn area_source_points(
    a: &Polygon,
    b: &Polygon,
    blockers: &[&Polygon],
    k: Option<usize>,
) -> Vec<(Vec3, f64)> {
    if let Some(k) = k {
        return source_points(a, k);
    }
    let every: Vec<usize> = (0..blockers.len()).collect();
    let (pieces, _) = split_at_kinks(a, b, blockers, &every, false);
    // largest first by area relative to the source, rounded so that equal pieces keep their
    // order in any units (the sort is stable); slivers below 1e-6 of the source, whose count
    // may change with the units' rounding, do not count against the cap
    let rel = |t: &[Vec3; 3]| (area3(t) / a.area() * 1e9).round() as i64;
    let counted = pieces.iter().filter(|t| rel(t) >= 1000).count();
    let upgrades = (MAX_SOURCE_POINTS.saturating_sub(counted) / 6).max(MIN_UPGRADED);
    let mut order: Vec<usize> = (0..pieces.len()).collect();
    order.sort_by_key(|&t| std::cmp::Reverse(rel(&pieces[t])));
    let (r7, centre) = (radon7(), [([1.0 / 3.0; 3], 1.0)]);
    order
        .iter()
        .enumerate()
        .flat_map(|(rank, &t)| {
            let rule: &[([f64; 3], f64)] = if rank < upgrades { &r7 } else { &centre };
            rule_points(rule, &pieces[t]).collect::<Vec<_>>()
        })
        .collect()
}

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

/// The longest edge of triangle t.
pub(super) fn longest_edge(t: &[Vec3; 3]) -> f64 {
    t[0].distance(t[1]).max(t[1].distance(t[2])).max(t[2].distance(t[0]))
}

/// How thin triangle t is: its longest edge over its least altitude (2/sqrt(3) for an
/// equilateral one, without bound for a sliver).
pub(super) fn aspect(t: &[Vec3; 3]) -> f64 {
    let l = longest_edge(t);
    l * l / (2.0 * area3(t))
}

/// A polygon's width: its area over its radius (about its least extent; for a needle, its
/// width across).
pub(super) fn width(p: &Polygon) -> f64 {
    p.area() / p.radius()
}

/// A triangle rule (barycentric points, weights summing to 1) mapped onto `t`: points and
/// weights summing to its area.
pub(super) fn rule_points<'r>(rule: &'r [([f64; 3], f64)], t: &[Vec3; 3]) -> impl Iterator<Item = (Vec3, f64)> + 'r {
    let (t, area) = (*t, area3(t));
    rule.iter().map(move |(b, w)| (t[0] * b[0] + t[1] * b[1] + t[2] * b[2], area * w))
}

/// Strang and Fix's interior 3-point rule of degree 2 on a triangle (barycentric points,
/// weights summing to 1).
pub(super) fn strang_fix3() -> [([f64; 3], f64); 3] {
    let (a, b) = (2.0 / 3.0, 1.0 / 6.0);
    [([a, b, b], 1.0 / 3.0), ([b, a, b], 1.0 / 3.0), ([b, b, a], 1.0 / 3.0)]
}

/// Weights that give, from a function's values at the points of `rule` (barycentric, in
/// general position), the values at the triangle's three vertices of the quadratic that fits
/// them best (least squares; six points or more), or of the linear function (fewer): where the
/// function is smooth on the triangle these lie close to its values there, where it changes
/// steeply next to an edge or a corner they do not.
pub(super) fn vertex_extrapolation(rule: &[([f64; 3], f64)]) -> [Vec<f64>; 3] {
    // quadratic or linear basis in the barycentric coordinates (b1, b2)
    let n = if rule.len() >= 6 { 6 } else { 3 };
    let basis = |b: &[f64; 3]| [1.0, b[1], b[2], b[1] * b[1], b[1] * b[2], b[2] * b[2]][..n].to_vec();
    let rows: Vec<Vec<f64>> = rule.iter().map(|(b, _)| basis(b)).collect();
    // the normal equations' matrix A^T A, inverted by Gauss-Jordan with partial pivoting
    let mut m = vec![vec![0.0; 2 * n]; n];
    for (i, mi) in m.iter_mut().enumerate() {
        for j in 0..n {
            mi[j] = rows.iter().map(|r| r[i] * r[j]).sum();
        }
        mi[n + i] = 1.0;
    }
    for c in 0..n {
        let p = (c..n).max_by(|&a, &b| m[a][c].abs().total_cmp(&m[b][c].abs())).unwrap_or(c);
        m.swap(c, p);
        let d = m[c][c];
        for x in m[c].iter_mut() {
            *x /= d;
        }
        for r in 0..n {
            if r != c {
                let f = m[r][c];
                let pivot = m[c].clone();
                for (x, y) in m[r].iter_mut().zip(pivot) {
                    *x -= f * y;
                }
            }
        }
    }
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].map(|v| {
        // v^T (A^T A)^-1 A^T, one weight per rule point
        let bv = basis(&v);
        let coef: Vec<f64> = (0..n).map(|j| (0..n).map(|i| bv[i] * m[i][n + j]).sum()).collect();
        rows.iter().map(|r| r.iter().zip(&coef).map(|(a, c)| a * c).sum()).collect()
    })
}

/// [`vertex_extrapolation`] of Radon's rule ([`radon7`]), computed once.
pub(super) fn radon7_corner_weights() -> &'static [Vec<f64>; 3] {
    static WEIGHTS: std::sync::OnceLock<[Vec<f64>; 3]> = std::sync::OnceLock::new();
    WEIGHTS.get_or_init(|| vertex_extrapolation(&radon7()))
}

/// [`vertex_extrapolation`] of the 3-point rule ([`strang_fix3`]), computed once: vertex k is
/// 5/3 times point k less 1/3 times each other point.
pub(super) fn strang_fix3_corner_weights() -> &'static [Vec<f64>; 3] {
    static WEIGHTS: std::sync::OnceLock<[Vec<f64>; 3]> = std::sync::OnceLock::new();
    WEIGHTS.get_or_init(|| vertex_extrapolation(&strang_fix3()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 3-point rule's corner weights are those of the plane through its points (5/3 and
    /// -1/3, solved by hand): exact for a linear function, not for a quadratic.
    #[test]
    fn strang_fix3_corner_weights_are_those_of_the_plane() {
        let (rule, w) = (strang_fix3(), strang_fix3_corner_weights());
        for (k, wk) in w.iter().enumerate() {
            for (j, x) in wk.iter().enumerate() {
                let by_hand = if j == k { 5.0 / 3.0 } else { -1.0 / 3.0 };
                assert!((x - by_hand).abs() <= 1e-14, "vertex {k}, point {j}: {x}");
            }
        }
        let at = |f: &dyn Fn(&[f64; 3]) -> f64, k: usize| -> f64 {
            rule.iter().zip(&w[k]).map(|((p, _), wk)| wk * f(p)).sum()
        };
        let linear = |p: &[f64; 3]| 0.3 - 1.7 * p[1] + 2.9 * p[2];
        for (k, v) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].iter().enumerate() {
            assert!((at(&linear, k) - linear(v)).abs() <= 1e-14, "vertex {k}");
        }
        // the plane through 1/36, 4/9, 1/36 at the points gives 13/18 at vertex 1, not 1
        assert!((at(&|p| p[1] * p[1], 1) - 13.0 / 18.0).abs() <= 1e-14);
    }

    /// Radon's points determine a quadratic: its extrapolation to the vertices is exact for
    /// any quadratic (checked on random ones) and off for a cubic.
    #[test]
    fn vertex_extrapolation_is_exact_for_quadratics() {
        let rule = radon7();
        let w = vertex_extrapolation(&rule);
        let mut s = 12345u64;
        let mut r = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..20 {
            let c: [f64; 6] = std::array::from_fn(|_| r());
            let q = |b: &[f64; 3]| {
                c[0] + c[1] * b[1] + c[2] * b[2] + c[3] * b[1] * b[1] + c[4] * b[1] * b[2] + c[5] * b[2] * b[2]
            };
            for (k, v) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].iter().enumerate() {
                let e: f64 = rule.iter().zip(&w[k]).map(|((b, _), wk)| wk * q(b)).sum();
                assert!((e - q(v)).abs() <= 1e-12, "{e} for {}", q(v));
            }
        }
        let cubic = |b: &[f64; 3]| b[1] * b[1] * b[1];
        let e: f64 = rule.iter().zip(&w[1]).map(|((b, _), wk)| wk * cubic(b)).sum();
        assert!((e - 1.0).abs() > 1e-3, "{e}");
    }
}
