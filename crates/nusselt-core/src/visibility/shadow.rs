//! The exact part of a polygon visible from a point, by shadow projection (the View3D /
//! Walton pattern, docs/algorithms.md §6.3; Walton, NISTIR 6925, `viewobs.c` `ViewObstructed`).
//!
//! From a point p (with the normal n of its surface element), each blocker is clipped to the
//! region where it can hide part of the receiver, projected centrally from p onto the
//! receiver's plane, and the union of these shadows is subtracted from the receiver with a
//! robust 2-D boolean (the `i_overlay` crate, 64-bit integer engine). Lambert's contour
//! formula over the remaining contours then gives the exact point-to-polygon view factor with
//! partial obstruction (holes, oriented clockwise, subtract).
//!
//! Blockers are opaque from both sides, whichever way they face (View3D ignores blockers that
//! face the wrong way; docs/algorithms.md §8). Every tolerance is relative to the geometry.

use crate::geometry::turn_2d as turn;
use crate::geometry::{clip_to_halfspace, join_adjacent, newell_normal, tangent_frame, turns_left, Polygon, Vec3};
use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::float::single::SingleFloatOverlay;
use std::borrow::Cow;
use std::cell::RefCell;

/// Blocker points closer to p's height above the receiver than this fraction of it are cut
/// off, so that the central projection stays bounded. What is cut could hide only directions
/// within depth/distance of parallel to the receiver, which the window clip removes anyway,
/// unless the blocker passes within about depth x window slope of p.
const NEAR_P: f64 = 1e-9;

/// ... and than this many times p's coordinates (1000 x rounding): where p's height is large
/// a cut at 1e-9 of it dropped the near half of a face passing 1e-8 of that height above p
/// (a point F of 0.029 for 5e-16).
const NEAR_P_ABS: f64 = 2.2e-13;

/// ... but never less than this many times p's coordinates (16 ulp; and never more than half
/// p's height): where h_p is below that, a cut at 1e-9 h_p rounds to p's own plane and the
/// projection's depths to noise (a blocker through two faces' common edge stopped blocking
/// when the scene was moved by 7 of its sizes).
const NEAR_P_FLOOR: f64 = 16.0 * f64::EPSILON;

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
        Visible::Parts(contours) => contours,
    }
}

/// What [`visible`] found: nothing in view, the (clipped) receiver without any shadow on it,
/// or the contours left after subtracting the shadows from it.
enum Visible {
    Nothing,
    Whole(Vec<Vec3>),
    Parts(Vec<Vec<Vec3>>),
}

/// 2-D coordinates on the receiver's plane, relative to its centroid and in units of its
/// radius (so the boolean sees the same numbers at any scale).
#[derive(Default)]
struct Frame {
    c: Vec3,
    r: f64,
    tu: Vec3,
    tv: Vec3,
}

impl Frame {
    fn to2d(&self, x: Vec3) -> [f64; 2] {
        let d = x - self.c;
        [d.dot(self.tu) / self.r, d.dot(self.tv) / self.r]
    }
    fn to3d(&self, u: [f64; 2]) -> Vec3 {
        self.c + self.r * (u[0] * self.tu + u[1] * self.tv)
    }
}

/// The clipped receiver seen from p and the blockers' shadows on its plane (steps 1-3 of
/// [`visible_part`]), every shadow counter-clockwise in 2-D. Its buffers are kept per thread
/// (see [`with_cast`]): a point evaluation then allocates nothing once they have grown.
#[derive(Default)]
struct Cast {
    frame: Frame,
    rec: Vec<Vec3>,
    rec2: Vec<[f64; 2]>,
    shadows: Pieces,
    /// The receiver's bounding box grown by 1 %: shadows are bounded by it for the boolean.
    window: ([f64; 2], [f64; 2]),
    /// scratch: a blocker being clipped in 3-D, one shadow in 2-D (two buffers)
    cur: Vec<Vec3>,
    next: Vec<Vec3>,
    s: Vec<[f64; 2]>,
    t: Vec<[f64; 2]>,
}

thread_local! {
    static CAST: RefCell<Cast> = RefCell::new(Cast::default());
}

/// `f` of the cast from p (see [`cast_into`]), in this thread's buffers (fresh ones if they are
/// in use further up the stack); None when nothing of the receiver is in view from p.
fn with_cast<R>(p: Vec3, n: Vec3, receiver: &Polygon, blockers: &[&Polygon], f: impl FnOnce(&Cast) -> R) -> Option<R> {
    CAST.with(|cell| match cell.try_borrow_mut() {
        Ok(mut c) => cast_into(p, n, receiver, blockers, &mut c).then(|| f(&c)),
        Err(_) => cast(p, n, receiver, blockers).map(|c| f(&c)),
    })
}

/// [`cast_into`] into new buffers.
fn cast(p: Vec3, n: Vec3, receiver: &Polygon, blockers: &[&Polygon]) -> Option<Cast> {
    let mut c = Cast::default();
    cast_into(p, n, receiver, blockers, &mut c).then_some(c)
}

/// Steps 1-3 of [`visible_part`] into `out`; false when nothing of the receiver is in view
/// from p (n already normalised).
fn cast_into(p: Vec3, n: Vec3, receiver: &Polygon, blockers: &[&Polygon], out: &mut Cast) -> bool {
    if !p.is_finite() || !n.is_finite() || n == Vec3::ZERO {
        return false;
    }
    let nr = receiver.normal();
    let c = receiver.centroid();
    let r = receiver.radius();
    let h_p = nr.dot(p - c);
    let scale = r + (p - c).length();
    let tol = 1e-13 * scale;
    if h_p <= tol {
        return false;
    }
    let Cast { frame, rec, rec2, shadows, window, cur, next, s, t } = out;
    clip_to_halfspace(receiver.vertices(), p, n, tol, rec);
    if rec.len() < 3 || newell_normal(rec).dot(nr) <= 1e-14 * r * r {
        return false;
    }
    let (tu, tv) = tangent_frame(nr);
    *frame = Frame { c, r, tu, tv };
    rec2.clear();
    rec2.extend(rec.iter().map(|x| frame.to2d(*x)));
    drop_close(rec2);

    // Window: the clipped receiver's 2-D bounding box, grown by 1 % of its size.
    let (lo, hi) = bbox(rec2);
    let m = 0.01 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let (wlo, whi) = ([lo[0] - m, lo[1] - m], [hi[0] + m, hi[1] + m]);
    *window = (wlo, whi);
    let win = [[wlo[0], wlo[1]], [whi[0], wlo[1]], [whi[0], whi[1]], [wlo[0], whi[1]]];
    let win3 = win.map(|u| frame.to3d(u));
    let centre = frame.to3d([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])]);
    // Half-spaces (point, inward normal): the receiver side of the receiver plane, the front
    // of the point's surface element, below p; then the pyramid p -> window.
    let p_max = p.abs().max_element();
    let near = (NEAR_P * h_p).min(NEAR_P_ABS * (p_max + scale)).max(NEAR_P_FLOOR * p_max).min(0.5 * h_p);
    let mut clip_planes = [(c, nr), (p, n), (p - near * nr, -nr), (p, n), (p, n), (p, n), (p, n)];
    // the pyramid's planes, set when a blocker first needs them (most points need none)
    let mut pyramid = false;
    let set_pyramid = |planes: &mut [(Vec3, Vec3); 7]| {
        for k in 0..4 {
            let mut pn = (win3[k] - p).cross(win3[(k + 1) % 4] - p);
            if pn.dot(centre - p) < 0.0 {
                pn = -pn;
            }
            planes[3 + k] = (p, pn.normalize());
        }
    };
    let project = |x: Vec3| {
        let depth = nr.dot(p - x); // > 0 after the clip below p
        frame.to2d(p + (x - p) * (h_p / depth))
    };
    // Depth below p from which a shadow is the plain projection: at least 1e-3 h_p keeps the
    // projected coordinates within 1e3 times the blocker's distance from p.
    let deep = 1e-3 * h_p;
    let misses = |s: &[[f64; 2]]| {
        let (slo, shi) = bbox(s);
        slo[0] > whi[0] || slo[1] > whi[1] || shi[0] < wlo[0] || shi[1] < wlo[1]
    };

    shadows.clear();
    for b in blockers {
        let v = b.vertices();
        // Quick rejects: entirely on or behind the receiver plane, or behind p's plane; and
        // whether the blocker lies between the planes, well below p (see below), in one pass.
        let (mut off_r, mut off_n, mut plain) = (true, true, true);
        for x in v {
            let (hr, hn) = (nr.dot(*x - c), n.dot(*x - p));
            off_r &= hr <= tol;
            off_n &= hn <= tol;
            // (a vertex within rounding of a plane, as where a wall meets the floor, lies on it:
            // clipping it off would cut a sliver of rounding width at the cost of a clip)
            plain &= hr >= -tol && hn >= -tol && nr.dot(p - *x) >= deep;
        }
        if off_r || off_n {
            continue;
        }
        // Usual case: the whole blocker lies between the planes, well below p. Its shadow is
        // then the plain projection, and the pyramid clip only matters when that leaves the
        // window: a shadow missing the window is dropped without any clipping. (A shadow
        // reaching beyond the window is cut to it in 2-D by `difference` only if the boolean
        // is needed: the convex path takes it as it is.) A blocker that crosses a plane is
        // clipped to the three planes first, and to the pyramid only if it then still comes
        // close to p's height.
        s.clear();
        if plain {
            s.extend(v.iter().map(|x| project(*x)));
            if misses(s) {
                continue;
            }
        } else {
            cur.clear();
            cur.extend_from_slice(v);
            clip_3d(&clip_planes[..3], cur, next);
            if cur.len() < 3 {
                continue;
            }
            if cur.iter().all(|x| nr.dot(p - *x) >= deep) {
                s.extend(cur.iter().map(|x| project(*x)));
                if misses(s) {
                    continue;
                }
            } else {
                // close to p's height: the exact cone from p over the blocker, unless p lies
                // within rounding of the blocker's plane (or the blocker is concave)
                if cone_shadows(p, b, frame, *window, s, t, shadows) {
                    continue;
                }
                s.clear();
                if !pyramid {
                    set_pyramid(&mut clip_planes);
                    pyramid = true;
                }
                clip_3d(&clip_planes[3..], cur, next);
                if cur.len() < 3 {
                    continue;
                }
                s.extend(cur.iter().map(|x| project(*x)));
            }
        }
        push_shadow(s, shadows);
    }
    true
}

/// Appends the shadow `s` (2-D, either orientation) to `shadows`, counter-clockwise, unless it
/// has no area (an edge-on blocker, whose plane passes through p).
fn push_shadow(s: &mut Vec<[f64; 2]>, shadows: &mut Pieces) {
    drop_close(s);
    let a = signed_area(s);
    if !(a.abs() > 1e-15) || !a.is_finite() {
        return;
    }
    if a < 0.0 {
        s.reverse();
    }
    shadows.push(s);
}

/// The shadow of a convex blocker that comes close to p's height, without projecting any of
/// its points: a point y of the receiver's plane is hidden exactly when y lies beyond the
/// blocker's plane (seen from p) and inside the cone from p over the blocker, i.e. on the
/// inner side of each plane through p and an edge of the blocker. Each condition is a
/// half-plane on the receiver's plane, so the shadow is the window cut by them (pushed into
/// `shadows`: one for a polygon whose vertices lie on its plane to well within p's height
/// over it, else one per triangle of a fan, so that each plane is exact).
///
/// The central projection that this replaces divides by p's depth above each point; near p's
/// height that depth is rounding, so the blocker had to be cut a little below p, and where it
/// passes within about that cut's width of p (a face hovering 1e-12 over a source point), the
/// strip cut off covers a wide cone and light leaked through it. Here the inputs are the
/// blocker's own vertices (far from p) and the sign of p's height e over each triangle's
/// plane: for a counter-clockwise triangle, det(a_k - p, a_k+1 - p, x - p) = -e x (twice the
/// area of (a_k, a_k+1, x)) for x on the triangle's plane, so its inside is where
/// -sign(e) (a_k - p) x (a_k+1 - p) . (y - p) >= 0 (docs/algorithms.md §6.2).
///
/// False, with nothing pushed, when the blocker is not convex or |e| is within 64 ulp of the
/// coordinates for one of its triangles (p then lies on its plane within rounding, and which
/// side it is on is noise); the caller then cuts and projects.
fn cone_shadows(
    p: Vec3,
    b: &Polygon,
    frame: &Frame,
    window: ([f64; 2], [f64; 2]),
    s: &mut Vec<[f64; 2]>,
    t: &mut Vec<[f64; 2]>,
    shadows: &mut Pieces,
) -> bool {
    let v = b.vertices();
    let m = v.len();
    let v_max = v.iter().fold(0.0_f64, |m, x| m.max(x.abs().max_element()));
    // An edge within SHORT_EDGE_ULPS of the coordinates' rounding (and SHORT_EDGE of the
    // blocker's size) points where rounding says (a vertex doubled by a cut through it): its
    // plane through p would cut the cone at a random angle. It casts no plane of its own
    // (its neighbours' planes bound the cone to within its length), and a fan triangle with
    // such an edge no shadow.
    let short = (SHORT_EDGE_ULPS * f64::EPSILON * v_max).min(SHORT_EDGE * b.radius());
    let long = |i: usize| v[i].distance_squared(v[(i + 1) % m]) > short * short;
    if m > 3 && !turns_left(v, crate::geometry::turn_about(b.normal()), -1e-12) {
        return false;
    }
    let p_max = p.abs().max_element();
    // A polygon whose vertices all lie on its plane within a quarter of p's height over it
    // casts one shadow: the cone over all its edges (half the clips of a quad's fan, and one
    // shadow instead of two for the boolean). Every wall standing on a floor patch comes
    // here for each point of the patch: rows 95..100 of the 391-surface building at
    // obstructed_tol 1e-2, 8.10e9 -> 7.58e9 instructions (callgrind, -6.4 %).
    if m > 3 {
        let nb = b.normal();
        let coords = v_max + p_max;
        let e = nb.dot(p - v[0]);
        let bend = v.iter().fold(0.0_f64, |m, x| m.max(nb.dot(*x - v[0]).abs()));
        if e.abs() > 64.0 * f64::EPSILON * coords + 4.0 * bend {
            let edges = (0..m).filter(|&i| long(i)).map(|i| ((v[i] - p).cross(v[(i + 1) % m] - p), p));
            cone_shadow(-e.signum(), std::iter::once((nb, v[0])).chain(edges), frame, window, s, t, shadows);
            return true;
        }
    }
    let before = shadows.len();
    for k in 1..m - 1 {
        if !long(k) || (k == 1 && !long(0)) || (k == m - 2 && !long(m - 1)) {
            continue;
        }
        let tri = [v[0], v[k], v[k + 1]];
        // p's height e over the triangle's plane; within rounding, no side of it is known
        let nt = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
        let e = nt.dot(p - tri[0]);
        let coords = tri[0].abs().max(tri[1].abs()).max(tri[2].abs()).max_element() + p_max;
        if !(e.abs() > 64.0 * f64::EPSILON * coords) {
            shadows.truncate(before);
            return false;
        }
        let edge = |i: usize| ((tri[i] - p).cross(tri[(i + 1) % 3] - p), p);
        cone_shadow(-e.signum(), [(nt, tri[0]), edge(0), edge(1), edge(2)], frame, window, s, t, shadows);
    }
    true
}

/// Edges shorter than this many ulps of a blocker's largest coordinate cast no plane of their
/// own in [`cone_shadows`]: their direction is within 1e-6 rad of rounding (a quad cut with an
/// edge 1.3e-13 long at coordinates 0.7 put shadows 1.9e-3 of the point F off), while edges
/// that only look short, as in a thin wedge 1e-8 wide, keep theirs.
const SHORT_EDGE_ULPS: f64 = 1e6;

/// ... and no edge of more than this fraction of its radius is left out (a tiny blocker far
/// from the origin: leaving an edge's plane out widens the cone by a sliver as wide as it).
const SHORT_EDGE: f64 = 1e-8;

/// The window cut by the half-spaces sign m . (y - q) >= 0 of `planes` (normal m, point q),
/// on the receiver's plane, pushed into `shadows` unless nothing is left.
fn cone_shadow(
    sign: f64,
    planes: impl IntoIterator<Item = (Vec3, Vec3)>,
    frame: &Frame,
    (lo, hi): ([f64; 2], [f64; 2]),
    s: &mut Vec<[f64; 2]>,
    t: &mut Vec<[f64; 2]>,
    shadows: &mut Pieces,
) {
    s.clear();
    s.extend_from_slice(&[lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]]);
    for (m, q) in planes {
        let m = sign * m / m.length();
        // m . (y(u) - q) for y(u) = c + r (u0 tu + u1 tv), in units of r
        let h = [m.dot(frame.c - q) / frame.r, m.dot(frame.tu), m.dot(frame.tv)];
        clip_where(s, |u| h[0] + h[1] * u[0] + h[2] * u[1], t);
        std::mem::swap(s, t);
        if s.len() < 3 {
            return;
        }
    }
    push_shadow(s, shadows);
}

/// Sutherland-Hodgman: the part of the polygon `v` where `d` (affine in the point) is >= 0,
/// into `out` (each vertex's side computed once: edge (x, y) for x = previous vertex). A concave
/// polygon may come out with edges doubled back along the line, which area-based uses do not
/// mind.
fn clip_where(v: &[[f64; 2]], d: impl Fn([f64; 2]) -> f64, out: &mut Vec<[f64; 2]>) {
    out.clear();
    let Some(&last) = v.last() else { return };
    let (mut x, mut dx) = (last, d(last));
    for &y in v {
        let dy = d(y);
        if (dx > 0.0 && dy < 0.0) || (dx < 0.0 && dy > 0.0) {
            let t = dx / (dx - dy);
            out.push([x[0] + t * (y[0] - x[0]), x[1] + t * (y[1] - x[1])]);
        }
        if dy >= 0.0 {
            out.push(y);
        }
        (x, dx) = (y, dy);
    }
}

/// `cur` clipped successively to the half-spaces (point, inward normal), through `next`;
/// a half-space holding all of it costs no copy.
fn clip_3d(planes: &[(Vec3, Vec3)], cur: &mut Vec<Vec3>, next: &mut Vec<Vec3>) {
    for (q, qn) in planes {
        if cur.iter().all(|x| qn.dot(*x - *q) >= 0.0) {
            continue;
        }
        clip_to_halfspace(cur, *q, *qn, 0.0, next);
        std::mem::swap(cur, next);
        if cur.len() < 3 {
            return;
        }
    }
}

fn visible(p: Vec3, n: Vec3, receiver: &Polygon, blockers: &[&Polygon]) -> Visible {
    with_cast(p, n, receiver, blockers, |cast| {
        if cast.shadows.is_empty() {
            Visible::Whole(cast.rec.clone())
        } else {
            Visible::Parts(difference(cast))
        }
    })
    .unwrap_or(Visible::Nothing)
}

/// Step 4 of [`visible_part`]: the receiver minus the union of the shadows (non-zero fill),
/// by the robust boolean, back in 3-D.
fn difference(cast: &Cast) -> Vec<Vec<Vec3>> {
    // Shadows cut to the window (in 2-D, the same as cutting the blocker to the pyramid p ->
    // window), so the boolean's integer grid is set by the receiver's size.
    let (lo, hi) = cast.window;
    let mut shadows = Vec::with_capacity(cast.shadows.len());
    let mut tmp = Vec::new();
    for s in cast.shadows.iter() {
        let mut c = s.to_vec();
        for (u, w) in [
            ([lo[0], lo[1]], [hi[0], lo[1]]),
            ([hi[0], lo[1]], [hi[0], hi[1]]),
            ([hi[0], hi[1]], [lo[0], hi[1]]),
            ([lo[0], hi[1]], [lo[0], lo[1]]),
        ] {
            clip_2d(&c, u, w, true, &mut tmp);
            std::mem::swap(&mut c, &mut tmp);
        }
        if c.len() >= 3 {
            shadows.push(c);
        }
    }
    let result = cast.rec2.overlay_as::<i64>(&shadows, OverlayRule::Difference, FillRule::NonZero);
    let mut out = Vec::new();
    for shape in result {
        for contour in shape {
            if contour.len() >= 3 {
                out.push(contour.iter().map(|u| cast.frame.to3d(*u)).collect());
            }
        }
    }
    out
}

/// Lambert's F from p over the part of the clipped receiver inside the union of the
/// shadows, without a general boolean, when the receiver and every shadow reaching it are
/// convex (always so for convex blockers, as clipping keeps convexity). The shadows are
/// subtracted in turn from the visible part of the receiver (disjoint convex pieces, at first
/// the receiver itself; each subtraction splits a piece along the shadow's edges by
/// Sutherland-Hodgman half-plane clips), largest first, and the hidden F is Lambert over the
/// receiver minus Lambert over what is left. A shadow is cut only from what the earlier ones
/// left, so overlapping and nested shadows cost little. (Cutting the union into pieces
/// instead, each shadow minus every earlier one, took O(k^2) splits: 20 overlapping shadows
/// from the walls of two coaxial cylinders cost 18 us per point, now 5.) Many shadows
/// (see [`MERGE_FROM`]) are first joined where tiles share edges. Exactly 0 when no shadow
/// cuts the receiver. None when something is not convex (the caller then uses the boolean).
fn shadowed_convex(p: Vec3, n: Vec3, cast: &Cast) -> Option<f64> {
    let (rlo, rhi) = bbox(&cast.rec2);
    if !is_convex(&cast.rec2) {
        return None;
    }
    let free = || crate::unobstructed::analytic::point_contour(p, n, &cast.rec).max(0.0);
    // Lambert over a 2-D piece, through the buffer `piece3` for its 3-D outline
    let lambert = |piece: &[[f64; 2]], piece3: &mut Vec<Vec3>| {
        piece3.clear();
        piece3.extend(piece.iter().map(|u| cast.frame.to3d(*u)));
        crate::unobstructed::analytic::point_contour(p, n, piece3)
    };
    SCRATCH.with(|cell| {
        let mut guard = cell.borrow_mut();
        let Scratch { pieces, split, a, b, c, piece3, order, sel, merged } = &mut *guard;
        // only the shadows reaching the receiver's box matter; each must be convex
        sel.clear();
        for (k, s) in cast.shadows.iter().enumerate() {
            if overlap(bbox(s), (rlo, rhi)) {
                if !is_convex(s) {
                    return None;
                }
                sel.push(k);
            }
        }
        let shadows: &Pieces = if sel.len() >= MERGE_FROM {
            let mut joined: Vec<Cow<'_, [[f64; 2]]>> =
                sel.iter().map(|&k| Cow::Borrowed(cast.shadows.get(k))).collect();
            merge_adjacent(&mut joined);
            merged.clear();
            for s in &joined {
                merged.push(s);
            }
            sel.clear();
            sel.extend(0..merged.len());
            merged
        } else {
            &cast.shadows
        };
        if let [k] = sel[..] {
            let s = shadows.get(k);
            // one shadow: Lambert over receiver ∩ shadow directly (one piece, not the ring
            // of pieces around it); exactly 0 if they do not overlap, exactly all of the
            // receiver's F if it covers the receiver
            a.clear();
            a.extend_from_slice(&cast.rec2);
            let mut covers = true;
            for e in 0..s.len() {
                if split_2d(a, s[e], s[(e + 1) % s.len()], b, c) {
                    covers = false;
                    std::mem::swap(a, b);
                    if a.len() < 3 {
                        return Some(0.0);
                    }
                }
            }
            if covers {
                return Some(free());
            }
            return Some(lambert(a, piece3).max(0.0));
        }
        order.clear();
        order.extend(sel.iter().map(|&k| (signed_area(shadows.get(k)), k)));
        // largest first: the big shadows leave little for the others to cut
        order.sort_unstable_by(|x, y| y.0.total_cmp(&x.0));
        pieces.clear();
        pieces.push(&cast.rec2);
        let mut cut = false;
        for &(_, k) in order.iter() {
            // [methods] one work unit per 32 pieces a shadow is cut from (a cut that the
            // piece's box rules out costs about a thirtieth of a ray test; many small shadows
            // split the receiver into many pieces: 10 000 blockers cost seconds per point);
            // cancelled or over budget, stop (the caller discards the value, crate::work)
            if !crate::work::spend(pieces.len() as u64 / 32) {
                return Some(0.0);
            }
            let s = shadows.get(k);
            split.clear();
            for i in 0..pieces.len() {
                cut |= subtract_convex(pieces.get(i), s, split, a, b, c);
            }
            std::mem::swap(pieces, split);
            if pieces.is_empty() {
                return Some(free());
            }
        }
        if !cut {
            return Some(0.0);
        }
        let lit: f64 = (0..pieces.len()).map(|i| lambert(pieces.get(i), piece3)).sum();
        Some((free() - lit.max(0.0)).max(0.0))
    })
}

/// Convex 2-D pieces laid end to end (piece i is `pts[ends[i - 1]..ends[i]]`), so that
/// cutting and collecting them allocates nothing once the buffers have grown.
#[derive(Default)]
struct Pieces {
    pts: Vec<[f64; 2]>,
    ends: Vec<usize>,
}

impl Pieces {
    fn clear(&mut self) {
        self.pts.clear();
        self.ends.clear();
    }
    fn push(&mut self, q: &[[f64; 2]]) {
        self.pts.extend_from_slice(q);
        self.ends.push(self.pts.len());
    }
    /// Keeps the first `n` pieces.
    fn truncate(&mut self, n: usize) {
        self.ends.truncate(n);
        self.pts.truncate(self.ends.last().copied().unwrap_or(0));
    }
    fn len(&self) -> usize {
        self.ends.len()
    }
    fn get(&self, i: usize) -> &[[f64; 2]] {
        &self.pts[if i == 0 { 0 } else { self.ends[i - 1] }..self.ends[i]]
    }
    fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }
    fn iter(&self) -> impl Iterator<Item = &[[f64; 2]]> {
        (0..self.len()).map(|i| self.get(i))
    }
}

/// The convex path's buffers, one set per thread: it runs once per point evaluation, and
/// fresh vectors there were a large part of an obstructed run's malloc and free.
#[derive(Default)]
struct Scratch {
    pieces: Pieces,
    split: Pieces,
    a: Vec<[f64; 2]>,
    b: Vec<[f64; 2]>,
    c: Vec<[f64; 2]>,
    piece3: Vec<Vec3>,
    /// (area, index) of the shadows reaching the receiver
    order: Vec<(f64, usize)>,
    /// the shadows reaching the receiver (indices), and those joined (see [`MERGE_FROM`])
    sel: Vec<usize>,
    merged: Pieces,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// From this many shadows on, [`shadowed_convex`] first joins the shadows of edge-adjacent
/// tiles: many shadows are usually a meshed blocker's tiles, whose one-by-one subtraction
/// cuts the visible part into ever more slivers (20 x 20 tiles over a square: 706 us per
/// point without joining, 222 with), while joining costs more than it saves for a few
/// dozen overlapping shadows (the walls of two coaxial prisms: 4.5 us per point, 13 with).
const MERGE_FROM: usize = 32;

/// Joins shadows that share an edge (the same two points, in opposite directions: tiles of
/// a meshed blocker cast such shadows, bit for bit) wherever the union is convex, so that a
/// meshed face casts one shadow instead of one per tile ([`join_adjacent`], as for occluders).
fn merge_adjacent(shadows: &mut Vec<Cow<'_, [[f64; 2]]>>) {
    let mut outline: Vec<Vec<[f64; 2]>> = shadows.iter().map(|s| s.to_vec()).collect();
    let group = join_adjacent(&mut outline, |p: [f64; 2]| p.map(f64::to_bits), |_, _, s, t| join(s, t));
    *shadows = outline
        .into_iter()
        .zip(group)
        .enumerate()
        .filter(|(k, (_, g))| g == k)
        .map(|(_, (o, _))| Cow::Owned(o))
        .collect();
}

/// The union of the convex counter-clockwise polygons s and t if they share an edge and the
/// union is convex, without the vertices left straight at the joint.
fn join(s: &[[f64; 2]], t: &[[f64; 2]]) -> Option<Vec<[f64; 2]>> {
    let turn = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        let (cross, scale) = turn(a, b, c);
        (cross, (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]), scale)
    };
    crate::geometry::join_convex(s, t, turn, 1e-14)
}

/// Appends to `out` the convex pieces of q \ t (q and t convex, counter-clockwise): for each
/// edge of t in turn, the part of what is left outside it, then the rest is cut to its inside.
/// `a`, `b`, `c`: scratch.
fn subtract_convex(
    q: &[[f64; 2]],
    t: &[[f64; 2]],
    out: &mut Pieces,
    a: &mut Vec<[f64; 2]>,
    b: &mut Vec<[f64; 2]>,
    c: &mut Vec<[f64; 2]>,
) -> bool {
    // Separated by one of t's edges (the usual case for neighbouring shadows): q is untouched.
    let m = t.len();
    for e in 0..m {
        let (u, v) = (t[e], t[(e + 1) % m]);
        if u != v && q.iter().all(|x| orient(u, v, *x) <= 0.0) {
            out.push(q);
            return false;
        }
    }
    let rest = c;
    rest.clear();
    rest.extend_from_slice(q);
    for e in 0..m {
        let (u, v) = (t[e], t[(e + 1) % m]);
        if u == v {
            continue; // no direction (drop_close leaves none but a lone point)
        }
        if !split_2d(rest, u, v, b, a) {
            continue; // nothing of it right of this edge
        }
        if a.len() >= 3 {
            out.push(a);
        }
        std::mem::swap(rest, b);
        if rest.len() < 3 {
            return true;
        }
    }
    // what is left lies inside t: hidden by it
    true
}

/// Both halves of [`clip_2d`] in one pass, the points on the line in both: the part of `v`
/// left of u -> w into `left`, the part right of it into `right` (the same points, bit for
/// bit, as two clips). False, with both untouched, when no vertex lies right of the line.
fn split_2d(v: &[[f64; 2]], u: [f64; 2], w: [f64; 2], left: &mut Vec<[f64; 2]>, right: &mut Vec<[f64; 2]>) -> bool {
    if v.iter().all(|x| orient(u, w, *x) >= 0.0) {
        return false;
    }
    left.clear();
    right.clear();
    let Some(&last) = v.last() else { return true };
    let (mut x, mut dx) = (last, orient(u, w, last));
    for &y in v {
        let dy = orient(u, w, y);
        if (dx > 0.0 && dy < 0.0) || (dx < 0.0 && dy > 0.0) {
            let t = dx / (dx - dy);
            let z = [x[0] + t * (y[0] - x[0]), x[1] + t * (y[1] - x[1])];
            left.push(z);
            right.push(z);
        }
        if dy >= 0.0 {
            left.push(y);
        }
        if dy <= 0.0 {
            right.push(y);
        }
        (x, dx) = (y, dy);
    }
    true
}

/// [`clip_where`]: the part of the polygon `v` left of the directed line u -> w (`left`) or
/// right of it.
fn clip_2d(v: &[[f64; 2]], u: [f64; 2], w: [f64; 2], left: bool, out: &mut Vec<[f64; 2]>) {
    let sign = if left { 1.0 } else { -1.0 };
    clip_where(v, |x| sign * orient(u, w, x), out)
}

/// Twice the signed area of (u, w, x): positive when x is left of u -> w.
#[inline]
fn orient(u: [f64; 2], w: [f64; 2], x: [f64; 2]) -> f64 {
    (w[0] - u[0]) * (x[1] - u[1]) - (w[1] - u[1]) * (x[0] - u[0])
}

/// Counter-clockwise and convex: no right turn beyond rounding (a vertex on a straight edge,
/// as clipping leaves, is fine: its half-plane is that of the edge).
fn is_convex(v: &[[f64; 2]]) -> bool {
    turns_left(v, turn, -1e-12)
}

/// Removes vertices at rounding distance from their predecessor, as clipping leaves when a
/// vertex lies almost on a clip plane: the direction of such an edge is noise, and the
/// half-plane clips of the convex path must not cut along it.
fn drop_close(v: &mut Vec<[f64; 2]>) {
    let eps = |u: [f64; 2]| 1e-11 * (1.0 + u[0].abs().max(u[1].abs()));
    let mut k = 1;
    while k < v.len() {
        let (a, b) = (v[k - 1], v[k]);
        if (a[0] - b[0]).abs().max((a[1] - b[1]).abs()) <= eps(a) {
            v.remove(k);
        } else {
            k += 1;
        }
    }
    while v.len() > 1 {
        let (a, b) = (v[v.len() - 1], v[0]);
        if (a[0] - b[0]).abs().max((a[1] - b[1]).abs()) <= eps(a) {
            v.pop();
        } else {
            break;
        }
    }
}

fn bbox(v: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for u in v {
        for k in 0..2 {
            lo[k] = lo[k].min(u[k]);
            hi[k] = hi[k].max(u[k]);
        }
    }
    (lo, hi)
}

fn overlap(a: ([f64; 2], [f64; 2]), b: ([f64; 2], [f64; 2])) -> bool {
    a.0[0] <= b.1[0] && a.0[1] <= b.1[1] && b.0[0] <= a.1[0] && b.0[1] <= a.1[1]
}

/// True if `blocker` alone hides every point of the convex hull of `target` from every point
/// of the convex hull of `source` (vertex lists): the blocker is convex, the two lie strictly
/// on opposite sides of its plane, and every segment between their vertices crosses the plane
/// strictly inside the blocker. That suffices: from a fixed source point the crossings of the
/// segments to the target are its central projection, the convex hull of the vertices'
/// crossings; the same holds from a fixed target point towards the source.
pub fn hides_whole(source: &[Vec3], target: &[Vec3], blocker: &Polygon) -> bool {
    let (v, n) = (blocker.vertices(), blocker.normal());
    let m = v.len();
    let margin = 1e-9 * blocker.radius();
    let edge = |k: usize| (v[k], v[(k + 1) % m] - v[k]);
    // convex: every turn to the left about n (collinear vertices allowed), an absolute margin
    if !turns_left(v, |a, b, c| ((b - a).cross(c - b).dot(n), margin * margin), -1.0) {
        return false;
    }
    let height = |x: &Vec3| n.dot(*x - v[0]);
    let side = height(&source[0]);
    let strictly = |x: &Vec3, s: f64| height(x) * s.signum() > margin;
    if !(side.abs() > margin) || !source.iter().all(|x| strictly(x, side)) || !target.iter().all(|y| strictly(y, -side))
    {
        return false;
    }
    source.iter().all(|&x| {
        target.iter().all(|&y| {
            let (hx, hy) = (height(&x), height(&y));
            let c = x + (y - x) * (hx / (hx - hy));
            (0..m).all(|k| {
                let (q, e) = edge(k);
                e.cross(c - q).dot(n) > margin * e.length()
            })
        })
    })
}

/// True if the blockers together hide every point of the convex hull of `target` from every
/// point of the convex hull of `source` (vertex lists), where no one of them alone need do so
/// ([`hides_whole`]): a wall or slab meshed into tiles between two rooms, or a wall with an
/// opening and, behind the opening, something that covers it.
///
/// A plane that holds blockers and strictly separates the two hulls is crossed by every
/// segment between them inside the convex hull H of the crossings of the vertex-to-vertex
/// segments (as in [`hides_whole`]: from a fixed point the crossings are a central projection
/// of the other hull). Where the union U of the blockers in that plane covers H, grown a
/// little, every segment is blocked. Where it leaves gaps, a segment through a gap is blocked
/// if the rest of it, from the gap on, is: the convex hulls of the gaps become the sources for
/// the next plane, up to three planes deep (following, at each depth, the plane that leaves
/// the least open). The cover is tested with the robust 2-D boolean (H minus U, non-zero
/// fill) in coordinates relative to H, so the answer does not depend on the scene's scale or
/// position; what it leaves must be below 1e-12 of H's area (a crack narrower than the
/// boolean's integer grid counts as closed).
///
/// `band` = 0: strict. The hulls must lie 1e-9 of their size off each plane and H is grown by
/// 1e-9: a source or target touching a wall's plane (as every floor of a closed building
/// touches its partitions) is never claimed hidden. `band` > 0: the segments within `band` of
/// the size of an outline (source, target, gap) are not followed: each is shrunk by that much
/// towards its centroid first, and H grown by 1e-12 only. In a closed model those segments
/// run along the joints of the walls and are blocked anyway; where they are not, they carry
/// at most about 10 x `band` of the unobstructed F.
pub fn hides_whole_together(source: &[Vec3], target: &[Vec3], blockers: &[&Polygon], band: f64) -> bool {
    if blockers.is_empty() || source.len() < 3 || target.is_empty() || !(band >= 0.0) {
        return false;
    }
    let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
    for v in source.iter().chain(target) {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    let size = (hi - lo).length();
    if !(size > 0.0) || !size.is_finite() {
        return false;
    }
    let (margin, grow) = if band > 0.0 { (1e-12 * size, 1e-12) } else { (1e-9 * size, 1e-9) };
    let portal = Portal { target: shrink(target, band), blockers, margin, grow, band };
    portal.hidden_past_planes(&[shrink(source, band)], PORTAL_PLANES)
}

/// `v` shrunk by `band` of its size towards its vertex centroid.
fn shrink(v: &[Vec3], band: f64) -> Vec<Vec3> {
    let c = v.iter().copied().sum::<Vec3>() / v.len() as f64;
    v.iter().map(|x| c + (*x - c) * (1.0 - band)).collect()
}

/// Most planes a segment is followed through by [`hides_whole_together`]; at most this many
/// times the blockers' planes are each tried once.
const PORTAL_PLANES: usize = 3;

/// Most gaps one plane may leave for the next to close ([`hides_whole_together`]).
const MAX_GAPS: usize = 16;

/// What [`hides_whole_together`] follows the segments to: the target (shrunk), the blockers,
/// the length under which a point counts as on a plane, how much H is grown, and the band.
struct Portal<'a> {
    target: Vec<Vec3>,
    blockers: &'a [&'a Polygon],
    margin: f64,
    grow: f64,
    band: f64,
}

impl Portal<'_> {
    /// [`hides_whole_together`] from the convex `sources` (all on one side of each plane tried),
    /// `planes` planes deep.
    fn hidden_past_planes(&self, sources: &[Vec<Vec3>], planes: usize) -> bool {
        let (target, blockers, margin) = (&self.target[..], self.blockers, self.margin);
        if sources.is_empty() || sources.iter().any(|s| s.len() < 3) {
            return false;
        }
        let mut tried = vec![false; blockers.len()];
        // the plane leaving the least open so far: (open share, its gaps in 3-D)
        let mut best: Option<(f64, Vec<Vec<Vec3>>)> = None;
        for k in 0..blockers.len() {
            if tried[k] {
                continue;
            }
            let (q, n) = (blockers[k].vertices()[0], blockers[k].normal());
            let height = |x: &Vec3| n.dot(*x - q);
            // the blockers in k's plane (either facing), within 1e-9 of their own size
            let members: Vec<usize> = (k..blockers.len())
                .filter(|&m| {
                    let b = blockers[m];
                    let tol = 1e-9 * b.radius();
                    b.normal().dot(n).abs() >= 1.0 - 1e-12 && b.vertices().iter().all(|v| height(v).abs() <= tol)
                })
                .collect();
            for &m in &members {
                tried[m] = true;
            }
            let side = height(&sources[0][0]);
            let strictly = |x: &Vec3, s: f64| height(x) * s.signum() > margin;
            if !sources.iter().flatten().all(|x| strictly(x, side)) || !target.iter().all(|y| strictly(y, -side)) {
                continue;
            }
            let (tu, tv) = tangent_frame(n);
            let hulls: Vec<Vec<[f64; 2]>> = sources
                .iter()
                .map(|src| {
                    let mut crossings = Vec::with_capacity(src.len() * target.len());
                    for x in src {
                        for y in target {
                            let (hx, hy) = (height(x), height(y));
                            let c = *x + (*y - *x) * (hx / (hx - hy));
                            crossings.push([c.dot(tu), c.dot(tv)]);
                        }
                    }
                    convex_hull_2d(crossings)
                })
                .collect();
            // coordinates relative to the hulls: centred, in units of their extent
            let all: Vec<[f64; 2]> = hulls.iter().flatten().copied().collect();
            let (hlo, hhi) = bbox(&all);
            let centre = [0.5 * (hlo[0] + hhi[0]), 0.5 * (hlo[1] + hhi[1])];
            let extent = (hhi[0] - hlo[0]).max(hhi[1] - hlo[1]);
            if !(extent > 0.0) || !extent.is_finite() {
                continue;
            }
            let rel = |u: [f64; 2]| [(u[0] - centre[0]) / extent, (u[1] - centre[1]) / extent];
            let cover: Vec<Vec<[f64; 2]>> = members
                .iter()
                .map(|&m| {
                    let mut c: Vec<[f64; 2]> =
                        blockers[m].vertices().iter().map(|v| rel([v.dot(tu), v.dot(tv)])).collect();
                    if signed_area(&c) < 0.0 {
                        c.reverse();
                    }
                    c
                })
                .collect();
            let (mut open, mut total) = (0.0, 0.0);
            let mut gaps: Vec<Vec<[f64; 2]>> = Vec::new();
            for hull in hulls.iter().filter(|h| h.len() >= 3) {
                // grown by 1e-9 of its size about its own centre
                let (lo, hi) = bbox(hull);
                let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
                let grown: Vec<[f64; 2]> = hull.iter().map(|&u| rel(scaled_about(u, c, 1.0 + self.grow))).collect();
                total += signed_area(&grown).abs();
                for shape in grown.overlay_as::<i64>(&cover, OverlayRule::Difference, FillRule::NonZero) {
                    let area: f64 = shape.iter().map(|c| signed_area(c)).sum::<f64>().abs();
                    open += area;
                    if let Some(outer) = shape.first() {
                        gaps.push(convex_hull_2d(outer.to_vec()));
                    }
                }
            }
            if !(total > 0.0) {
                continue;
            }
            if open <= 1e-12 * total {
                return true;
            }
            let share = open / total;
            if planes > 1 && share < 1.0 - 1e-9 && gaps.len() <= MAX_GAPS && best.as_ref().is_none_or(|b| share < b.0) {
                // the gaps back in 3-D, in the plane
                let d = n.dot(q);
                let lift = |u: &[f64; 2]| n * d + (u[0] * extent + centre[0]) * tu + (u[1] * extent + centre[1]) * tv;
                let pieces: Vec<Vec<Vec3>> = gaps
                    .iter()
                    .filter(|g| g.len() >= 3)
                    .map(|g| {
                        // shrunk in the plane's coordinates (as the hulls were computed)
                        let c =
                            g.iter().fold([0.0, 0.0], |a, u| [a[0] + u[0], a[1] + u[1]]).map(|x| x / g.len() as f64);
                        g.iter().map(|&u| lift(&scaled_about(u, c, 1.0 - self.band))).collect()
                    })
                    .collect();
                if !pieces.is_empty() {
                    best = Some((share, pieces));
                }
            }
        }
        match best {
            Some((_, pieces)) => self.hidden_past_planes(&pieces, planes - 1),
            None => false,
        }
    }
}

/// u moved away from c by the factor f (towards it for f < 1).
fn scaled_about(u: [f64; 2], c: [f64; 2], f: f64) -> [f64; 2] {
    [c[0] + (u[0] - c[0]) * f, c[1] + (u[1] - c[1]) * f]
}

/// The convex hull of 2-D points, counter-clockwise (Andrew's monotone chain; collinear
/// points dropped).
fn convex_hull_2d(mut pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    // the lower chain left to right, then the upper one back, each without its last point
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * pts.len());
    let chain = |hull: &mut Vec<[f64; 2]>, points: &mut dyn Iterator<Item = &[f64; 2]>| {
        let start = hull.len();
        for &p in points {
            while hull.len() >= start + 2 && orient(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    };
    chain(&mut hull, &mut pts.iter());
    chain(&mut hull, &mut pts.iter().rev());
    hull
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
    let convex = with_cast(p, n, receiver, blockers, |cast| {
        shadowed_convex(p, n, cast)
            .map(|hidden| (crate::unobstructed::analytic::point_contour(p, n, &cast.rec) - hidden).max(0.0))
    });
    match convex {
        None => 0.0,
        Some(Some(f)) => f,
        Some(None) => visible_part(p, n, receiver, blockers)
            .iter()
            .map(|c| crate::unobstructed::analytic::point_contour(p, n, c))
            .sum(),
    }
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
    with_cast(p, n, receiver, blockers, |cast| shadowed(p, n, cast)).unwrap_or(0.0)
}

/// [`point_shadowed_view_factor`] and, if `with_free`, Lambert's F from p to the receiver
/// without blockers (the part in front of p), from one projection of the blockers (None
/// without: a contour sum per point saved). NaN for non-finite p or n.
pub fn point_shadowed_and_free(
    p: Vec3,
    n: Vec3,
    receiver: &Polygon,
    blockers: &[&Polygon],
    with_free: bool,
) -> (f64, Option<f64>) {
    if !p.is_finite() || !n.is_finite() || n == Vec3::ZERO {
        return (f64::NAN, Some(f64::NAN));
    }
    let n = n.normalize();
    with_cast(p, n, receiver, blockers, |cast| {
        let hidden = shadowed(p, n, cast);
        let free = with_free.then(|| crate::unobstructed::analytic::point_contour(p, n, &cast.rec).max(0.0));
        (hidden, free)
    })
    .unwrap_or((0.0, with_free.then_some(0.0)))
}

fn shadowed(p: Vec3, n: Vec3, cast: &Cast) -> f64 {
    if cast.shadows.is_empty() {
        return 0.0;
    }
    shadowed_convex(p, n, cast).unwrap_or_else(|| shadowed_boolean(p, n, cast))
}

/// [`point_shadowed_view_factor`] by the general boolean: Lambert over the clipped receiver
/// minus Lambert over what is left after subtracting the union of the shadows.
fn shadowed_boolean(p: Vec3, n: Vec3, cast: &Cast) -> f64 {
    let lit: f64 = difference(cast).iter().map(|c| crate::unobstructed::analytic::point_contour(p, n, c)).sum();
    (crate::unobstructed::analytic::point_contour(p, n, &cast.rec) - lit).max(0.0)
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
