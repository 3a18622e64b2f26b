//! dA -> A_j by subdivision of the receiver: uniform (`subdivision`) and adaptive
//! (`adaptive`), with 0/1 visibility per piece.

use super::rules::centroid3;
use super::sampled::{cut_at_blocker_planes, per_direction};
use super::AdaptiveOptions;
use crate::geometry::{Polygon, Vec3};
use crate::quadrature::adaptive::{refine_locally, split_in_four, Step};
use crate::unobstructed::analytic;

/// The receiver's triangles, each split uniformly into d^2 sub-triangles.
pub(super) fn subdivide(b: &Polygon, d: usize) -> Vec<[Vec3; 3]> {
    let v = b.vertices();
    let mut out = Vec::new();
    for t in b.triangulate() {
        let (p0, p1, p2) = (v[t[0]], v[t[1]], v[t[2]]);
        let at = |i: usize, j: usize| p0 + (p1 - p0) * (i as f64 / d as f64) + (p2 - p0) * (j as f64 / d as f64);
        for i in 0..d {
            for j in 0..d - i {
                out.push([at(i, j), at(i + 1, j), at(i, j + 1)]);
                if i + j + 1 < d {
                    out.push([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
                }
            }
        }
    }
    out
}

/// The receiver's triangles for `subdivision` and the point form of `quadrature`: `b` cut
/// along the planes of the blockers through it (see [`cut_at_blocker_planes`]), each piece
/// split into about d^2 times its share of the area, so that a shadow edge at the foot of a
/// blocker standing on b runs along the pieces instead of across them (a partition next to
/// a point: 1.8e-3 from 0/1 visibility of pieces cut by the shadow's edge).
pub(super) fn subdivide_at_blockers(b: &Polygon, blockers: &[&Polygon], d: usize) -> Vec<[Vec3; 3]> {
    let parts = cut_at_blocker_planes(b, blockers);
    if parts.len() == 1 {
        return subdivide(b, d);
    }
    parts.iter().flat_map(|q| subdivide(q, per_direction(d, q.area() / b.area()).max(1))).collect()
}

/// Uniform subdivision: sum over pieces of Lambert's exact F to the piece times the piece's
/// visibility at its centre (Wallace et al.'s better leaf estimator, docs/algorithms.md §6.1).
pub(super) fn uniform_point(x: Vec3, n: Vec3, pieces: &[[Vec3; 3]], visible: &dyn Fn(Vec3) -> bool) -> f64 {
    pieces
        .iter()
        .map(|t| {
            let f = analytic::point_polygon(x, n, t);
            if f > 0.0 && visible(centroid3(t)) {
                f
            } else {
                0.0
            }
        })
        .sum()
}

/// Adaptive subdivision: a piece is split in four while visibility differs among its seven
/// samples (corners pulled 1 % inwards, edge midpoints, centre) and its exact unobstructed
/// contribution (Lambert) exceeds `tol`, down to `max_depth`; there the visible fraction of
/// the samples weights it. Pieces whose samples agree are still refined to `MIN_DEPTH`
/// levels, so that a shadow smaller than a first-level piece is not missed between samples.
pub(super) fn adaptive_point(
    x: Vec3,
    n: Vec3,
    b: &Polygon,
    visible: &dyn Fn(Vec3) -> bool,
    o: &AdaptiveOptions,
) -> f64 {
    // 2 levels (16 pieces per triangle, 7 samples each) find shadows of blockers down to about
    // a tenth of the receiver (16 blockers of 0.1 between unit plates: 9e-4 at tol 1e-4);
    // 4 levels cost 2.5x as much for the same accuracy on bench/methods.py's pairs.
    const MIN_DEPTH: usize = 2;
    let v = b.vertices();
    let start: Vec<([Vec3; 3], usize)> = b.triangulate().iter().map(|t| ([v[t[0]], v[t[1]], v[t[2]]], 0)).collect();
    let mut sum = 0.0;
    refine_locally(start, |(t, depth)| {
        let f = analytic::point_polygon(x, n, &t);
        if f <= 0.0 {
            return Step::Done;
        }
        let c = centroid3(&t);
        // a ray to an exact shared edge is ambiguous: pull the boundary samples inwards
        let inward = |y: Vec3| y + 0.01 * (c - y);
        let (m01, m12, m20) = (0.5 * (t[0] + t[1]), 0.5 * (t[1] + t[2]), 0.5 * (t[2] + t[0]));
        let samples = [c, inward(t[0]), inward(t[1]), inward(t[2]), inward(m01), inward(m12), inward(m20)];
        let seen = samples.iter().filter(|&&y| visible(y)).count();
        let uniform = seen == 0 || seen == samples.len();
        let done = if uniform { depth >= MIN_DEPTH.min(o.max_depth) } else { depth >= o.max_depth };
        if done || f <= o.tol {
            sum += f * seen as f64 / samples.len() as f64;
            return Step::Done;
        }
        Step::Split(split_in_four(&t).map(|k| (k, depth + 1)))
    });
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plate(z: f64) -> Polygon {
        let (a, b, c, d) =
            (Vec3::new(0.0, 0.0, z), Vec3::new(1.0, 0.0, z), Vec3::new(1.0, 1.0, z), Vec3::new(0.0, 1.0, z));
        Polygon::new(vec![a, d, c, b]).unwrap()
    }

    #[test]
    fn adaptive_point_adds_its_pieces_to_the_exact_value() {
        // Everything visible: the pieces' exact Lambert values add up to the whole receiver's
        // (additivity), whatever the refinement; half hidden by the plane y = 0.5 (an edge the
        // pieces resolve to max_depth): within the depth's strip width of the exact half.
        let (x, n, b) = (Vec3::new(0.3, 0.4, 0.0), Vec3::Z, plate(1.0));
        let o = AdaptiveOptions { tol: 1e-9, max_depth: 10, ..Default::default() };
        let whole = analytic::point_polygon(x, n, b.vertices());
        let all = adaptive_point(x, n, &b, &|_| true, &o);
        assert!((all - whole).abs() <= 1e-14 * whole, "{all} vs {whole}");
        let half = adaptive_point(x, n, &b, &|y| y.y < 0.5, &o);
        let lower = plate(1.0).vertices().iter().map(|v| Vec3::new(v.x, v.y.min(0.5), v.z)).collect::<Vec<_>>();
        let exact = analytic::point_polygon(x, n, &lower);
        // pieces at depth 10 are 2^-10 wide; the ones the edge cuts count their visible
        // samples' fraction, each off by at most its whole F (< 1e-6 of F along the edge)
        assert!((half - exact).abs() <= 2e-3 * exact, "{half} vs {exact}");
    }
}
