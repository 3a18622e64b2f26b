//! `clipping` (and obstructed pairs of `auto`): the exact visible region per source point,
//! integrated over the source adaptively.

use super::kinks::{grade_slivers, split_at_kinks_along};
use super::rules::{
    area3, aspect, centroid3, longest_edge, radon7, radon7_corner_weights, rule_points, source_points, strang_fix3,
    strang_fix3_corner_weights, width,
};
use super::{ClippingOptions, Estimate};
use crate::geometry::{
    clip_to_halfspace, newell_normal, plane_chord, plane_tol, segment_distance, triangles_of, turn_about, turns_left,
    within_triangles, Polygon, Vec3,
};
use crate::quadrature::adaptive::split_in_four;
use crate::unobstructed::analytic::{point_polygon, point_polygon_unrouted, polygon_pair_within};
use crate::visibility::shadow::point_shadowed_and_free;

/// G = A_a F_ab of a pair by `clipping`, given its candidate `blockers` (none hides it whole),
/// the indices of those of them that cast a shadow of their own (`casting`: a blocker that the
/// others hide from the whole source hides nothing they do not), the parts `sa`, `sb` of a and
/// b in front of each other and its unobstructed G `free`.
pub(super) fn pair(
    a: &Polygon,
    b: &Polygon,
    sa: &Polygon,
    sb: &Polygon,
    blockers: &[&Polygon],
    casting: &[usize],
    free: f64,
    o: &ClippingOptions,
) -> Estimate {
    match o.source {
        None => {
            // G = G_free - (integral of the shadowed part): the exact kernel handles
            // touching pairs, the adaptive rule refines along shadows only.
            // Relative target: blocked F <= unobstructed F, so an error of tol * G_free
            // is also within tol absolute, and small (distant) pairs cost little.
            if free <= 0.0 {
                return Estimate::exact(0.0);
            }
            // G is symmetric: integrate over the side the blockers keep farther from
            // (a blocker close above the source makes the shadowed F peak beneath it)
            let (ca, cb) = (clearance(a, blockers), clearance(b, blockers));
            // ... unless one side's part in front is far the smaller and no blocker comes
            // closer to it than a hinge: over the larger side the kernel then gathers within
            // about the small one's size of it, between the samples (see SMALL_SIDE)
            let (small_a, small_b) = (far_smaller(sa, sb), far_smaller(sb, sa));
            let by_size_a = small_a && part_clearance(ca, a, sa) >= HINGED_CLEARANCE;
            let by_size_b = small_b && part_clearance(cb, b, sb) >= HINGED_CLEARANCE;
            let over_a = if by_size_a {
                true
            } else if by_size_b {
                false
            } else {
                ca >= cb
            };
            let (first, second) =
                if over_a { ((a, b, sa, sb), (b, a, sb, sa)) } else { ((b, a, sb, sa), (a, b, sa, sb)) };
            let goal = o.tol * free;
            let (mut hidden, mut err) = hidden_over(first, blockers, casting, (free, goal), o);
            // A side whose integral ran out of evaluations short of the goal is tried from the
            // other side, which replaces it when it has the smaller error estimate and the two
            // agree within SIDES_DISAGREE times their estimates: a blocker's vertex 1e-9 off the
            // source's corner sent an integral to a thin receiver whose edge lies in the
            // blocker's plane, where 60 000 evaluations ended 29 x the goal away with too
            // little hidden (an obstacle then raised F by 2.7e-6 of the unobstructed F;
            // tests/test_properties.py); the other side met the goal. Sides that disagree by
            // more leave the first: one of them has missed a feature between its samples and
            // its estimate says nothing. A blocker hovering 1e-8 over one face of a pair lets
            // light through a wedge as thin, which that face's samples all miss: it claims the
            // pair hidden whole (visible G 3.8e-16, estimate 2.3e-16) while the other side, out
            // of evaluations at obstructed_tol 1e-9, has the visible 2.4705e-9 within 1.5e-12
            // (keeping the larger hidden part, as before, was 2 600 x tol off). Two crossed
            // faces whose first side ran out at obstructed_tol 1e-10 with an estimate 10 %
            // short of its error (1.09e-8 for 9.9e-9) take the second (within 1.3e-12).
            // Both sides are integrated, too, when blockers come close to both, and there the
            // larger hidden part is kept: a face 1e-6 under a thin face that shares its edge
            // hid a layer of it 1e-6 wide, which that side's samples all missed (its estimate
            // met the goal), while the other side had only a blocker's vertex 1e-9 off its
            // corner (the obstacle then raised F by 3.6e-6 of the unobstructed F); the side
            // that misses the shadow within 1e-8 of a thin wedge's common edge claims the goal
            // met with nothing hidden (`test_replay_thin_wedge_scaled`). So, too, when one side's
            // part in front is far the smaller but a blocker comes close to it even at that
            // part's width (`part_clearance`): the larger side misses what the kernel gathers
            // next to the small part, the small one may miss the close blocker's shadow. (Seed
            // 43 came here, 4 % of the unobstructed F missed over the larger side, until its
            // blocker, 8e-8 over a sliver 2e-7 wide, was measured against that width; no case
            // known now takes this branch.)
            let close_to_both = ca.max(cb) < BOTH_SIDES_CLEARANCE || (small_a && !by_size_a) || (small_b && !by_size_b);
            // A side chosen as far the smaller is not replaced by the other, whose samples lie
            // far from where the kernel gathers and whose estimate says nothing (seed 43 moved:
            // the sliver's integral ended 1.3 x its goal away but within 7.7e-7 of the
            // unobstructed F, the other side claimed 1e-8 and was 1.3e-4 off)
            let by_size = by_size_a || by_size_b;
            if (err > goal && !by_size) || close_to_both {
                let (other, other_err) = hidden_over(second, blockers, casting, (free, goal), o);
                if close_to_both {
                    if other > hidden {
                        (hidden, err) = (other, other_err);
                    }
                } else if (other - hidden).abs() <= SIDES_DISAGREE * (err + other_err)
                    && other_err < err
                    && !lies_flat_over(second.2, blockers)
                {
                    (hidden, err) = (other, other_err);
                } else {
                    // the first is kept, but the two sides disagree: neither is known better
                    err = err.max((other - hidden).abs());
                }
            }
            // An integral that ran out of evaluations short of its goal says so: its error
            // estimate is the pair's std_err (0 = the goal was met), which the Python layer
            // reports (`ToleranceWarning`, the result's std_err) instead of a silent number.
            let value = (free - hidden).clamp(0.0, free);
            Estimate { value, std_err: if err > goal { err.min(free) } else { 0.0 } }
        }
        Some(k) => {
            // Ratio estimator: the exact unobstructed G times the rule's visible fraction of
            // the point F. Exact for pairs fully hidden or not hidden at all; a touching
            // pair's steep kernel cancels in the ratio.
            let (mut vis, mut all) = (0.0, 0.0);
            let casting: Vec<&Polygon> = casting.iter().map(|&k| blockers[k]).collect();
            for (x, w) in source_points(sa, k) {
                // [methods] one unit per evaluation and blocker; over budget or cancelled,
                // stop (the result is discarded, crate::work)
                if !crate::work::spend(casting.len().max(1) as u64) {
                    break;
                }
                let (f_hidden, f_free) = point_shadowed_and_free(x, a.normal(), b, &casting, true);
                let f_free = f_free.unwrap_or(0.0);
                vis += w * (f_free - f_hidden);
                all += w * f_free;
            }
            Estimate::exact(if all > 0.0 { (free * vis / all).clamp(0.0, free) } else { free })
        }
    }
}

/// The hidden G of a pair integrated over `src` (`side` = (src, rec, the part of src in front
/// of rec, the part of rec in front of src)) and the integral's error estimate (see
/// [`adaptive_over_source`]).
fn hidden_over(
    side: (&Polygon, &Polygon, &Polygon, &Polygon),
    blockers: &[&Polygon],
    casting: &[usize],
    (free, goal): (f64, f64),
    o: &ClippingOptions,
) -> (f64, f64) {
    hidden_over_from(side, blockers, casting, None, (free, goal), o)
}

/// [`hidden_over`] from the start pieces given (None: the source's part cut at the kinks, its
/// slivers graded). `free` is the pair's unobstructed G, `goal` the error allowed.
fn hidden_over_from(
    side: (&Polygon, &Polygon, &Polygon, &Polygon),
    blockers: &[&Polygon],
    casting: &[usize],
    start: Option<&[[Vec3; 3]]>,
    (free, goal): (f64, f64),
    o: &ClippingOptions,
) -> (f64, f64) {
    let (src, rec, src_part, rec_part) = side;
    let point =
        |x: Vec3, bl: &[&Polygon], with_free: bool| point_shadowed_and_free(x, src.normal(), rec, bl, with_free);
    // a piece's own unobstructed G, for the pieces that integrate the visible F
    let piece_free =
        |t: &[Vec3; 3], tol: f64| Polygon::new(t.to_vec()).ok().map(|p| polygon_pair_within(&p, rec_part, tol));
    let cut = cut_to_slab(src, rec, blockers);
    let all: Vec<&Polygon> = blockers.iter().zip(&cut).map(|(b, c)| c.as_ref().unwrap_or(b)).collect();
    let casters: Vec<&Polygon> = casting.iter().map(|&k| all[k]).collect();
    let casting_blockers: Vec<&Polygon> = casting.iter().map(|&k| blockers[k]).collect();
    let test = ShadowTest::new(rec_part, &casting_blockers);
    // the receiver's part in front of the source has kinks of its own (see split_at_kinks);
    // so do the blockers as cut to the slab, which cast the shadows: where a blocker crosses
    // a plane its cut has new vertices and an edge along it, and their events are kinks
    // (the seed-24 pair listed from another vertex: 2.86 -> 0.79 x tol at the default,
    // tests/test_properties.py). The kinks are those of all the blockers: the start pieces
    // of the casting ones alone were coarser, and the error estimate on them missed (1.7 x
    // tol on one pair of the building at obstructed_tol 1e-3, 0.015 x with all); the casting
    // ones' events come first (see split_at_kinks).
    // Slivers near the receiver are cut across their length besides (see grade_slivers).
    let whole_source = start.is_none();
    let (start, kinked, along) = match start {
        Some(t) => (t.to_vec(), vec![false; t.len()], Vec::new()),
        None => {
            let (start, kinked, along) = split_at_kinks_along(src_part, rec_part, &all, casting, o.tol < KINKED_BELOW);
            let (start, kinked) = grade_slivers(start, kinked, rec_part);
            (start, kinked, along)
        }
    };
    let free_point = |x: Vec3| point_polygon(x, src.normal(), rec.vertices());
    let quick_free = |x: Vec3| point_polygon_unrouted(x, src.normal(), rec.vertices());
    // (start pieces given need not cover the source: no free G to hold them to)
    let free = whole_source.then_some(free);
    let integrand =
        Integrand { point: &point, free_point: &free_point, quick_free: &quick_free, piece_free: &piece_free, free };
    let plane = (src.centroid(), src.normal());
    let (pieces, outline) = (Pieces { start: &start, kinked: &kinked, along: &along }, src_part.vertices());
    adaptive_over_source(pieces, plane, outline, &casting_blockers, &integrand, &casters, &test, goal, o)
}

/// How far the blockers keep from the plane of `p`, relative to p's size: the least height of
/// a blocker vertex in front of it, and [`CROSSING_CLEARANCE`] for a blocker that crosses
/// the plane (or the greatest height of its vertices, if less). A vertex within the pair
/// test's tolerance of the plane ([`crate::geometry::plane_tol`]: 1e-10 of p's size and the
/// rounding of the distance) counts as on it, so that a vertex shared with p gives the same
/// answer wherever the scene lies (its distance rounds to 0 or +-1e-16 |x|). The band is the
/// pair test's, not wider: a blocker leaning 1e-9 out of p's plane (a face facing p across
/// that gap, which the pair test keeps as a pair) crosses it, and the integral runs over the
/// other side. With a band of 1e-9 it counted as lying on p's plane, the integral ran over p,
/// and the point evaluations from p cut the blocker 1e-9 of their height below them (see
/// `visibility::shadow`), where all of it lies: F 0.032 for 0, and 0.023 moved
/// (`test_replay_seed_28_face_within_the_band_of_another`). A crossing blocker gives exactly
/// [`CROSSING_CLEARANCE`] (not that times the radius and divided again, whose rounding made two
/// crossed faces tie or not depending on where the scene lies, and so chose the side to
/// integrate over by translation). A blocker that crosses the plane beside p, its trace
/// running over p for no more than [`TRACE_OVERLAP`] of p's radius, counts as close as its
/// lowest vertex in front, as one that does not cross: nothing cuts p along its trace, and
/// where it hovers low over p the shadowed F changes within its height. A face leaning 1e-5
/// out of a plane, a blocker crossing its plane at a point of its edge and hovering 1e-5 over
/// it along another edge of the blocker: the hidden F rose from 0 within 1e-5 of the
/// blocker's plane, along a start piece whose rule and children's agreed (5 x tol off at the
/// default over the leaning face, 0.05 x over the other; tests/test_properties.py, seed 32).
fn clearance(p: &Polygon, blockers: &[&Polygon]) -> f64 {
    let (c, n, r) = (p.centroid(), p.normal(), p.radius());
    let mut least = f64::INFINITY;
    for b in blockers {
        let tol = plane_tol(r, r + c.distance(b.centroid()) + b.radius());
        let (mut above, mut highest, mut below) = (f64::INFINITY, 0.0_f64, false);
        let bv = b.vertices();
        for v in bv {
            let h = n.dot(*v - c);
            if h > tol {
                above = above.min(h);
                highest = highest.max(h);
            }
            below |= h < -tol;
        }
        // (a crossing blocker that rises less than CROSSING_CLEARANCE above the plane hovers
        // over the source where its trace does not cut it: hinged on the source's edge)
        let crossing = CROSSING_CLEARANCE.min(highest / r);
        let on = |k: usize| n.dot(bv[k] - c).abs() <= tol;
        let hinged = !below
            && above < f64::INFINITY
            && (0..bv.len()).any(|k| {
                let k1 = (k + 1) % bv.len();
                on(k) && on(k1) && touches(p, bv[k], bv[k1], tol)
            });
        least = least.min(if hinged {
            HINGED_CLEARANCE.min(highest / r)
        } else if below && above < f64::INFINITY {
            // (a blocker crossing the plane beside p, its trace not running over p, is cut
            // along nothing there and hovers over p as low as its vertices come)
            match plane_chord(b, c, n) {
                Some(chord) if !runs_over(p, chord, tol) => crossing.min(above / r),
                _ => crossing,
            }
        } else {
            above / r
        });
    }
    least
}

/// True if the chord `(s, e)` (in the plane of polygon p) runs over p, or along its edge, for
/// more than [`TRACE_OVERLAP`] of p's radius, points within `tol` of p counting as on it.
fn runs_over(p: &Polygon, (s, e): (Vec3, Vec3), tol: f64) -> bool {
    let (n, len, least) = (p.normal(), s.distance(e), TRACE_OVERLAP * p.radius());
    if !(len > least) {
        return false;
    }
    triangles_of(p).iter().any(|t| {
        // the stretch of the chord inside each edge's line (grown by tol), as parameters
        let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let inward = n.cross(b - a).normalize_or_zero();
            let (f0, f1) = (inward.dot(s - a) + tol, inward.dot(e - a) + tol);
            if f0 < 0.0 && f1 < 0.0 {
                return false;
            } else if f0 < 0.0 {
                lo = lo.max(f0 / (f0 - f1));
            } else if f1 < 0.0 {
                hi = hi.min(f0 / (f0 - f1));
            }
        }
        (hi - lo) * len > least
    })
}

/// Share of a polygon's radius that a blocker's trace on its plane must run over it for the
/// blocker to count as crossing it (see [`clearance`]): a trace that only touches it, at a
/// point of its edge, cuts nothing.
const TRACE_OVERLAP: f64 = 1e-6;

/// True if the segment pq (in the plane of polygon s) meets s within `tol`: an end inside it,
/// or within `tol` of one of its edges.
fn touches(s: &Polygon, p: Vec3, q: Vec3, tol: f64) -> bool {
    let (v, tris) = (s.vertices(), triangles_of(s));
    within_triangles(&tris, s.normal(), p, tol)
        || within_triangles(&tris, s.normal(), q, tol)
        || (0..v.len()).any(|k| segment_distance(p, q, v[k], v[(k + 1) % v.len()]) <= tol)
}

/// The blockers as the point evaluations from `source` towards `receiver` need them: cut once
/// to the slab between the two planes (the receiver's side of its plane, the front of the
/// source's), which every point evaluation would otherwise cut them to again (a quarter of
/// the building's CPU at obstructed_tol 1e-3). A blocker inside the slab, or whose cut is no
/// polygon, stays as it is (the evaluation cuts or rejects it itself). A vertex within
/// [`plane_tol`] of a plane lies on it: a blocker sharing a vertex with the receiver, that
/// vertex 1e-17 behind the receiver's plane by rounding, was cut into a quad with an edge
/// 1e-13 long, and the point evaluations on it were 4e-5 of the pair's F off (as is, the same
/// scene gave the true value: seed 48 of tests/test_properties.py).
fn cut_to_slab(source: &Polygon, receiver: &Polygon, blockers: &[&Polygon]) -> Vec<Option<Polygon>> {
    let planes = [(receiver.centroid(), receiver.normal()), (source.centroid(), source.normal())];
    let radii = [receiver.radius(), source.radius()];
    let (mut cur, mut next) = (Vec::new(), Vec::new());
    blockers
        .iter()
        .map(|b| {
            let v = b.vertices();
            if planes.iter().all(|(q, n)| v.iter().all(|x| n.dot(*x - *q) >= 0.0)) {
                return None;
            }
            cur.clear();
            cur.extend_from_slice(v);
            for ((q, n), r) in planes.iter().zip(radii) {
                let tol = plane_tol(b.radius(), r + q.distance(b.centroid()) + b.radius());
                clip_to_halfspace(&cur, *q, *n, tol, &mut next);
                std::mem::swap(&mut cur, &mut next);
            }
            Polygon::new(cur.clone()).ok()
        })
        .collect()
}

/// True if a blocker lies flat over the polygon `p` (convex): its part over p (in front of it,
/// inside the prism on p) covers at least [`FLAT_SHARE`] of p's area and rises nowhere more
/// than [`BOTH_SIDES_CLEARANCE`] of p's radius above it. From such a side the shadow's edges
/// sweep bands as narrow as that height over the source, which the samples can miss while the
/// estimate looks converged; it does not replace the other side (see [`pair`]). A blocker that
/// only comes close at a point (a vertex 1e-9 off p's corner, the blocker rising steeply from
/// there) covers nothing flat and is no reason to distrust p's estimate.
fn lies_flat_over(p: &Polygon, blockers: &[&Polygon]) -> bool {
    let (n, c, v) = (p.normal(), p.centroid(), p.vertices());
    if !turns_left(v, turn_about(n), -1e-12) {
        return false;
    }
    let (height, least_area) = (BOTH_SIDES_CLEARANCE * p.radius(), FLAT_SHARE * p.area());
    let (mut cur, mut next) = (Vec::new(), Vec::new());
    blockers.iter().any(|b| {
        cur.clear();
        cur.extend_from_slice(b.vertices());
        clip_to_halfspace(&cur, c, n, 0.0, &mut next);
        std::mem::swap(&mut cur, &mut next);
        for k in 0..v.len() {
            if cur.len() < 3 {
                return false;
            }
            let (a, e) = (v[k], v[(k + 1) % v.len()] - v[k]);
            clip_to_halfspace(&cur, a, n.cross(e), 0.0, &mut next);
            std::mem::swap(&mut cur, &mut next);
        }
        cur.len() >= 3
            && cur.iter().all(|x| n.dot(*x - c) <= height)
            && 0.5 * newell_normal(&cur).dot(n).abs() >= least_area
    })
}

/// Share of a polygon's area that a blocker must cover, flat over it, for [`lies_flat_over`].
const FLAT_SHARE: f64 = 0.01;

/// How many times their two error estimates the sides of a pair may differ by before the
/// side integrated first stays though it ran out of evaluations (see [`pair`]).
const SIDES_DISAGREE: f64 = 10.0;

/// Clearance below which, on both polygons of a pair, both sides are integrated and the
/// larger hidden part kept (see [`pair`]).
const BOTH_SIDES_CLEARANCE: f64 = 1e-3;

/// The clearance a blocker crossing the source's plane counts as. Its trace on the plane is
/// a kink line the source is cut along first, so the shadowed F is smooth beside it; a
/// blocker hovering just above the source (or lying on it but for a vertex) has no such cut
/// and makes the shadowed F change within its height, which samples miss. Counting crossings
/// as 0 integrated over the hovered side: a triangle hovering 1e-8 to 0.1 over the source
/// (docs/algorithms.md §6.2) was off by 1e-2 to 4e-7 of the unobstructed F at tol 1e-9, the
/// crossed side by at most 1e-10. obstructed_fuzz 150 at tol 1e-4/1e-5/1e-6 (against its own
/// tol 1e-9 result): 3/2/5 -> 4/3/6 pairs over target, worst 12.4/19.1/191 x unchanged.
pub(super) const CROSSING_CLEARANCE: f64 = 0.1;

/// The clearance a blocker hinged on the source (an edge of it lies on the source, the rest in
/// front) counts as at most: from points near the hinge the blocker turns edge-on, and the
/// shadowed F changes at the scale of their distance from it, along a sliver of start pieces
/// whose rule misses it. Below [`CROSSING_CLEARANCE`], so that a pair whose other face a
/// blocker crosses is integrated there (the sliver replay of tests/test_properties.py: 1.15 x
/// tol over the hinged face at 1e-5, exact over the crossed one).
const HINGED_CLEARANCE: f64 = 0.05;
const _: () = assert!(HINGED_CLEARANCE < CROSSING_CLEARANCE);

/// Ratio of the radii of a pair's parts in front of each other below which the pair is
/// integrated over the smaller part whatever the clearances (as long as no blocker comes
/// closer to it than a hinge). Only a triangle 6e-5 across of a face lay in front of the other
/// face (radius 0.8), a blocker crossing that face's plane and hinged on the small part: over
/// the large face (the larger clearance) the kernel lay within 1e-4 of a vertex, the samples
/// far from it saw only a point F of 2e-14 (within the visible-part switch's rounding
/// allowance) and the pair came out all hidden at obstructed_tol 1e-3 (F 2.8e-13 for
/// 1.096e-9) and 27 % high at the default, where that side ran out of evaluations; over the
/// small part it met every target (the seed-38 replay of tests/test_properties.py).
const SMALL_SIDE: f64 = 1e-2;

/// Whether `p` is far smaller than `q` for [`SMALL_SIDE`]: in radius, or in width (area over
/// radius), for a part in front that is a sliver along the other face: two faces meeting at
/// an edge nearly back to back see each other only within 1e-7 of it, and over the larger
/// face the kernel gathers within that of the edge, far below its samples (seed 43 of
/// tests/test_properties.py: a blocker across the wedge hid 42 % of the unobstructed F, of
/// which the integral over the larger face found 4 % and claimed every target met).
fn far_smaller(p: &Polygon, q: &Polygon) -> bool {
    let (rp, rq) = (p.radius(), q.radius());
    rp <= SMALL_SIDE * rq || width(p) <= SMALL_SIDE * width(q)
}

/// The clearance `c` of polygon `p` (relative to its radius, see [`clearance`]) relative to
/// the width of its part in front `part` instead, if that is less: the integral over a sliver
/// resolves it at its width, and a blocker as high above it as that does not hover over it
/// (seed 43: face 4's vertex 8e-8 over face 0, clearance 8e-8, over its part in front 1e-7
/// wide, where the integral meets every target; over the other face it missed 1.3e-4 of the
/// unobstructed F in one placement and 2.4e-2 in another, in either direction).
fn part_clearance(c: f64, p: &Polygon, part: &Polygon) -> f64 {
    c * (p.radius() / width(part)).max(1.0)
}

/// Relative targets from which the adaptive source integration computes a start piece's
/// children only when the piece needs refining; until then its error estimate is twice the
/// difference between the rule and the centroid rule (4 or 8 evaluations instead of 15 or 35).
/// Most obstructed pairs stop at their kink-split start, so this sets the cost of a pair. 300
/// obstructed room pairs (`obstructed_schemes`, 9/15/21 quads per wall edge) at tol 1e-2:
/// largest error 1.0e-4/1.7e-4/4.1e-5 of the unobstructed F in 41/25/17 us per pair, against
/// 8.7e-6/1.6e-5/4.3e-6 in 114/65/42 us with the full start. 500 obstructed pairs of the
/// building and office of bench/scenes.py (bench/obstructed_calibration.py, against clipping
/// at 1e-11), error / (tol x unobstructed F): at tol 1e-3 largest 2.0 (1 pair above 1) with
/// this start against 1.9 (1 pair) with the full one; at 1e-4 2.1 (3 pairs) against 2.1
/// (6 pairs); at 1e-5 and 1e-6 at most 0.90 and 0.91. At 1e-7 3 pairs exceeded tol (1.96):
/// below 1e-6 the full start is kept. The 391-surface building at obstructed_tol 1e-3: 17.9
/// instead of 40.5 s of CPU, row sums within 5.8e-4 (5.7e-4). At the default the full start
/// would cost the building 27 % more work units; the one pair known to need it there (seed
/// 45's third case in tests/test_properties.py, 2.7 x tol off) is caught by
/// [`DEPARTURE_SHARE`] instead.
pub(super) const COARSE_START_TOL: f64 = 1e-6;

/// A start piece keeps the coarse estimate only while its samples lie within this factor of
/// each other: where the shadowed F changes by more across a piece, the degree-2 rule and the
/// centroid may err alike, and their difference says nothing (one start piece under a blocker
/// close to the source, samples 1.9e-3 .. 2.0e-4: both 12 % off, estimate 8 x too small,
/// 4.3 x tol at obstructed_tol 1e-3; `test_replay_loose_tol_moved_scene`). Such pieces get
/// their children; the room with a crate at 1e-4 0.85 -> 0.91 s (least of 5, one core), the
/// building at 1e-3 within the host's noise.
const COARSE_SPREAD: f64 = 3.0;

/// Under the 3-point rule a start piece keeps the coarse estimate only while its value is at
/// most this many times the integral's goal: beyond, the estimate must hold to better than a
/// percent of the value, and the degree-2 rule and the centroid can agree that closely while
/// both are further off. Two pieces of the building of bench/scenes.py, each half of a
/// ceiling patch with most of the hidden part, had the rule and the centroid 0.04 % apart and
/// the rule 0.25 % off (1.96 x tol at obstructed_tol 1e-3) and 0.6 % off (3.2 x tol at 1e-4).
const COARSE_MOST: f64 = 100.0;

/// Under Radon's rule a start piece's error estimate is at least this share of its area times
/// how far the F just inside its corners departs from the quadratic through its samples: the
/// rule and the centroid, or the rule and the children's, can agree by chance where the
/// integrand is not quadratic. A start piece of seed 45 (tests/test_properties.py), its
/// samples 7.1e-4 .. 1.8e-3 falling towards a corner, had the rule and the centroid 3e-7 apart
/// (estimate 1.4e-11) while the rule was 1.6e-4 off (3.9e-9, 2.7 x the pair's goal); area
/// times departure was 3.6e-6, 900 x the error. Elsewhere that product is about half the
/// coarse estimate: the building of bench/scenes.py spent 0.01 % more work units at the
/// default, 0.02 % at 1e-5, for coarse start pieces. For start pieces refined at once, too
/// (seed 51: an integral claimed the default goal met while 3.84 x off, the corners departing
/// below EDGE_SHARE): the building 125.2 -> 136.3 M work units at the default (rows 3.7e-8
/// -> 2.5e-8), 1.1 % more at 1e-5.
const DEPARTURE_SHARE: f64 = 1e-2;

/// Share of a steep leaf's linear gap (its children's rule against their equal-weight rule)
/// that counts as its error at least (see `refine` in [`adaptive_over_source`]). With 1e-2
/// three property-test replays that were 3.4, 6.9 and 64 x tol off at the default meet it
/// (3e-3 left the first at 3.4 x); the room with a crate of bench/scenes.py at 1e-6 spends
/// 8.5 % more work units (3.95 -> 4.29 M), the 391-surface building at the default 1.3 %
/// (107.5 -> 108.9 M); at targets from LOW_DEGREE_TOL on the rule is itself equal-weight, its
/// gap 0, and [`uncancelled_difference`] takes its place. First for start pieces only; a
/// leaf two levels down is as steep (seed 35 of tests/test_properties.py: 2.9 x tol off at
/// the default), and for every leaf the building at the default spends 0.5 % more (107.17 ->
/// 107.74 M).
const STEEP_SHARE: f64 = 0.01;

/// Spread of a leaf's children's samples (largest over least) beyond which the leaf counts
/// twice its estimate under the 3-point rule (targets from LOW_DEGREE_TOL on; Radon's rule
/// has the corner checks of EDGE_SHARE and DEPARTURE_SHARE): that far from where the rule
/// converges, the children's rule can be off by as much as it differs from the leaf's
/// (`a_very_steep_leaf_is_not_trusted_on_one_level`). A thin start piece under the 3-point rule, its
/// children's samples 9.7e-5 .. 3.3e-2, went from 3.67e-5 to 5.29e-5 with one level (its
/// estimate that whole difference) while the truth was about 1.5e-4: the pair 5.6 x tol off
/// at obstructed_tol 1e-3, and 1.2 x scaled by 1e-3 and moved (the seed-56 replay of
/// tests/test_properties.py). The building of bench/scenes.py at 1e-3: 7.095 -> 7.105 M work
/// units, rows within 8.1e-5 instead of 1.07e-4.
const VERY_STEEP: f64 = 30.0;

/// Share of its value that a steep start piece (samples spread by more than COARSE_SPREAD)
/// crossed by a kink the split left uncut (past MAX_KINK_PIECES) counts as error at least, for
/// targets below KINKED_BELOW: on such a piece Radon's rule and its children's can agree far
/// below their error (a piece of the seed-29 replay in tests/test_properties.py, samples
/// spread 11-fold: 6.5e-5 of the piece apart, both 4 % off; the grandchildren's rule was 5 %
/// away), and the piece is refined at least once where that matters. The 391-surface
/// building of bench/scenes.py at the default: 108.9 -> 116.4 M work units, rows within
/// 1.107e-7 (1.09e-7). For every kinked piece, steep or not, 2.0 x the work; at
/// obstructed_tol 1e-3 the steep ones alone 2.3 x (7.4 -> 17.3 M), hence the threshold.
const KINKED_SHARE: f64 = 0.05;

/// Targets below which [`KINKED_SHARE`] applies.
const KINKED_BELOW: f64 = 1e-5;

/// Relative targets from which the adaptive source integration uses Strang and Fix's
/// interior 3-point rule (degree 2) instead of Radon's 7 points (degree 5). The source is cut
/// at its kinks and vertex-edge events first, so the integrand is smooth on every piece and
/// degree 2 meets such targets with fewer evaluations (300 obstructed room pairs,
/// `obstructed_schemes`, 9/15/21 quads per wall edge, at tol 1e-4: largest error
/// 8.7e-6/1.6e-5/4.3e-6 of the unobstructed F in 115/65/43 us per pair, against
/// 6.5e-8/2.2e-7/7.2e-8 in 242/137/90 us with Radon's rule). On those small pairs it also
/// met 1e-6 (2.2e-7 at most, 20-40 % faster), but on the unit squares of bench/obstructed.py
/// (a centred square blocker) it needed 2.6 instead of 0.56 ms at 1e-6: it stops at 1e-4.
pub(super) const LOW_DEGREE_TOL: f64 = 1e-4;

/// The triangle rule of the adaptive source integration for a relative target `tol`.
pub(super) fn source_rule(tol: f64) -> Vec<([f64; 3], f64)> {
    if tol >= LOW_DEGREE_TOL {
        strang_fix3().to_vec()
    } else {
        radon7().to_vec()
    }
}

/// Which blockers may hide part of the receiver from some point of a source triangle: those
/// meeting the shaft (convex hull) of the triangle and the receiver. Where none does, every
/// segment from the triangle to the receiver is free and the shadowed F is 0 there, so the
/// adaptive rule spends no evaluation on such pieces; where some do, only they are projected.
struct ShadowTest<'a> {
    receiver: &'a Polygon,
    /// blocker triangles and their normals, blocker by blocker
    triangles: Vec<([Vec3; 3], Vec3)>,
    /// blocker k's triangles are `triangles[ends[k - 1]..ends[k]]`
    ends: Vec<usize>,
    max_abs: f64,
}

impl<'a> ShadowTest<'a> {
    pub(super) fn new(receiver: &'a Polygon, blockers: &[&Polygon]) -> Self {
        let mut triangles = Vec::new();
        let mut ends = Vec::with_capacity(blockers.len());
        let mut max_abs: f64 = 0.0;
        for b in blockers {
            let v = b.vertices();
            for x in v {
                max_abs = max_abs.max(x.abs().max_element());
            }
            for t in b.triangulate() {
                triangles.push(([v[t[0]], v[t[1]], v[t[2]]], b.normal()));
            }
            ends.push(triangles.len());
        }
        ShadowTest { receiver, triangles, ends, max_abs }
    }

    /// The blockers among `within` (sorted indices) that meet the shaft of `t` and the
    /// receiver, sorted, into `out` (all of `within` if t is too thin to be a polygon).
    /// Only the triangles of blockers in `within` are tested (a leaf's blockers are a few
    /// of the pair's).
    pub(super) fn active(&self, t: &[Vec3; 3], within: &[usize], out: &mut Vec<usize>) {
        out.clear();
        let Ok(piece) = Polygon::new(t.to_vec()) else {
            out.extend_from_slice(within);
            return;
        };
        let shaft = crate::visibility::bvh::Shaft::new(&piece, self.receiver, self.max_abs);
        for &k in within {
            let start = if k == 0 { 0 } else { self.ends[k - 1] };
            if self.triangles[start..self.ends[k]].iter().any(|(v, n)| shaft.may_meet_triangle(v, *n)) {
                out.push(k);
            }
        }
    }
}

/// True if the segment pq comes within twice the longest edge of triangle t of its centroid.
fn near_segment(t: &[Vec3; 3], p: Vec3, q: Vec3) -> bool {
    let size = t[0].distance(t[1]).max(t[1].distance(t[2])).max(t[2].distance(t[0]));
    let c = centroid3(t);
    let d = q - p;
    let s = if d.length_squared() > 0.0 { ((c - p).dot(d) / d.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    c.distance(p + s * d) <= 2.0 * size
}

/// True if the segment pq (in the plane of triangle t) reaches into t: it has an end in t, or
/// it comes within 1e-9 of t's size of an edge and has vertices of t strictly on both sides of
/// its line. A segment along an edge of t, both ends beyond the edge's, only touches t.
fn reaches_into(t: &[Vec3; 3], p: Vec3, q: Vec3) -> bool {
    let eps = triangle_eps(t);
    if inside_triangle(t, p, eps) || inside_triangle(t, q, eps) {
        return true;
    }
    let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
    let d = q - p;
    let len = d.length();
    if !(len > 0.0) {
        return false;
    }
    let side = |x: Vec3| n.dot(d.cross(x - p)) / len;
    t.iter().any(|&x| side(x) > eps) && t.iter().any(|&x| side(x) < -eps) && near_an_edge(t, p, q, eps)
}

/// t's corners and then the midpoints of its edges, each moved 1e-6 of the way to t's
/// centroid: where a function steep along t's outline takes its limits from inside t.
fn just_inside(t: &[Vec3; 3]) -> [Vec3; 6] {
    let c = centroid3(t);
    let mids = [0.5 * (t[0] + t[1]), 0.5 * (t[1] + t[2]), 0.5 * (t[2] + t[0])];
    [t[0], t[1], t[2], mids[0], mids[1], mids[2]].map(|x| x + (c - x) * 1e-6)
}

/// 1e-9 of triangle t's longest edge: the distance within which [`reaches_into`] counts a
/// point as on t.
fn triangle_eps(t: &[Vec3; 3]) -> f64 {
    1e-9 * longest_edge(t)
}

/// True if the segment pq (not a point) comes within `eps` of an edge of triangle t.
fn near_an_edge(t: &[Vec3; 3], p: Vec3, q: Vec3, eps: f64) -> bool {
    p != q && (0..3).any(|k| segment_distance(p, q, t[k], t[(k + 1) % 3]) <= eps)
}

/// True if x (in the plane of triangle t) lies in t or within `eps` of it.
fn inside_triangle(t: &[Vec3; 3], x: Vec3, eps: f64) -> bool {
    let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
    (0..3).all(|k| {
        let (a, b) = (t[k], t[(k + 1) % 3]);
        n.dot((b - a).cross(x - a)) >= -eps * a.distance(b)
    })
}

/// The least and the greatest of non-negative values (infinity and 0 for none).
fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| (lo.min(v), hi.max(v)))
}

/// A leaf's children's difference from it (`kids` summed less `whole`) under the equal-weight
/// rule ([`source_rule`] from [`LOW_DEGREE_TOL`] on), counted without the cancellation between
/// the children, for a leaf of area `area` with the values `points` at its rule's points. The
/// parent's samples set a linear model of the integrand, and each child departs from it: a
/// corner child (children 0-2 of [`split_in_four`], at vertices 0-2) by its rule less area / 4
/// times the parent's sample at its centroid, which is the parent's rule point at that vertex;
/// the middle child by its rule less a quarter of the parent's. A quadratic integrand, which
/// both levels integrate exactly, departs by d, d, d, -3d (the corner children are translates
/// of each other); that part is taken out, and the residuals, which still sum to the
/// children's difference, are returned as their root sum of squares: what that sum would be
/// were their signs independent, which does not vanish where they cancel by chance. 0 for a
/// quadratic integrand; on a smooth one of the order of the rule's error (third derivatives).
fn uncancelled_difference(area: f64, whole: f64, points: [f64; 3], kids: &[f64; 4]) -> f64 {
    let quarter = 0.25 * area;
    let linear = [quarter * points[0], quarter * points[1], quarter * points[2], 0.25 * whole];
    let d: [f64; 4] = std::array::from_fn(|k| kids[k] - linear[k]);
    const QUADRATIC: [f64; 4] = [1.0, 1.0, 1.0, -3.0];
    let c = (d[0] + d[1] + d[2] - 3.0 * d[3]) / 12.0;
    d.iter().zip(QUADRATIC).map(|(x, u)| (x - c * u).powi(2)).sum::<f64>().sqrt()
}

/// Most integrand evaluations one adaptive source integral may spend (about 0.5-4 s). At
/// 60 000 the blocked cylinder's sphere pairs, which see each other past 32 blockers, ran out
/// (pair (274, 418) after both sides, 1.2 s, 1.06e-9 of std_err) where 100 000 meet the default
/// goal (0.7 s: a side that runs out makes the other run too); the building of bench/scenes.py
/// kept 4 entries with a std_err at the default, and the seed-34 replay of
/// tests/test_properties.py ran out under EDGE_SHARE 3 %. At 250 000 the cylinder takes 294
/// instead of 314 s at the default (one core) and the building's entries meet the goal.
pub const MAX_SOURCE_EVALS: usize = 250_000;

/// What [`adaptive_over_source`] integrates: the part of the point F from a source point to
/// the receiver that the given blockers hide and, when asked for, the point F without
/// blockers (one projection gives both, see [`point_shadowed_and_free`]); and a source
/// piece's exact unobstructed G to the receiver (None for a sliver that is no polygon).
struct Integrand<'f> {
    point: &'f dyn Fn(Vec3, &[&Polygon], bool) -> (f64, Option<f64>),
    /// the point F without blockers alone
    free_point: &'f dyn Fn(Vec3) -> f64,
    /// the same to a few eps absolute (see `missed` in [`adaptive_over_source`])
    quick_free: &'f dyn Fn(Vec3) -> f64,
    /// (to the relative accuracy given)
    piece_free: &'f dyn Fn(&[Vec3; 3], f64) -> Option<f64>,
    /// the unobstructed G of the whole source, if the start pieces cover it
    free: Option<f64>,
}

/// Share of the pair's error target `goal` that a piece's exact unobstructed G
/// ([`Integrand::piece_free`]) may err by, and below which a piece (its unobstructed G by its
/// samples) keeps the hidden part whatever it looks like: a sliver's or a small piece's G
/// asked to a relative 1e-4 took the analytic kernel's slow routes (70 ms for one piece).
/// Samples whose free F spreads by more than [`COARSE_SPREAD`] do not say what the piece's G
/// is: there the piece's G itself is asked for (to PIECE_FREE_TOL of the pair's relative
/// target, an absolute error within this share of the goal), and the piece keeps the hidden
/// part only if it is that small. Two faces nearly in contact along an edge, a third hiding
/// them from each other whole: the samples of the one start piece gave 1.5e-11 for its G of
/// 5.5e-7, at obstructed_tol 1e-3 it integrated the hidden part, whose samples all lie below
/// the rise towards the edge, and F came out 0.99994 x the unobstructed F for 0
/// (tests/test_properties.py, seed 32). The 391-surface building spends nothing more.
const PIECE_FREE_TOL: f64 = 0.1;

/// Share of the point F at most visible at every sample of a start piece that integrates the
/// visible part (see [`adaptive_over_source`]).
const VISIBLE_SHARE: f64 = 0.01;

/// Under the 3-point rule (targets from [`LOW_DEGREE_TOL`] on) a start piece asks for the free
/// F at its samples, to see whether it integrates the visible part, once its hidden samples
/// spread by more than this factor (Radon's rule: [`COARSE_SPREAD`]). Three samples say less
/// of how the integrand bends than seven: a start piece hidden whole from the receiver, its
/// samples 2.7-fold apart, the kernel falling tenfold within it towards where the receiver's
/// plane crosses the source, kept the coarse estimate of its hidden part, the rule and the
/// centroid 0.5 % apart while both were 12 % off: the pair 2.5 x tol off at obstructed_tol
/// 1e-3, while the scene scaled by 1e-6 and moved met it (long-run seed 63,
/// `a_start_piece_hidden_whole_asks_its_free_f_where_its_samples_spread`).
/// Its visible part is 0, and exact. The building of bench/scenes.py: 26.71 -> 27.78 M work
/// units at 1e-3 (+4.0 %), 38.79 -> 39.72 M at 1e-4 (+2.4 %), the same pairs within tol;
/// with 2 on every use of COARSE_SPREAD under the 3-point rule, +7.7 % at 1e-3.
const VISIBLE_SPREAD_LINEAR: f64 = 2.0;

/// Visible part of a sample's point F that counts as none whatever the share (see
/// [`adaptive_over_source`]), times 1 + the coordinates' size over the receiver's: the
/// rounding of the difference of two point F (each a contour sum of terms of at most 1/2,
/// whose directions from the sample carry the coordinates' rounding), a few ulps per term.
/// F is dimensionless, so this is the same at any scale. A receiver whose part in front of the
/// source is a sliver 6e-8 wide, hidden whole behind faces sharing the source's edge: from
/// most of the source its point F is 1e-16, free and hidden computed along two routes
/// differing in the last bit (visible +-0.64 ulp, 5-20 % of it); by the share alone the start
/// pieces along the shared edge integrated the hidden part, the kernel's rise towards the edge
/// within 6e-8 of it, ran out of evaluations at 0.7 % hidden (estimate 0.35 %), and F was the
/// unobstructed 8.667e-9 for 0 (0 when the scene was moved, where the two routes agreed
/// exactly; the seed-30 replay of tests/test_properties.py). The 391-surface building of
/// bench/scenes.py spends the same work units at obstructed_tol 1e-3 and at the default.
const VISIBLE_ROUNDING: f64 = 64.0 * f64::EPSILON;

/// Multiple of the visible part's rounding allowance ([`VISIBLE_ROUNDING`]) up to which a
/// sample's free F says nothing about the share of it visible. A start piece all of whose
/// samples are that small and mostly hidden looks, before it takes the visible part, at points
/// 1e-6 inside its corners and edge midpoints, where the kernel may rise towards a line along
/// which the receiver meets the source: if one of them sees more than a small share of a free
/// F above that, the piece keeps the hidden part. A receiver crossing the source's plane
/// along a line through the source, only a wedge 2.2e-10 thick in front of it, that a
/// blocker in the plane of the source's edge hides a little of: the free F at the samples of
/// the 3-point rule was 1e-19 (rounding) and the visible part 0, so the pieces took the
/// visible part, found 0, and F was 0 for 7.52e-11 at obstructed_tol 1e-4 and looser (long-run
/// seed 42; the seed-30 pieces, hidden whole, still take the visible part).
const UNINFORMATIVE: f64 = 1e3;

/// Share of the largest integrand (the hidden F, or the visible F of a piece that integrates
/// that) at a start piece's samples and corners by which a corner's value (1e-6 inside it) may
/// depart from the quadratic that fits Radon's seven samples before
/// the piece counts its area times that departure as error, and its children do the same
/// while theirs departs too. Where the hidden F changes steeply within a few percent of the
/// piece next to an edge or a corner, no sample of the piece or of its children reaches that
/// stretch, and the two rules agree far below their error: a piece along a kink plane that
/// holds an edge of the receiver and a nearly collinear edge of a blocker (the hidden F's
/// slope grows without bound towards it), 9.3e-8 off with 1.1e-8 claimed (long-run seed 40:
/// 4.5 x tol at the default; the corner departed by 37 %); a piece next to a pierce point's
/// fan, one leaf claiming 1.9e-13 for 5.7e-9 (seed 41: an obstacle that hides nothing of the
/// pair raised F by 1.4 x the slack at every tol; 23 %). Smooth pieces depart by a few percent.
/// The 391-surface building of bench/scenes.py at the default: 108.5 -> 122.0 M work units
/// (+12 %, most of it the three corner evaluations of every start piece), rows within 3.4e-8
/// instead of 3.0e-7. The pieces that integrate the visible part compare their corners too
/// (a sliver of seed 44, 99 % hidden, its visible F rising 5e4-fold within 1e-3 of its length
/// towards a corner, claimed 5.1e-13 for an error of 1.7e-9; the building spends the same
/// work units within 1e-6). 10 % first; 3 % since a start piece refined once missed a dip of
/// 4 % of its largest value within 1 % of its size of a corner, its rule and its children's
/// agreeing to 9e-11, 12.3 x the slack at the default (seed 49 of tests/test_properties.py,
/// an obstacle raising F[3, 4]): the building 136.3 -> 146.8 M work units at the default
/// (with the larger MAX_SOURCE_EVALS, without which the seed-34 replay ran out of evaluations
/// and took the other side, 4.1 x tol off).
const EDGE_SHARE: f64 = 0.03;

/// EDGE_SHARE for targets below [`EDGE_TIGHT_BELOW`]: a piece next to where face 1 of seed 41
/// pierces the source, its corner dipping by 2-3 % within 1 % of its size, left the integral
/// over that face 1.2 x tol low at 1e-8 (against the other face's at 1e-9) with 3 %.
const EDGE_SHARE_TIGHT: f64 = 0.01;

/// EDGE_SHARE under the 3-point rule (targets from [`LOW_DEGREE_TOL`] on), whose three samples
/// fix a plane and no quadratic: a corner departs from that plane by the integrand's
/// curvature, so only a departure of half the largest value says that the samples miss
/// something. Asked at the start pieces whose hidden samples spread by more than
/// [`COARSE_SPREAD`] only (those not yet where the rule converges; the 3 corner evaluations
/// at every start piece cost the building below 1.5 x the CPU at 1e-3). Two cases:
/// - where the source touches the receiver, the point F from points near the contact does
///   not shrink with their distance to it, and the hidden F about a point of the contact
///   where a blocker's plane passes depends on the direction from that point alone. A layer
///   along a start piece's edge as thin as 1 % of the distance from such a point then holds
///   the hidden F at every scale, and no sample of the piece or of its children reaches it
///   (faces sharing an edge, a blocker crossing both; the seed-56 replays of
///   tests/test_properties.py: hidden F 0.34 at the edge, below 1e-5 at every sample; the
///   integral ended at 6.4e-4 for 8.6e-4, claiming 6.6e-5, and F was 1.3 x tol off at
///   obstructed_tol 1e-3, 3.9 x scaled and moved);
/// - under a blocker close to the source the hidden F rises and falls within a few percent of
///   a start piece next to its edge, beyond its samples and its children's (rule and
///   children 11 % high and 0.5 % apart: a pair of the `obstructed_fuzz` example, 500 pairs
///   with seed 11, 3.3 x tol at 1e-3; 0.49 x now).
///
/// The 391-surface building of bench/scenes.py at 1e-3: 7.105 -> 7.463 M work units (+5 %),
/// rows within 7.7e-5 (8.1e-5).
const LINEAR_EDGE_SHARE: f64 = 0.5;

/// Under the 3-point rule the start pieces at least this thin ([`aspect`]: longest edge over
/// least altitude, as the kink split's slivers) compare their corners too, whatever their
/// samples' spread: a sliver's three samples
/// lie along its middle, within a few percent of its width of each other, and see nothing of
/// what happens near its narrow ends. Two sliver start pieces (0.8 x 0.01) of the fuzz pair
/// above were crossed near their narrow end by the same steep feature, their samples within
/// 3-fold: each claimed 1e-7 and was 1.4e-5 and 1.8e-5 off (4.83 x tol at 1e-4; 0.26 x now).
const SLIVER_PROBE: f64 = 25.0;

/// Targets below which [`EDGE_SHARE_TIGHT`] applies (the building at the default would spend
/// 180.2 instead of 146.8 M work units with it).
const EDGE_TIGHT_BELOW: f64 = 1e-7;

/// Factor (either way) by which the centroid rule over the start pieces may put the source's
/// unobstructed G off its exact value before the integral checks, at its end, that its final
/// leaves see it (see `missed` in [`adaptive_over_source`]).
const MASS_FACTOR: f64 = 2.0;

/// Deepest leaf below a start piece that still counts its corners' departure (see
/// EDGE_SHARE).
const EDGE_DEPTH: usize = 4;

/// The start pieces of [`adaptive_over_source`], whether an uncut kink crosses each, and the
/// kink planes along the source's edges (see `split_at_kinks_along`).
#[derive(Clone, Copy)]
struct Pieces<'a> {
    start: &'a [[Vec3; 3]],
    kinked: &'a [bool],
    along: &'a [(Vec3, Vec3)],
}

/// The integral over the source of the hidden part of the point F and its error estimate, by
/// globally adaptive triangle subdivision: every leaf triangle carries its value by the rule of
/// [`source_rule`] (degree 5, or 2 for loose targets), the sum over its four children and
/// the difference of the two as error estimate (the point F is given only the blockers that
/// meet the leaf's shaft, as `casters`: the same blockers, cut to where they can cast, see
/// [`cut_to_slab`]). The leaf with the largest estimate is split until the estimates add up
/// to `goal` (an error bound on G = A_i F), the depth limit or the evaluation budget is
/// reached. The visible-region F is continuous but has kinks along shadow lines: a global
/// criterion spends the refinement along those lines only as far as the total error needs
/// it (a local criterion would refine them without end).
///
/// A start piece whose hidden samples differ by more than [`COARSE_SPREAD`] (under the 3-point
/// rule [`VISIBLE_SPREAD_LINEAR`]) and each leave at most [`VISIBLE_SHARE`] of the point F
/// visible integrates the visible part instead, and counts its exact unobstructed G minus that
/// as hidden: where a receiver touching the source
/// is hidden (nearly) whole, the hidden part carries the kernel's steep rise towards the
/// shared vertex or edge, the visible part is 0 or small and smooth (an obstacle that turned
/// the integral to such a side put F 2.0e-7 above its exact 0, 1.1e-4 of the unobstructed F,
/// at every tol; tests/test_properties.py). A piece hidden whole from a receiver away from it
/// keeps the hidden part, smooth there, and its coarse estimate. Cost: the building of
/// bench/scenes.py at obstructed_tol 1e-3 about 3 % more CPU (10 215 such pieces); taking
/// every piece more than half hidden, with the free F at every sample, cost 2.5 x.
///
/// The blockers' traces on the source's `plane` (a point of it and its normal) mark where the
/// shadowed F is not smooth at any scale (`near_cut`, `reaches_into` below). They were taken
/// in the plane of the first start piece, which the kink split may leave a sliver: one of
/// 2.6e-12 of the source's area, two of its vertices 5e-12 apart, had its normal 1.8e-5 rad
/// off the source's by their rounding, and two blockers that cross the source's plane 6.4e-6
/// deep, 3e-6 beside its corner, lay on one side of that plane: no trace, and the start piece
/// at the corner counted a quarter of its children's difference (7.8e-7 for a goal of
/// 2.75e-6) while the rule there was 10 % off. F came out 32 x tol low at obstructed_tol
/// 1e-3 (0.03 x with the traces), right where the scene was moved and the sliver's rounding
/// differed (`the_traces_lie_in_the_plane_of_the_source`).
#[allow(clippy::too_many_arguments)]
fn adaptive_over_source(
    Pieces { start, kinked, along }: Pieces,
    plane: (Vec3, Vec3),
    outline: &[Vec3],
    blockers: &[&Polygon],
    integrand: &Integrand,
    casters: &[&Polygon],
    test: &ShadowTest,
    goal: f64,
    o: &ClippingOptions,
) -> (f64, f64) {
    use std::cmp::Ordering;
    use std::collections::BinaryHeap;
    struct Leaf {
        t: [Vec3; 3],
        /// whether the leaf integrates the visible part of the point F (else the hidden part)
        visible: bool,
        /// the rule's value on t
        whole: f64,
        /// the rule's values on the four children, once computed (the returned value)
        kids: Option<[f64; 4]>,
        err: f64,
        depth: usize,
        /// the blockers that may cast a shadow from this leaf (indices into `blockers`)
        active: Vec<usize>,
        /// a start piece that a kink left uncut crosses (see KINKED_SHARE)
        kinked: bool,
        /// the integrand at the equal-weight rule's points (None under Radon's rule; see
        /// `uncancelled_difference`)
        points: Option<[f64; 3]>,
        /// the four children's, once computed
        kid_points: Option<[[f64; 3]; 4]>,
        /// descends from a start piece all of whose samples were 0 (see `edge_limit`)
        blind: bool,
        /// the integrand at the corners departs from the samples' quadratic (see EDGE_SHARE),
        /// with the samples and those corner values; the kids' once computed
        edge: Option<Edge>,
        kid_edges: Option<[Edge; 4]>,
    }
    #[derive(Clone, Copy)]
    struct Edge {
        /// (the first three under the 3-point rule)
        samples: [f64; 7],
        corners: [f64; 3],
    }
    impl Leaf {
        fn value(&self) -> f64 {
            self.kids.map_or(self.whole, |k| k.iter().sum())
        }
        /// the leaf's contribution to the hidden G (a visible leaf's piece counts its
        /// unobstructed G once, in `offset` below)
        fn hidden(&self) -> f64 {
            if self.visible {
                -self.value()
            } else {
                self.value()
            }
        }
    }
    impl PartialEq for Leaf {
        fn eq(&self, o: &Self) -> bool {
            self.err == o.err
        }
    }
    impl Eq for Leaf {}
    impl PartialOrd for Leaf {
        fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
            Some(self.cmp(o))
        }
    }
    impl Ord for Leaf {
        fn cmp(&self, o: &Self) -> Ordering {
            self.err.total_cmp(&o.err)
        }
    }
    // Every evaluation of the integral, counted (against `max_evals`) and metered here.
    // [methods] work budget: one unit per evaluation and blocker it casts (the start pieces'
    // samples too: the building of bench/scenes.py reported 7.55 M units at obstructed_tol
    // 1e-3 without them, 24.4 M with); cancelled or over budget, no more evaluations (each
    // casts every active blocker: 10 000 of them cost milliseconds; the result is discarded,
    // see crate::work)
    let evals = std::cell::Cell::new(0usize);
    let point = |x: Vec3, bl: &[&Polygon], visible: bool| {
        evals.set(evals.get() + 1);
        if crate::work::spend(bl.len().max(1) as u64) {
            (integrand.point)(x, bl, visible)
        } else {
            (0.0, Some(0.0))
        }
    };
    // the integrand of a visible or a hidden leaf (a point asked for its free F has it)
    let part = |visible: bool, (hidden, free): (f64, Option<f64>)| {
        if visible {
            (free.unwrap_or(hidden) - hidden).max(0.0)
        } else {
            hidden
        }
    };
    // all but a small share of the point F hidden
    // (or less than the rounding of the two point F at x: see VISIBLE_ROUNDING)
    let coords = |x: Vec3| 1.0 + x.abs().max(test.receiver.centroid().abs()).max_element() / test.receiver.radius();
    let mostly_hidden = |x: Vec3, (hidden, free): (f64, Option<f64>)| {
        free.is_some_and(|f| f - hidden <= VISIBLE_SHARE * f + VISIBLE_ROUNDING * coords(x))
    };
    // a free F too small for the share of it visible to say anything (see UNINFORMATIVE)
    let below_rounding =
        |x: Vec3, free: Option<f64>| free.is_some_and(|f| f <= UNINFORMATIVE * VISIBLE_ROUNDING * coords(x));
    // some point 1e-6 inside t's corners or edge midpoints sees a free F above rounding and
    // more than a small share of it (see UNINFORMATIVE)
    let seen_at_edges = |t: &[Vec3; 3], bl: &[&Polygon]| {
        just_inside(t).into_iter().any(|y| {
            let v = point(y, bl, true);
            !below_rounding(y, v.1) && !mostly_hidden(y, v)
        })
    };
    let rule = source_rule(o.tol);
    let radon = rule.len() == 7;
    // (see VISIBLE_SPREAD_LINEAR)
    let visible_spread = if radon { COARSE_SPREAD } else { VISIBLE_SPREAD_LINEAR };
    // the rule's point at the centroid, if it has one (Radon's does): the coarse start's
    // centroid value is then that sample (one evaluation of eight saved at tight targets)
    let centroid_sample = rule.iter().position(|(b, _)| *b == [1.0 / 3.0; 3]);
    // (the source's own plane: a start piece's, set by its vertices, tilts by rounding over a
    // sliver; see `plane` above)
    let cuts: Vec<Option<(Vec3, Vec3)>> = blockers.iter().map(|b| plane_chord(b, plane.0, plane.1)).collect();
    // true where a blocker among `active` passes through or touches the source's plane within
    // two sizes of t: there the shadowed F is not smooth at any scale
    let near_cut =
        |t: &[Vec3; 3], active: &[usize]| active.iter().any(|&k| cuts[k].is_some_and(|(p, q)| near_segment(t, p, q)));
    // true where t touches the receiver's plane (the source's part in front of the receiver
    // ends there, or the two share an edge): there the point F falls to 0 like the height
    // over that plane, and the shadows of blockers that touch the receiver turn with it, so
    // the hidden F is not smooth to the rule's degree. Two leaves along such an edge had
    // Radon's rule 7.5e-4 and 9e-4 off (a leaf's children's rule 2e-4 off, its estimate a
    // quarter of its difference from the leaf's rule: 18 x too small), the pair 2.7 x tol at
    // the default (seed 47 of tests/test_properties.py). The building of bench/scenes.py
    // spends 0.4 % more work units at obstructed_tol 1e-3, 0.01 % at the default.
    // how many of t's corners lie on the plane (q, n), within t's rounding
    let on_plane = |t: &[Vec3; 3], (q, n): (Vec3, Vec3)| {
        let eps = triangle_eps(t);
        t.iter().filter(|x| n.dot(**x - q).abs() <= eps).count()
    };
    let receiver_plane = (test.receiver.centroid(), test.receiver.normal());
    let near_receiver_plane = |t: &[Vec3; 3]| on_plane(t, receiver_plane) >= 1;
    // true where an edge of t lies on a kink plane that holds an edge of the source (see
    // `split_at_kinks_along`): the plane through a receiver edge and a blocker edge bounds
    // the source there, and the hidden (or visible) F can sit in a layer along it. A blocker
    // hovering 1e-8 over the receiver let light through a wedge whose events all lay in the
    // plane of the source's edge: leaves along that edge had their rule 18 % off and claimed
    // 20 x less (the pair 1.3 and 2.1 x tol off at 1e-7 and 1e-8)
    let along_kink = |t: &[Vec3; 3]| along.iter().any(|&plane| on_plane(t, plane) >= 2);
    // The ends of the blockers' traces inside the source (farther than 1e-9 of its size from
    // its outline): there an edge of the blocker pierces the source's plane. A wall standing
    // on a floor patch ends on the patch's edge, and such ends are left out: there the wall
    // is large and the samples see its shadow at every scale.
    let reach = outline.iter().map(|x| x.distance(plane.0)).fold(0.0, f64::max);
    let interior = |x: Vec3| {
        (0..outline.len()).all(|k| segment_distance(x, x, outline[k], outline[(k + 1) % outline.len()]) > 1e-9 * reach)
            && start.iter().any(|t| inside_triangle(t, x, triangle_eps(t)))
    };
    let pierce: Vec<Vec<Vec3>> = cuts
        .iter()
        .map(|c| c.map_or(Vec::new(), |(p, q)| [p, q].into_iter().filter(|&x| interior(x)).collect()))
        .collect();
    // The largest hidden F just off a pierce point in t (1e-6 of the way to each corner and to
    // the centroid), 0 for none: close to a pierce point the hidden F depends on the direction
    // from it and not on the distance, so these are its limits there.
    let pierce_limit = |t: &[Vec3; 3], active: &[usize], bl: &[&Polygon]| {
        let eps = triangle_eps(t);
        let c = centroid3(t);
        let mut most = 0.0_f64;
        for e in active.iter().flat_map(|&k| &pierce[k]).filter(|&&e| inside_triangle(t, e, eps)) {
            for x in t.iter().chain([&c]).filter(|x| x.distance(*e) > eps) {
                most = most.max(point(*e + (*x - *e) * 1e-6, bl, false).0);
            }
        }
        most
    };
    let pick = |active: &[usize]| active.iter().map(|&k| casters[k]).collect::<Vec<&Polygon>>();
    // the integrand of a hidden or a visible leaf at a point
    let corner = |y: Vec3, bl: &[&Polygon], visible: bool| part(visible, point(y, bl, visible));
    // The largest hidden F just inside t at its corners and the midpoints of its edges (1e-6
    // of the way to the centroid), for a leaf descending from a blind start piece whose
    // children's samples are all 0 too. A steep hidden F along an edge or in a corner of the
    // leaf, between a cut and a shadow line a few percent of the leaf away, lies beyond every
    // sample of the leaf and its children, which then agree on 0; the leaf counts its area
    // times the largest limit as error until its samples reach it. Long-run seed 41: a sliver
    // piece 0.008 x 0.14 along the trace of a face piercing the source, 2e-2 hidden in its
    // corner, 0 at its 35 samples (4.0 x tol at the default); a needle cut along an obstacle's
    // plane, 6e-3 hidden within 1 % of its length, all leaves there 0 to the end (the obstacle
    // raised F by 5 x tol at every tol; `a_blind_start_piece_asks_the_limits_at_its_edges`).
    // The building of bench/scenes.py: the same F, 0.35 % more work units at
    // obstructed_tol 1e-3, 0.02 % at the default.
    // A leaf of the visible part asks them whether or not a sample is lit: there a gap
    // between shadows lets light through in a corner, and a sample lit at a rounding's level
    // says nothing of it. Long-run seed 53: a start piece, 35 samples dark but one at 1e-31,
    // light coming through within 1.5 % of its size of a corner (visible F 2.4e-5 of a free
    // 0.43), 1.6e-6 of the hidden part missed, claiming the default goal met; seed 49 moved
    // likewise (tests/test_properties.py). The building: 1.3 % more work units at 1e-3
    // (7.00 -> 7.10 M), 0.3 % at the default (124.9 -> 125.2 M), rows as before.
    let edge_limit = |t: &[Vec3; 3], bl: &[&Polygon], visible: bool| {
        just_inside(t).map(|y| corner(y, bl, visible)).into_iter().fold(0.0, f64::max)
    };
    // Radon's samples' quadratic, or the 3-point rule's samples' plane, extrapolated to the
    // corners (see EDGE_SHARE and LINEAR_EDGE_SHARE)
    let extrapolation = if radon { radon7_corner_weights() } else { strang_fix3_corner_weights() };
    // how far the corner values depart from it
    let deviation = |e: &Edge| {
        (0..3)
            .map(|k| (e.corners[k] - extrapolation[k].iter().zip(&e.samples).map(|(a, b)| a * b).sum::<f64>()).abs())
            .fold(0.0, f64::max)
    };
    // ... if by more than EDGE_SHARE of the largest value
    let edge_share = if !radon {
        LINEAR_EDGE_SHARE
    } else if o.tol < EDGE_TIGHT_BELOW {
        EDGE_SHARE_TIGHT
    } else {
        EDGE_SHARE
    };
    let departure = |e: &Edge| {
        let most = e.samples.iter().chain(&e.corners).fold(0.0_f64, |m, v| m.max(v.abs()));
        Some(deviation(e)).filter(|&dev| dev > edge_share * most)
    };
    // The samples must see where the unobstructed F gathers: two faces nearly in one plane,
    // facing each other across a gap 1e-8 of their size wide where their edges meet, see each
    // other only within a band as wide along that edge (F 1e-8). A blocker standing across the
    // gap hid all but 3e-12 of it, but every sample lay far from the band: the start pieces'
    // unobstructed G by their samples was 1e-16 of the exact 2.5e-9, the hidden part followed
    // them, and the pair claimed the default goal met with nothing hidden when the scene was
    // moved (seed 36 of tests/test_properties.py). Where the centroid rule over the start
    // pieces puts the source's unobstructed G more than MASS_FACTOR off (one contour sum per
    // start piece in every integral), the integral's final leaves (and the pieces no blocker
    // reaches) give the unobstructed G by their samples at its end, and how far that lies
    // from the exact one counts as error: the part of it their samples do not see may be
    // hidden or not. (Holding each piece to its own exact G instead cost 1-70 ms a piece
    // where the band is, and no refinement reached it.)
    let rough_free = |t: &[Vec3; 3]| rule_points(&rule, t).map(|(x, w)| w * (integrand.quick_free)(x)).sum::<f64>();
    // (the exact unobstructed G, where the check is due)
    let missed = integrand.free.filter(|&f| {
        let rough: f64 = start.iter().map(|t| area3(t) * (integrand.quick_free)(centroid3(t))).sum();
        (f - rough).abs() > goal && !(rough * MASS_FACTOR >= f && rough <= MASS_FACTOR * f)
    });
    // the pieces no blocker reaches, for that check
    let mut unreached: Vec<[Vec3; 3]> = Vec::new();
    // the leaf's children values and error estimate
    let refine = |l: &mut Leaf| {
        let bl = pick(&l.active);
        let (zero, lit) = (std::cell::Cell::new(false), std::cell::Cell::new(false));
        let g = |x: Vec3| {
            let v = part(l.visible, point(x, &bl, l.visible));
            if v == 0.0 {
                zero.set(true)
            } else {
                lit.set(true)
            }
            v
        };
        let k = split_in_four(&l.t);
        // the kids' rule values, the spread of their samples and their linear gap (see below)
        let (mut lo, mut hi, mut linear_gap) = (f64::INFINITY, 0.0_f64, 0.0);
        let mut kid_samples = [[0.0; 7]; 4];
        let kids = [0, 1, 2, 3].map(|i| {
            let (mut sum, mut mean) = (0.0, 0.0);
            for (j, (x, w)) in rule_points(&rule, &k[i]).enumerate() {
                let v = g(x);
                (lo, hi) = (lo.min(v), hi.max(v));
                sum += w * v;
                mean += v;
                kid_samples[i][j] = v;
            }
            linear_gap += (sum - area3(&k[i]) * mean / rule.len() as f64).abs();
            sum
        });
        // |kids - whole| bounds the coarse value's error; the kids' sum (what is returned) is
        // better by 2^6 on smooth pieces and by 2^3 next to an unsplit kink: count a quarter.
        // A leaf whose samples are partly 0 holds the edge of the region the shadow reaches,
        // where the shadowed F starts without a smooth transition and a small shadow may be
        // caught by few samples: count the whole difference there (300 room pairs at tol 1e-5:
        // largest error 4.7e-5 -> 8.1e-6 of the unobstructed F, 3 % more evaluations).
        // A leaf next to where a blocker passes through or touches the source's plane (the blocker
        // reaches the source points, their shadowed F is not smooth there at any scale) gets
        // the whole difference too (three mutually blocking triangles: error 5.1 x tol at
        // 1e-6 with a quarter, docs/algorithms.md §6.2).
        let weight = if (zero.get() && lit.get())
            || near_cut(&l.t, &l.active)
            || near_receiver_plane(&l.t)
            || along_kink(&l.t)
        {
            1.0
        } else {
            0.25
        };
        l.err = weight * (kids.iter().sum::<f64>() - l.whole).abs();
        // A leaf whose samples spread by more than COARSE_SPREAD is not yet where the rule
        // converges fast (the point F rises steeply towards a blocker close to the source),
        // and there the rule and the children's can agree by chance: a start piece whose
        // samples ran from 1.7e-4 to 5.9e-3 had both 0.19 % off and agreeing to 7e-6 (64 x tol
        // at the default, `a_steep_start_piece_is_not_trusted_on_one_level`). It counts at
        // least STEEP_SHARE of how far its children's rule lies from their equal-weight
        // (linear) rule, which takes it on to its grandchildren where that matters. At every
        // depth, not only on start pieces: whether a steep stretch falls into a start piece or
        // into a leaf further down depends on how the pieces happen to be cut, and a leaf two
        // levels down whose samples spread 27-fold had both 0.07 % off and agreeing to 7e-11
        // (2.9 x tol at the default, `a_steep_leaf_is_not_trusted_on_one_level_at_any_depth`).
        // Under the equal-weight rule (targets from LOW_DEGREE_TOL on) that gap is 0: there
        // the leaf counts its children's difference without their cancellation instead, at the
        // weight above (`uncancelled_difference`). A start piece at a corner of the source,
        // its samples 5.3e-4 .. 7.8e-3 rising towards it, had its rule 9.1e-5 off and its
        // children's 8.8e-5 (the corner child's departure from the parent's samples, 8.2e-5,
        // offset by the others'): 3.1e-6 apart, the uncancelled difference 7.6e-5; at
        // obstructed_tol 1e-2 and 3e-3 the pair was 3.2 and 10.7 x tol low, now 0.07 and 0.05
        // (`a_steep_leaf_under_the_equal_weight_rule_is_not_trusted_by_chance`).
        if lo > 0.0 && hi > COARSE_SPREAD * lo {
            // (see VERY_STEEP)
            if !radon && hi > VERY_STEEP * lo {
                l.err *= 2.0;
            }
            l.err = l.err.max(STEEP_SHARE * linear_gap);
            if let Some(p) = l.points {
                l.err = l.err.max(weight * uncancelled_difference(area3(&l.t), l.whole, p, &kids));
            }
        }
        if l.kinked && lo > 0.0 && hi > COARSE_SPREAD * lo {
            l.err = l.err.max(KINKED_SHARE * kids.iter().sum::<f64>().abs());
        }
        // A leaf with a pierce point in it may hold a spike of the hidden F there, as wide as
        // the blocker's part close to the plane, that no sample of it or its children reaches:
        // it counts its area times the spike's height (the limit at the pierce point) until it
        // is small enough. A sliver start piece 0.18 long, cornered at the point where a face
        // 0.007 in front pierced the source, had its rule and its children's agreeing at
        // 3.8e-10 for 2.9e-7, 8.9 x the goal at the default; the hidden F rose to 0.6 at that
        // corner (`a_leaf_where_a_blocker_pierces_the_source_asks_the_limit_there`). The
        // building of bench/scenes.py has no such point: its work is unchanged.
        if !l.visible {
            l.err = l.err.max(area3(&l.t) * pierce_limit(&l.t, &l.active, &bl));
        }
        if l.blind && (l.visible || !lit.get()) {
            l.err = l.err.max(area3(&l.t) * edge_limit(&l.t, &bl, l.visible));
        }
        // (a leaf of either part may carry an edge: see where edges are set)
        if let Some(e) = l.edge {
            l.err = l.err.max(area3(&l.t) * departure(&e).unwrap_or(0.0));
            // the kids' corners: the leaf's own and its edges' midpoints
            let inside = just_inside(&l.t);
            let m = [3, 4, 5].map(|k| corner(inside[k], &bl, l.visible));
            let v = e.corners;
            let corners = [[v[0], m[0], m[2]], [m[0], v[1], m[1]], [m[2], m[1], v[2]], [m[0], m[1], m[2]]];
            l.kid_edges = Some(std::array::from_fn(|i| Edge { samples: kid_samples[i], corners: corners[i] }));
        }
        l.kids = Some(kids);
        if !radon {
            l.kid_points = Some(kid_samples.map(|p| [p[0], p[1], p[2]]));
        }
    };
    let mut heap = BinaryHeap::new();
    // the unobstructed G of the visible leaves' pieces, less that of their children that no
    // blocker reaches (whose visible part is all of it)
    let mut offset = 0.0;
    let all: Vec<usize> = (0..blockers.len()).collect();
    let coarse_start = o.tol >= COARSE_START_TOL;
    let mut samples = Vec::with_capacity(rule.len());
    for (&t, &kinked) in start.iter().zip(kinked) {
        let mut active = Vec::new();
        test.active(&t, &all, &mut active);
        if active.is_empty() {
            if missed.is_some() {
                unreached.push(t);
            }
            continue;
        }
        let bl = pick(&active);
        samples.clear();
        samples.extend(rule_points(&rule, &t).map(|(x, w)| (x, w, point(x, &bl, false))));
        let (lo, hi) = bounds(samples.iter().map(|s| s.2 .0));
        // (the free F only where the hidden part is steep: a contour sum per sample saved)
        if hi > visible_spread * lo && lo > 0.0 {
            for (x, _, v) in samples.iter_mut() {
                v.1 = Some((integrand.free_point)(*x));
            }
        }
        let free = if samples.iter().all(|s| mostly_hidden(s.0, s.2))
            && !(samples.iter().all(|s| below_rounding(s.0, s.2 .1)) && seen_at_edges(&t, &bl))
        {
            let rough: f64 = samples.iter().map(|&(_, w, v)| w * v.1.unwrap_or(0.0)).sum();
            let allowed = PIECE_FREE_TOL * goal;
            // (the free F at the samples spreads: asked only when the samples' G is small)
            let free_spreads = || {
                let (flo, fhi) = bounds(samples.iter().map(|s| s.2 .1.unwrap_or(0.0)));
                fhi > COARSE_SPREAD * flo
            };
            if rough > allowed {
                (integrand.piece_free)(&t, allowed / rough)
            } else if free_spreads() {
                // (samples whose free F spreads may all lie below its rise towards an edge
                // or vertex the pair shares: the piece's own G says, to a tenth of the goal)
                (integrand.piece_free)(&t, PIECE_FREE_TOL * o.tol).filter(|&g| g > allowed)
            } else {
                None
            }
        } else {
            None
        };
        let visible = free.is_some();
        offset += free.unwrap_or(0.0);
        let whole = samples.iter().map(|&(_, w, v)| w * part(visible, v)).sum::<f64>();
        let (least, most) = bounds(samples.iter().map(|&(_, _, v)| part(visible, v)));
        // A start piece all of whose samples are 0 although a blocker meets its shaft may hold
        // a shadow that starts between them (its centroid is 0 too, so the coarse estimate is
        // 0): it gets its children. First seen next to where a blocker reaches the source's
        // plane (a blocker in the plane of another face, both through the source's vertex:
        // 61 x tol at 1e-6, docs/algorithms.md §6.2); then away from it, where a second
        // blocker's kinks had cut the start into smaller pieces (53 x tol at 1e-6, the replay
        // in tests/test_properties.py). Costs nothing measurable: the building at 1e-3 12.5 s
        // either way, the room with a crate at 1e-6 1.9 s. (A visible piece all 0 may hold
        // a gap between the shadows in the same way.)
        let blind = whole == 0.0;
        // So does a piece a blocker's trace on the source's plane reaches into (the shadowed F
        // is not smooth there at any scale). A trace along the piece's edge, such as the foot
        // of a wall standing on a floor patch's edge, only bounds it: the F is smooth up to
        // the edge (the wall hides what lies beyond its plane alike from all points near it).
        // The building of bench/scenes.py at obstructed_tol 1e-3: 60 326 -> 25 923 start
        // pieces refined at once, 7 % fewer evaluations and CPU, row sums 2.09e-4 -> 1.70e-4.
        // (a source the split left whole, one start piece, is not trusted to the coarse
        // estimate: a blocker crossing both planes away from the pair, whose shadow moves
        // smoothly over the receiver, left it 9 x tol off at 1e-3 with the rule and the
        // centroid erring alike; the seed-31 replay of tests/test_properties.py)
        let coarse = coarse_start
            && start.len() > 1
            && !blind
            && !kinked
            && !active.iter().any(|&k| cuts[k].is_some_and(|(p, q)| reaches_into(&t, p, q)));
        let points = (!radon).then(|| [0, 1, 2].map(|j| part(visible, samples[j].2)));
        // (under the 3-point rule where the samples spread, or on a sliver: see
        // LINEAR_EDGE_SHARE and SLIVER_PROBE)
        let probe = (!blind && (radon || hi > COARSE_SPREAD * lo || aspect(&t) > SLIVER_PROBE)).then(|| {
            let inside = just_inside(&t);
            Edge {
                samples: std::array::from_fn(|j| samples.get(j).map_or(0.0, |s| part(visible, s.2))),
                corners: [0, 1, 2].map(|k| corner(inside[k], &bl, visible)),
            }
        });
        // how far the corners depart from the samples' quadratic, however little (see
        // DEPARTURE_SHARE)
        // (Radon's rule only: a linear fit departs at the corners by the curvature's share)
        let raw_dev = if radon { probe.as_ref().map_or(0.0, deviation) } else { 0.0 };
        let edge = probe.filter(|e| departure(e).is_some());
        // (see COARSE_MOST)
        let coarse = coarse && edge.is_none() && (radon || whole.abs() <= COARSE_MOST * goal);
        let mut l = Leaf {
            t,
            visible,
            whole,
            kids: None,
            err: 0.0,
            depth: 0,
            active,
            kinked,
            points,
            kid_points: None,
            blind,
            edge,
            kid_edges: None,
        };
        if coarse {
            // children only where needed (see COARSE_START_TOL)
            let c = match centroid_sample {
                Some(k) => part(visible, samples[k].2),
                None => part(visible, point(centroid3(&t), &bl, visible)),
            };
            let centre = area3(&t) * c;
            if most.max(c) <= COARSE_SPREAD * least.min(c) {
                l.err = 2.0 * (whole - centre).abs();
            } else {
                refine(&mut l);
            }
        } else {
            refine(&mut l);
        }
        // (see DEPARTURE_SHARE)
        l.err = l.err.max(DEPARTURE_SHARE * raw_dev * area3(&t));
        heap.push(l);
    }
    // (the start pieces that integrate the visible part count their exact unobstructed G)
    let counted = offset;
    let mut total_err: f64 = heap.iter().map(|l| l.err).sum();
    let mut done = Vec::new(); // leaves at the depth limit
                               // [methods] `go_on`: stop at cancellation or when the pair's work budget is spent
    while total_err > goal && evals.get() < o.max_evals && crate::work::go_on() {
        let Some(mut worst) = heap.pop() else { break };
        total_err -= worst.err;
        let Some(kids) = worst.kids else {
            refine(&mut worst);
            total_err += worst.err;
            heap.push(worst);
            continue;
        };
        if worst.depth >= o.max_depth {
            total_err += worst.err;
            done.push(worst);
            continue;
        }
        for (i, (k, whole)) in split_in_four(&worst.t).into_iter().zip(kids).enumerate() {
            let mut active = Vec::new();
            test.active(&k, &worst.active, &mut active);
            if active.is_empty() {
                if missed.is_some() && !worst.visible {
                    unreached.push(k);
                }
                // nothing hidden there: exactly 0 (its whole value is 0 up to rounding), or
                // for a visible leaf all of the child's unobstructed G
                if worst.visible {
                    let tol = PIECE_FREE_TOL * goal / whole.abs().max(f64::MIN_POSITIVE);
                    offset -= (integrand.piece_free)(&k, tol).unwrap_or(whole);
                }
                continue;
            }
            let depth = worst.depth + 1;
            let points = worst.kid_points.map(|p| p[i]);
            let mut l = Leaf {
                t: k,
                visible: worst.visible,
                whole,
                kids: None,
                err: 0.0,
                depth,
                active,
                kinked: false,
                points,
                kid_points: None,
                blind: worst.blind,
                edge: worst.kid_edges.map(|e| e[i]).filter(|e| depth <= EDGE_DEPTH && departure(e).is_some()),
                kid_edges: None,
            };
            refine(&mut l);
            total_err += l.err;
            heap.push(l);
        }
        // guard against drift of the running sum
        total_err = total_err.max(0.0);
    }
    // (see `missed`: the leaves' own samples, or their children's once computed)
    if let Some(free) = missed {
        let seen = |l: &Leaf| {
            if l.kids.is_some() {
                split_in_four(&l.t).iter().map(rough_free).sum()
            } else {
                rough_free(&l.t)
            }
        };
        let hidden_part = heap.iter().chain(&done).filter(|l| !l.visible);
        let rough = hidden_part.map(seen).sum::<f64>() + unreached.iter().map(rough_free).sum::<f64>();
        let unseen = (free - counted - rough).abs();
        if unseen > goal {
            total_err += unseen;
        }
    }
    (offset + heap.iter().chain(done.iter()).map(Leaf::hidden).sum::<f64>(), total_err)
}

#[cfg(test)]
mod tests {
    use super::super::{pair, Context, Estimator};
    use super::*;
    use crate::quadrature::gauss_legendre;
    use crate::unobstructed::method::{self, Method};
    use crate::visibility::{Bvh, Occluders};

    /// G of the pair (i, j) of `polys` by `clipping`, every other polygon a blocker, its
    /// unobstructed G to `exact_tol`.
    fn clipping(polys: &[Polygon], i: usize, j: usize, o: &ClippingOptions, exact_tol: f64) -> f64 {
        clipping_estimate(polys, i, j, o, exact_tol).value
    }

    /// [`clipping`] with the estimate's error (see [`pair`]).
    fn clipping_estimate(polys: &[Polygon], i: usize, j: usize, o: &ClippingOptions, exact_tol: f64) -> Estimate {
        let occ = Occluders::new(polys);
        let bvh = Bvh::new(&occ.polygons).unwrap();
        let ctx = Context { polygons: polys, occluders: &occ, vis: &bvh, rules: None, exact_tol };
        pair(&ctx, i, j, &Estimator::Clipping(*o)).unwrap()
    }

    /// A pair whose integral runs out of evaluations short of its goal reports its error
    /// estimate, and that covers the true error; one that meets its goal reports 0. A wall of
    /// height h = 1/2 stands on the source's edge x = 0 (and reaches beyond both polygons
    /// along y); the receiver lies at z = 1. From a source point at x0 the line to a receiver
    /// point at xr clears the wall where x0 / (x0 - xr) > h, so the point sees the rectangle
    /// xr >= x0 (1 - 1/h) (>= -1 for x0 <= 1) whole: the reference is Lambert's F of that
    /// rectangle, integrated over the source by a 48 x 48 Gauss-Legendre rule (smooth).
    #[test]
    fn an_integral_out_of_evaluations_reports_its_error() {
        let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        let h = 0.5;
        let source = facing_quad(vec![v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.0, 1.0, 0.0), v(0.0, 1.0, 0.0)], Vec3::Z);
        let receiver =
            facing_quad(vec![v(-1.0, 0.0, 1.0), v(1.0, 0.0, 1.0), v(1.0, 1.0, 1.0), v(-1.0, 1.0, 1.0)], -Vec3::Z);
        let wall = facing_quad(vec![v(0.0, -1.0, 0.0), v(0.0, 2.0, 0.0), v(0.0, 2.0, h), v(0.0, -1.0, h)], Vec3::X);
        let rule = gauss_legendre(48);
        let mut exact = 0.0;
        for &(x0, wx) in rule {
            for &(y0, wy) in rule {
                let lo = x0 * (1.0 - 1.0 / h);
                let seen = [v(lo, 0.0, 1.0), v(lo, 1.0, 1.0), v(1.0, 1.0, 1.0), v(1.0, 0.0, 1.0)];
                exact += wx * wy * point_polygon(v(x0, y0, 0.0), Vec3::Z, &seen);
            }
        }
        let free = polygon_pair_within(&source, &receiver, 0.0);
        assert!(exact < 0.9 * free && exact > 0.3 * free, "{exact} of {free}");
        let polys = [source, receiver, wall];
        let mut short = 0;
        for max_evals in [20, 60, 200, 600] {
            let o = ClippingOptions { tol: 1e-6, max_evals, ..Default::default() };
            let e = clipping_estimate(&polys, 0, 1, &o, 1e-12);
            let err = (e.value - exact).abs();
            if e.std_err > 0.0 {
                short += 1;
                assert!(e.std_err > 1e-6 * free, "max_evals {max_evals}: reports {:e}, within its goal", e.std_err);
                assert!(err <= e.std_err, "max_evals {max_evals}: error {err:e}, reports {:e}", e.std_err);
            } else {
                assert!(err <= 1e-6 * free, "max_evals {max_evals}: error {err:e} reported met");
            }
        }
        assert!(short >= 2, "{short} of 4 budgets ran out");
        let e = clipping_estimate(&polys, 0, 1, &ClippingOptions { tol: 1e-6, ..Default::default() }, 1e-12);
        assert_eq!(e.std_err, 0.0);
        assert!((e.value - exact).abs() <= 1e-6 * free, "{:e} for {exact:e}", e.value);
    }

    /// G of the pair (i, j) of `polys` integrated over polygon i, whichever side the
    /// clearances choose (every other polygon a blocker).
    fn over_first(polys: &[Polygon], i: usize, j: usize, o: &ClippingOptions) -> f64 {
        use super::super::{casting, clip_pair_polygons, hidden_band};
        use crate::visibility::Visibility;
        let occ = Occluders::new(polys);
        let bvh = Bvh::new(&occ.polygons).unwrap();
        let (a, b) = (&polys[i], &polys[j]);
        let (ca, cb) = clip_pair_polygons(a, b).unwrap();
        let (sa, sb) = (ca.as_ref().unwrap_or(a), cb.as_ref().unwrap_or(b));
        let mut cand = Vec::new();
        bvh.candidates_between(sa, sb, &[occ.owner[i], occ.owner[j]], &mut cand);
        let blockers: Vec<&Polygon> = cand.iter().map(|&k| &occ.polygons[k as usize]).collect();
        let cast = casting(sa, &blockers, hidden_band(&Estimator::Clipping(*o)));
        let free = polygon_pair_within(a, b, 0.0);
        let (hidden, _) = hidden_over((a, b, sa, sb), &blockers, &cast, (free, o.tol * free), o);
        (free - hidden).clamp(0.0, free)
    }

    /// Asserts that `clipping` gives the G of pair (i, j) within tol x `free` of `reference`
    /// at each of `tols`.
    fn assert_meets(polys: &[Polygon], (i, j): (usize, usize), reference: f64, free: f64, tols: &[f64]) {
        for &tol in tols {
            let g = clipping(polys, i, j, &ClippingOptions { tol, ..Default::default() }, 1e-12);
            let off = (g - reference) / (tol * free);
            assert!(off.abs() <= 1.0, "tol {tol:e}: G {g:e}, {off:.2} x tol");
        }
    }

    /// Asserts that the integral of pair (i, j) over polygon i (the side a long run found
    /// wrong) at each of `side_tols`, and the pair at each of `tols`, meet the reference: the
    /// integral over polygon j at 1e-9 (an identity). Returns the reference and the free G.
    fn assert_side_meets_the_other(
        polys: &[Polygon],
        (i, j): (usize, usize),
        side_tols: &[f64],
        tols: &[f64],
    ) -> (f64, f64) {
        let free = polygon_pair_within(&polys[i], &polys[j], 0.0);
        let reference = over_first(polys, j, i, &ClippingOptions { tol: 1e-9, ..Default::default() });
        for &tol in side_tols {
            let g = over_first(polys, i, j, &ClippingOptions { tol, ..Default::default() });
            let off = (g - reference) / (tol * free);
            assert!(off.abs() <= 1.0, "({i}, {j}) tol {tol:e}: G {g:e} for {reference:e}: {off:.2} x tol");
        }
        assert_meets(polys, (i, j), reference, free, tols);
        (reference, free)
    }

    /// A uniformly random point of triangle t.
    fn in_triangle(rng: &mut crate::visibility::bvh::tests::Rng, t: &Polygon) -> Vec3 {
        let w = t.vertices();
        crate::sampling::uniform_triangle([rng.f(), rng.f()], w[0], w[1], w[2])
    }

    /// Triangles from literal vertex lists.
    fn triangles(raw: &[[[f64; 3]; 3]]) -> Vec<Polygon> {
        raw.iter().map(|p| Polygon::new(p.iter().map(|&v| Vec3::from_array(v)).collect()).unwrap()).collect()
    }

    /// Every index of `blockers`: all of them cast.
    fn every<T>(blockers: &[T]) -> Vec<usize> {
        (0..blockers.len()).collect()
    }

    /// `auto`'s default `tol`: the unobstructed G of a pair nobody computed for it.
    fn auto_tol() -> f64 {
        method::Options::default().tol
    }

    /// A quad with the given corners, turned to face along `normal`.
    fn facing_quad(mut v: Vec<Vec3>, normal: Vec3) -> Polygon {
        if (v[1] - v[0]).cross(v[2] - v[0]).dot(normal) < 0.0 {
            v.reverse();
        }
        Polygon::new(v).unwrap()
    }

    /// The faces of the box [lo, hi], facing out.
    fn box_faces(lo: Vec3, hi: Vec3) -> Vec<Polygon> {
        let mut out = Vec::new();
        for axis in 0..3 {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            for (side, sign) in [(lo, -1.0), (hi, 1.0)] {
                let corner = |a: f64, b: f64| {
                    let mut p = side.to_array();
                    (p[u], p[w]) = ([lo, hi][a as usize].to_array()[u], [lo, hi][b as usize].to_array()[w]);
                    Vec3::from_array(p)
                };
                let normal = Vec3::from_array(std::array::from_fn(|k| if k == axis { sign } else { 0.0 }));
                out.push(facing_quad(vec![corner(0., 0.), corner(1., 0.), corner(1., 1.), corner(0., 1.)], normal));
            }
        }
        out
    }

    /// A blocker standing on the source's plane and reaching up towards the receiver: the
    /// integral runs over the receiver (the side the blocker keeps away from), whichever way
    /// round the pair is asked for, so both orders give the same G bit for bit, within tol of
    /// a tight reference.
    #[test]
    fn the_integral_runs_over_the_side_away_from_the_blockers() {
        let plate = |z: f64, up: bool| {
            facing_quad(
                vec![Vec3::new(0.0, 0.0, z), Vec3::new(1.0, 0.0, z), Vec3::new(1.0, 1.0, z), Vec3::new(0.0, 1.0, z)],
                if up { Vec3::Z } else { -Vec3::Z },
            )
        };
        let blocker = facing_quad(
            vec![
                Vec3::new(0.3, -0.2, -0.1),
                Vec3::new(0.6, -0.2, 0.5),
                Vec3::new(0.6, 0.7, 0.5),
                Vec3::new(0.3, 0.7, -0.1),
            ],
            Vec3::new(-2.0, 0.0, 1.0),
        );
        let polys = vec![plate(0.0, true), plate(1.0, false), blocker];
        assert!(clearance(&polys[0], &[&polys[2]]) < clearance(&polys[1], &[&polys[2]]));
        let o = ClippingOptions { tol: 1e-5, ..Default::default() };
        let (g01, g10) = (clipping(&polys, 0, 1, &o, 1e-12), clipping(&polys, 1, 0, &o, 1e-12));
        assert_eq!(g01.to_bits(), g10.to_bits());
        let reference = clipping(&polys, 0, 1, &ClippingOptions { tol: 1e-10, max_evals: 2_000_000, ..o }, 1e-12);
        let free = method::area_factor(&polys[0], &polys[1], Method::Analytic, &Default::default(), None).unwrap();
        assert!(reference < 0.9 * free && reference > 0.1 * free, "hidden fraction {}", 1.0 - reference / free);
        assert!(
            (g01 - reference).abs() <= 1e-5 * free,
            "error {:.2e} of the unobstructed G",
            (g01 - reference).abs() / free
        );
    }

    /// A wall tile and a ceiling tile on either side of a crate's vertical edge: the edge's
    /// shadow crosses the ceiling tile nearly parallel to one of its edges (3.6 degrees), so
    /// the shadowed F turns from linear to 0 within 3 % of the source's width (a near-kink that
    /// only the vertex-edge cuts expose; without them the error at tol 1e-4 was 2.2e-4 of
    /// the unobstructed F). Each target is met against the result at tol 1e-10.
    #[test]
    fn nearly_parallel_edges_meet_the_target() {
        let (y0, y1, z0) = (5.0 / 7.0, 6.0 / 7.0, 6.0 / 7.0);
        let source = facing_quad(
            vec![Vec3::new(0.0, y0, z0), Vec3::new(0.0, y1, z0), Vec3::new(0.0, y1, 1.0), Vec3::new(0.0, y0, 1.0)],
            Vec3::X,
        );
        let (x0, y2) = (20.0 / 7.0, 4.0 / 7.0);
        let receiver = facing_quad(
            vec![Vec3::new(x0, y0, 3.0), Vec3::new(3.0, y0, 3.0), Vec3::new(3.0, y2, 3.0), Vec3::new(x0, y2, 3.0)],
            -Vec3::Z,
        );
        let mut polys = vec![source, receiver];
        polys.extend(box_faces(Vec3::new(0.8, 0.7, 1.1), Vec3::new(1.8, 1.7, 2.1)));
        let value = |tol: f64| clipping(&polys, 0, 1, &ClippingOptions { tol, ..Default::default() }, 1e-12);
        let free = method::area_factor(&polys[0], &polys[1], Method::Analytic, &Default::default(), None).unwrap();
        let reference = value(1e-10);
        assert!(reference > 0.05 * free && reference < 0.15 * free, "visible fraction {}", reference / free);
        for tol in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6] {
            let err = (value(tol) - reference).abs() / free;
            assert!(err <= tol, "tol {tol:e}: error {err:.2e} of the unobstructed F");
        }
    }

    /// Four triangles meeting at the origin, where a blocker touches the source along an
    /// edge and the receiver touches both at the shared vertex (found by a property test).
    fn vertex_faces(shift: Vec3, scale: f64) -> Vec<Polygon> {
        let raw = [
            [[0., 0., 0.], [0., 0., 1.], [0., 1., 0.]],
            [[0., 0., 0.], [0., -1., 0.], [-1., 0., 0.]],
            [[0., 0., 0.], [0., -1., 0.], [-1., 0., 0.25]],
            [[0., 1., -0.75], [0., 0., 0.], [1., 1., 1.]],
        ];
        raw.iter()
            .map(|p| Polygon::new(p.iter().map(|&v| scale * Vec3::from_array(v) + shift).collect()).unwrap())
            .collect()
    }

    /// Moved or scaled, the pair takes the same adaptive decisions: its G differs by rounding
    /// only (the kink split once classed the blocker vertices on the source's plane by the sign
    /// of their rounded distance, and the results were 28 x tol apart at tol 1e-3), and each
    /// meets its target against a tight reference.
    #[test]
    fn decisions_do_not_depend_on_where_the_scene_lies() {
        let g = |shift: Vec3, scale: f64, tol: f64| {
            let o = ClippingOptions { tol, max_evals: 2_000_000, ..Default::default() };
            clipping(&vertex_faces(shift, scale), 2, 3, &o, 1e-12) / (scale * scale)
        };
        let p = vertex_faces(Vec3::ZERO, 1.0);
        let free = method::area_factor(&p[2], &p[3], Method::Analytic, &Default::default(), None).unwrap();
        let reference = g(Vec3::ZERO, 1.0, 1e-10);
        assert!(reference < 0.8 * free, "hidden fraction {}", 1.0 - reference / free);
        for tol in [1e-2, 1e-3, 1e-4, 1e-6] {
            let here = g(Vec3::ZERO, 1.0, tol);
            assert!(
                (here - reference).abs() <= tol * free,
                "tol {tol:e}: error {:.2e} x tol",
                (here - reference).abs() / (tol * free)
            );
            for (shift, scale) in [
                (Vec3::splat(7.0), 1.0),
                (Vec3::new(-3.0, 5.0, 11.0), 1.0),
                (Vec3::ZERO, 1024.0),
                (Vec3::splat(7e3), 1e3),
            ] {
                let there = g(shift, scale, tol);
                assert!(
                    (there - here).abs() <= 1e-9 * free,
                    "tol {tol:e}, moved by {shift:?}, scaled by {scale}: {:.2e} x tol apart",
                    (there - here).abs() / (tol * free)
                );
            }
        }
    }

    /// Source and receiver meet at the origin, where the four blockers all pass through or
    /// touch the source's plane; two of them lie in the plane x = 0 (found by a property
    /// test). A start piece with an edge on that plane sees a shadow none of its samples
    /// catches: once it was never refined and G was 61 x tol off at the default 1e-6.
    #[test]
    fn a_shadow_between_the_samples_of_a_start_piece_is_found() {
        let raw: [[[f64; 3]; 3]; 6] = [
            [[1., 1., -1.], [0., -1., 0.], [-0.5, 0., 0.]],
            [[0., 0., 0.], [0., 0.5, 0.], [0.5, 0.75, -1.]],
            [[0., 0., 0.], [0., 0., 1.], [0., 1., 0.]],
            [[0., 0., 0.], [1., 0., 0.], [0., 0., 1.]],
            [[0., 0.5, -0.5], [-0.6875, 0.4375, 0.], [1., -1., 0.375]],
            [[0., 0., 1.], [0., 1., -1.], [0., 0., 0.]],
        ];
        let polys = triangles(&raw);
        let free = method::area_factor(&polys[0], &polys[1], Method::Analytic, &Default::default(), None).unwrap();
        let g = |tol: f64| {
            clipping(&polys, 0, 1, &ClippingOptions { tol, max_evals: 2_000_000, ..Default::default() }, auto_tol())
        };
        let reference = g(1e-10);
        assert!(reference < 0.99 * free, "hidden fraction {}", 1.0 - reference / free);
        for tol in [1e-3, 1e-4, 1e-5, 1e-6] {
            let err = (g(tol) - reference).abs() / free;
            assert!(err <= tol, "tol {tol:e}: error {:.2e} x tol", err / tol);
        }
    }

    /// Faces 0 and 2 lie in the plane x = 0 and meet at a vertex, a thin gap between them;
    /// the source (face 1) has an edge in that plane and cuts the receiver (face 3) to a small
    /// triangle, two of whose vertices the source's plane makes (found by the long property
    /// run, tests/test_properties.py). Where the gap's shadow crosses those vertices the
    /// shadowed F bends within a strip of a start piece that its samples missed: the kinks of
    /// the whole receiver do not have these events. G was 94 x tol off at the default 1e-6.
    #[test]
    fn kinks_of_the_receiver_part_in_front() {
        let raw: [[[f64; 3]; 3]; 4] = [
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.5, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.25], [-0.5, 0.5, 0.5]],
            [[0.0, 1.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0625, 1.0]],
            [[1.0, 0.0, -0.5], [0.0, 0.0, -1.0], [-1.0, 0.0, -1.0]],
        ];
        let polys = triangles(&raw);
        let free = method::area_factor(&polys[3], &polys[1], Method::Analytic, &Default::default(), None).unwrap();
        let g = |tol: f64| {
            clipping(&polys, 3, 1, &ClippingOptions { tol, max_evals: 2_000_000, ..Default::default() }, auto_tol())
        };
        let reference = g(1e-10);
        assert!(reference < 0.1 * free, "visible fraction {}", reference / free);
        for tol in [1e-4, 1e-5, 1e-6, 1e-7] {
            let err = (g(tol) - reference).abs() / free;
            assert!(err <= tol, "tol {tol:e}: error {:.2e} x tol", err / tol);
        }
    }

    /// Five triangles, three of them meeting at the origin, and an obstacle that hides nothing
    /// of the pair (2, 4) but meets its candidate shaft (found by the long property run,
    /// tests/test_properties.py). Its planes and events took the kink split's budget before
    /// the events bounding face 1's shadow on the source, whose samples then all missed it:
    /// G with the obstacle was 19 x tol above G without it at the default 1e-6, 2e5 x at 1e-10.
    #[test]
    fn a_blocker_that_hides_nothing_changes_nothing() {
        let raw: [[[f64; 3]; 3]; 6] = include!("../../../../tests/data/hidden_obstacle.txt");
        let all = triangles(&raw);
        let free = method::area_factor(&all[2], &all[4], Method::Analytic, &Default::default(), None).unwrap();
        let g = |polys: &[Polygon], i: usize, j: usize, tol: f64| {
            clipping(polys, i, j, &ClippingOptions { tol, max_evals: 2_000_000, ..Default::default() }, auto_tol())
        };
        let reference = g(&all[..5], 4, 2, 1e-10);
        assert!(reference < 0.99 * free, "hidden fraction {}", 1.0 - reference / free);
        for tol in [1e-4, 1e-6, 1e-8] {
            for (polys, i, j) in [(&all[..], 2, 4), (&all[..], 4, 2), (&all[..5], 2, 4)] {
                let err = (g(polys, i, j, tol) - reference).abs() / free;
                assert!(err <= tol, "{} polygons, ({i}, {j}), tol {tol:e}: error {:.2e} x tol", polys.len(), err / tol);
            }
        }
    }

    /// Every point evaluation counts against the pair's work budget, the start pieces' samples
    /// too: two unit squares 1 apart and a centred square blocker, the source integral at
    /// loose targets (at least 3 samples on each of at least 2 start pieces, each casting the
    /// one blocker) spends more than 5 units. The start pieces' samples were
    /// not counted: the building of bench/scenes.py reported 7.55 M units at obstructed_tol
    /// 1e-3 for 24.4 M spent, so a pair's budget saw under a third of its work.
    #[test]
    fn every_evaluation_counts_against_the_budget() {
        use crate::unobstructed::far_field::tests::square;
        let polys =
            [square(0.0, 0.0, 1.0, 0.0, true), square(0.0, 0.0, 1.0, 1.0, false), square(0.4, 0.4, 0.2, 0.5, true)];
        for tol in [1e-2, 1e-3] {
            let o = ClippingOptions { tol, ..Default::default() };
            let g = crate::work::metered(1 << 20, String::new, || Ok(clipping(&polys, 0, 1, &o, 1e-12))).unwrap();
            assert!(g < polygon_pair_within(&polys[0], &polys[1], 0.0));
            let short = crate::work::metered(5, String::new, || Ok(clipping(&polys, 0, 1, &o, 1e-12)));
            assert!(matches!(short, Err(crate::error::Error::Budget { .. })), "tol {tol:e}: {short:?}");
        }
    }

    /// Five faces meeting at the origin and an obstacle near face 2's plane (found by the long
    /// property run, tests/test_properties.py): face 3 hides face 2 from face 4 whole (every
    /// segment between random points of the two passes through it), and the two share the
    /// vertex (0, 1, 0). The obstacle turned the integral to face 4, where the hidden part is all
    /// of the point F and steep towards that vertex: G was 1.06e-4 of the unobstructed G at
    /// every tol, short of the budget. The pieces now integrate the visible part, 0. (The
    /// obstacle, hinged on face 2, crosses face 4's plane beside it, touching its edge, and
    /// hovers 2^-8 over its corner: it counts as about as close to both, and face 4's side is
    /// checked by itself.)
    #[test]
    fn a_hidden_touching_pair_integrates_the_visible_part() {
        use crate::visibility::bvh::tests::{ray_polygon, Rng};
        let raw: [[[f64; 3]; 3]; 6] = [
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
            [[0.00390625, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.00390625, 1.0, 0.0]],
        ];
        let polys = triangles(&raw);
        let mut rng = Rng::new(3);
        for _ in 0..10_000 {
            let (x, y) = (in_triangle(&mut rng, &polys[4]), in_triangle(&mut rng, &polys[2]));
            let t = ray_polygon(&polys[3], x, y - x).expect("face 3 hides the segment");
            assert!(t > 0.0 && t < 1.0);
        }
        let free = method::area_factor(&polys[4], &polys[2], Method::Analytic, &Default::default(), None).unwrap();
        for tol in [1e-4, 1e-6, 1e-8] {
            let o = ClippingOptions { tol, ..Default::default() };
            for (i, j) in [(4, 2), (2, 4)] {
                let g = if i == 4 { over_first(&polys, i, j, &o) } else { clipping(&polys, i, j, &o, auto_tol()) };
                assert!(
                    (0.0..=tol * free).contains(&g),
                    "({i}, {j}), tol {tol:e}: G {g:e}, {:.2e} x tol",
                    g / (tol * free)
                );
            }
        }
    }

    /// A thin source (face 4, 2^-8 thick) whose edge lies in the plane of a blocker, which
    /// also comes within 1e-9 of the receiver's corner (found by the long property run,
    /// tests/test_properties.py): the clearance sends the integral to face 4, where the hidden
    /// F sits in a layer along that edge and 60 000 evaluations end far from the goal with
    /// too little hidden. The other side, tried then, finds more: G is within tol of a tight
    /// reference over face 3, and
    /// the obstacle no longer raises G above that of face 0 alone (they hide nearly the same
    /// segments: those crossing y = 0 at x > 0 cross x = 0 at y < 0).
    #[test]
    fn a_side_out_of_evaluations_is_integrated_from_the_other() {
        let raw: [[[f64; 3]; 3]; 3] = [
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[0.0, 0.0, 0.0], [-0.5, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[0.00390625, 0.0, 0.5], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]],
        ];
        let mut polys = triangles(&raw);
        polys.extend(triangles(&[[[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [1e-9, 0.0, 0.0]]]));
        let (f0, f3, f4, obstacle) = (&polys[0], &polys[1], &polys[2], &polys[3]);
        let free = method::area_factor(f4, f3, Method::Analytic, &Default::default(), None).unwrap();
        let both = [f0, obstacle];
        assert!(clearance(f3, &both) < clearance(f4, &both));
        // (the budget this case was found with: at 250 000 face 4's side meets its goal)
        let o = ClippingOptions { tol: 1e-6, max_evals: 60_000, ..Default::default() };
        let goal = o.tol * free;
        let (_, err4) = hidden_over((f4, f3, f4, f3), &both, &[0, 1], (free, goal), &o);
        assert!(err4 > 10.0 * goal, "over face 4: error estimate {:.2e} x the goal", err4 / goal);
        let tight = ClippingOptions { tol: 1e-10, max_evals: 2_000_000, ..o };
        let (hidden, _) = hidden_over((f3, f4, f3, f4), &both, &[0, 1], (free, 1e-10 * free), &tight);
        let reference = free - hidden;
        let alone = clipping(&polys[..3], 2, 1, &tight, 1e-12);
        assert!(reference <= alone + 1e-10 * free);
        for tol in [1e-4, 1e-6, 1e-8] {
            let g = clipping(&polys, 2, 1, &ClippingOptions { tol, ..o }, 1e-12);
            assert!((g - reference).abs() <= tol * free, "tol {tol:e}: {:.2e} x tol", (g - reference) / (tol * free));
        }
    }

    /// The converse of the test above: face 2's corner lifted 1e-8 over it hides all of face 4
    /// but a wedge as thin, so face 2's samples see nothing and that side claims the pair
    /// hidden whole with an error estimate of 2e-16; face 4's side, out of evaluations at tol
    /// 1e-9, has the visible G within its estimate. The sides disagree beyond both estimates,
    /// so face 4's stays: G within 1e-9 of the unobstructed G from 2.4698e-9 (F = 4.9396e-9,
    /// a graded 80 x 12 x 40 Gauss rule over face 4 of the exact point F; it was 3.8e-16).
    #[test]
    fn a_side_claiming_the_pair_hidden_does_not_replace_one_out_of_evaluations() {
        let raw: [[[f64; 3]; 3]; 3] = [
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            [[0.00390625, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
            [[1e-8, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
        ];
        let polys = triangles(&raw);
        let free = method::area_factor(&polys[0], &polys[1], Method::Analytic, &Default::default(), None).unwrap();
        let reference = 4.9396e-9 * polys[0].area();
        let o = ClippingOptions { tol: 1e-9, ..Default::default() };
        let rest: Vec<&Polygon> = polys[2..].iter().collect();
        let (h2, e2) =
            hidden_over((&polys[0], &polys[1], &polys[0], &polys[1]), &rest, &every(&rest), (free, o.tol * free), &o);
        assert!((free - h2 - reference).abs() > 1e3 * e2, "face 2's side no longer claims it hidden");
        let g = clipping(&polys, 0, 1, &o, 1e-13);
        assert!((g - reference).abs() <= o.tol * free, "{:.2e} x tol", (g - reference) / (o.tol * free));
    }

    /// Two faces crossing each other's planes (clearances tied at CROSSING_CLEARANCE) with a
    /// third between them, found by the long property run: face 1's side runs out of
    /// evaluations from tol 1e-8 on, its estimate short of its error, while face 2's side meets
    /// a goal of 1e-10 x the unobstructed G. The sides agree within 10 x their estimates, so
    /// face 2's stays (the larger hidden part, face 1's, was 90 x tol off at 1e-8); with a
    /// million evaluations at 1e-10 either side gives the reference.
    #[test]
    fn a_side_out_of_evaluations_gives_way_to_one_that_meets_the_goal() {
        let polys = triangles(&[
            [[0.0, 0.0, 0.3671875], [-1.0, 0.0, 0.0], [-0.9375, -1.0, 0.0]],
            [[0.0, 0.0, -1.0], [-0.9375, -0.9375, 0.0], [0.0, 0.0, 1.0]],
            [[0.0, -1.0, 0.0], [-0.5, 0.0, 0.484375], [-0.015625, -0.1640625, 0.265625]],
        ]);
        let free = method::area_factor(&polys[1], &polys[2], Method::Analytic, &Default::default(), None).unwrap();
        // either side, given evaluations enough, meets the goal
        let tight = ClippingOptions { tol: 1e-10, max_evals: 1_000_000, ..Default::default() };
        let reference = clipping(&polys, 1, 2, &tight, 1e-13);
        // (at 1e-6 face 1's side meets its goal and ends 1.06 x tol off: not this test's)
        for tol in [1e-8, 1e-10] {
            let g = clipping(&polys, 1, 2, &ClippingOptions { tol, ..Default::default() }, 1e-13);
            let bound = tol.max(1e-9) * free; // at 1e-10 the budget ends within 1e-9
            assert!((g - reference).abs() <= bound, "tol {tol:e}: {:.2e} x the bound", (g - reference) / bound);
        }
    }

    /// Blockers close to both polygons of a pair (found by the long property run after the
    /// test above): face 4 lies 1e-6 off the plane of face 1, which shares its edge and hides
    /// a layer of face 4 1e-6 wide from face 3; an obstacle's vertex lies 1e-9 off face 3's
    /// corner. The clearances send the integral to face 4, whose samples all miss the layer
    /// (its error estimate meets the goal); integrated from both sides, the larger hidden part
    /// is face 3's, and the obstacle changes G by no more than tol.
    #[test]
    fn blockers_close_to_both_sides_integrate_both() {
        let raw: [[[f64; 3]; 3]; 5] = [
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.125, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[0.0, 0.0, 0.0], [-0.5, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[1e-6, 0.0, 0.5], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]],
            [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [1e-9, 0.0, 0.0]],
        ];
        let polys = triangles(&raw);
        let (f3, f4) = (&polys[2], &polys[3]);
        let free = method::area_factor(f4, f3, Method::Analytic, &Default::default(), None).unwrap();
        let all = [&polys[0], &polys[1], &polys[4]];
        let (c3, c4) = (clearance(f3, &all), clearance(f4, &all));
        assert!(c3 < c4 && c4 < BOTH_SIDES_CLEARANCE, "clearances {c3:e}, {c4:e}");
        let o = ClippingOptions { tol: 1e-6, ..Default::default() };
        let goal = o.tol * free;
        let (over4, err4) = hidden_over((f4, f3, f4, f3), &all, &every(&all), (free, goal), &o);
        let (over3, _) = hidden_over((f3, f4, f3, f4), &all, &every(&all), (free, goal), &o);
        assert!(err4 <= goal && over3 - over4 > 2.0 * goal, "face 4 misses {:.2e} x the goal", (over3 - over4) / goal);
        let tight = ClippingOptions { tol: 1e-10, max_evals: 2_000_000, ..o };
        let without = clipping(&polys[..4], 3, 2, &tight, 1e-12);
        for tol in [1e-4, 1e-6, 1e-8] {
            let g = clipping(&polys, 3, 2, &ClippingOptions { tol, ..o }, 1e-12);
            assert!(
                g <= without + tol * free,
                "tol {tol:e}: the obstacle adds {:.2e} x tol",
                (g - without) / (tol * free)
            );
            assert!((g - without).abs() <= tol * free, "tol {tol:e}: {:.2e} x tol", (g - without) / (tol * free));
        }
    }

    /// A face hinged on an edge of a thin face (face 0 in the plane x = 0, face 4 1e-6 off it)
    /// crosses that face's plane, but along the edge: no cut, and it hovers within 1e-6 over
    /// the face, hiding a 1e-6 layer of it (found by the long property run). Counted as
    /// crossing (0.1), it tied with the receiver's clearance, so the pair's order chose the
    /// side: from face 4 the layer was missed (hidden 3e-14 of the unobstructed G instead of
    /// 3.7e-6), and an obstacle that broke the tie raised F. It counts as high as it rises.
    #[test]
    fn a_blocker_hinged_on_the_source_edge_hovers() {
        let raw: [[[f64; 3]; 3]; 5] = [
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, -1.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
            [[0.0, 0.0, 0.0], [-1.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[1e-6, 0.0, 0.5], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]],
        ];
        let polys = triangles(&raw);
        let (f3, f4) = (&polys[3], &polys[4]);
        let free = method::area_factor(f4, f3, Method::Analytic, &Default::default(), None).unwrap();
        let hinged = [&polys[0]];
        assert!(clearance(f4, &hinged) < 1e-5 && clearance(f3, &hinged) >= CROSSING_CLEARANCE);
        let tight = ClippingOptions { tol: 1e-10, max_evals: 2_000_000, ..Default::default() };
        let reference = clipping(&polys, 3, 4, &tight, 1e-12);
        assert!(free - reference > 3e-6 * free, "hidden share {:.2e}", 1.0 - reference / free);
        for tol in [1e-4, 1e-6, 1e-8] {
            let o = ClippingOptions { tol, ..Default::default() };
            let (g43, g34) = (clipping(&polys, 4, 3, &o, 1e-12), clipping(&polys, 3, 4, &o, 1e-12));
            assert!((g43 - g34).abs() <= 1e-12 * free, "tol {tol:e}: {g43:e} and {g34:e}");
            assert!(
                (g43 - reference).abs() <= tol * free,
                "tol {tol:e}: {:.2e} x tol",
                (g43 - reference) / (tol * free)
            );
        }
    }

    /// A blocker's trace reaches into a start piece when it crosses it or ends in it; one
    /// along the piece's edge with both ends beyond it (a wall standing on a floor patch's
    /// edge) only touches it, as does one through a vertex alone.
    #[test]
    fn a_trace_along_an_edge_only_touches_the_piece() {
        let t = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let v = |x: f64, y: f64| Vec3::new(x, y, 0.0);
        // along the edge y = 0, ends beyond the edge's ends: touches only
        assert!(near_an_edge(&t, v(-1.0, 0.0), v(2.0, 0.0), triangle_eps(&t)));
        assert!(!reaches_into(&t, v(-1.0, 0.0), v(2.0, 0.0)));
        // along the edge, one end on it: the trace ends there, the shadow's corner sweeps in
        assert!(reaches_into(&t, v(-1.0, 0.0), v(0.5, 0.0)));
        // across the piece, inside it, or ending in it
        assert!(reaches_into(&t, v(0.2, -1.0), v(0.2, 2.0)));
        assert!(reaches_into(&t, v(0.1, 0.1), v(0.2, 0.2)));
        assert!(reaches_into(&t, v(-1.0, 0.3), v(0.2, 0.3)));
        // through a vertex only, along the hypotenuse, or missing the piece
        assert!(near_an_edge(&t, v(0.0, -1.0), v(2.0, 1.0), triangle_eps(&t)));
        assert!(!reaches_into(&t, v(0.0, -1.0), v(2.0, 1.0)));
        assert!(!reaches_into(&t, v(-1.0, 2.0), v(2.0, -1.0)));
        assert!(!reaches_into(&t, v(2.0, 2.0), v(3.0, 1.0)));
    }

    /// Three faces meeting at the origin between a source and a receiver (the seed-27 replay of
    /// tests/test_properties.py): face 1 pierces the source's edge at V = (2/17, 0, -15/17),
    /// and the lines from near V through its edge and an edge of face 2 end on the receiver's
    /// edges along two curves through V whose tangents run into the source (edge-edge-edge
    /// events). Near V the shadowed F depends on the direction from V alone, so a kink in that
    /// narrow sector of directions was missed on every corner piece at V alike: the source
    /// integral over a triangle at V converged to 7.3e-5 of its unobstructed G off at every tol
    /// from 1e-8 down. Cut along the tangents alone it converged to 4e-8 off (the curves bend
    /// away from their tangents, hugging the cut within the samples' margin); with their
    /// chords too every target is met (docs/algorithms.md §6.2). The reference is a polar
    /// Gauss rule about V (400 x 4 angles, none aligned to the kinks, x 12 radii; 800 angles
    /// or 24 radii change it by 1e-11).
    #[test]
    fn kinks_through_a_pierce_point_are_cut_along_their_tangents() {
        let polys = triangles(&[
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.125, 0.0, -1.0]],
            [[0.0, 0.0, 0.0], [0.0, -1.0, -1.0], [-1.0, 0.0, 0.0]],
            [[0.0, 1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]],
            [[0.0, -0.75, 0.0], [0.0, -1.0, 0.0], [-1.0, 0.0, 0.0]],
        ]);
        let receiver = &polys[4];
        let v = Vec3::new(2.0 / 17.0, 0.0, -15.0 / 17.0);
        let e1 = (Vec3::X - v).normalize();
        let u = (Vec3::new(1.0 / 6.0, 5.0 / 6.0, 0.0) - v).normalize();
        let rho = 0.02;
        let source = facing_quad(vec![v, v + rho * e1, v + rho * u], polys[3].normal());
        let blockers: Vec<&Polygon> = polys[..3].iter().collect();
        let casting = every(&blockers);
        let free = polygon_pair_within(&source, receiver, 1e-13);
        let hidden = |tol: f64| {
            let o = ClippingOptions { tol, ..Default::default() };
            hidden_over((&source, receiver, &source, receiver), &blockers, &casting, (free, tol * free), &o).0
        };
        let point = |x: Vec3| point_shadowed_and_free(x, source.normal(), receiver, &blockers, false).0;
        let e2 = (u - e1 * e1.dot(u)).normalize();
        let angle = e1.angle_between(u);
        let (p1, p2) = (v + rho * e1, v + rho * u);
        let (panels, gl) = (400, crate::quadrature::gauss_legendre(12));
        let mut reference = 0.0;
        for k in 0..panels {
            for &(ta, wa) in crate::quadrature::gauss_legendre(4) {
                let th = angle * (k as f64 + ta) / panels as f64;
                let d = th.cos() * e1 + th.sin() * e2;
                // the ray v + r d meets the edge p1 p2 where (p1 - v + s (p2 - p1)) x d = 0
                let n = source.normal();
                let s = -n.dot((p1 - v).cross(d)) / n.dot((p2 - p1).cross(d));
                let r_end = (p1 + s * (p2 - p1) - v).length();
                let radial: f64 = gl.iter().map(|&(tr, wr)| wr * point(v + tr * r_end * d) * tr * r_end).sum();
                reference += wa * angle / panels as f64 * r_end * radial;
            }
        }
        assert!(reference > 0.5 * free && reference < free, "hidden share {}", reference / free);
        for tol in [1e-6, 1e-7, 1e-8, 1e-9] {
            let err = (hidden(tol) - reference).abs() / free;
            assert!(err <= tol, "tol {tol:e}: error {err:.2e} of the unobstructed G");
        }
    }

    /// Four triangles from the long property run (seed 26, `test_replay_default_tol_miss_of_
    /// seed_26` in tests/test_properties.py): face 2 alone stands between faces 1 and 3, close
    /// to face 1 beside one start piece, where the shadowed F rises 35-fold across it. That
    /// piece's rule and its children's were both 0.19 % off and agreed to 7e-6, so the pair
    /// was 64 x tol off at the default with its estimate content. The reference integrates over
    /// the other face (other pieces, other samples) at tol 1e-10.
    #[test]
    fn a_steep_start_piece_is_not_trusted_on_one_level() {
        let polys = triangles(&[
            [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]],
            [[0.0, 0.0, -0.75], [-0.9765625, 0.6875, 0.625], [0.0, -0.283203125, 0.0]],
            [[0.0, 0.0, -0.984375], [0.0, -1.0, 0.0], [-0.09436022758029039, -0.1328125, 0.8125]],
            [[0.0, -0.53125, 0.25], [0.7109375, 0.0, 0.8203125], [0.58984375, 0.84375, 0.53125]],
        ]);
        let (a, b) = (&polys[1], &polys[3]);
        let free = polygon_pair_within(a, b, 1e-13);
        let tight = ClippingOptions { tol: 1e-10, max_evals: 2_000_000, ..Default::default() };
        let hidden = hidden_over((b, a, b, a), &[&polys[2]], &[0], (free, 1e-10 * free), &tight).0;
        let reference = free - hidden;
        assert!(hidden > 0.03 * free, "hidden share {}", hidden / free);
        let tol = 1e-6; // auto's default obstructed_tol
        let g = clipping(&polys, 1, 3, &ClippingOptions { tol, ..Default::default() }, 1e-12);
        let err = (g - reference).abs() / (tol * free);
        assert!(err <= 1.0, "error {err:.2} x tol of the unobstructed G");
    }

    /// Four triangles from the long property run (seed 35, tests/test_properties.py): faces 1
    /// and 2 pierce each other, their parts in front of each other touching along a stretch of
    /// the line where their planes meet; face 3 alone stands between them, cut to the slab a
    /// wedge with an edge in each plane, its trace 0.015-0.018 beside face 2's edge. Integrated
    /// over face 2, a leaf two levels below a start piece next to that edge has samples spread
    /// 27-fold, its rule and its children's 0.07 % off and agreeing to 7e-11: the pair ended
    /// 2.9 x tol off at the default with the estimate under its goal (which start pieces the
    /// leaf came from turned on face 1's coordinate of 1e-60, which tilts its plane so that
    /// face 2's vertex on it lies behind and the part of face 2 starts at another vertex;
    /// moved or scaled, the pair met the goal). The reference, F_12 = 8.45365862264e-3, is
    /// independent of nusselt: the unobstructed F by the 40-digit contour integral of
    /// tests/pair_reference.py less the hidden part, a Lambert formula on the receiver clipped
    /// to the blocker's projection at each point, by Gauss rules on the kink-cut source
    /// (converged to 1e-15); clipping at tol 1e-10 agrees to 1.2e-13.
    #[test]
    fn a_steep_leaf_is_not_trusted_on_one_level_at_any_depth() {
        let polys = triangles(&[
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.671875], [0.96875, 0.0, -0.828125], [-0.84375, 1e-60, -0.04296875]],
            [[0.0, 0.0, -0.98046875], [0.0, -0.93359375, -0.6796875], [-0.13671875, 0.07095695185751683, 0.0]],
            [[0.0, 0.06411104616764818, 0.0], [0.015625, -0.634765625, -0.40625], [-0.44257406402799526, 0.0, 0.0]],
        ]);
        let free = polygon_pair_within(&polys[1], &polys[2], 1e-13);
        let reference = 8.45365862264e-3 * polys[1].area();
        let tol = 1e-6; // auto's default obstructed_tol
        let g = clipping(&polys, 1, 2, &ClippingOptions { tol, ..Default::default() }, 1e-12);
        let err = (g - reference).abs() / (tol * free);
        assert!(err <= 1.0, "error {err:.2} x tol of the unobstructed G");
    }

    /// A blocker standing on an edge of the source counts as hinged there (at most
    /// HINGED_CLEARANCE, below a crossing blocker's); standing on the source's plane away from
    /// the source, it keeps its height; a face that leans over it from a vertex on the source's
    /// plane, beside the source, likewise.
    #[test]
    fn a_blocker_standing_on_the_sources_edge_is_hinged() {
        let source = facing_quad(
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            Vec3::Z,
        );
        let wall = |x: f64| {
            Polygon::new(vec![
                Vec3::new(x, 0.0, 0.0),
                Vec3::new(x, 1.0, 0.0),
                Vec3::new(x, 1.0, 1.0),
                Vec3::new(x, 0.0, 1.0),
            ])
            .unwrap()
        };
        let r = source.radius();
        let (on_edge, beside) = (wall(1.0), wall(1.5));
        assert_eq!(clearance(&source, &[&on_edge]), HINGED_CLEARANCE);
        // (its lowest vertex above the plane is 1 high)
        assert_eq!(clearance(&source, &[&beside]), 1.0 / r);
        // a low wall on the edge: its height, if less
        let low = Polygon::new(vec![
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.01),
            Vec3::new(1.0, 0.0, 0.01),
        ])
        .unwrap();
        assert_eq!(clearance(&source, &[&low]), 0.01 / r);
        // a triangle touching the plane at one vertex beside the source only
        let leaning =
            Polygon::new(vec![Vec3::new(2.0, 0.5, 0.0), Vec3::new(0.5, 0.0, 1.0), Vec3::new(0.5, 1.0, 1.0)]).unwrap();
        assert_eq!(clearance(&source, &[&leaning]), 1.0 / r);
    }

    /// Five faces, face 3 leaning 1e-5 out of the plane x = 0 (found by the long property run
    /// with seed 32, tests/test_properties.py). Face 2 crosses face 3's plane beside it, its
    /// trace touching face 3 at one point of its edge, and its edge from the origin hovers up
    /// to 1e-5 over face 3: it counts as that close, not as crossing, and the pair (3, 4) is
    /// integrated over face 4. Over face 3 the hidden F rose from 0 within 1e-5 of face 2's
    /// plane along a start piece whose rule and children's agreed: 4.9 x tol off at the default.
    /// Where the trace runs over the source, the blocker still counts as crossing.
    #[test]
    fn a_blocker_crossing_beside_the_source_hovers() {
        let polys = triangles(&[
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 0.5], [0.0, -1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.9375, 1.0], [-1.0, 0.0, 0.0]],
            [[0.0, 0.0, 0.5], [0.0, 1.0, 0.0], [1e-5, 0.0, 0.0]],
            [[0.0, 1.0, 0.0], [0.0, 1.0, 1.0], [-1.0, 1.0, 0.0]],
        ]);
        let (c3, c4) = (clearance(&polys[3], &[&polys[2]]), clearance(&polys[4], &[&polys[2]]));
        assert!(c3 < 1e-4 && c3 < c4, "{c3:e} {c4:e}");
        let free = method::area_factor(&polys[3], &polys[4], Method::Analytic, &Default::default(), None).unwrap();
        let o = ClippingOptions { tol: auto_tol(), ..Default::default() };
        let reference = clipping(&polys, 3, 4, &ClippingOptions { tol: 1e-10, ..o }, 1e-12);
        for (i, j) in [(3, 4), (4, 3)] {
            let g = clipping(&polys, i, j, &o, 1e-12);
            assert!((g - reference).abs() <= o.tol * free, "({i}, {j}): {:.2} x tol", (g - reference) / (o.tol * free));
        }
        // the same blocker through the middle of face 3: crossing
        let through = triangles(&[[[-1.0, 0.5, 0.0], [0.5, 0.5, 0.0], [0.0, 0.25, 1.0]]]);
        assert_eq!(clearance(&polys[3], &[&through[0]]), CROSSING_CLEARANCE);
    }

    /// Two faces 1e-5 from contact along an edge, a third hiding them from each other whole
    /// (seed 32 of the long property run): the samples of the one start piece have a free F
    /// 1e-10 .. 4e-9 and put its G at 1.5e-11 for 5.5e-7, all of it near the edge. At
    /// obstructed_tol 1e-3 the piece integrated the hidden part (all of the point F there) and
    /// G came out 0.99994 x the unobstructed G for 0; it now asks for its own G and integrates
    /// the visible part, 0.
    #[test]
    fn a_steep_piece_below_the_goal_by_its_samples_asks_its_g() {
        let polys = triangles(&[
            [[0.0, 0.0, 0.0], [0.0, 0.0, 0.125], [0.0, -1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]],
            [[0.0, 0.0, 0.5], [0.0, 1.0, 0.0], [1e-5, 0.0, 0.0]],
        ]);
        // (independent of the integration: faces 1 and 2 together cross every segment between
        // random points of faces 0 and 3)
        use crate::visibility::bvh::tests::{ray_polygon, Rng};
        let mut rng = Rng::new(5);
        for _ in 0..10_000 {
            let (x, y) = (in_triangle(&mut rng, &polys[0]), in_triangle(&mut rng, &polys[3]));
            let hit = |k: usize| ray_polygon(&polys[k], x, y - x).is_some_and(|t| t > 0.0 && t < 1.0);
            assert!(hit(1) || hit(2), "{x} -> {y}");
        }
        let free = method::area_factor(&polys[0], &polys[3], Method::Analytic, &Default::default(), None).unwrap();
        for tol in [1e-3, 1e-4, auto_tol()] {
            let o = ClippingOptions { tol, ..Default::default() };
            for (i, j) in [(0, 3), (3, 0)] {
                let g = over_first(&polys, i, j, &o);
                assert!(g <= tol * free, "({i}, {j}), tol {tol:e}: G {g:e}, {:.2e} x tol", g / (tol * free));
            }
        }
    }

    /// The triangles `raw` at the origin and scaled by 1e-6 and moved by 7e-6 (the long property
    /// run's placements), with the factor G scales by.
    fn placements(raw: &[[[f64; 3]; 3]]) -> [(Vec<Polygon>, f64); 2] {
        let s = 1e-6;
        let moved: Vec<[[f64; 3]; 3]> = raw.iter().map(|p| p.map(|v| v.map(|x| s * x + 7.0 * s))).collect();
        [(triangles(raw), 1.0), (triangles(&moved), s * s)]
    }

    /// The seed-33 scene of the long property run (face 2 leans 1e-5) in both [`placements`].
    fn seed_33_placements() -> [(Vec<Polygon>, f64); 2] {
        placements(&[
            [[0.0, 0.0, 0.0], [0.0, 0.0, -0.25], [0.8448319428180837, 0.5, 0.0]],
            [[0.0, 0.0, -0.25], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
            [[0.0, -0.5, -0.25], [0.82421875, 0.0, -0.9375], [1e-05, 0.0, -0.25]],
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]],
            [[2.220446049250313e-16, -0.5, -0.9375], [0.0, 0.53125, -0.375], [0.0, 0.0, 0.0]],
        ])
    }

    /// The seed-33 pair's G (faces 2 and 4) integrated over face 4 at tol 1e-9: G is symmetric,
    /// so this other side, with its own start pieces and samples, is an independent route to
    /// the value the tests integrate over face 2 (the two agree to 1.2e-8 of it).
    fn seed_33_reference(polys: &[Polygon], scale: f64) -> f64 {
        let reference = over_first(polys, 4, 2, &ClippingOptions { tol: 1e-9, ..Default::default() });
        assert!((reference / scale - 1.9497639e-3).abs() < 1e-9, "{reference:e}");
        reference
    }

    /// Face 2 leans 1e-5 (seed 33 of the long property run): its corner (1e-5, 0, -0.25) lies
    /// 1e-5 above face 4, beside the edge that faces 0 and 1 share on face 4, and both cross
    /// face 2's plane 6.4e-6 deep there. The first start piece over face 2 is a sliver whose
    /// plane missed their traces (see `adaptive_over_source`): at obstructed_tol 1e-3 G was
    /// 32 x tol low at the origin, 0.03 x where the scene is scaled by 1e-6 and moved.
    #[test]
    fn the_traces_lie_in_the_plane_of_the_source() {
        let o = ClippingOptions { tol: 1e-3, ..Default::default() };
        for (polys, scale) in seed_33_placements() {
            let free = polygon_pair_within(&polys[2], &polys[4], 0.0);
            let reference = seed_33_reference(&polys, scale);
            let g = clipping(&polys, 2, 4, &o, 1e-12);
            let off = (g - reference) / (o.tol * free);
            assert!(off.abs() <= 1.0, "scale {scale:e}: G {g:e}, {off:.2} x tol");
        }
    }

    /// Face 4 leans 2^-24 out of the plane of face 3, which covers it 6e-8 above (seed 30 of
    /// the long property run): F to face 2 past face 3 is 2.95451e-4 (graded Gauss over face 4
    /// of the exact point F, 2.954492e-4 / 2.954520e-4 with 6 / 10 points a panel). Over face
    /// 2 the integral runs out of evaluations 6e-9 from that; face 4's side claimed 4.3e-9 and
    /// was 9e-8 off, and replaced it: 5 x tol at 1e-6.
    #[test]
    fn a_side_a_blocker_lies_flat_over_does_not_replace_the_other() {
        let a = -5.960464477539063e-08;
        let polys = triangles(&[
            [[0.0, 0.0, -0.5], [0.0, 1.0, 0.0], [a, 0.0, 0.0]],
            [
                [0.0, 0.0, 0.0],
                [0.6750968359876115, 0.6448861784688971, 0.6925955256530236],
                [-0.9109849740018543, 0.0, -1.0],
            ],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, -1.0]],
        ]);
        let o = ClippingOptions { tol: 1e-6, ..Default::default() };
        let (area, free) = (polys[0].area(), polygon_pair_within(&polys[0], &polys[1], 0.0));
        let f = clipping(&polys, 0, 1, &o, 1e-12) / area;
        let off = (f - 2.95451e-4) / (o.tol * free / area);
        assert!(off.abs() <= 1.0, "F {f:e}: {off:.2} x tol");
        assert!(lies_flat_over(&polys[0], &[&polys[2]]));
        // a blocker that only comes close at a point (a vertex 1e-9 off the corner) is not flat
        let corner = triangles(&[
            [[0.0, 0.0, 0.0], [-0.5, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [1e-09, 0.0, 0.0]],
        ]);
        assert!(!lies_flat_over(&corner[0], &[&corner[1]]));
    }

    /// Face 4 leans 2^-24 out of the plane x = 0 of faces 0 and 1, which share face 3's edge
    /// along the y axis: its part in front of face 3 is a sliver 6e-8 wide along that edge,
    /// and faces 0 and 1 hide it whole (every segment from face 3 to it crosses x = 0 at
    /// z >= 0). From most of face 3 its point F is 1e-16, free and hidden differing in the
    /// last bit; the start pieces along the edge must still integrate the visible part
    /// (the hidden one rises as the kernel within 6e-8 of the edge): by the share of the
    /// point F alone, the integral over face 3 ran out of evaluations at 0.7 % hidden, and F
    /// was the unobstructed one. Moved, the two point F agreed exactly and it was 0.
    #[test]
    fn a_sliver_hidden_whole_is_not_lost_to_rounding() {
        let o = ClippingOptions { tol: 1e-6, ..Default::default() };
        for (polys, _) in placements(&[
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]],
            [[0.0, 0.0, 0.0], [1.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
            [[0.0, -1.0, -1.0], [0.0, 1.0, 0.0], [-5.960464477539063e-08, 0.0, 0.0]],
        ]) {
            let free = polygon_pair_within(&polys[3], &polys[4], 0.0);
            // (the integral runs over face 3: faces 0 and 1 hover 6e-8 over face 4)
            assert!(clearance(&polys[3], &[&polys[0], &polys[1]]) > clearance(&polys[4], &[&polys[0], &polys[1]]));
            for g in [over_first(&polys, 3, 4, &o), clipping(&polys, 3, 4, &o, 1e-12)] {
                assert!(g <= o.tol * free, "visible {:.3e} of the unobstructed G", g / free);
            }
        }
    }

    /// The uncancelled difference is 0 for a quadratic integrand, which both levels of the
    /// equal-weight rule integrate exactly, wherever the leaf lies and however it is shaped,
    /// and at least half the children's difference otherwise (its residuals sum to it).
    #[test]
    fn the_uncancelled_difference_leaves_out_what_a_quadratic_gives() {
        let t = [Vec3::new(0.3, -1.0, 2.0), Vec3::new(1.7, 0.2, 2.5), Vec3::new(-0.4, 0.9, 1.0)];
        let rule = source_rule(LOW_DEGREE_TOL);
        let level = |f: &dyn Fn(Vec3) -> f64| {
            let values = |t: &[Vec3; 3]| rule_points(&rule, t).map(|(x, w)| (f(x), w)).collect::<Vec<_>>();
            let whole: f64 = values(&t).iter().map(|(v, w)| v * w).sum();
            let points = [0, 1, 2].map(|j| values(&t)[j].0);
            let kids = split_in_four(&t).map(|k| values(&k).iter().map(|(v, w)| v * w).sum::<f64>());
            (whole, points, kids)
        };
        let quadratic = |x: Vec3| 1.0 + 2.0 * x.x - x.y + 0.5 * x.x * x.y + 3.0 * x.z * x.z - x.y * x.y;
        let (whole, points, kids) = level(&quadratic);
        let u = uncancelled_difference(area3(&t), whole, points, &kids);
        assert!(u <= 1e-14 * whole.abs(), "{u:e} of {whole:e}");
        // steep towards vertex 1, as the point F at a corner of the source near a blocker
        let steep = |x: Vec3| 1.0 / (0.05 + x.distance(t[1]));
        let (whole, points, kids) = level(&steep);
        let u = uncancelled_difference(area3(&t), whole, points, &kids);
        let difference = kids.iter().sum::<f64>() - whole;
        assert!(u >= 0.5 * difference.abs() && u > 0.0, "{u:e} for {difference:e}");
    }

    /// Long-run seed 56 (tests/test_properties.py): faces 1 and 2 share a vertex and face 0
    /// hides 0.8 % of their unobstructed F. Over face 1 a thin start piece under the 3-point
    /// rule, its children's samples spread 340-fold, went from 3.67e-5 to 5.29e-5 with one level
    /// and counted that difference while about 1e-4 was missing: 5.6 x tol at obstructed_tol
    /// 1e-3 (see VERY_STEEP). The reference is the integral over face 2 (an identity).
    #[test]
    fn a_very_steep_leaf_is_not_trusted_on_one_level() {
        let polys = triangles(&[
            [[0.0, 0.0, -0.5], [0.0, -1.0, 1.0], [1.0, -0.5, 0.0]],
            [[0.5, -1.0, 0.25], [0.0, 0.0, 0.0], [0.0, 0.25, 0.0]],
            [[0.5, -1.0, 0.25], [1.0, 0.0, 0.0], [0.0, 0.125, 0.0]],
        ]);
        assert_side_meets_the_other(&polys, (1, 2), &[1e-2, 1e-3], &[1e-2, 1e-3]);
    }

    /// Faces 1 and 2 share the stretch of an edge from their common vertex, face 0 crosses
    /// both: about the point where its plane meets that edge the hidden F depends on the
    /// direction alone, 0.34 along the edge of a start piece of face 1 and below 1e-5 at all
    /// of its samples and its children's (a layer 1 % of the distance from that point thick).
    /// Under the 3-point rule the integral over face 1 claimed 6.6e-5 and was 2.2e-4 low: 1.3
    /// x tol at obstructed_tol 1e-3 (long-run seed 56, see LINEAR_EDGE_SHARE).
    #[test]
    fn a_layer_along_a_piece_touching_the_receiver_is_found_under_the_3_point_rule() {
        let polys = triangles(&[
            [[0.0, 0.0, -0.5], [1.0, -0.625, 0.0], [0.5, -1.0, 0.75]],
            [[0.75, -0.875, 0.375], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            [[0.75, -0.875, 0.375], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]],
        ]);
        assert_side_meets_the_other(&polys, (1, 2), &[1e-2, 3e-3, 1e-3], &[1e-2, 1e-3]);
    }

    /// A pair of the `obstructed_fuzz` example (500 pairs, seed 11) under four blockers, one
    /// 0.1-0.2 over the source: the hidden F rises towards the edge of a start piece of the
    /// source and falls again within 6 % of the piece from it, beyond every sample of the piece
    /// and its children. Both rules were 11 % high and 0.5 % apart, the integral claimed its
    /// goal and was 3.3 x tol off at 1e-3 (see LINEAR_EDGE_SHARE). At 1e-4 the same feature
    /// crossed two sliver start pieces near their narrow ends, their samples within 3-fold:
    /// 4.83 x tol (see SLIVER_PROBE).
    #[test]
    fn a_steep_piece_compares_its_corners_under_the_3_point_rule() {
        let raw: Vec<Vec<[f64; 3]>> = vec![
            vec![
                [-0.6002069276353428, 0.3955572573754915, -0.1346719928175414],
                [-0.9475215719701408, 0.1583493286777854, -0.11609111591808746],
                [-0.7601535648886969, -1.2649045121629703, 0.08910444177920043],
                [-0.6101820214955654, -1.3406016510703807, 0.10579446281882805],
                [0.6418052304725735, -0.7555935977149251, 0.0762848894598676],
                [0.6876750496351329, -0.4746456243204798, 0.039198165234610234],
            ],
            vec![
                [0.5601310140593052, -0.9938054407852824, 1.0388533399468864],
                [0.1335109551380009, -1.004111252520718, 1.0526585408846516],
                [0.3764973756718119, 0.4184266926150101, 0.950173666162622],
            ],
            vec![
                [-0.02648522621785354, -0.024738449257087864, 0.6965334222155929],
                [-0.2158059524165899, 0.02804316656690574, 0.7355817644802598],
                [-0.2634125423556455, 0.03816248700818864, 0.772180719793649],
                [-0.3453144527788976, 0.04750846611932086, 0.9036264799663961],
                [-0.08935770926181258, -0.07399420346052253, 1.276704245510281],
                [-0.0331780942381538, -0.09037364578150345, 1.2712052849384912],
            ],
            vec![
                [0.31719194353555585, 0.24781196860337323, 0.7018000605508163],
                [0.2993019948308323, 0.22132880916941894, 0.7066126668896213],
                [0.2707364114970522, 0.18386601717492357, 0.7194742195801074],
                [0.13145325958902282, 0.4501234232599222, 1.2639749203827275],
                [0.40714554141604975, 0.45609264725917437, 0.7582200911149088],
            ],
            vec![
                [0.3152544042947607, 0.7668797731652633, -0.019828135806854878],
                [-0.2168932645563436, 0.45839748223889365, -0.3020219832363217],
                [-0.2546736343997598, 0.25368294731179464, -0.21959837996964401],
                [0.31120977975071973, 0.1889100171898923, 0.3006374138318715],
            ],
            vec![
                [-0.021663277018845573, -0.3766251052005133, 0.15098299371117993],
                [-0.8218837797198986, -0.15096251710998243, 0.167080175266265],
                [-0.8365686130196948, -0.17238543265848488, 0.16425296410634277],
                [-0.8649185324379156, -0.22376484960995308, 0.15757078992895085],
                [-0.811912686526298, -0.679556288633875, 0.1026561165301951],
                [-0.047176705485936554, -0.5606040348174058, 0.1281446328228693],
            ],
        ];
        let polys: Vec<Polygon> =
            raw.into_iter().map(|v| Polygon::new(v.into_iter().map(Vec3::from_array).collect()).unwrap()).collect();
        assert_side_meets_the_other(&polys, (0, 1), &[1e-2, 1e-3, 1e-4], &[1e-3, 1e-4]);
    }

    /// Two pairs of the building of bench/scenes.py with the blockers between them: a ceiling
    /// patch (polygon 0, the side integrated) and the narrow reveal of a door under a wall's
    /// end (1.96 x tol at obstructed_tol 1e-3), and a ceiling patch and a sill under a reveal
    /// (3.2 x tol at 1e-4). Each time one of the two start pieces held most of the hidden G,
    /// its rule and centroid 0.04 % apart while the rule was 0.25 and 0.6 % off (see
    /// COARSE_MOST).
    #[test]
    fn a_start_piece_holding_most_of_the_integral_keeps_no_coarse_estimate() {
        let quad = |v: [[f64; 3]; 4]| Polygon::new(v.into_iter().map(Vec3::from_array).collect()).unwrap();
        let (x0, x1) = (2.5799999999999996, 4.859999999999999);
        let door = [
            quad([[x0, 7.7, 6.2], [x1, 7.7, 6.2], [x1, 5.91, 6.2], [x0, 5.91, 6.2]]),
            quad([[8.12, 7.7, 4.1], [8.2, 7.7, 4.1], [8.2, 7.7, 5.3], [8.12, 7.7, 5.3]]),
            quad([[8.12, 5.35, 3.2], [8.12, 7.7, 3.2], [8.12, 7.7, 5.3], [8.12, 5.35, 5.3]]),
            quad([[8.0, 5.35, 5.3], [8.0, 7.7, 5.3], [8.0, 7.7, 3.2], [8.0, 5.35, 3.2]]),
            quad([[8.0, 5.35, 5.3], [8.12, 5.35, 5.3], [8.12, 7.7, 5.3], [8.0, 7.7, 5.3]]),
        ];
        assert_side_meets_the_other(&door, (0, 1), &[1e-2, 1e-3], &[1e-3]);
        let sill = [
            quad([[x0, 5.91, 6.2], [x1, 5.91, 6.2], [x1, 4.12, 6.2], [x0, 4.12, 6.2]]),
            quad([[4.6, 7.7, 4.1], [5.35, 7.7, 4.1], [5.35, 8.0, 4.1], [4.6, 8.0, 4.1]]),
            quad([[4.6, 7.7, 4.1], [4.6, 8.0, 4.1], [4.6, 8.0, 5.5], [4.6, 7.7, 5.5]]),
            quad([[2.6, 7.7, 4.1], [4.6, 7.7, 4.1], [4.6, 7.7, 5.5], [2.6, 7.7, 5.5]]),
        ];
        assert_side_meets_the_other(&sill, (0, 1), &[1e-3, 1e-4], &[1e-4]);
    }

    /// The five faces of long-run seed 63 (tests/test_properties.py), over face 0 towards face
    /// 4 at obstructed_tol 1e-3: a start piece next to where face 4's plane crosses face 0 is
    /// hidden whole, its hidden samples 1.9e-4 .. 5.1e-4 (2.7-fold) while the kernel falls to
    /// 5e-5 within it; under the 3-point rule it kept the coarse estimate of the hidden part,
    /// 12 % above its exact unobstructed G (4.60e-6), and G was 2.5 x tol off (see
    /// VISIBLE_SPREAD_LINEAR). The reference is the integral over face 4 at 1e-9.
    #[test]
    fn a_start_piece_hidden_whole_asks_its_free_f_where_its_samples_spread() {
        let polys = triangles(&[
            [
                [0.0, 0.0, 0.0],
                [0.4963909986989725, 0.0, 0.48916857966083893],
                [-0.4462023292954477, -0.9685899589081393, 0.49090201057060523],
            ],
            [
                [0.0, 0.8323927916661442, -0.6794596292833313],
                [0.0, -0.6828418250427766, -0.605756203842032],
                [-0.12234379998886546, 1e-12, 0.7266535689310558],
            ],
            [
                [0.5412756564101509, 0.4970412022116013, 5e-324],
                [0.5680459082084659, -0.9999999999999999, -0.4404649102103292],
                [-0.12565265960291794, -1.2598012284350193e-118, -0.17194676756353],
            ],
            [
                [0.07454692760374626, 0.0, -0.380977129367538],
                [6.190028139677765e-96, 5.960464477539063e-08, 0.9375],
                [-0.4462023292954477, -0.9685899589081393, 0.49090201057060523],
            ],
            [
                [-0.216234854666985, -0.3333333333333333, -0.25903958579530284],
                [-0.31758478202177665, -0.23655274232290657, 0.0],
                [0.0, 5.960464477539063e-08, 0.9375],
            ],
        ]);
        assert_side_meets_the_other(&polys, (0, 4), &[1e-3], &[1e-3]);
    }

    /// The scene of `the_traces_lie_in_the_plane_of_the_source` at the looser targets of the
    /// equal-weight rule: the start piece at face 2's corner near the blockers, its samples
    /// 5.3e-4 .. 7.8e-3 rising towards the corner, had its rule and its children's agreeing to
    /// 3.1e-6 while both were 9e-5 off (see `uncancelled_difference`): G was 3.2 and 10.7 x tol
    /// low at obstructed_tol 1e-2 and 3e-3, at both placements.
    #[test]
    fn a_steep_leaf_under_the_equal_weight_rule_is_not_trusted_by_chance() {
        for (polys, scale) in seed_33_placements() {
            let free = polygon_pair_within(&polys[2], &polys[4], 0.0);
            let reference = seed_33_reference(&polys, scale);
            for tol in [1e-2, 3e-3] {
                let g = clipping(&polys, 2, 4, &ClippingOptions { tol, ..Default::default() }, 1e-12);
                let off = (g - reference) / (tol * free);
                assert!(off.abs() <= 1.0, "scale {scale:e}, tol {tol:e}: G {g:e}, {off:.2} x tol");
            }
        }
    }

    /// The seed-37 replay of tests/test_properties.py: an edge of face 3 pierces face 1's plane
    /// inside face 1. Near that point face 3 is close to every source point, and the hidden F
    /// to face 4 runs up to 0.6 within about the size of face 3's part in front (0.007); a
    /// sliver start piece cornered there (0.18 long) had every sample beyond that, its rule
    /// and its children's agreeing at 3.8e-10 for 2.9e-7 (8.9 x the goal over face 1 at the
    /// default). Integrated over face 1, the hidden G must agree with the same integral over
    /// face 4, which nothing pierces (G is symmetric).
    #[test]
    fn a_leaf_where_a_blocker_pierces_the_source_asks_the_limit_there() {
        let polys = triangles(&[
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.25, 1.0, 0.0]],
            [[0.0, 0.0, 0.576171875], [0.9375, 0.0, 0.0], [-0.328125, 0.904296875, -1.0]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, -0.5]],
            [[0.0, 0.0, 1.0], [0.0, 0.13620460344004104, 0.0], [0.8125, 0.05790897567968201, 0.9453125]],
            [[-0.66796875, 0.0, 0.9296875], [0.44902525456830156, 0.25390625, 0.0], [0.0, -0.21875, 0.443359375]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, -0.25], [0.0, 1.0, 0.0]],
        ]);
        let free = polygon_pair_within(&polys[1], &polys[4], 0.0);
        let reference = over_first(&polys, 4, 1, &ClippingOptions { tol: 1e-8, ..Default::default() });
        let tol = 1e-6;
        let g = over_first(&polys, 1, 4, &ClippingOptions { tol, ..Default::default() });
        let off = (g - reference) / (tol * free);
        assert!(off.abs() <= 1.0, "G {g:e} for {reference:e}: {off:.2} x tol");
    }

    /// Two start pieces all of whose samples, and their children's, were 0 while a steep
    /// hidden F lay along one of their edges (see `edge_limit` in `adaptive_over_source`).
    /// Long-run seed 41 of tests/test_properties.py, scene test. (a) Face 1 pierces face 3's
    /// plane along an edge of a sliver start piece of face 3 (0.008 x 0.14); the hidden F is up
    /// to 2e-2 in a corner of it next to that edge and 0 at its 35 samples: F[2, 3] 4.0 x tol
    /// x F_free high at the default. (b) An obstacle's plane cut face 4 along a needle piece's short
    /// edge, where faces 0-2 hide up to 6e-3 within 1 % of its length: the obstacle raised
    /// F[3, 4] by 2.5 x the slack (1.4e-7), at every tol, the leaves there all-0 to the end.
    /// Each reference is the integral over the other face (an identity), where no piece
    /// holds such an edge.
    #[test]
    fn a_blind_start_piece_asks_the_limits_at_its_edges() {
        let a = triangles(&[
            [
                [-0.8730321434529524, -2.225073858507e-311, 0.1669194989722238],
                [-2.2250738585072014e-308, -9.844898802101006e-78, 0.0],
                [-0.6179240651941543, -0.7562221966110352, -0.9274688690658568],
            ],
            [
                [-0.4472043649612977, -0.5702831701882579, -0.5629253366088668],
                [0.3241339112698245, -0.08988404864817734, 0.052234655406105945],
                [0.558944636848056, 0.7921606187462218, 0.14259677932698245],
            ],
            [
                [0.0, -0.774317764458075, -0.8869390887928565],
                [-4.172141648151047e-228, -1.0, -1.6483082360298924e-194],
                [0.2665827028332137, -0.37408989876157317, 0.6493375136306505],
            ],
            [
                [-0.4116674657516811, 0.8879729346947487, -0.6675667991867944],
                [-0.4158922440508891, -1.6508794878190337e-87, 1.0],
                [0.1745165074236652, -0.8698120397686897, -0.7016997321854022],
            ],
            [
                [0.0, 0.0, 0.0],
                [-0.6149165243927265, 0.0, 0.0],
                [-0.807227615196977, -0.39660830628184296, -0.5103047371426096],
            ],
        ]);
        let b = triangles(&[
            [[0.0, 0.0, 0.0], [0.0, 0.0, 0.3241339112698245], [-0.4472043649612977, 0.0, -0.5629253366088668]],
            [[0.0, 0.0, 0.0], [0.0, 0.0, -0.8869390887928565], [0.0, -1.0, 0.0]],
            [
                [0.0, 0.0, 0.0],
                [0.0, -0.9274688690658568, -0.7562221966110352],
                [-0.8730321434529524, 0.0, 0.1669194989722238],
            ],
            [[0.0, 1.0, 0.0], [-0.6149165243927265, 0.0, 0.0], [-0.807227615196977, -0.5, -0.5]],
            [[0.1875, -1.0, -0.75], [-0.5, 1.0, -0.5], [-0.375, 0.0, 1.0]],
            [[0.0, -1.0, -0.25], [0.0, -0.25, 0.0], [-1.0, 0.0, 0.0]],
        ]);
        assert_side_meets_the_other(&a, (3, 2), &[1e-6], &[1e-3, 1e-6, 1e-8]);
        assert_side_meets_the_other(&b, (4, 3), &[1e-6], &[1e-3, 1e-6, 1e-8]);
    }

    /// Face 2 crosses face 0's plane along a line through face 0, only a wedge 2.2e-10 thick
    /// in front of it, and face 1 lies in the plane of face 0's bottom edge (long-run seed 42).
    /// Over face 0 the free F at the 3-point rule's samples is 1e-19, rounding, and the
    /// visible part there 0: the pieces took the visible part (see UNINFORMATIVE), found 0,
    /// and F was 0 for 7.52e-11 from obstructed_tol 1e-4 on. The reference is the integral
    /// over face 2 (an identity), where the samples see the wedge.
    #[test]
    fn samples_at_rounding_do_not_claim_the_pair_hidden() {
        let polys = triangles(&[
            [[0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.75, 0.0, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, -1.0, 0.0], [1.0, 0.5, 0.0]],
            [[0.0, 0.0, -1.0], [0.0, -1.0, 0.0], [0.5, 2.226117160647273e-10, 1.0]],
        ]);
        // (the pair not below 1e-4: the unobstructed G of this pair is itself known to about
        // 2.5e-6, the two orders of the analytic kernel differing by that much)
        let (reference, free) = assert_side_meets_the_other(&polys, (0, 2), &[1e-2, 1e-3, 1e-4], &[1e-2, 1e-4]);
        assert!(reference > 0.99 * free, "{reference:e} of {free:e}");
    }

    /// Start pieces where the hidden F changes steeply next to an edge or a corner, beyond
    /// every sample of the piece and its children (see EDGE_SHARE). (a) Long-run seed 40:
    /// faces 0 and 1 (the blockers) and an edge of face 3 lie in the plane x = 0, that edge
    /// 1.6e-3 rad off the blockers' common edge; along the kink plane through both the hidden
    /// F's slope grows without bound: F[2, 3] 4.5 x tol x F_free low at the default. (b)
    /// Long-run seed 41: over face 3, a piece next to the fan of a point where face 1 pierces
    /// it held a rise along its edge that its one leaf missed (1.9e-13 claimed for 5.7e-9):
    /// the obstacle, which hides nothing of the pair (3, 4), raised F by 1.4 x the slack at
    /// every tol. Each reference is the integral over the other face (an identity).
    #[test]
    fn a_piece_whose_corners_leave_its_samples_quadratic_is_refined() {
        let raw: [[[f64; 3]; 3]; 4] = include!("../../../../tests/data/seed_40_edge_in_the_blockers_plane.txt");
        let a = triangles(&raw);
        let raw: [[[f64; 3]; 3]; 6] = include!("../../../../tests/data/seed_41_pierce_point.txt");
        let b = triangles(&raw);
        assert_side_meets_the_other(&a, (2, 3), &[1e-6], &[1e-5, 1e-6, 1e-8]);
        assert_side_meets_the_other(&b, (3, 4), &[1e-6], &[1e-5, 1e-6, 1e-8]);
    }

    /// A floor (face 0) of the 391-surface building of bench/scenes.py and a ceiling strip
    /// 5.5 above it (face 1) that it sees over a stair's side wall (face 7, its top 0.6 high
    /// along the floor's edge y = 1.5) and past a wall standing under the ceiling (face 6), with
    /// four risers and a tread of the stair (faces 2-5, 8). Over the floor, the hidden F falls
    /// 20-fold within y = 1.65 .. 1.68, where the side wall's top edge lines up with the
    /// ceiling's edges: two kink planes along all of the floor. In blocker order the risers'
    /// events came first, planes x = const that are events only within 0.09 of the floor's
    /// edge, and cut it into strips that used up the split's pieces; long start pieces across
    /// that band then had all their samples beyond it and their coarse estimate content (in
    /// the building one of them 3.2e-6 for 9.3e-6). F was 1.6, 4.0 and 11.4 x tol off at
    /// obstructed_tol 3e-3, 1e-3 and 3e-4. The reference, F = 1.2962187e-3, is a tensor Gauss
    /// rule over the floor of the exact point F (visible region by clipping), its panels cut at
    /// the traces of the planes through an axis-parallel edge and a vertex of the scene (4 and
    /// 8 panels of 4 x 4 points between them: 1.29621869e-3 and 1.29621867e-3); clipping at
    /// tol 1e-9 agrees to 2e-11.
    #[test]
    fn kink_cuts_that_run_over_the_source_come_first() {
        let quads: [[[f64; 3]; 4]; 9] = [
            [[9.4, 1.5, 0.0], [11.7, 1.5, 0.0], [11.7, 3.5666666666666664, 0.0], [9.4, 3.5666666666666664, 0.0]],
            [[9.05, 0.3, 5.5], [9.8, 0.3, 5.5], [9.8, 0.0, 5.5], [9.05, 0.0, 5.5]],
            [[9.86, 0.3, 0.9], [9.86, 1.5, 0.9], [9.86, 1.5, 0.6], [9.86, 0.3, 0.6]],
            [[10.09, 0.3, 1.2], [10.09, 1.5, 1.2], [10.09, 1.5, 0.9], [10.09, 0.3, 0.9]],
            [[10.32, 0.3, 1.5], [10.32, 1.5, 1.5], [10.32, 1.5, 1.2], [10.32, 0.3, 1.2]],
            [[10.55, 0.3, 1.8], [10.55, 1.5, 1.8], [10.55, 1.5, 1.5], [10.55, 0.3, 1.5]],
            [[9.8, 0.3, 5.5], [11.7, 0.3, 5.5], [11.7, 0.3, 4.1], [9.8, 0.3, 4.1]],
            [[9.63, 1.5, 0.6], [11.7, 1.5, 0.6], [11.7, 1.5, 0.3], [9.63, 1.5, 0.3]],
            [[9.86, 0.3, 0.9], [10.09, 0.3, 0.9], [10.09, 1.5, 0.9], [9.86, 1.5, 0.9]],
        ];
        let polys: Vec<Polygon> =
            quads.iter().map(|q| Polygon::new(q.iter().map(|&v| Vec3::from_array(v)).collect()).unwrap()).collect();
        let free = polygon_pair_within(&polys[0], &polys[1], 1e-13);
        let reference = 1.2962187e-3 * polys[0].area();
        assert!(reference < 0.9 * free);
        assert_meets(&polys, (0, 1), reference, free, &[1e-2, 3e-3, 1e-3, 3e-4]);
    }

    /// The seed-38 replay of tests/test_properties.py: only a triangle 6e-5 across of face 0
    /// lies in front of face 2 (radius 0.8), whose vertex it has; face 1 crosses face 2's plane
    /// and stands on face 0 across that triangle. Over face 2 the kernel gathers within 1e-4
    /// of the vertex: F came out 2.8e-13 at obstructed_tol 1e-3 and 1.39e-9 at the default.
    /// Reference: graded tensor Gauss of the exact point F over the triangle, cut along face
    /// 1's trace (6 points a panel, graded by 10 towards every vertex; 3 and 5 levels agree to
    /// 1e-12 and the free F the same way is within 5e-9 of the closed form).
    #[test]
    fn a_pair_whose_part_in_front_is_far_smaller_is_integrated_over_it() {
        let polys = triangles(&[
            [[0.0, 0.0, 0.0], [-1.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
            [[0.0, 0.0, 1.0], [1.0, 1.0, 0.0], [-6.103515625e-05, 0.0, 0.0]],
            [[0.0, 1.0, 0.0], [0.0, -1.0, 1.0], [-6.103515625e-05, 0.0, 0.0]],
        ]);
        let free = polygon_pair_within(&polys[0], &polys[2], 1e-13);
        let reference = 1.0960495670e-9 * polys[0].area();
        assert_meets(&polys, (0, 2), reference, free, &[1e-3, 1e-6]);
    }

    /// Seed 39 of the long property run (tests/test_properties.py): faces 0-2 each have an edge
    /// in y = 0, within 4e-8 of face 4's plane (face 4 leans 6e-8 out of it), and face 3 crosses
    /// that plane, so an edge of a blocker and a vertex of face 3's part in front span a kink
    /// plane 4e-8 rad off face 4's. Over face 4 that plane lies within the split's tolerance
    /// (1e-9 of the pair's size) along a band 0.04 wide, and a start piece with vertices on
    /// both sides of the band and two in it was cut into halves that overlapped (area 0.0532
    /// -> 0.0560): the start pieces' unobstructed G summed to 6.0914e-4 for the face's
    /// 6.0667e-4, and F[3, 4] over face 4 came out 3.3042e-5 at every tol for 6.506920e-5
    /// (nested adaptive Gauss-Kronrod over face 3 of the exact point F, to 1e-11 of F:
    /// 6.5069200e-5 / 6.5069254e-5 from two of its vertices). The second scene (face 2 moved,
    /// faces 0-4 rounded) at 3 p + 21, where the same kind of plane split a piece of 0.2933
    /// into 0.3062: 3.1607e-5 for 3.2836996e-5 (64 x tol; at the origin, where the plane's
    /// rounding differs, 3.2836752e-5). Such a piece now stays whole (`geometry::cuts_in_two`).
    #[test]
    fn a_kink_plane_nearly_in_the_sources_plane_cuts_no_overlapping_halves() {
        let first = triangles(&[
            [
                [0.0, 0.0, 0.4643752850792635],
                [0.0, 0.0, -0.30993796626476466],
                [0.0, 0.4959378708484483, 0.4916379264466204],
            ],
            [
                [0.0, 0.0, -0.9213925681584167],
                [0.0, 0.0, -0.3036873413796738],
                [0.0, 0.4083555728127941, -0.7256366774880623],
            ],
            [
                [0.0, 0.0, 0.9999999999999999],
                [0.43926912210183633, 0.0, -0.6206510770004806],
                [-0.9474149672713192, 0.5263460985521964, 0.5],
            ],
            [
                [0.0, -0.035490666954058225, 0.0],
                [0.0, -0.029731871631357043, -0.2424826093484571],
                [-0.5155422402224391, 0.3119631603455597, 0.9548792880155585],
            ],
            [
                [0.15058686561303403, 0.0, 0.27732066287958834],
                [0.6820315858517412, 5.960464477539063e-08, -0.8556063093113888],
                [-0.24309367533859905, 0.0, -1.0],
            ],
        ]);
        let second: Vec<[[f64; 3]; 3]> = [
            [[0.0, 0.0, 0.4643752850792635], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]],
            [[0.0, 0.0, -0.9375], [0.0, 0.0, 0.0], [0.0, 1.0, -1.0]],
            [[0.0, 1.0, 0.0], [0.5, 0.0, 1.0], [-0.5, 0.5263460985521964, 0.5]],
            [[0.0, -0.03125, 0.0], [0.0, -0.03125, -0.125], [-0.515625, 0.5, 0.75]],
            [
                [0.15058686561303403, 0.0, 0.28125],
                [0.6820315858517412, 5.960464477539063e-08, -0.8556063093113888],
                [-0.244140625, 0.0, -1.0],
            ],
        ]
        .iter()
        .map(|p| p.map(|v| v.map(|x| 3.0 * x + 21.0)))
        .collect();
        let tol = 1e-6;
        for (polys, f34) in [(first, 6.506920e-5), (triangles(&second), 3.2836996e-5)] {
            let free = polygon_pair_within(&polys[3], &polys[4], 0.0);
            let reference = f34 * polys[3].area();
            for (i, j) in [(4, 3), (3, 4)] {
                let g = over_first(&polys, i, j, &ClippingOptions { tol, ..Default::default() });
                let off = (g - reference) / (tol * free);
                assert!(off.abs() <= 0.5, "over face {i}: G {g:e} for {reference:e}, {off:.2} x tol");
            }
        }
    }

    /// The hidden G of the pair (triangle `src`, `rec`) behind `blockers` by a tensor rule
    /// independent of the adaptive one: over the distance d from src's edge v1 v2 (src =
    /// d v0 + (1 - d) ((1 - t) v1 + t v2)) Gauss-Legendre on `panels` panels of ln d from
    /// 1e-14 to 1, over t adaptive Gauss between the places where the point's shadow starts,
    /// ends or covers its whole F (found on a `scan`-step scan and bisected to 1e-13; a stretch
    /// narrower than a step can be missed, so the scan is the reference's accuracy knob): for
    /// a hidden F gathered within 1e-7 of that edge, which no rule on the whole triangle sees.
    /// The "not hidden" state allows rounding (1e-12 of the free F): with `h <= 0` a steep
    /// stretch 1 % of t long merged into a flat one and the adaptive rule converged without
    /// it (1.5e-4 of the unobstructed F off in the test below).
    fn hidden_near_edge(src: &Polygon, rec: &Polygon, blockers: &[&Polygon], panels: usize, scan: usize) -> f64 {
        let [v0, v1, v2] = [0, 1, 2].map(|k| src.vertices()[k]);
        let n = src.normal();
        let at = |d: f64, t: f64| v0 * d + (v1 * (1.0 - t) + v2 * t) * (1.0 - d);
        let hidden = |d: f64, t: f64| point_shadowed_and_free(at(d, t), n, rec, blockers, false).0;
        let state = |d: f64, t: f64| {
            let (h, f) = point_shadowed_and_free(at(d, t), n, rec, blockers, true);
            let f = f.unwrap_or(0.0);
            if h <= 1e-12 * f {
                0
            } else if h >= f {
                2
            } else {
                1
            }
        };
        let gl = gauss_legendre(8);
        let (lo, hi) = (1e-14_f64.ln(), 0.0);
        let mut total = 0.0;
        for p in 0..panels {
            let (u0, u1) = (lo + (hi - lo) * p as f64 / panels as f64, lo + (hi - lo) * (p + 1) as f64 / panels as f64);
            for &(x, w) in gl {
                let d = (u0 + (u1 - u0) * x).exp();
                let mut cuts = vec![0.0];
                let mut next = state(d, 0.0);
                for k in 0..scan {
                    let (mut a, mut b) = (k as f64 / scan as f64, (k + 1) as f64 / scan as f64);
                    let s = next;
                    next = state(d, b);
                    if next != s {
                        while b - a > 1e-13 {
                            let m = 0.5 * (a + b);
                            if state(d, m) == s {
                                a = m
                            } else {
                                b = m
                            }
                        }
                        cuts.push(0.5 * (a + b));
                    }
                }
                cuts.push(1.0);
                let inner: f64 =
                    cuts.windows(2).map(|c| adaptive_gauss(&|t| hidden(d, t), c[0], c[1], 1e-10, 30)).sum();
                // dA = 2 A (1 - d) dd dt, dd = d du
                total += w * (u1 - u0) * d * (1.0 - d) * inner;
            }
        }
        2.0 * src.area() * total
    }

    /// The integral of f over [a, b] by 8-point Gauss-Legendre, halved until the halves'
    /// sum is within `eps` of the whole (at most `depth` times).
    fn adaptive_gauss(f: &dyn Fn(f64) -> f64, a: f64, b: f64, eps: f64, depth: usize) -> f64 {
        let rule =
            |a: f64, b: f64| gauss_legendre(8).iter().map(|&(y, v)| v * (b - a) * f(a + (b - a) * y)).sum::<f64>();
        let m = 0.5 * (a + b);
        let (whole, halves) = (rule(a, b), rule(a, m) + rule(m, b));
        if (whole - halves).abs() <= eps || depth == 0 {
            halves
        } else {
            adaptive_gauss(f, a, m, 0.5 * eps, depth - 1) + adaptive_gauss(f, m, b, 0.5 * eps, depth - 1)
        }
    }

    /// Seed 36 of the long run (tests/test_properties.py): face 0 leans 1e-8 out of the plane
    /// y = 0 of face 2, the two facing each other across that gap where their edges run along
    /// the line y = z = 0, and face 1 stands across the gap in the plane z = 0. They see each
    /// other only within about 1e-8 of that line (unobstructed F 1e-8), and face 1 hides all
    /// but about 3e-12 of it; no start piece's samples come near. Scaled and moved, the pair
    /// claimed the default goal met with nothing hidden. Held to the start pieces' exact
    /// unobstructed G (`missed` in `adaptive_over_source`), it does not resolve the band but
    /// says so: its error estimate covers its error. The reference is a tensor Gauss rule over
    /// face 0 of the visible point F, its panels graded by 10 towards the two edges of face 0
    /// at the origin, down to 1e-16; the same rule gives the unobstructed G to 1e-6.
    #[test]
    fn samples_that_miss_where_the_unobstructed_f_gathers_say_so() {
        let raw = [
            [[0.0, 0.0, 0.0], [0.0, 0.0, 0.5], [-1.0, 1e-8, 0.0]],
            [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]],
            [[0.0, 0.0, 0.0], [1.0, 0.0, -1.0], [-1.0, 0.0, 0.0]],
        ];
        let polys = triangles(&raw);
        let (f0, f2) = (&polys[0], &polys[2]);
        let (o, e1, e2) = (f0.vertices()[0], f0.vertices()[1] - f0.vertices()[0], f0.vertices()[2] - f0.vertices()[0]);
        let jacobian = e1.cross(e2).length();
        // panels on [0, len] graded by 10 towards 0
        let graded = |len: f64| {
            let mut cuts: Vec<f64> = (0..=30).map(|k| len * 4f64.powi(-k)).collect();
            cuts.push(0.0);
            cuts.windows(2)
                .flat_map(|w| {
                    gauss_legendre(8).iter().map(move |&(y, wt)| (w[1] + (w[0] - w[1]) * y, wt * (w[0] - w[1])))
                })
                .collect::<Vec<_>>()
        };
        let (mut visible, mut all) = (0.0, 0.0);
        for (u, wu) in graded(1.0) {
            for (w, ww) in graded(1.0 - u) {
                let x = o + e1 * u + e2 * w;
                let (hidden, free) = point_shadowed_and_free(x, f0.normal(), f2, &[&polys[1]], true);
                let free = free.unwrap();
                visible += wu * ww * jacobian * (free - hidden);
                all += wu * ww * jacobian * free;
            }
        }
        let free = polygon_pair_within(f0, f2, 0.0);
        assert!((all - free).abs() <= 1e-6 * free, "the rule's unobstructed G {all:e} for {free:e}");
        assert!(visible < 1e-3 * free, "visible {visible:e} of {free:e}");
        for scale in [1.0, 1e-6] {
            let moved: Vec<Polygon> = polys
                .iter()
                .map(|p| {
                    Polygon::new(p.vertices().iter().map(|x| *x * scale + Vec3::splat(7.0 * scale)).collect()).unwrap()
                })
                .collect();
            let (reference, free) = (visible * scale * scale, free * scale * scale);
            for tol in [1e-6, 1e-3] {
                let e = clipping_estimate(&moved, 0, 2, &ClippingOptions { tol, ..Default::default() }, 1e-12);
                let err = (e.value - reference).abs();
                assert!(
                    err <= e.std_err.max(tol * free),
                    "scale {scale}, tol {tol}: error {:.3} of the free G, reported {:.3}",
                    err / free,
                    e.std_err / free
                );
            }
        }
    }

    /// Seed 43 of the long run (tests/test_properties.py, scene test, on 7d6ef69): faces 0 and
    /// 2 meet at an edge nearly back to back, 1.2e-7 apart at one end, and see each other only
    /// within 1e-7 of it; face 1 lies in the plane through that edge between them and hides
    /// 42 % of their unobstructed F. Face 0's part in front of face 2 is a sliver 1e-7 wide, so
    /// it is far the smaller (`far_smaller`: its radius was not, its width is), and face 4's
    /// vertex 8e-8 over face 0 (clearance 8e-8 of face 0's radius, face 2's 1.3e-2) is no hover
    /// over a part 1e-7 wide (`part_clearance`: 0.37). The clearances had sent the integral over
    /// face 2, whose samples lie far outside the layer where the hidden F gathers: 4 % of the
    /// unobstructed F off, every target claimed met. The long run's second case (0f6e4c5, face
    /// 4's third vertex elsewhere) moved: the sliver's integral ran out short of its goal (but
    /// within 7.7e-7 of the unobstructed F) and face 2's replaced it, 1.3e-4 off; a side chosen
    /// as far the smaller is now kept. The reference is an independent tensor rule over face 0
    /// (`hidden_near_edge`; doubling its panels moved it by 1e-6 of the unobstructed F, and
    /// the second case needs a finer scan: 400 steps were 1.8e-4 off, 2 000 2.8e-5, 3 000 and
    /// 8 000 within 1e-5 of the pair).
    #[test]
    fn a_sliver_in_front_is_integrated_though_a_blocker_comes_close_to_it() {
        let scene: [[[f64; 3]; 3]; 5] = include!("../../../../tests/data/seed_43_sliver_in_front.txt");
        // the long run's second case: face 4's third vertex elsewhere (its vertex near face 0
        // as before), where moved the other side replaced the sliver's integral
        let mut other = scene;
        other[4][2] = [-0.7131272104126429, 0.0, 0.11025108287547725];
        // faces 0, 1, 2 alone: the width makes face 0 the smaller side; all five: face 4 too
        for (raw, scan) in [(&scene[..3], 400), (&scene[..], 400), (&other[..], 3000)] {
            // as they are and scaled by 1e-6 and moved by 7e-6 (rounding moves the sides' plane
            // tests: a different side's estimate ran out there)
            let [(polys, _), (moved, _)] = placements(raw);
            let blockers: Vec<&Polygon> =
                polys.iter().enumerate().filter(|&(k, _)| k != 0 && k != 2).map(|(_, p)| p).collect();
            let free = polygon_pair_within(&polys[0], &polys[2], 0.0) / polys[0].area();
            let reference = free - hidden_near_edge(&polys[0], &polys[2], &blockers, 120, scan) / polys[0].area();
            assert!((reference / free - 0.577).abs() < 1e-3, "reference {reference:e} of {free:e}");
            for (placed, polys) in [("as is", &polys[..]), ("moved", &moved[..])] {
                // (at 1e-3 the sliver's integral is 1.3 x tol off: within the property test's 2 x)
                for (tol, bound) in [(1e-3, 2e-3), (1e-6, 1e-5)] {
                    // (either order where the clearances tie and the first is integrated; each of
                    // these pairs takes about a second)
                    let orders: &[(usize, usize)] = if polys.len() == 3 { &[(0, 2), (2, 0)] } else { &[(0, 2)] };
                    for &(i, j) in orders {
                        let o = ClippingOptions { tol, ..Default::default() };
                        let f = clipping(polys, i, j, &o, 1e-12) / polys[0].area();
                        let off = (f - reference) / free;
                        assert!(
                            off.abs() <= bound,
                            "{} faces {placed}, ({i}, {j}), tol {tol:e}: F {f:e} for {reference:e}: {off:.2e} of the free F",
                            polys.len()
                        );
                    }
                }
            }
        }
    }

    /// Seed 44 of the long property run (tests/data/seed_44_needle_in_front.txt): only a needle
    /// of face 2 (1.25 long, 6.1e-5 high) lies in front of face 4, which it pierces along a
    /// segment 0.014 long, and face 3's trace crosses that segment. The integral runs over the
    /// needle, far the smaller side; the kink split leaves it in slivers up to 0.69 long and
    /// 3.5e-5 wide, cornered where face 4's edge meets it, where the point F changes on the
    /// scale of the distance from that corner. As slivers (each child a sliver like its
    /// parent) they ended 4.4e-5 of the unobstructed F off at the default, every target
    /// claimed met; then, their corners compared, 2.9e-6 off out of evaluations. Graded, they
    /// meet it. The reference: [`SEED_44_F42`].
    #[test]
    fn a_needle_in_front_is_graded_where_the_receiver_meets_it() {
        let raw: [[[f64; 3]; 3]; 5] = include!("../../../../tests/data/seed_44_needle_in_front.txt");
        for (polys, _) in placements(&raw) {
            let (area, free) = (polys[4].area(), polygon_pair_within(&polys[4], &polys[2], 0.0));
            assert!(far_smaller(
                &super::super::clip_pair_polygons(&polys[2], &polys[4]).unwrap().0.unwrap(),
                &polys[4]
            ));
            for tol in [1e-6, 1e-7] {
                let o = ClippingOptions { tol, ..Default::default() };
                for (how, g) in
                    [("over the needle", over_first(&polys, 2, 4, &o)), ("clipping", clipping(&polys, 4, 2, &o, 1e-12))]
                {
                    let off = (g - SEED_44_F42 * area) / free;
                    assert!(off.abs() <= tol, "{how}, tol {tol:e}: F {:e}, {off:.2e} of the free F", g / area);
                }
            }
        }
    }

    /// F from face 4 to face 2 of seed 44, by an integration that shares nothing with
    /// `clipping`: over the needle, face 4's part in front less face 3's shadow cone (clipped
    /// by half-planes) per point, Lambert's contour sum, nested adaptive Gauss-Kronrod (scipy,
    /// relative 1e-8, estimated error 2.3e-12); the same rule gives the unobstructed F within
    /// 4e-16 of the exact one. `test_seed_44_reference` in tests/test_properties.py (slow)
    /// repeats it.
    const SEED_44_F42: f64 = 3.530038657707e-5;

    /// The start piece of seed 44's needle beyond the pierce segment's end P, as the kink split
    /// leaves it (0.6 long, 3.5e-5 wide, cornered at P): its samples are 99 % hidden and it
    /// integrates the visible part, which rises from 7e-8 to 4e-3 of the point F towards P
    /// within 1e-3 of its length, beyond every sample of it and its children. Its estimate
    /// must say so. Before the corners of the pieces that integrate the visible part were
    /// compared with their samples' quadratic too, it claimed 5.1e-13 for an error of 1.7e-9
    /// (F units). Reference: the hidden F over the piece 1.50565e-8 (x face 4's area; the
    /// integration of [`SEED_44_F42`] over this triangle, from P, relative 1e-9; repeated by
    /// `test_seed_44_reference`).
    #[test]
    fn a_visible_piece_compares_its_corners_with_its_samples() {
        let raw: [[[f64; 3]; 3]; 5] = include!("../../../../tests/data/seed_44_needle_in_front.txt");
        let polys = triangles(&raw);
        let piece = [
            Vec3::new(0.41015625, -0.515625, 0.0),
            Vec3::new(-0.18911304644732252, -0.2682762589384444, 2.927897029611217e-5),
            Vec3::new(-0.18948271022069518, -0.26810338777587256, 0.0),
        ];
        let (ca, cb) = super::super::clip_pair_polygons(&polys[2], &polys[4]).unwrap();
        let (sa, sb) = (ca.unwrap(), cb.unwrap());
        let blockers: Vec<&Polygon> = [0, 1, 3].iter().map(|&k| &polys[k]).collect();
        let (area, free) = (polys[4].area(), polygon_pair_within(&polys[4], &polys[2], 0.0));
        let o = ClippingOptions { tol: 1e-6, ..Default::default() };
        let goal = o.tol * free;
        let (hidden, err) =
            hidden_over_from((&polys[2], &polys[4], &sa, &sb), &blockers, &[0, 1, 2], Some(&[piece]), (free, goal), &o);
        let off = (hidden / area - 1.50565e-8).abs() * area;
        assert!(off <= err.max(goal), "off {off:e}, estimate {err:e}, goal {goal:e}");
    }

    /// A blocker that shares a vertex with the receiver, that vertex within rounding behind
    /// the receiver's plane (the scene scaled by 0.1 and moved by 0.7), is cut to the slab
    /// whole: no quad with an edge of rounding length (see `cut_to_slab`).
    #[test]
    fn a_vertex_shared_with_the_receiver_is_not_cut_off() {
        let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        let x0 = 0.7000000000000001;
        let source = Polygon::new(vec![v(x0, x0, x0), v(x0, x0, 0.8), v(x0, 0.8, x0)]).unwrap();
        let receiver = Polygon::new(vec![
            v(x0, 0.76875, 0.7841473395305626),
            v(x0, x0, 0.7757812500000001),
            v(0.6875000000000001, x0, 0.7250000000000001),
        ])
        .unwrap();
        let blocker = Polygon::new(vec![
            v(x0, x0, x0),
            v(x0, 0.74375, 0.7808593750000001),
            v(0.6875000000000001, x0, 0.7250000000000001),
        ])
        .unwrap();
        let cut = cut_to_slab(&source, &receiver, &[&blocker]);
        let kept = cut[0].as_ref().unwrap_or(&blocker);
        assert_eq!(kept.vertices().len(), 3, "{:?}", kept.vertices());
    }

    /// Seed 47 of tests/test_properties.py: over face 1, whose part in front of face 3 ends at
    /// face 3's plane and whose blockers touch face 3 at its vertices, the leaves along that
    /// edge had their rule 9e-4 off and their estimate 18 x too small (2.7 x tol at the
    /// default). Leaves touching the receiver's plane count their whole difference.
    #[test]
    fn leaves_on_the_receivers_plane_count_their_whole_difference() {
        let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        let polys = [
            Polygon::new(vec![v(0.0, 0.0, 0.0), v(0.5, 0.5, 0.0), v(-0.40625, 0.0, 0.0)]).unwrap(),
            Polygon::new(vec![v(0.0, 1.0, 0.0), v(1.0, 0.0, 0.5), v(-0.5, 1.0, 0.125)]).unwrap(),
            Polygon::new(vec![v(0.0, 0.40625, -0.875), v(0.0, 0.03125, 0.75), v(0.0, -1.0, 0.0)]).unwrap(),
            Polygon::new(vec![v(0.375, 0.0, -0.5), v(0.0, -1.0, 0.0), v(0.0, 0.0, 0.0)]).unwrap(),
        ];
        assert_side_meets_the_other(&polys, (1, 3), &[1e-4, 1e-5, 1e-6], &[1e-3, 1e-6]);
    }

    /// Seed 50 of tests/test_properties.py: over face 2 (the long run's face 3), one start
    /// piece integrating the visible F had its 7 samples and its children's 28 in the shadows
    /// of faces 0 and 1, while near a corner up to 1 % of the free F came through the gap
    /// between them: G 3.7e-6 of itself low at every tol, while the other side was right.
    /// The gap's edge-edge-edge events are cut along (see `gap_chords` in kinks.rs).
    #[test]
    fn a_gap_between_two_shadows_is_cut_along_its_events() {
        let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        let polys = [
            Polygon::new(vec![
                v(0.5834344732009976, 0.0, 0.0),
                v(0.3333333333333333, 0.8134613990200181, 0.2676669448118274),
                v(0.14437714378005073, -0.3115530688414284, 0.0),
            ])
            .unwrap(),
            Polygon::new(vec![
                v(-0.05551362362587198, -0.11230303670122699, 0.0),
                v(0.0, -0.25120451086312146, -0.42556938510445386),
                v(0.5057808230093057, 0.24216463717099068, 0.0),
            ])
            .unwrap(),
            Polygon::new(vec![
                v(0.5661550787254854, -0.5259756847622777, 0.9),
                v(-2.612168588997259e-16, 0.0, -0.12338351339437925),
                v(1e-14, 0.4693412878996772, -0.5736047901251212),
            ])
            .unwrap(),
            Polygon::new(vec![
                v(-0.2831793327881308, 0.30925921026087466, -0.6077014464345906),
                v(0.6490271984464662, 0.33673889207489016, -0.6895780414664165),
                v(0.0, 0.0, 0.0),
            ])
            .unwrap(),
        ];
        assert_side_meets_the_other(&polys, (2, 3), &[1e-6, 1e-8], &[1e-3, 1e-6]);
    }

    /// Seed 45's third case of tests/test_properties.py: over face 4 a coarse start piece had
    /// its rule 1.6e-4 off and 3e-7 from its centroid value, the pair 2.7 x tol off at the
    /// default (see DEPARTURE_SHARE).
    #[test]
    fn a_coarse_piece_whose_corners_depart_is_not_trusted_by_chance() {
        let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
        let polys = [
            Polygon::new(vec![v(0.0, 0.0, 0.0), v(0.0, 0.0, -1.0), v(1.0, 0.0, 0.0)]).unwrap(),
            Polygon::new(vec![
                v(0.0, 1.0, 0.05977671361710102),
                v(0.0, 0.6186375174692582, 0.683122959190301),
                v(-0.09993839983683261, 0.33501723155085394, -0.9733139018287171),
            ])
            .unwrap(),
            Polygon::new(vec![
                v(0.0, -0.20326763832084072, 0.10632651596078335),
                v(0.46875, 0.0, 0.0),
                v(0.06299767811831303, 0.4427793657128054, 0.8766341686788581),
            ])
            .unwrap(),
            Polygon::new(vec![
                v(0.638671875, 0.7993437120978211, 0.04248816441465508),
                v(-0.7582202342443249, 0.0, -0.5621064531278795),
                v(-0.15890910981662576, 0.060114020170549454, -0.14029518611141456),
            ])
            .unwrap(),
            Polygon::new(vec![
                v(0.8728051321147716, 0.6811541323941599, 0.0),
                v(-0.3147727875888958, -0.4733073001111733, 0.9941554061686784),
                v(0.0, 0.382202328696702, 0.0),
            ])
            .unwrap(),
        ];
        assert_side_meets_the_other(&polys, (4, 1), &[1e-5, 1e-6], &[1e-6]);
    }
}
