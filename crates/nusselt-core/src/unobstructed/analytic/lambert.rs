//! Differential area to polygon: Lambert's closed form (docs/algorithms.md §1.3).

use super::area_routes::point_over_area;
use crate::geometry::{bounding_diameter, clip_to_halfspace, newell_normal, Vec3, COINCIDENT_TOL};
use std::f64::consts::TAU;

/// F from a differential area at `p` with unit normal `n` to the polygon `poly` (vertices
/// counter-clockwise about its front normal). Only the polygon's front side receives: 0 when
/// p lies behind or in the polygon's plane. The polygon is first clipped to the half-space
/// n.(x - p) >= 0 (without clipping the contour formula is wrong, docs/algorithms.md §1.4), then
/// [`point_contour`] is evaluated on the remainder. NaN for non-finite input or n = 0.
pub fn point_polygon(p: Vec3, n: Vec3, poly: &[Vec3]) -> f64 {
    point_polygon_routed(p, n, poly, true)
}

/// [`point_polygon`] without the area route for sums that cancel: their rounding, a few eps
/// times the terms' magnitudes (at most about pi), stays in the result. For sums over many
/// points where that absolute error is small enough and the route would cost milliseconds a
/// point (p within 1e-8 of the polygon's plane beside it).
pub fn point_polygon_unrouted(p: Vec3, n: Vec3, poly: &[Vec3]) -> f64 {
    point_polygon_routed(p, n, poly, false)
}

fn point_polygon_routed(p: Vec3, n: Vec3, poly: &[Vec3], route: bool) -> f64 {
    if !p.is_finite() || !n.is_finite() || n == Vec3::ZERO || poly.iter().any(|v| !v.is_finite()) {
        return f64::NAN;
    }
    if poly.len() < 3 {
        return 0.0;
    }
    let n = n.normalize();
    let nv = newell_normal(poly);
    let len = nv.length();
    let diam = bounding_diameter(poly);
    if !(len > 0.0) {
        return 0.0;
    }
    // Scale-relative tolerance: the polygon's size and p's distance both set the scale.
    let scale = diam.max(p.distance(poly[0]));
    let tol = COINCIDENT_TOL * scale;
    // Front side only: p must lie strictly in front of the polygon's plane.
    if (p - poly[0]).dot(nv / len) <= tol {
        return 0.0;
    }
    let mut clipped = Vec::with_capacity(poly.len() + 2);
    clip_to_halfspace(poly, p, n, tol, &mut clipped);
    if clipped.len() < 3 {
        return 0.0;
    }
    // Lambert's terms cancel for p near the polygon's plane beside it, or far from it (F ~ the
    // height, or ~ (size / distance)^2, from terms ~ the angles subtended): such sums are
    // recomputed by the area integral, whose terms have one sign.
    let (f, mag) = point_contour_terms(p, n, &clipped);
    if route && mag > POINT_ILL_CONDITIONED * f.max(0.0) {
        if let Some(g) = point_over_area(p, n, &clipped, nv / len, 1e-14) {
            return g;
        }
    }
    f.max(0.0)
}

/// Cancellation (sum of |terms| over F) above which Lambert's sum is recomputed by the area
/// route: its relative error is ~ eps times the ratio.
const POINT_ILL_CONDITIONED: f64 = 1e3;

/// Signed Lambert contour sum for a closed contour lying in p's front half-space (no clipping):
///
///   F = -(1/2 pi) sum_k gamma_k n.(R_k x R_k+1) / |R_k x R_k+1|,
///   R_k = v_k - p,  gamma_k = atan2(|R_k x R_k+1|, R_k . R_k+1)
///
/// (Hottel & Sarofim 1967 p. 48; View3D `V1AIpart`): gamma_k is the angle the edge subtends
/// at p and the unit cross product is the normal of the plane through p and the edge, so each
/// term is beta_k cos alpha_k. The atan2 form stays accurate for edges seen nearly end-on or
/// far away. Positive for a contour counter-clockwise about a normal facing p; a clockwise
/// contour (a hole) gives the negative of its area's factor, so summing over the contours of a
/// region with holes gives the region's factor. Edges through p contribute 0.
pub fn point_contour(p: Vec3, n: Vec3, contour: &[Vec3]) -> f64 {
    point_contour_terms(p, n, contour).0
}

/// [`point_contour`] and the sum of its terms' magnitudes (same scale): the sum's rounding is
/// a few eps times the latter, which exceeds F where the terms cancel (p near the contour's
/// plane, or far from a small contour).
pub fn point_contour_terms(p: Vec3, n: Vec3, contour: &[Vec3]) -> (f64, f64) {
    let m = contour.len();
    let mut sum = 0.0;
    let mut mag = 0.0;
    for k in 0..m {
        let a = contour[k] - p;
        let e = contour[(k + 1) % m] - contour[k];
        // a x b = a x e and a . b = a . a + a . e: for an edge far from p (or seen end-on)
        // a x b cancels to the edge's size; a x e never does.
        let c = a.cross(e);
        let len = c.length();
        if len > 0.0 {
            let t = len.atan2(a.dot(a) + a.dot(e)) * n.dot(c) / len;
            sum += t;
            mag += t.abs();
        }
    }
    (-sum / TAU, mag / TAU)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadrature::gauss::gauss_legendre_pm1 as gauss_legendre;
    use std::f64::consts::PI;

    /// Gauss-Legendre (n x n per triangle of a fan) of the point kernel
    /// cos_p cos_q / (pi r^2) over a convex polygon's front side: independent of Lambert.
    fn kernel_quad(p: Vec3, n: Vec3, poly: &[Vec3], order: usize) -> f64 {
        let (x, w) = gauss_legendre(order);
        let nq = newell_normal(poly).normalize();
        let mut acc = 0.0;
        for t in 1..poly.len() - 1 {
            let (a, b, c) = (poly[0], poly[t], poly[t + 1]);
            let jac = (b - a).cross(c - a).length();
            // collapsed square (Duffy) map of the triangle
            for i in 0..order {
                let u = 0.5 * (1.0 + x[i]);
                for j in 0..order {
                    let v = 0.5 * (1.0 + x[j]);
                    let q = a + u * (b - a) + u * v * (c - b);
                    let d = q - p;
                    let r2 = d.length_squared();
                    let cp = n.dot(d).max(0.0);
                    let cq = (-nq.dot(d)).max(0.0);
                    acc += 0.25 * w[i] * w[j] * u * jac * cp * cq / (PI * r2 * r2);
                }
            }
        }
        acc
    }

    fn square(c: Vec3, s: f64, down: bool) -> Vec<Vec3> {
        let mut v = vec![
            c + Vec3::new(-s, -s, 0.),
            c + Vec3::new(s, -s, 0.),
            c + Vec3::new(s, s, 0.),
            c + Vec3::new(-s, s, 0.),
        ];
        if down {
            v.reverse();
        }
        v
    }

    #[test]
    fn matches_kernel_quadrature() {
        let pts = [
            (Vec3::new(0.1, -0.2, 0.0), Vec3::Z),
            (Vec3::new(0.3, 0.4, -0.5), Vec3::new(0.2, -0.1, 1.0).normalize()),
            (Vec3::new(-2.0, 0.0, -1.0), Vec3::new(0.6, 0.0, 0.8)),
        ];
        let tri = vec![Vec3::new(-1.0, -0.5, 1.0), Vec3::new(0.0, 1.2, 1.3), Vec3::new(1.1, -0.3, 0.9)];
        for (p, n) in pts {
            for poly in [square(Vec3::new(0.2, 0.1, 1.0), 0.7, true), tri.clone()] {
                let poly = if newell_normal(&poly).z > 0.0 { poly.into_iter().rev().collect() } else { poly };
                let f = point_polygon(p, n, &poly);
                let q = kernel_quad(p, n, &poly, 60);
                assert!((f - q).abs() < 1e-12 * q, "{f} {q}");
            }
        }
    }

    #[test]
    fn behind_or_in_plane_is_zero_and_orientation() {
        let up = square(Vec3::new(0., 0., 1.), 0.5, false); // faces +z, away from the origin
        assert_eq!(point_polygon(Vec3::ZERO, Vec3::Z, &up), 0.0);
        let down = square(Vec3::new(0., 0., 1.), 0.5, true);
        assert!(point_polygon(Vec3::ZERO, Vec3::Z, &down) > 0.0);
        // p in the polygon's plane
        assert_eq!(point_polygon(Vec3::new(3., 0., 1.), Vec3::Z, &down), 0.0);
        // polygon entirely behind the element
        assert_eq!(point_polygon(Vec3::new(0., 0., 2.), Vec3::Z, &square(Vec3::new(0., 0., 1.), 0.5, false)), 0.0);
        assert!(point_polygon(Vec3::NAN, Vec3::Z, &down).is_nan());
        assert!(point_polygon(Vec3::ZERO, Vec3::ZERO, &down).is_nan());
        // the contour sum is signed: reversing the contour flips it
        let f = point_contour(Vec3::ZERO, Vec3::Z, &down);
        assert!((point_contour(Vec3::ZERO, Vec3::Z, &up) + f).abs() < 1e-16);
    }

    #[test]
    fn clipping_keeps_the_part_in_front() {
        // Square in the plane x = 1 (facing -x) straddling the element plane z = 0: only
        // z >= 0 counts. The kept part is built by hand and integrated by quadrature.
        let p = Vec3::ZERO;
        let n = Vec3::Z;
        let full = vec![
            Vec3::new(1., -0.5, -0.4),
            Vec3::new(1., -0.5, 0.6),
            Vec3::new(1., 0.5, 0.6),
            Vec3::new(1., 0.5, -0.4),
        ];
        assert!(newell_normal(&full).x < 0.0);
        let kept =
            vec![Vec3::new(1., -0.5, 0.0), Vec3::new(1., -0.5, 0.6), Vec3::new(1., 0.5, 0.6), Vec3::new(1., 0.5, 0.0)];
        let q = kernel_quad(p, n, &kept, 64);
        let f = point_polygon(p, n, &full);
        assert!((f - q).abs() < 1e-12 * q, "{f} {q}");
        // the unclipped contour sum is wrong (part of the square lies below the horizon)
        assert!((point_contour(p, n, &full) - q).abs() > 1e-3);
    }

    #[test]
    fn hole_subtracts_and_scale_invariance() {
        let p = Vec3::new(0.1, 0.05, 0.0);
        let outer = square(Vec3::new(0., 0., 1.), 1.0, true);
        let hole: Vec<Vec3> = square(Vec3::new(0.2, 0., 1.), 0.3, false); // clockwise seen from p
        let ring = point_contour(p, Vec3::Z, &outer) + point_contour(p, Vec3::Z, &hole);
        let want =
            point_polygon(p, Vec3::Z, &outer) - point_polygon(p, Vec3::Z, &square(Vec3::new(0.2, 0., 1.), 0.3, true));
        assert!((ring - want).abs() < 1e-15);
        let f = point_polygon(p, Vec3::Z, &outer);
        for s in [1e-3, 1e3, 1e6] {
            let scaled: Vec<Vec3> = outer.iter().map(|v| *v * s).collect();
            let g = point_polygon(p * s, Vec3::Z, &scaled);
            assert!((g - f).abs() < 1e-14 * f, "{s}");
        }
        // Large square seen from close by: F -> 1.
        let big = square(Vec3::new(0., 0., 1e-3), 1e3, true);
        assert!((point_polygon(Vec3::ZERO, Vec3::Z, &big) - 1.0).abs() < 1e-11);
    }
}
