//! Well-conditioned area routes for pairs whose double contour sum cancels heavily (a polygon
//! clipped to a sliver, or a pair far apart compared with its size). The contour sum adds
//! edge-pair terms of the size of the edges' product that cancel down to the pair's G, so its
//! rounding is relative to the terms, not to G (docs/algorithms.md §1.2). The routes add terms of
//! one sign instead:
//!
//! * far apart: the double area integral of cos cos / (pi r^2) by tensor Gauss, accepted when
//!   two orders agree to 5e-14 (the kernel is analytic and positive; every term is rounded
//!   relative to itself, also for grazing pairs where Lambert's sum still cancels);
//! * otherwise Lambert's exact point form integrated over the source by adaptive Gauss,
//!   A_s F_st = int_s F(dA_x -> t) dA_x, F(dA_x -> t) >= 0 by [`point_contour`](super::point_contour), rounded
//!   relative to itself up to the cancellation inside Lambert's sum (about the ratio of t's
//!   distance to its size). The integrand is analytic away from t, so Gauss converges
//!   geometrically on a source that does not touch the target, and refinement resolves a
//!   contact at a point;
//! * touching along one line (a shared edge, the cut of a piercing pair): the same integral
//!   in coordinates along and across the line, graded towards it and towards the contact's
//!   ends (`lambert_along_line`).
//!
//! The routes work on the clipped outlines as given, not in the caller's shifted and scaled
//! frame: a sliver's width is known to the rounding of its own coordinates, and a frame
//! change would round it again (eps / width relative: 1.9e-9 for a strip 1e-8 wide).

use super::lambert::point_contour_terms;
use crate::geometry::{
    accurate_normal, bounding_diameter, clip_to_halfspace, newell_normal, segment_distance, turn_about, turns_left,
    Vec3,
};
use crate::quadrature::adaptive::{refine_locally, split_in_four, Step};
use crate::quadrature::{gauss_legendre, triangle_rule};
use std::cell::Cell;

/// Cancellation ratio above which a contour sum is recomputed by the area route. Each term
/// of a contour sum is accurate to a few eps, so its relative error is up to ~3e-14 times the
/// ratio (random pairs against 40-digit references): 6e-11 at this bound.
pub const ILL_CONDITIONED: f64 = 2e3;

/// A_a F_ab by an area route when a contour sum over the clipped outlines `pa`, `pb`
/// (normals `na`, `nb`; in the input's coordinates) cancels by more than ILL_CONDITIONED:
/// `sum` of edge-pair terms, `mag` of their magnitudes (in any frame). The cancellation
/// counted is the larger of mag / |sum| (between terms) and (distance / size)^2 (inside each
/// term for a pair far apart compared with its size, where the inner integrals cancel like
/// that). None when the sum is well conditioned, the outlines touch along several lines or
/// nearly along one (`Contact::Other`), or the area route does not converge: the caller
/// keeps its sum. Pairs far apart go to `area_area`, the rest (and far pairs it refuses)
/// to [`lambert_over_area`] or, touching along a line and cancelling by more than
/// `line_threshold`, `lambert_along_line`, over the smaller outline. `rel_tol` is the
/// relative target of [`lambert_over_area`] (see [`area_route_tol`]).
#[allow(clippy::too_many_arguments)]
pub fn if_cancelling(
    pa: &[Vec3],
    na: Vec3,
    pb: &[Vec3],
    nb: Vec3,
    sum: f64,
    mag: f64,
    line_threshold: f64,
    rel_tol: f64,
) -> Option<f64> {
    let (da, db) = (bounding_diameter(pa), bounding_diameter(pb));
    let mean = |p: &[Vec3]| p.iter().fold(Vec3::ZERO, |s, v| s + *v) / p.len() as f64;
    let far = mean(pa).distance(mean(pb)) / da.max(db);
    let ratio = (mag / sum.abs()).max(far * far);
    if !(ratio > ILL_CONDITIONED) {
        return None;
    }
    if far * far > ILL_CONDITIONED {
        if let Some(g) = area_area(pa, na, pb, nb) {
            return Some(g);
        }
    }
    let (src, n, tgt, n_tgt) = if da <= db { (pa, na, pb, nb) } else { (pb, nb, pa, na) };
    // Lambert's integrand measures the target from the source's plane: for a sliver that
    // plane needs more than plain arithmetic gives (a tilt of 8e-13 moved F by 1e-8 for a
    // triangle 2e-5 wide). The clipped outline has the polygon's orientation.
    let exact = accurate_normal(src);
    let n = if exact.dot(n) > 0.0 { exact.normalize() } else { n };
    // (tested only here: outlines 45 sizes apart cannot touch)
    match contact(src, n, tgt) {
        Contact::Points => over_pieces(src, n, tgt, rel_tol).or_else(|| {
            // Triangles did not converge: a point contact at the end of the source's cut edge
            // (it lies in the target's plane, beside the target, where Lambert's integrand is
            // steep). The line route grades towards that edge and the contact on it.
            let snap = snap_distance(src, tgt);
            let in_plane = |x: Vec3| n_tgt.dot(x - tgt[0]).abs() <= snap;
            let (p, q) = edges(src).into_iter().find(|&(p, q)| p != q && in_plane(p) && in_plane(q))?;
            lambert_along_line(src, n, tgt, p, (q - p).normalize())
        }),
        Contact::Line(p, u) if ratio > line_threshold => lambert_along_line(src, n, tgt, p, u),
        Contact::Line(..) | Contact::Other => None,
    }
}

/// [`lambert_over_area`] of `src` towards `tgt`, over the pieces of `src` that the outline of
/// `tgt`, projected orthogonally onto the source's plane, cuts it into (both convex; else over
/// `src` whole). Where the target lies over the source close to its plane, Lambert's F rises
/// from nearly 0 beside that outline to O(1) over it within the target's height, and a cancelling
/// pair's overlap is a small part of the source: the first samples may all miss it, and the
/// rule then converges to the value without it (two triangles 1e-9 out of one plane, facing
/// each other across 7e-10 over 4.3e-4 of one's area: F 3.5e-16 for 4.2563e-4 at five of six
/// scales; tests/test_properties.py, seed 36). Cut along the outline, the overlap is a piece
/// of its own with samples in it. None when any piece does not converge. Each piece is
/// integrated to `rel_tol` of itself, the whole so to `rel_tol` of the total.
fn over_pieces(src: &[Vec3], n: Vec3, tgt: &[Vec3], rel_tol: f64) -> Option<f64> {
    // the target's outline on the source's plane, counter-clockwise about `up`
    let shadow: Vec<Vec3> = tgt.iter().map(|x| *x - n * n.dot(*x - src[0])).collect();
    let twice = newell_normal(&shadow).dot(n);
    let up = n * twice.signum();
    let size = bounding_diameter(src).max(bounding_diameter(tgt));
    let convex = |p: &[Vec3], about: Vec3| turns_left(p, turn_about(about), -1e-12);
    if !(twice.abs() > 1e-12 * size * size) || !convex(&shadow, up) || !convex(src, n) {
        return lambert_over_area(src, n, tgt, rel_tol);
    }
    // the pieces of src outside each edge's half-plane in turn, then the overlap
    let (mut rest, mut out, mut inside) = (src.to_vec(), Vec::new(), Vec::new());
    let mut total = 0.0;
    let m = shadow.len();
    for k in 0..m {
        let (a, b) = (shadow[k], shadow[(k + 1) % m]);
        if a == b {
            continue;
        }
        let inward = up.cross(b - a).normalize();
        clip_to_halfspace(&rest, a, -inward, 0.0, &mut out);
        // (a cut through a vertex leaves a piece of rounding's area: nothing to integrate)
        if out.len() >= 3 && newell_normal(&out).dot(n) > 1e-15 * size * size {
            total += lambert_over_area(&out, n, tgt, rel_tol)?;
        }
        clip_to_halfspace(&rest, a, inward, 0.0, &mut inside);
        std::mem::swap(&mut rest, &mut inside);
        if rest.len() < 3 {
            return Some(total);
        }
    }
    Some(total + lambert_over_area(&rest, n, tgt, rel_tol)?)
}

/// Rounding of an analytic sum of a pair in line contact, per unit of its cancellation: the
/// worst measured against 40-digit references (tube panels, strips, slivers sharing an edge).
const SUM_ERROR_PER_CANCELLATION: f64 = 1.4e-14;

/// Cancellation above which a pair in contact along a line takes `lambert_along_line`
/// (milliseconds a pair) rather than keeping an analytic sum (a microsecond): up to
/// SUM_ERROR_PER_CANCELLATION times this (4e-10) below it. Contour sums of nearly touching
/// edges are not that good (1.5e-5 at a gap of 1e-12), so contour passes ILL_CONDITIONED.
const LINE_ILL_CONDITIONED: f64 = 3e4;

/// The `line_threshold` of [`if_cancelling`] for an analytic sum whose caller is content with
/// relative accuracy `tol` (auto's target; 0 for the analytic method): the sum is kept while
/// its expected rounding stays below `tol` and below LINE_ILL_CONDITIONED's.
pub fn analytic_line_threshold(tol: f64) -> f64 {
    LINE_ILL_CONDITIONED.max(tol / SUM_ERROR_PER_CANCELLATION)
}

/// Relative target of the area route ([`lambert_over_area`]) for the analytic method (0:
/// to rounding).
pub const EXACT_AREA_TOL: f64 = 1e-14;

/// Share of a caller's relative accuracy `tol` that the area route of [`if_cancelling`] is
/// asked for: its estimate (the change of a split under an order-8 rule) overstates the error
/// of the refined value it returns, so a tenth leaves room.
const AREA_ROUTE_SHARE: f64 = 0.1;

/// The `rel_tol` of [`if_cancelling`] for a caller content with relative accuracy `tol` (0
/// for the analytic method, [`EXACT_AREA_TOL`]). A source piece of an obstructed pair whose
/// own unobstructed G is asked to a tenth of the pair's target cost 35 ms at 1e-14 wherever
/// that target lay: a window 0.2 m tall crossing the plane of a partition's top 0.12 m wide,
/// two pieces along that plane (G 1e-8 and 2e-9), 98 % of one pair's 72 ms in the building
/// of bench/scenes.py at obstructed_tol 1e-3.
pub fn area_route_tol(tol: f64) -> f64 {
    (AREA_ROUTE_SHARE * tol).max(EXACT_AREA_TOL)
}

/// The edges of an outline, as pairs of vertices.
fn edges(p: &[Vec3]) -> Vec<(Vec3, Vec3)> {
    (0..p.len()).map(|i| (p[i], p[(i + 1) % p.len()])).collect()
}

/// Gauss orders per direction compared by `area_area`, and the relative agreement that
/// accepts the higher one. From 45 sizes apart (where it is tried) order 5 is at the rounding
/// floor of the far-field tables (quadrature.rs: 2e-14 for any polygons from 32 apart).
const AREA_ORDERS: (usize, usize) = (5, 6);
const AREA_AGREE: f64 = 5e-14;

/// [`triangle_rule`] points and weights (order per direction) on the signed fan of `p`.
fn fan_rule(p: &[Vec3], n: Vec3, order: usize) -> Vec<(Vec3, f64)> {
    (1..p.len() - 1)
        .flat_map(|k| {
            let (a, b, c) = (p[0], p[k], p[k + 1]);
            triangle_rule(a, b, c, (b - a).cross(c - a).dot(n), order)
        })
        .collect()
}

/// A_a F_ab as the double area integral of cos_a cos_b / (pi r^2) over the (clipped) outlines
/// by tensor Gauss of AREA_ORDERS per direction: Some when they agree to AREA_AGREE (a pair
/// far apart compared with its size), None otherwise. Signed fans keep concave outlines
/// exact: the kernel stays analytic and non-negative over each outline's convex hull.
fn area_area(pa: &[Vec3], na: Vec3, pb: &[Vec3], nb: Vec3) -> Option<f64> {
    let g = |order: usize| {
        let (ra, rb) = (fan_rule(pa, na, order), fan_rule(pb, nb, order));
        let mut acc = 0.0;
        for &(x, wx) in &ra {
            let mut row = 0.0;
            for &(y, wy) in &rb {
                let d = y - x;
                let r2 = d.length_squared();
                row += wy * na.dot(d) * (-nb.dot(d)) / (r2 * r2);
            }
            acc += wx * row;
        }
        acc / std::f64::consts::PI
    };
    let (lo, hi) = (g(AREA_ORDERS.0), g(AREA_ORDERS.1));
    (hi > 0.0 && (hi - lo).abs() <= AREA_AGREE * hi).then_some(hi)
}

/// How the target comes near the source along lines: a target edge nearly collinear with a
/// source edge, their spans overlapping (within 1e-3 of the smaller outline), as a shared
/// edge, the cut edges of a piercing pair, or a gap between them.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Contact {
    /// Not along a line: apart, or at isolated points (a shared vertex, a vertex on the other's
    /// edge, crossing edges), which `adaptive_area` resolves by refining towards the point.
    Points,
    /// Every such target edge lies over one line of the source's plane (on it or above it, to
    /// SNAP): a point of the line and its unit direction.
    Line(Vec3, Vec3),
    /// Such target edges lie over several lines: no area route.
    Other,
}

/// Distance within which a vertex counts as lying on a contact line, in units of the rounding
/// of the coordinates (eps times the largest of them, or of the pair's size): a clipped
/// vertex is rounded by about that. `lambert_along_line` moves such vertices onto the line;
/// for a sliver of width w that moves F by up to (distance / w) relative, so the bound stays
/// near rounding (1e-13 of the size moved a sliver 2e-5 wide by 5e-9).
const SNAP: f64 = 32.0 * f64::EPSILON;

/// SNAP's distance for the outlines `a` and `b`.
fn snap_distance(a: &[Vec3], b: &[Vec3]) -> f64 {
    let largest = a.iter().chain(b).fold(0.0f64, |m, x| m.max(x.abs().max_element()));
    SNAP * largest.max(bounding_diameter(a)).max(bounding_diameter(b))
}

/// [`Contact`] of `src` (plane normal `n_src`) with `tgt`. The line is the longest target
/// edge near the source, projected into the source's plane: Lambert's integrand over the
/// source is singular (or, for a gap, nearly so) where the target's edges are.
fn contact(src: &[Vec3], n_src: Vec3, tgt: &[Vec3]) -> Contact {
    let tol = 1e-3 * bounding_diameter(src).min(bounding_diameter(tgt));
    let off_line = |x: Vec3, p: Vec3, u: Vec3| {
        let r = x - p;
        (r - r.dot(u) * u).length()
    };
    let mut near: Vec<(Vec3, Vec3)> = Vec::new();
    for (p, q) in edges(src) {
        let len = (q - p).length();
        let u = (q - p) / len;
        for (r, s) in edges(tgt) {
            if segment_distance(p, q, r, s) > tol || off_line(r, p, u) > tol || off_line(s, p, u) > tol {
                continue;
            }
            // collinear: do their spans along the line overlap by more than tol?
            let (t0, t1) = ((r - p).dot(u), (s - p).dot(u));
            if t0.max(t1).min(len) - t0.min(t1).max(0.0) > tol {
                near.push((r, s));
            }
        }
    }
    let Some(&(r, s)) =
        near.iter().max_by(|a, b| (a.1 - a.0).length_squared().total_cmp(&(b.1 - b.0).length_squared()))
    else {
        return Contact::Points;
    };
    let onto_plane = |x: Vec3| x - n_src * n_src.dot(x - src[0]);
    let (p, u) = (onto_plane(r), (onto_plane(s) - onto_plane(r)).normalize());
    let across = |x: Vec3, p: Vec3, u: Vec3| (x - p).dot(n_src.cross(u)).abs();
    let snap = snap_distance(src, tgt);
    // A source edge on that line (a shared edge, a cut) gives the same line from the input's
    // own vertices: measured from them, a sliver's width keeps every digit the input has
    // (exactly, for axis-aligned input).
    let (p, u) = edges(src)
        .into_iter()
        .filter(|&(a, b)| across(a, p, u) <= snap && across(b, p, u) <= snap && a != b)
        .max_by(|x, y| (x.1 - x.0).length_squared().total_cmp(&(y.1 - y.0).length_squared()))
        .map_or((p, u), |(a, b)| (a, (b - a).normalize()));
    if near.iter().all(|&(r, s)| across(r, p, u) <= snap && across(s, p, u) <= snap) {
        Contact::Line(p, u)
    } else {
        Contact::Other
    }
}

/// Gauss order per piece of `lambert_along_line`'s adaptive rules, and the most bisections
/// it spends (inner and outer together) before giving up.
const LINE_ORDER: usize = 8;
const LINE_BUDGET: usize = 40_000;
/// Orders compared on the starting pieces before any adaptive rule, and the agreement that
/// accepts the higher: a piece 3x its distance from a singularity converges like 3^-2n, so
/// the higher order's error is a small part of the difference. Measured on strips, tubes and
/// slivers against 40-digit references: orders (10, 14) at most 1e-13 relative; (8, 12) 5e-13,
/// and 5e-11 at an agreement of 1e-9, where convergence is slower than 3^-2n. (10, 14) also
/// falls back to the adaptive rules less often: a 256-panel tube took 4.9 s instead of 9.6 s.
const LINE_CHECK: (usize, usize) = (10, 14);
const LINE_AGREE: f64 = 1e-10;
/// Relative tolerance of each piece (to the integral it belongs to); up to ~100 pieces add up.
const LINE_TOL: f64 = 1e-14;
/// Rounding of Lambert's sum along the contact, in units of its magnitude: measured jitter up
/// to ~300 eps beside a target seen nearly edge-on (its edges nearly end-on).
const LINE_NOISE: f64 = 1024.0 * f64::EPSILON;
/// Ratio of the geometric grading towards the contact line (in the distance d from it) and
/// towards the contact's ends (along it, in units of d) that the adaptive rules start from.
const GRADING: f64 = 0.25;
/// Innermost level of the grading towards the line, relative to the source's extent from it.
/// Inside it J(d) = J(0) + O(d ln d), which Gauss on the one slab [0, LINE_DEPTH] takes to
/// ~LINE_DEPTH^2 ln LINE_DEPTH of the whole (1e-18 changed no result of the tests).
const LINE_DEPTH: f64 = 1e-9;

/// int over the source polygon `src` (plane normal `n_src`) of Lambert's F to `target`, for a
/// target whose edges near the source lie over the line through `p` with direction `u` in the
/// source's plane ([`Contact::Line`]: a shared edge, the cut of a piercing pair, a gap).
/// Lambert's integrand is bounded but singular all along a contact, ~ d ln d in the distance
/// d from the line (nearly so across a gap), and at the contact's ends it depends on the
/// direction to the end, so no polynomial rule on triangles converges. In the source's plane
/// with coordinates s along the line and d across it:
///   A F = int dd J(d),  J(d) = int_{chords of src at d} F(s, d) ds,
/// both by adaptive Gauss (bisect a piece until it and its halves agree). The outer rule
/// starts from slabs between the vertices' levels and levels graded geometrically towards
/// d = 0; the inner one from each chord cut at the contact's ends (the target's vertices over
/// the line) and at distances |d| / GRADING^j from them; bisection then resolves what the
/// grading does not foresee (target edges leaving an end close to the source's plane). In
/// this frame the vertices within SNAP of the line are moved onto it, so that points at any
/// small d keep their position relative to the contact. None when the rules take more than
/// LINE_BUDGET bisections.
fn lambert_along_line(src: &[Vec3], n_src: Vec3, target: &[Vec3], p: Vec3, u: Vec3) -> Option<f64> {
    let v = n_src.cross(u);
    let snap = snap_distance(src, target);
    let local = |x: Vec3| {
        let r = x - p;
        Vec3::new(r.dot(u), r.dot(v), r.dot(n_src))
    };
    // The source in its plane (s, d); the target in the frame (s, d, height).
    let sd: Vec<(f64, f64)> = src
        .iter()
        .map(|x| {
            let w = local(*x);
            (w.x, if w.y.abs() <= snap { 0.0 } else { w.y })
        })
        .collect();
    let snapped = |x: f64| if x.abs() <= snap { 0.0 } else { x };
    let tgt: Vec<Vec3> = target
        .iter()
        .map(|x| {
            let w = local(*x);
            Vec3::new(w.x, snapped(w.y), snapped(w.z))
        })
        .collect();
    // Where the target's vertices on (or over) the line are, the integrand near the line
    // changes on the scale of d.
    let ends: Vec<f64> = tgt.iter().filter(|w| w.y == 0.0).map(|w| w.x).collect();
    // Levels in d: the vertices', 0, and geometric towards 0 from either side.
    let mut levels: Vec<f64> = sd.iter().map(|w| w.1).collect();
    levels.push(0.0);
    for extent in [levels.iter().cloned().fold(0.0, f64::max), levels.iter().cloned().fold(0.0, f64::min)] {
        let mut l = extent * GRADING;
        while l.abs() > extent.abs() * LINE_DEPTH {
            levels.push(l);
            l *= GRADING;
        }
    }
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    // The pieces of the chords of the source at d, cut as above.
    let pieces_at = |d: f64| -> Vec<(f64, f64)> {
        let mut chords = Vec::new();
        for k in 0..sd.len() {
            let (a, b) = (sd[k], sd[(k + 1) % sd.len()]);
            // no vertex lies at a Gauss node's d
            if (a.1 > d) != (b.1 > d) {
                chords.push(a.0 + (d - a.1) / (b.1 - a.1) * (b.0 - a.0));
            }
        }
        chords.sort_by(f64::total_cmp);
        let mut cuts = Vec::new();
        for c in chords.chunks_exact(2) {
            let (a, b) = (c[0], c[1]);
            cuts.extend([a, b]);
            for &e in &ends {
                let mut r = 0.0;
                while e - r > a || e + r < b {
                    cuts.extend([e - r, e + r].into_iter().filter(|&x| x > a && x < b));
                    r = if r == 0.0 { d.abs() } else { r / GRADING };
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        // pieces between chords (outside the source) are skipped by the parity of the cut
        let inside = |x: f64| chords.partition_point(|&c| c <= x) % 2 == 1;
        cuts.windows(2).map(|w| (w[0], w[1])).filter(|w| inside(0.5 * (w.0 + w.1))).collect()
    };
    let lambert = |s: f64, d: f64| point_contour_terms(Vec3::new(s, d, 0.0), Vec3::Z, &tgt);
    let slabs: Vec<(f64, f64)> = levels.windows(2).map(|w| (w[0], w[1])).collect();
    // Estimates of the whole on the starting pieces, by Gauss of an order per piece.
    let estimate_by = |order: usize| -> f64 {
        let rule = gauss_legendre(order);
        let gauss = |a: f64, b: f64, g: &mut dyn FnMut(f64) -> f64| {
            (b - a) * rule.iter().map(|&(x, w)| w * g(a + (b - a) * x)).sum::<f64>()
        };
        slabs
            .iter()
            .map(|&(a, b)| {
                gauss(a, b, &mut |d| pieces_at(d).iter().map(|&(s0, s1)| gauss(s0, s1, &mut |s| lambert(s, d).0)).sum())
            })
            .sum()
    };
    let (lower, estimate) = (estimate_by(LINE_CHECK.0), estimate_by(LINE_CHECK.1));
    if !(estimate > 0.0) {
        return None;
    }
    // Where the grading resolves the integrand (most contacts) the orders agree, and the
    // higher one's own error is orders of magnitude below the difference: done at about a
    // third of the adaptive rules' cost.
    if (estimate - lower).abs() <= LINE_AGREE * estimate {
        return Some(estimate);
    }
    let rule = gauss_legendre(LINE_ORDER);
    let budget = Cell::new(LINE_BUDGET);
    // J(d) at a node of an outer piece of width h: its error enters the whole times h at most,
    // so its tolerance is LINE_TOL * estimate / h or relative to J itself, whichever is looser
    // (near the line, where Lambert's sum is rounding noise, only the first is attainable).
    // An inner rule that gives up makes the outer one give up: NaN is not finite.
    let chord_integral = |d: f64, h: f64| -> (f64, f64) {
        adaptive_gauss(&pieces_at(d), rule, &budget, LINE_TOL * estimate / h, |s, _| lambert(s, d))
            .unwrap_or((f64::NAN, f64::NAN))
    };
    let (g, _) = adaptive_gauss(&slabs, rule, &budget, LINE_TOL * estimate, chord_integral)?;
    (g > 0.0).then_some(g)
}

/// int of `g(x, width of x's piece)` (returning the integrand and the magnitude its rounding
/// scales with) over the union of `pieces`, by `rule` (Gauss on [0, 1]) on each piece,
/// bisected until a piece's value and the sum of its halves' differ by less than `floor`,
/// LINE_TOL times the first estimate of the whole (the integrand is non-negative), or the
/// rounding of the integrand (LINE_NOISE times the integrated magnitude). Returns the integral
/// and the integrated magnitude; None when more than `budget` bisections are needed or the
/// integrand is not finite.
fn adaptive_gauss(
    pieces: &[(f64, f64)],
    rule: &[(f64, f64)],
    budget: &Cell<usize>,
    floor: f64,
    mut g: impl FnMut(f64, f64) -> (f64, f64),
) -> Option<(f64, f64)> {
    let mut gauss = |a: f64, b: f64| {
        rule.iter().fold((0.0, 0.0), |(v, m), &(x, w)| {
            let (fv, fm) = g(a + (b - a) * x, b - a);
            (v + (b - a) * w * fv, m + (b - a) * w * fm)
        })
    };
    let work: Vec<(f64, f64, (f64, f64))> = pieces.iter().map(|&(a, b)| (a, b, gauss(a, b))).collect();
    let first: f64 = work.iter().map(|w| w.2 .0).sum();
    if !first.is_finite() {
        return None;
    }
    let (mut sum, mut mag) = (0.0, 0.0);
    let finished = refine_locally(work, |(a, b, whole)| {
        let m = 0.5 * (a + b);
        let (l, r) = (gauss(a, m), gauss(m, b));
        let (parts, parts_mag) = (l.0 + r.0, l.1 + r.1);
        if !parts.is_finite() {
            return Step::GiveUp;
        }
        if (parts - whole.0).abs() <= (LINE_TOL * first.abs()).max(floor).max(LINE_NOISE * parts_mag)
            || !(a < m && m < b)
        {
            sum += parts;
            mag += parts_mag;
            return Step::Done;
        }
        if budget.get() == 0 {
            return Step::GiveUp;
        }
        budget.set(budget.get() - 1);
        Step::Split([(a, m, l), (m, b, r)])
    });
    finished.then_some((sum, mag))
}

/// Order per direction of the triangle rule in `adaptive_area`.
const ORDER: usize = 8;
/// Rounding of an integrand (a Lambert sum: a few eps per term), in units of its magnitude.
const NOISE_EPS: f64 = 64.0 * f64::EPSILON;
/// Most triangles refined before giving up (each costs 5 ORDER^2 point evaluations).
const MAX_TRIANGLES: usize = 400;

/// int over the source polygon `src` (plane normal `n_src`, vertices in order about it) of
/// Lambert's F to the contour `target`, which must lie in the front half-space of every point
/// of `src` (a clipped pair), by `adaptive_area`.
pub fn lambert_over_area(src: &[Vec3], n_src: Vec3, target: &[Vec3], rel_tol: f64) -> Option<f64> {
    adaptive_area(src, n_src, |x| point_contour_terms(x, n_src, target), rel_tol)
}

/// F(dA at p, unit normal n -> polygon `poly`, plane normal `n_poly`) as the area integral
///   (h / pi) int n.(y - p) / |y - p|^4 dA_y,  h = n_poly.(p - y) (the same for every y),
/// by `adaptive_area`: the route for points near the polygon's plane (beside the polygon)
/// or far from it, where Lambert's contour sum cancels. `poly` must lie in p's front
/// half-space (clipped); None as for `adaptive_area`.
pub fn point_over_area(p: Vec3, n: Vec3, poly: &[Vec3], n_poly: Vec3, rel_tol: f64) -> Option<f64> {
    let h = n_poly.dot(p - poly[0]);
    if !(h > 0.0) {
        return None;
    }
    let g = adaptive_area(
        poly,
        n_poly,
        |y| {
            let d = y - p;
            let r2 = d.length_squared();
            let v = n.dot(d).max(0.0) / (r2 * r2);
            (v, v)
        },
        rel_tol,
    )?;
    Some(h * g / std::f64::consts::PI)
}

/// int over the polygon `src` (plane normal `n_src`, vertices in order about it) of `f`,
/// which returns the integrand and the magnitude its rounding scales with, by [`triangle_rule`]
/// (ORDER per direction) on a signed fan, each triangle split in four until the split
/// changes it by less than `rel_tol` times the total (by its share of the area) or by the
/// rounding of `f` (NOISE_EPS times the integrated magnitude). The integrand must be analytic
/// on the source's convex hull; None when the total is not positive or convergence takes
/// more than MAX_TRIANGLES splits (a singularity on or near the source).
fn adaptive_area(src: &[Vec3], n_src: Vec3, f: impl Fn(Vec3) -> (f64, f64), rel_tol: f64) -> Option<f64> {
    // [`triangle_rule`] on a triangle with twice its signed area `twice` (about n_src), with
    // the same rule applied to the magnitudes. Children get a quarter of their parent's
    // `twice`, exactly: recomputed from the vertices, a sliver's area carries rounding
    // ~ eps times its aspect ratio, which would pose as quadrature error.
    let tri = |t: &[Vec3; 3], twice: f64| -> (f64, f64) {
        triangle_rule(t[0], t[1], t[2], twice, ORDER).fold((0.0, 0.0), |(acc, mag), (x, w)| {
            let (v, m) = f(x);
            (acc + w * v, mag + w.abs() * m)
        })
    };
    // Signed fan: exact for concave outlines too, the integrand being analytic on the hull.
    let work: Vec<([Vec3; 3], f64, f64)> = (1..src.len().saturating_sub(1))
        .map(|k| {
            let t = [src[0], src[k], src[k + 1]];
            let twice = (t[1] - t[0]).cross(t[2] - t[0]).dot(n_src);
            (t, twice, tri(&t, twice).0)
        })
        .collect();
    let area: f64 = work.iter().map(|w| 0.5 * w.1.abs()).sum();
    let total: f64 = work.iter().map(|w| w.2).sum();
    if !(total > 0.0) || !(area > 0.0) {
        return None;
    }
    // Near a point where the integrand jumps (a contact point) a split's change only shrinks
    // with the area, never relative to it: changes below this are negligible, and the
    // MAX_TRIANGLES splits together stay below rel_tol of the total.
    let negligible = rel_tol * total / (4 * MAX_TRIANGLES) as f64;
    let mut sum = 0.0;
    let mut refined = 0;
    let finished = refine_locally(work, |(t, twice, whole)| {
        let kids = split_in_four(&t);
        let vals = kids.map(|k| tri(&k, 0.25 * twice));
        let parts: f64 = vals.iter().map(|v| v.0).sum();
        let noise: f64 = vals.iter().map(|v| v.1).sum::<f64>() * NOISE_EPS;
        let share = 0.5 * twice.abs() / area;
        // Converged, or changing only by the rounding of the integrand (refining further
        // cannot tell more), or by a negligible amount.
        if (parts - whole).abs() <= (rel_tol * total * share).max(noise).max(negligible) {
            sum += parts;
            return Step::Done;
        }
        refined += 1;
        if refined > MAX_TRIANGLES {
            return Step::GiveUp;
        }
        Step::Split([0, 1, 2, 3].map(|c| (kids[c], 0.25 * twice, vals[c].0)))
    });
    (finished && sum > 0.0).then_some(sum)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Polygon;
    use std::f64::consts::PI;

    /// Parallel, directly opposed squares X x X at gap 1: Hottel's closed form evaluated at 30
    /// digits (mpmath; the 15-digit table value for X = 0.1 is off by 3.6e-15).
    #[test]
    fn opposed_squares_match_the_closed_form() {
        for (x, want) in [(0.1, 0.003162056838757602), (0.4, 0.0461374167448751), (1.0, 0.1998248956983874)] {
            let src = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(x, 0.0, 0.0), Vec3::new(x, x, 0.0), Vec3::new(0.0, x, 0.0)];
            let tgt = [Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, x, 1.0), Vec3::new(x, x, 1.0), Vec3::new(x, 0.0, 1.0)];
            let got = lambert_over_area(&src, Vec3::Z, &tgt, 1e-14).unwrap() / (x * x);
            let tol = if x == 1.0 { 1e-9 } else { 1e-13 };
            assert!((got - want).abs() <= tol * want, "{x}: {got} {want}");
        }
    }

    /// Regular m-gon of unit circumradius in the plane z, counter-clockwise about +z (or
    /// about -z with `flip`), and its area.
    fn ring(m: usize, z: f64, flip: bool) -> (Vec<Vec3>, f64) {
        let mut v: Vec<Vec3> = (0..m)
            .map(|k| {
                let t = 2.0 * PI * k as f64 / m as f64;
                Vec3::new(t.cos(), t.sin(), z)
            })
            .collect();
        if flip {
            v.reverse();
        }
        (v, 0.5 * m as f64 * (2.0 * PI / m as f64).sin())
    }

    /// F between coaxial disks of area `area` at distance d (Howell C-41) in its
    /// cancellation-free form: X = 2 + d^2 / r^2, F = 2 / (X + sqrt(X^2 - 4)). Regular m-gons
    /// of that area differ by their second moments, ~(2 pi / m)^2 / 6, which moves F by that
    /// times (r / d)^2: below 1e-8 for the cases here.
    fn equal_disks(area: f64, d: f64) -> f64 {
        let x = 2.0 + d * d * PI / area;
        2.0 / (x + (x * x - 4.0).sqrt())
    }

    /// Far apart, against the coaxial disk-to-disk closed form.
    #[test]
    fn far_coaxial_regular_polygons_approach_the_disk_closed_form() {
        for d in [100.0, 1e3, 1e5] {
            let ((src, area), (tgt, _)) = (ring(256, 0.0, false), ring(256, d, true));
            let got = lambert_over_area(&src, Vec3::Z, &tgt, 1e-14).unwrap() / area;
            let want = equal_disks(area, d);
            assert!((got - want).abs() <= 1e-9 * want, "{d}: {got} {want}");
        }
    }

    #[test]
    fn area_area_far_apart_and_refused_near() {
        for d in [1e2, 1e4, 1e6] {
            let ((src, area), (tgt, _)) = (ring(64, 0.0, false), ring(64, d, true));
            let got = area_area(&src, Vec3::Z, &tgt, -Vec3::Z).expect("converged") / area;
            let want = equal_disks(area, d);
            assert!((got - want).abs() <= 1e-8 * want, "{d}: {got} {want}");
        }
        // one radius apart the two orders differ: refused
        assert!(area_area(&ring(64, 0.0, false).0, Vec3::Z, &ring(64, 1.0, true).0, -Vec3::Z).is_none());
    }

    #[test]
    fn line_contacts_are_told_from_point_contacts() {
        let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        let floor = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.0, 1.0, 0.0), v(0.0, 1.0, 0.0)];
        // a wall on the floor's edge y = 0 (shared edge), on part of it, and one touching
        // the floor's corner only
        let wall = [v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0), v(1.0, 0.0, 1.0), v(1.0, 0.0, 0.0)];
        let part = [v(0.2, 0.0, 0.0), v(0.2, 0.0, 1.0), v(0.6, 0.0, 1.0), v(0.6, 0.0, 0.0)];
        let corner = [v(1.0, 1.0, 0.0), v(1.0, 1.0, 1.0), v(2.0, 1.0, 1.0), v(2.0, 1.0, 0.0)];
        let touching = |a: &[Vec3], b: &[Vec3]| contact(a, Vec3::Z, b) != Contact::Points;
        assert!(touching(&floor, &wall));
        assert!(touching(&floor, &part));
        assert!(!touching(&floor, &corner));
        // collinear edges that only meet end to end are a point contact
        let beyond = [v(1.0, 0.0, 0.0), v(1.0, 0.0, 1.0), v(2.0, 0.0, 1.0), v(2.0, 0.0, 0.0)];
        assert!(!touching(&floor, &beyond));
        // the line runs through the source's edge on it (the first argument's)
        assert_eq!(contact(&wall, Vec3::Y, &floor), Contact::Line(v(1.0, 0.0, 0.0), -Vec3::X));
        // a strip 1e-6 tall on the floor's edge: its top edge is near the contact line too, as
        // a source edge beside the line, or as a target edge over it
        let strip = [v(0.0, 0.0, 0.0), v(0.0, 0.0, 1e-6), v(1.0, 0.0, 1e-6), v(1.0, 0.0, 0.0)];
        assert_eq!(contact(&strip, Vec3::Y, &floor), Contact::Line(v(1.0, 0.0, 0.0), -Vec3::X));
        assert!(matches!(contact(&floor, Vec3::Z, &strip), Contact::Line(..)));
        // a wall 1e-6 above the floor's edge (a gap): the line is the floor's edge, in the
        // wall's plane below it
        let gap = wall.map(|x| x + v(0.0, 0.0, 1e-6));
        assert_eq!(contact(&gap, Vec3::Y, &floor), Contact::Line(v(0.0, 0.0, 0.0), Vec3::X));
        // a wall turned by 1e-6 about the floor's corner: the line follows the wall's bottom
        // edge (where the integrand over the floor is singular), not the floor's edge
        let turned = [v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0), v(1.0, 1e-6, 1.0), v(1.0, 1e-6, 0.0)];
        assert!(matches!(contact(&floor, Vec3::Z, &turned), Contact::Line(_, u) if (u - Vec3::X).length() > 1e-7));
        // along two lines (an L-shaped wall on two edges of the floor): Other
        let two = [
            v(0.0, 1.0, 0.0),
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(1.0, 0.0, 1.0),
            v(0.0, 0.0, 1.0),
            v(0.0, 1.0, 1.0),
        ];
        assert_eq!(contact(&floor, Vec3::Z, &two), Contact::Other);
    }

    /// The line route against Howell C-14 (perpendicular rectangles sharing an edge, in
    /// closed_forms.rs), for a wall of height h on the floor's edge, from either side: the
    /// integrand is singular along the whole source edge on the contact, and at its ends the
    /// target's side edges leave the contact in the source's plane.
    #[test]
    fn line_route_matches_perpendicular_rectangles_sharing_an_edge() {
        let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        let floor = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.0, 1.0, 0.0), v(0.0, 1.0, 0.0)];
        for h in [1.0, 0.1, 1e-2] {
            let wall = [v(0.0, 0.0, 0.0), v(0.0, 0.0, h), v(1.0, 0.0, h), v(1.0, 0.0, 0.0)];
            let want = super::super::closed_forms::perpendicular_rectangles(1.0, 1.0, h).unwrap();
            let g = lambert_along_line(&floor, Vec3::Z, &wall, v(0.0, 0.0, 0.0), Vec3::X).unwrap();
            assert!((g - want).abs() <= 1e-13 * want, "floor to wall {h}: {g} {want}");
            let g = lambert_along_line(&wall, Vec3::Y, &floor, v(1.0, 0.0, 0.0), -Vec3::X).unwrap();
            assert!((g - want).abs() <= 1e-13 * want, "wall to floor {h}: {g} {want}");
        }
    }

    /// Additivity along and across the contact: a strip at 30 degrees on the floor's edge
    /// y = 0.5, leaning over it, cut in two along its length, and the floor cut in two across
    /// the contact line (which then ends inside the strip's contact). Each part goes through
    /// the line route.
    #[test]
    fn line_route_is_additive() {
        let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        let (c, s) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
        let w = 1e-5;
        let n = v(0.0, -s, c); // the strip's normal, facing the floor
        let strip =
            |x0: f64, x1: f64| [v(x0, 0.5, 0.0), v(x1, 0.5, 0.0), v(x1, 0.5 + w * c, w * s), v(x0, 0.5 + w * c, w * s)];
        let floor = |x0: f64, x1: f64| [v(x0, 0.0, 0.0), v(x1, 0.0, 0.0), v(x1, 0.5, 0.0), v(x0, 0.5, 0.0)];
        let g = |src: &[Vec3], tgt: &[Vec3]| {
            let Contact::Line(p, u) = contact(src, n, tgt) else { panic!("line contact expected") };
            lambert_along_line(src, n, tgt, p, u).unwrap()
        };
        let whole = g(&strip(0.2, 0.8), &floor(0.0, 1.0));
        let along = g(&strip(0.2, 0.45), &floor(0.0, 1.0)) + g(&strip(0.45, 0.8), &floor(0.0, 1.0));
        let across = g(&strip(0.2, 0.8), &floor(0.0, 0.6)) + g(&strip(0.2, 0.8), &floor(0.6, 1.0));
        for (name, parts) in [("along", along), ("across", across)] {
            assert!((parts - whole).abs() <= 1e-13 * whole, "{name}: {parts} {whole}");
        }
    }

    #[test]
    fn triangles_on_a_line_contact_stop_short() {
        // Perpendicular unit squares sharing an edge: F = 0.2000438 (Howell C-14), the
        // integrand is singular along the shared edge. Refinement towards the whole edge stops
        // at the negligible-change floor, 3e-10 off: why line contacts take lambert_along_line
        // (line_route_matches_perpendicular_rectangles_sharing_an_edge: 1e-13).
        let src =
            [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let tgt =
            [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 0.0)];
        let g = lambert_over_area(&src, Vec3::Z, &tgt, 1e-14).expect("converged");
        assert!((g - 0.200043776376147).abs() < 1e-9, "{g}");
    }

    /// Two triangles 1e-9 out of one plane (the first's third vertex raised 1e-9) face each
    /// other across at most 7.4e-10 where their outlines overlap, 4.2563e-4 of the first's
    /// area: across so thin a gap they see each other wholly there and hardly at all beside it,
    /// so F is the overlap's share of the area up to the gap over its size (the overlap by
    /// 2-D clipping below, 4.256309646526581e-4; a 40-digit contour integral gives
    /// 4.25630964653407e-4). The contour sum cancels 1e4-fold; the area route's first samples
    /// missed the overlap at every scale but 1 (F 2e-16 .. 4e-16).
    #[test]
    fn a_small_overlap_across_a_thin_gap_is_not_missed() {
        let a = [[0.0, 0.0, 0.0], [-0.3125, 0.875, 0.0], [-0.0703125, 0.25, 1e-9]];
        let b = [[0.25, 0.0, 0.0], [0.5, 0.0, 0.0], [-0.09765625, 0.3125, 0.0]];
        for s in [1e-9, 1e-6, 1e-3, 0.1, 1.0, 3.0, 1e3, 1e6] {
            let poly = |p: &[[f64; 3]; 3]| Polygon::new(p.iter().map(|v| Vec3::from_array(*v) * s).collect()).unwrap();
            let (pa, pb) = (poly(&a), poly(&b));
            let f = crate::unobstructed::analytic::polygon_pair(&pa, &pb) / pa.area();
            assert!((f - 4.25630964653407e-4).abs() <= 1e-12, "scale {s}: F {f:e}");
        }
    }
}
