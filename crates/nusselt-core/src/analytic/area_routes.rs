//! Well-conditioned area routes for pairs whose double contour sum cancels heavily (a polygon
//! clipped to a sliver, or a pair far apart compared with its size). The contour sum adds
//! edge-pair terms of the size of the edges' product that cancel down to the pair's G, so its
//! rounding is relative to the terms, not to G (algorithms.md 1.2). The routes add terms of
//! one sign instead:
//!
//! * far apart: the double area integral of cos cos / (pi r^2) by tensor Gauss, accepted when
//!   two orders agree to 5e-14 (the kernel is analytic and positive; every term is rounded
//!   relative to itself, also for grazing pairs where Lambert's sum still cancels);
//! * otherwise Lambert's exact point form integrated over the source by adaptive Gauss,
//!   A_s F_st = int_s F(dA_x -> t) dA_x, F(dA_x -> t) >= 0 by [`point_contour`], rounded
//!   relative to itself up to the cancellation inside Lambert's sum (about the ratio of t's
//!   distance to its size). The integrand is analytic away from t, so Gauss converges
//!   geometrically on a source that does not touch the target, and refinement resolves a
//!   contact at a point; a pair touching along a line is refused and the caller keeps its sum.

use super::lambert::point_contour_terms;
use crate::geometry::{bounding_diameter, segment_distance, Vec3};
use crate::quadrature::triangle_rule;

/// Cancellation ratio above which a contour sum is recomputed by the area route. Each term
/// of a contour sum is accurate to a few eps, so its relative error is up to ~3e-14 times the
/// ratio (random pairs against 40-digit references): 6e-11 at this bound.
const ILL_CONDITIONED: f64 = 2e3;

/// A_a F_ab by an area route when a contour sum over the clipped outlines `pa`, `pb`
/// (normals `na`, `nb`) cancels by more than ILL_CONDITIONED: `sum` of edge-pair terms, `mag`
/// of their magnitudes. The cancellation counted is the larger of mag / |sum| (between terms)
/// and (distance / size)^2 (inside each term for a pair far apart compared with its size,
/// where the inner integrals cancel like that). None when the sum is well conditioned, the
/// outlines touch along a line (Lambert's integrand is singular all along it), or the area route
/// does not converge: the caller keeps its sum. Pairs far apart go to [`area_area`], the
/// rest (and far pairs it refuses) to [`lambert_over_area`] over the smaller outline.
pub fn if_cancelling(pa: &[Vec3], na: Vec3, pb: &[Vec3], nb: Vec3, sum: f64, mag: f64) -> Option<f64> {
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
    // (tested only here: outlines 45 sizes apart cannot touch)
    if touching(pa, pb) {
        return None;
    }
    let (src, n, tgt) = if da <= db { (pa, na, pb) } else { (pb, nb, pa) };
    lambert_over_area(src, n, tgt, 1e-14)
}

/// Gauss orders per direction compared by [`area_area`], and the relative agreement that
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

/// Whether the two outlines meet along a line: a pair of edges nearly collinear and
/// overlapping (within 1e-3 of the smaller outline), as the cut edges of a piercing pair or
/// a shared edge. Lambert's integrand is singular all along such a contact and the area
/// route would not converge; a contact at isolated points (a shared vertex, a vertex on
/// the other's edge, crossing edges) it resolves by refining towards the point.
fn touching(pa: &[Vec3], pb: &[Vec3]) -> bool {
    let tol = 1e-3 * bounding_diameter(pa).min(bounding_diameter(pb));
    let edges = |p: &[Vec3]| (0..p.len()).map(move |i| (p[i], p[(i + 1) % p.len()])).collect::<Vec<_>>();
    let (ea, eb) = (edges(pa), edges(pb));
    let off_line = |x: Vec3, p: Vec3, u: Vec3| {
        let r = x - p;
        (r - r.dot(u) * u).length()
    };
    ea.iter().any(|&(p, q)| {
        let len = (q - p).length();
        let u = (q - p) / len;
        eb.iter().any(|&(r, s)| {
            if segment_distance(p, q, r, s) > tol || off_line(r, p, u) > tol || off_line(s, p, u) > tol {
                return false;
            }
            // collinear: do their spans along the line overlap by more than tol?
            let (t0, t1) = ((r - p).dot(u), (s - p).dot(u));
            t0.max(t1).min(len) - t0.min(t1).max(0.0) > tol
        })
    })
}

/// Order per direction of the triangle rule in [`adaptive_area`].
const ORDER: usize = 8;
/// Rounding of an integrand (a Lambert sum: a few eps per term), in units of its magnitude.
const NOISE_EPS: f64 = 64.0 * f64::EPSILON;
/// Most triangles refined before giving up (each costs 5 ORDER^2 point evaluations).
const MAX_TRIANGLES: usize = 400;

/// int over the source polygon `src` (plane normal `n_src`, vertices in order about it) of
/// Lambert's F to the contour `target`, which must lie in the front half-space of every point
/// of `src` (a clipped pair), by [`adaptive_area`].
pub fn lambert_over_area(src: &[Vec3], n_src: Vec3, target: &[Vec3], rel_tol: f64) -> Option<f64> {
    adaptive_area(src, n_src, |x| point_contour_terms(x, n_src, target), rel_tol)
}

/// F(dA at p, unit normal n -> polygon `poly`, plane normal `n_poly`) as the area integral
///   (h / pi) int n.(y - p) / |y - p|^4 dA_y,  h = n_poly.(p - y) (the same for every y),
/// by [`adaptive_area`]: the route for points near the polygon's plane (beside the polygon)
/// or far from it, where Lambert's contour sum cancels. `poly` must lie in p's front
/// half-space (clipped); None as for [`adaptive_area`].
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
    let split = |t: &[Vec3; 3]| -> [[Vec3; 3]; 4] {
        let (ab, bc, ca) = (0.5 * (t[0] + t[1]), 0.5 * (t[1] + t[2]), 0.5 * (t[2] + t[0]));
        [[t[0], ab, ca], [ab, t[1], bc], [ca, bc, t[2]], [ab, bc, ca]]
    };
    // Signed fan: exact for concave outlines too, the integrand being analytic on the hull.
    let mut work: Vec<([Vec3; 3], f64, f64)> = (1..src.len().saturating_sub(1))
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
    let mut sum = 0.0;
    let mut refined = 0;
    while let Some((t, twice, whole)) = work.pop() {
        let kids = split(&t);
        let vals = kids.map(|k| tri(&k, 0.25 * twice));
        let parts: f64 = vals.iter().map(|v| v.0).sum();
        let noise: f64 = vals.iter().map(|v| v.1).sum::<f64>() * NOISE_EPS;
        let share = 0.5 * twice.abs() / area;
        // Converged, or changing only by the rounding of the integrand (refining further
        // cannot tell more), or by a negligible amount: near a point where the integrand
        // jumps (a contact point) the change only shrinks with the area, never relative to
        // it, and the MAX_TRIANGLES splits together stay below rel_tol of the total.
        let negligible = rel_tol * total / (4 * MAX_TRIANGLES) as f64;
        if (parts - whole).abs() <= (rel_tol * total * share).max(noise).max(negligible) {
            sum += parts;
            continue;
        }
        refined += 1;
        if refined > MAX_TRIANGLES {
            return None;
        }
        for (k, v) in kids.into_iter().zip(vals) {
            work.push((k, 0.25 * twice, v.0));
        }
    }
    (sum > 0.0).then_some(sum)
}

#[cfg(test)]
mod tests {
    use super::*;
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
        assert!(touching(&floor, &wall));
        assert!(touching(&floor, &part));
        assert!(!touching(&floor, &corner));
        // collinear edges that only meet end to end are a point contact
        let beyond = [v(1.0, 0.0, 0.0), v(1.0, 0.0, 1.0), v(2.0, 0.0, 1.0), v(2.0, 0.0, 0.0)];
        assert!(!touching(&floor, &beyond));
    }

    #[test]
    fn touching_target_is_refused_or_converges() {
        // Perpendicular unit squares sharing an edge: F = 0.2000438 (Howell C-14), the
        // integrand is singular along the shared edge.
        let src = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let tgt = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(1.0, 0.0, 0.0)];
        if let Some(g) = lambert_over_area(&src, Vec3::Z, &tgt, 1e-14) {
            assert!((g - 0.200043776376147).abs() < 1e-9, "{g}");
        }
    }
}
