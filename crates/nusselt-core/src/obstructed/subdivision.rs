//! dA -> A_j by subdivision of the receiver: uniform (`subdivision`) and adaptive
//! (`adaptive`), with 0/1 visibility per piece.

use super::rules::centroid3;
use super::sampled::{cut_at_blocker_planes, per_direction};
use super::VisOptions;
use crate::geometry::{Polygon, Vec3};
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
pub(super) fn adaptive_point(x: Vec3, n: Vec3, b: &Polygon, visible: &dyn Fn(Vec3) -> bool, o: &VisOptions) -> f64 {
    // 2 levels (16 pieces per triangle, 7 samples each) find shadows of blockers down to about
    // a tenth of the receiver (16 blockers of 0.1 between unit plates: 9e-4 at tol 1e-4);
    // 4 levels cost 2.5x as much for the same accuracy on bench/methods.py's pairs.
    const MIN_DEPTH: usize = 2;
    fn rec(x: Vec3, n: Vec3, t: [Vec3; 3], depth: usize, visible: &dyn Fn(Vec3) -> bool, o: &VisOptions) -> f64 {
        let f = analytic::point_polygon(x, n, &t);
        if f <= 0.0 {
            return 0.0;
        }
        let c = centroid3(&t);
        let m01 = 0.5 * (t[0] + t[1]);
        let m12 = 0.5 * (t[1] + t[2]);
        let m20 = 0.5 * (t[2] + t[0]);
        // a ray to an exact shared edge is ambiguous: pull the boundary samples inwards
        let inward = |y: Vec3| y + 0.01 * (c - y);
        let samples = [c, inward(t[0]), inward(t[1]), inward(t[2]), inward(m01), inward(m12), inward(m20)];
        let seen = samples.iter().filter(|&&y| visible(y)).count();
        let uniform = seen == 0 || seen == samples.len();
        let done = if uniform { depth >= MIN_DEPTH.min(o.max_depth) } else { depth >= o.max_depth };
        if done || f <= o.tol {
            return f * seen as f64 / samples.len() as f64;
        }
        [[t[0], m01, m20], [m01, t[1], m12], [m20, m12, t[2]], [m01, m12, m20]]
            .into_iter()
            .map(|s| rec(x, n, s, depth + 1, visible, o))
            .sum()
    }
    let v = b.vertices();
    b.triangulate().iter().map(|t| rec(x, n, [v[t[0]], v[t[1]], v[t[2]]], 0, visible, o)).sum()
}
