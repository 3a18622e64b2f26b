//! The exact part of a polygon visible from a point, by shadow projection (the View3D /
//! Walton pattern, algorithms.md 6.3; Walton, NISTIR 6925, `viewobs.c` `ViewObstructed`).
//!
//! From a point p (with the normal n of its surface element), each blocker is clipped to the
//! region where it can hide part of the receiver, projected centrally from p onto the
//! receiver's plane, and the union of these shadows is subtracted from the receiver with a
//! robust 2-D boolean (the `i_overlay` crate, 64-bit integer engine). Lambert's contour
//! formula over the remaining contours then gives the exact point-to-polygon view factor with
//! partial obstruction (holes, oriented clockwise, subtract).
//!
//! Blockers are opaque from both sides, whichever way they face (View3D ignores blockers that
//! face the wrong way; reference-cases.md). Every tolerance is relative to the geometry.

use crate::geometry::{clip_to_halfspace, newell_normal, tangent_frame, Polygon, Vec3};
use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::float::single::SingleFloatOverlay;

/// Blocker points closer to p's height above the receiver than this fraction are cut off, so
/// the central projection stays bounded (they could hide only a cone of that relative width
/// around directions parallel to the receiver, which the window clip removes anyway).
const NEAR_P: f64 = 1e-9;

/// The part of `receiver` visible from the point `p`, as contours on the receiver's plane.
///
/// The receiver is first clipped to the front half-space n . (x - p) >= 0 of the point's
/// surface element (only its front sees anything) and nothing is visible if p is not in
/// front of the receiver (receivers receive on their front side only). Outer contours are
/// counter-clockwise about the receiver's normal, holes clockwise, so the signed areas add up
/// to the visible area. Empty when nothing is visible or when p or n is not finite.
///
/// Method, for each blocker B:
/// 1. clip B to the receiver's side of its plane (parts beyond it cannot block), to p's
///    front half-space (segments from p to the clipped receiver stay in it), to a plane just
///    below p parallel to the receiver (relative offset 1e-9 of p's height, which keeps the
///    projection finite), and to the pyramid from p through a window slightly larger than
///    the clipped receiver (so the shadow is bounded by the window and well conditioned);
/// 2. project it centrally from p: x' = p + (x - p) h_p / (n_r . (p - x)), h_p = height of p;
/// 3. express the shadow in 2-D coordinates of the receiver plane, relative to the receiver's
///    centroid and in units of its radius (so the boolean sees the same numbers at any scale);
/// 4. subtract the union of all shadows (non-zero fill, all made counter-clockwise) from the
///    receiver.
pub fn visible_part(p: Vec3, n: Vec3, receiver: &Polygon, blockers: &[&Polygon]) -> Vec<Vec<Vec3>> {
    match visible(p, n, receiver, blockers) {
        Visible::Nothing => Vec::new(),
        Visible::Whole(rec) => vec![rec],
        Visible::Parts { contours, .. } => contours,
    }
}

/// What [`visible`] found: nothing in view, the (clipped) receiver without any shadow on it,
/// or the contours left after subtracting the shadows from it.
enum Visible {
    Nothing,
    Whole(Vec<Vec3>),
    Parts { rec: Vec<Vec3>, contours: Vec<Vec<Vec3>> },
}

fn visible(p: Vec3, n: Vec3, receiver: &Polygon, blockers: &[&Polygon]) -> Visible {
    if !p.is_finite() || !n.is_finite() || n == Vec3::ZERO {
        return Visible::Nothing;
    }
    let n = n.normalize();
    let nr = receiver.normal();
    let c = receiver.centroid();
    let r = receiver.radius();
    let h_p = nr.dot(p - c);
    let scale = r + (p - c).length();
    let tol = 1e-13 * scale;
    if h_p <= tol {
        return Visible::Nothing;
    }
    let mut rec = Vec::with_capacity(receiver.vertices().len() + 2);
    clip_to_halfspace(receiver.vertices(), p, n, tol, &mut rec);
    if rec.len() < 3 || newell_normal(&rec).dot(nr) <= 1e-14 * r * r {
        return Visible::Nothing;
    }
    let (tu, tv) = tangent_frame(nr);
    let to2d = |x: Vec3| -> [f64; 2] {
        let d = x - c;
        [d.dot(tu) / r, d.dot(tv) / r]
    };
    let to3d = |u: [f64; 2]| -> Vec3 { c + r * (u[0] * tu + u[1] * tv) };
    let rec2: Vec<[f64; 2]> = rec.iter().map(|x| to2d(*x)).collect();

    // Window: the clipped receiver's 2-D bounding box, grown by 1 % of its size.
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for u in &rec2 {
        for k in 0..2 {
            lo[k] = lo[k].min(u[k]);
            hi[k] = hi[k].max(u[k]);
        }
    }
    let m = 0.01 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let win = [[lo[0] - m, lo[1] - m], [hi[0] + m, lo[1] - m], [hi[0] + m, hi[1] + m], [lo[0] - m, hi[1] + m]];
    let win3: Vec<Vec3> = win.iter().map(|u| to3d(*u)).collect();
    let centre = to3d([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])]);
    // Planes through p (point p, inward normal) bounding the pyramid p -> window.
    let mut clip_planes: Vec<(Vec3, Vec3)> = Vec::with_capacity(7);
    clip_planes.push((c, nr)); // receiver side of the receiver plane
    clip_planes.push((p, n)); // front of the point's surface element
    clip_planes.push((p - NEAR_P * h_p * nr, -nr)); // below p
    for k in 0..4 {
        let mut pn = (win3[k] - p).cross(win3[(k + 1) % 4] - p);
        if pn.dot(centre - p) < 0.0 {
            pn = -pn;
        }
        clip_planes.push((p, pn.normalize()));
    }

    let mut shadows: Vec<Vec<[f64; 2]>> = Vec::new();
    let mut cur: Vec<Vec3> = Vec::new();
    let mut next: Vec<Vec3> = Vec::new();
    for b in blockers {
        // Quick rejects: entirely on or behind the receiver plane, or behind p's plane.
        if b.vertices().iter().all(|x| nr.dot(x - c) <= tol) || b.vertices().iter().all(|x| n.dot(x - p) <= tol) {
            continue;
        }
        cur.clear();
        cur.extend_from_slice(b.vertices());
        for (q, qn) in &clip_planes {
            clip_to_halfspace(&cur, *q, *qn, 0.0, &mut next);
            std::mem::swap(&mut cur, &mut next);
            if cur.len() < 3 {
                break;
            }
        }
        if cur.len() < 3 {
            continue;
        }
        let mut s: Vec<[f64; 2]> = cur
            .iter()
            .map(|x| {
                let depth = nr.dot(p - *x); // > 0 after the clip below p
                to2d(p + (*x - p) * (h_p / depth))
            })
            .collect();
        let a = signed_area(&s);
        if !(a.abs() > 1e-15) || !a.is_finite() {
            continue; // edge-on blocker (its plane passes through p): no area
        }
        if a < 0.0 {
            s.reverse();
        }
        shadows.push(s);
    }
    if shadows.is_empty() {
        return Visible::Whole(rec);
    }
    let result = rec2.overlay_as::<i64>(&shadows, OverlayRule::Difference, FillRule::NonZero);
    let mut out = Vec::new();
    for shape in result {
        for contour in shape {
            if contour.len() >= 3 {
                out.push(contour.iter().map(|u| to3d(*u)).collect());
            }
        }
    }
    Visible::Parts { rec, contours: out }
}

/// Exact view factor from the differential area at `p` (unit normal `n`) to the part of
/// `receiver` visible from it past `blockers` (opaque from both sides): Lambert's contour
/// formula summed over the contours of [`visible_part`] (holes subtract). 0 when nothing is
/// visible; NaN when p or n is not finite.
pub fn point_visible_view_factor(p: Vec3, n: Vec3, receiver: &Polygon, blockers: &[&Polygon]) -> f64 {
    if !p.is_finite() || !n.is_finite() || n == Vec3::ZERO {
        return f64::NAN;
    }
    let n = n.normalize();
    visible_part(p, n, receiver, blockers).iter().map(|c| crate::analytic::point_contour(p, n, c)).sum()
}

/// The part of the unobstructed point view factor that the blockers hide: Lambert's formula
/// over the clipped receiver minus [`point_visible_view_factor`], and exactly 0 wherever no
/// shadow is cast. Integrating this over a source and subtracting it from the exact
/// unobstructed F puts the adaptive effort on the shadows only: where a pair touches (shared
/// edge or vertex) the visible F varies steeply but the shadowed part is usually 0.
pub fn point_shadowed_view_factor(p: Vec3, n: Vec3, receiver: &Polygon, blockers: &[&Polygon]) -> f64 {
    if !p.is_finite() || !n.is_finite() || n == Vec3::ZERO {
        return f64::NAN;
    }
    let n = n.normalize();
    match visible(p, n, receiver, blockers) {
        Visible::Nothing | Visible::Whole(_) => 0.0,
        Visible::Parts { rec, contours } => {
            let lit: f64 = contours.iter().map(|c| crate::analytic::point_contour(p, n, c)).sum();
            (crate::analytic::point_contour(p, n, &rec) - lit).max(0.0)
        }
    }
}


/// Shoelace area of a 2-D contour (positive counter-clockwise).
fn signed_area(v: &[[f64; 2]]) -> f64 {
    let mut a = 0.0;
    for i in 0..v.len() {
        let (p, q) = (v[i], v[(i + 1) % v.len()]);
        a += p[0] * q[1] - p[1] * q[0];
    }
    0.5 * a
}

#[cfg(test)]
#[path = "shadow_tests.rs"]
mod tests;
