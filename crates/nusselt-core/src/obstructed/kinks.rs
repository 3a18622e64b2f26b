//! The kink lines of the visible-region F over a source: where the adaptive source
//! integration starts from cut pieces instead of chasing a kink by refinement.

use super::rules::{area3, width};
use crate::geometry::{
    crosses_plane, cuts_in_two, segment_distance, split_by_plane, triangles_of, within_triangles, Polygon, Vec3,
};

/// Most pieces the kink split may cut a source into (the planes after it are not cut). At 64
/// the planes of a blocker whose shadow lay inside another's spent it before the events that
/// bound that other shadow on the source, whose samples then all missed it: 19 x tol at the
/// default 1e-6 (`a_blocker_that_hides_nothing_changes_nothing`). 1552 pairs of a tiled room
/// with two crates took 1.11-1.25 s CPU at 128 against 1.15-1.20 s at 64 (the same within
/// the host's noise).
pub(super) const MAX_KINK_PIECES: usize = 128;

/// Most casting blockers of a pair whose vertex-edge events between each other are kink planes
/// (see [`kink_planes`]). At 24 instead of 16 the building of bench/scenes.py at
/// obstructed_tol 1e-3 took 1 % more evaluations (4.15 M), and a pair with 19 casting blockers
/// went from 2.6 x tol off at 1e-8 to exact.
const MAX_PAIRWISE_BLOCKERS: usize = 24;

/// The source's triangles, cut along the lines where the visible-region F has a kink that
/// the dyadic refinement would otherwise chase without end (an O(h^2) error instead of the
/// degree-5 rule's fast convergence on smooth pieces):
/// - a blocker's own plane: as the point crosses it, that face turns edge-on and the
///   silhouette switches edges (the strongest kink);
/// - the plane through a receiver edge and a parallel blocker edge: there the shadow's edge
///   slides over the receiver's edge and the clipped area changes slope. Parallel edges are
///   the rule in architectural and meshed scenes;
/// - then the vertex-edge events (a shadow vertex crosses a receiver edge, a shadow edge a
///   receiver vertex; discontinuity meshing's D2 lines) whose trace crosses the source. Only
///   the second derivative jumps there, but for nearly parallel edges the slope changes
///   within a strip so thin that the error estimate cannot see it (before these cuts, 300
///   room pairs of `obstructed_schemes` at tol 1e-3 had errors up to 1.6e-3 of the
///   unobstructed F, at 1e-6 up to 4.7e-6; with them 1.6e-5 and 7e-8).
///
/// `receiver` is the part of the receiver in front of the source's plane: no source point
/// sees more of it, and where that plane cuts the receiver, the cut's vertices and edge have
/// events of their own. `casting` indexes the blockers that cast a shadow of their own (the
/// others are hidden behind them from the whole source): their events come first, and only
/// theirs between blockers.
///
/// Returns the start triangles and, for each, whether a kink left uncut (past
/// MAX_KINK_PIECES) crosses it; with `mark_kinked` false, all false (testing every piece
/// against every uncut kink was a fifth of this function's time in the building of
/// bench/scenes.py at obstructed_tol 1e-3, where the flag is not used).
pub(super) fn split_at_kinks(
    a: &Polygon,
    receiver: &Polygon,
    blockers: &[&Polygon],
    casting: &[usize],
    mark_kinked: bool,
) -> (Vec<[Vec3; 3]>, Vec<bool>) {
    let (pieces, kinked, _) = split_at_kinks_along(a, receiver, blockers, casting, mark_kinked);
    (pieces, kinked)
}

/// [`split_at_kinks`], and the kink planes that hold an edge of `a` (no cut along them: they
/// bound it). Along such an edge the hidden F can change within a layer thinner than the
/// pieces there, which their rule does not resolve (see `along_kink` in clipping).
pub(super) fn split_at_kinks_along(
    a: &Polygon,
    receiver: &Polygon,
    blockers: &[&Polygon],
    casting: &[usize],
    mark_kinked: bool,
) -> (Vec<[Vec3; 3]>, Vec<bool>, Vec<(Vec3, Vec3)>) {
    let kinks = kink_planes(a, receiver, blockers, casting);
    let v = a.vertices();
    let on = |q: Vec3, n: Vec3, x: Vec3| n.dot(x - q).abs() <= kinks.tol;
    let along: Vec<(Vec3, Vec3)> = kinks
        .planes
        .iter()
        .filter(|&&(q, n)| (0..v.len()).any(|k| on(q, n, v[k]) && on(q, n, v[(k + 1) % v.len()])))
        .copied()
        .collect();
    let mut pieces: Vec<Piece> = a.triangulate().iter().map(|t| Piece::new(vec![v[t[0]], v[t[1]], v[t[2]]])).collect();
    // The planes, then the chords (each cutting only the pieces it meets), until the pieces
    // reach MAX_KINK_PIECES: a cut (q, n, the chord's other end) splits the pieces it crosses.
    let na = a.normal();
    let cuts: Vec<(Vec3, Vec3, Option<Vec3>)> = (kinks.planes.iter().map(|&(q, n)| (q, n, None)))
        .chain(kinks.chords.iter().map(|&(p0, p1)| (p0, (p1 - p0).cross(na).normalize_or_zero(), Some(p1))))
        .collect();
    // (a piece that a cut would split into overlapping halves stays whole: see cuts_in_two)
    let splits = |piece: &Piece, &(q, n, end): &(Vec3, Vec3, Option<Vec3>)| {
        !piece.beside(q, n, kinks.tol)
            && cuts_in_two(&piece.v, q, n, kinks.tol)
            && end.is_none_or(|p1| meets_chord(&piece.v, q, p1, n, kinks.tol))
    };
    let mut done = 0;
    let mut halves = Vec::with_capacity(2);
    while done < cuts.len() && pieces.len() < MAX_KINK_PIECES {
        // (most cuts split few pieces: those before the first are kept where they are)
        let cut = &cuts[done];
        if let Some(first) = pieces.iter().position(|p| splits(p, cut)) {
            let rest = pieces.split_off(first);
            for (k, piece) in rest.into_iter().enumerate() {
                if k == 0 || splits(&piece, cut) {
                    split_by_plane(&piece.v, cut.0, cut.1, kinks.tol, &mut halves);
                    pieces.extend(halves.drain(..).map(Piece::new));
                } else {
                    pieces.push(piece);
                }
            }
        }
        done += 1;
    }
    // the pieces that a cut left undone crosses (see `kinked` in clipping)
    let kinked = |piece: &Piece| mark_kinked && cuts[done..].iter().any(|c| splits(piece, c));
    // Every piece is convex (a triangle cut by planes): fan triangulation.
    let min_area = 1e-12 * a.area();
    let mut triangles = Vec::with_capacity(2 * pieces.len());
    let mut crossed = Vec::with_capacity(2 * pieces.len());
    for p in pieces.iter().filter(|p| p.v.len() >= 3) {
        let k = kinked(p);
        for t in fan_triangles(&p.v, min_area) {
            triangles.push(t);
            crossed.push(k);
        }
    }
    (triangles, crossed, along)
}

/// A convex piece of the kink split and the sphere about its vertices' mean that holds them.
struct Piece {
    v: Vec<Vec3>,
    centre: Vec3,
    radius: f64,
}

impl Piece {
    fn new(v: Vec<Vec3>) -> Self {
        let centre = v.iter().copied().sum::<Vec3>() / v.len().max(1) as f64;
        let radius = v.iter().map(|x| x.distance(centre)).fold(0.0, f64::max);
        Piece { v, centre, radius }
    }

    /// True if every vertex lies more than `tol` from the plane (q, unit n), all on one side,
    /// by the sphere alone: no cut there (`cuts_in_two` says the same, at the cost of every
    /// vertex; testing every piece against every cut was 13 % of the building's CPU at
    /// obstructed_tol 1e-3). The margin covers the rounding of the two dot products.
    fn beside(&self, q: Vec3, n: Vec3, tol: f64) -> bool {
        let off = self.centre - q;
        n.dot(off).abs() > self.radius + tol + 1e-12 * (off.length() + self.radius)
    }
}

/// Least ratio of a start piece's longest edge to its least altitude for [`grade_slivers`].
const SLIVER_ASPECT: f64 = 64.0;

/// Share of a sliver's length within which the receiver must come to it for
/// [`grade_slivers`] to cut it.
const GRADED_REACH: f64 = 0.125;

/// The start pieces, with each sliver (longest edge L at least [`SLIVER_ASPECT`] times its
/// least altitude h) that the receiver comes within [`GRADED_REACH`] L of cut across its length
/// at s, 2s, 4s, ... from its vertex nearest the receiver (s: that vertex's distance from the
/// receiver, at least h). Near a receiver the point F varies on the scale of the distance to
/// it, and a sliver's four children are slivers like it: a feature as wide as the sliver but
/// far shorter than it takes 4^k leaves across the width to resolve where graded pieces take
/// a handful. Seed 44 of tests/test_properties.py: a needle 3.8e-5 wide and 0.6 long, cornered
/// where the receiver's edge meets it, its visible F falling from 4e-3 to 7e-8 along it
/// within 1e-3 of its length; 129 000 evaluations to reach 1e-6 of the pair's F as one
/// piece (more than the budget: the pair ended 2.9 x tol off).
pub(super) fn grade_slivers(
    start: Vec<[Vec3; 3]>,
    kinked: Vec<bool>,
    receiver: &Polygon,
) -> (Vec<[Vec3; 3]>, Vec<bool>) {
    let (rec, rv, n) = (triangles_of(receiver), receiver.vertices(), receiver.normal());
    let distance = |x: Vec3| {
        let h = n.dot(x - rv[0]);
        if within_triangles(&rec, n, x - n * h, 0.0) {
            h.abs()
        } else {
            (0..rv.len()).map(|k| segment_distance(x, x, rv[k], rv[(k + 1) % rv.len()])).fold(f64::INFINITY, f64::min)
        }
    };
    let (mut pieces, mut flags) = (Vec::with_capacity(start.len()), Vec::with_capacity(start.len()));
    let mut cut: Vec<Vec<Vec3>> = Vec::new();
    for (t, k) in start.into_iter().zip(kinked) {
        let e =
            (0..3).max_by(|&i, &j| t[i].distance(t[(i + 1) % 3]).total_cmp(&t[j].distance(t[(j + 1) % 3]))).unwrap();
        let long = t[(e + 1) % 3] - t[e];
        let len = long.length();
        let least = 2.0 * area3(&t) / len;
        // (the receiver's distance only for slivers: this runs on every start piece)
        let graded = (len > SLIVER_ASPECT * least).then(|| t.map(distance)).and_then(|d| {
            let near = (0..3).min_by(|&i, &j| d[i].total_cmp(&d[j])).unwrap();
            let step = d[near].max(least);
            let far = d.iter().fold(0.0_f64, |m, &x| m.max(x));
            (step < GRADED_REACH * len && far > GRADED_REACH * len).then_some((t[near], step))
        });
        let Some((v, step)) = graded else {
            pieces.push(t);
            flags.push(k);
            continue;
        };
        let u = long / len;
        let (lo, hi) = t.iter().fold((0.0_f64, 0.0_f64), |(lo, hi), x| (lo.min(u.dot(*x - v)), hi.max(u.dot(*x - v))));
        let tol = 1e-9 * len;
        cut.clear();
        cut.push(t.to_vec());
        for dir in [1.0, -1.0] {
            let reach = if dir > 0.0 { hi } else { -lo };
            let mut at = step;
            while at < reach - step {
                // the piece beyond the cut at `at` is cut again; the near one is kept
                let Some(k) = cut.iter().position(|p| crosses_plane(p, v + u * (dir * at), u, tol)) else { break };
                let p = cut.swap_remove(k);
                split_by_plane(&p, v + u * (dir * at), u, tol, &mut cut);
                at *= 2.0;
            }
        }
        let min_area = 1e-12 * area3(&t);
        for p in cut.iter().filter(|p| p.len() >= 3) {
            for f in fan_triangles(p, min_area) {
                pieces.push(f);
                flags.push(k);
            }
        }
    }
    (pieces, flags)
}

/// Fan triangles of a convex piece (at least 3 vertices). Slivers from cuts through a vertex
/// carry no area but would put sample points on a kink line: those below `min_area` are left
/// out.
fn fan_triangles(p: &[Vec3], min_area: f64) -> impl Iterator<Item = [Vec3; 3]> + '_ {
    (1..p.len() - 1).map(move |k| [p[0], p[k], p[k + 1]]).filter(move |t| area3(t) > min_area)
}

/// True if the convex piece, which the line of the chord p0 p1 (in the plane with normal `n`
/// through p0) crosses, meets the chord itself: the stretch of that line inside the piece
/// overlaps the chord (within `tol`).
fn meets_chord(piece: &[Vec3], p0: Vec3, p1: Vec3, n: Vec3, tol: f64) -> bool {
    let u = p1 - p0;
    let len = u.length();
    if !(len > 0.0) {
        return false;
    }
    let u = u / len;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut take = |x: Vec3| {
        let s = u.dot(x - p0);
        lo = lo.min(s);
        hi = hi.max(s);
    };
    for k in 0..piece.len() {
        let (x, y) = (piece[k], piece[(k + 1) % piece.len()]);
        let (dx, dy) = (n.dot(x - p0), n.dot(y - p0));
        if dx.abs() <= tol {
            take(x);
        } else if (dx > tol && dy < -tol) || (dx < -tol && dy > tol) {
            take(x + (y - x) * (dx / (dx - dy)));
        }
    }
    hi >= -tol && lo <= len + tol
}

/// Where the line x + s t meets the segments e and f (each in a common plane with the line):
/// (s at e, s at f), or None if it misses either within 1e-9 of its length.
fn meets_both(x: Vec3, t: Vec3, e: (Vec3, Vec3), f: (Vec3, Vec3)) -> Option<(f64, f64)> {
    // s where the line meets the edge (p, q), if it does so between them (u from 0 at p to 1 at q)
    let meet = |(p, q): (Vec3, Vec3)| -> Option<f64> {
        let d = q - p;
        let c = d.cross(t);
        let cc = c.length_squared();
        if !(cc > 0.0) {
            return None;
        }
        let u = (x - p).cross(t).dot(c) / cc;
        (-1e-9..=1.0 + 1e-9).contains(&u).then(|| (x - p).cross(d).dot(c) / cc)
    };
    Some((meet(e)?, meet(f)?))
}

/// The direction of the line from x that meets the lines of the edges e and f: the line common
/// to the planes through x and each edge (0 where they coincide).
fn transversal(x: Vec3, e: (Vec3, Vec3), f: (Vec3, Vec3)) -> Vec3 {
    (e.0 - x).cross(e.1 - x).cross((f.0 - x).cross(f.1 - x))
}

/// The transversal from x through the lines of the edges e and f, where it meets the plane
/// through c with normal n: (that point, its parameter along the transversal, the parameters
/// where it meets e and f), or None if it runs parallel to the plane or misses either segment
/// (see [`meets_both`]).
fn transversal_trace(
    x: Vec3,
    e: (Vec3, Vec3),
    f: (Vec3, Vec3),
    (c, n): (Vec3, Vec3),
) -> Option<(Vec3, f64, (f64, f64))> {
    let t = transversal(x, e, f);
    let den = n.dot(t);
    if !(den.abs() > 0.0) {
        return None;
    }
    let reach = -n.dot(x - c) / den;
    let p = x + t * reach;
    if !p.is_finite() {
        return None;
    }
    Some((p, reach, meets_both(x, t, e, f)?))
}

/// Chords of the conic that the lines meeting the pierced edge v + s l (0 <= s <= 1) and the
/// edges e and f trace on the source's plane (through c with normal n), from its point V = v:
/// between the points whose transversals start 1/16, 1/8, 1/4, 1/2 and all of the way along
/// the pierced edge, while those still meet both edges (see `kink_planes`), into `out`.
fn conic_chords(
    v: Vec3,
    l: Vec3,
    e: (Vec3, Vec3),
    f: (Vec3, Vec3),
    (c, n): (Vec3, Vec3),
    tol: f64,
    out: &mut Vec<(Vec3, Vec3)>,
) {
    let mut prev = v;
    for s in [0.0625, 0.125, 0.25, 0.5, 1.0] {
        let Some((p, _, _)) = transversal_trace(v + l * s, e, f, (c, n)) else { break };
        if p.distance(prev) <= 1e3 * tol {
            break;
        }
        out.push((prev, p));
        prev = p;
    }
}

/// Most casting blockers of a pair for [`gap_chords`] (their edge pairs times the receiver's
/// edges are tried, each at GAP_STEPS points).
const MAX_GAP_BLOCKERS: usize = 8;

/// Points along a receiver edge from which [`gap_chords`] traces the conic.
const GAP_STEPS: usize = 8;

/// Chords of the edge-edge-edge events of two casting blockers and the receiver, into `out`:
/// where the lines from a source point through an edge of one blocker and an edge of another
/// end on an edge of the receiver, a gap between the two shadows opens or closes on the
/// receiver, and the point F has a kink (a gap through which 1 % of the free F came, 0 at
/// the 35 samples of the start piece it lay in: seed 50 of tests/test_properties.py). The
/// lines meeting three lines form a quadric, whose trace on the source's plane is a conic:
/// for points P along the receiver's edge, the transversal from P through both blocker edges
/// (meeting the segments, between P and the source's plane) meets that plane on the conic,
/// and consecutive such points are joined by chords. Only for up to MAX_GAP_BLOCKERS casting
/// blockers.
fn gap_chords(
    a: &Polygon,
    rec: &[Vec3],
    blockers: &[&Polygon],
    casting: &[usize],
    tol: f64,
    out: &mut Vec<(Vec3, Vec3)>,
) {
    if casting.len() < 2 || casting.len() > MAX_GAP_BLOCKERS {
        return;
    }
    let plane = (a.centroid(), a.normal());
    // (only chords over the source cut anything: the conic runs mostly beside it)
    let source = triangles_of(a);
    let over_source = |x0: Vec3, x1: Vec3| {
        let across = (x1 - x0).cross(plane.1).normalize_or_zero();
        source.iter().any(|t| meets_chord(t, x0, x1, across, tol))
    };
    let edges = |i: usize| {
        let v = blockers[i].vertices();
        (0..v.len()).map(move |k| (v[k], v[(k + 1) % v.len()]))
    };
    // where the transversal from P through the lines of e and f meets the source's plane, if it
    // meets both segments between P and that plane
    let trace = |p: Vec3, e: (Vec3, Vec3), f: (Vec3, Vec3)| -> Option<Vec3> {
        let (x, reach, (se, sf)) = transversal_trace(p, e, f, plane)?;
        let between = |s: f64| s * reach.signum() > 0.0 && s.abs() < reach.abs();
        (between(se) && between(sf)).then_some(x)
    };
    // each casting blocker's edges' arcs about each receiver edge's line (see `Arc`)
    let axes: Vec<Option<Axis>> = (0..rec.len()).map(|r| Axis::new(rec[r], rec[(r + 1) % rec.len()])).collect();
    let arcs: Vec<Vec<Vec<Option<Arc>>>> = casting
        .iter()
        .map(|&i| edges(i).map(|e| axes.iter().map(|ax| ax.as_ref()?.arc(e)).collect()).collect())
        .collect();
    for (ii, &i) in casting.iter().enumerate() {
        for (jj, &j) in casting.iter().enumerate().skip(ii + 1) {
            for (ei, e) in edges(i).enumerate() {
                for (fi, f) in edges(j).enumerate() {
                    // Edges with a common end V: every line from the receiver edge that meets
                    // both passes through V, and their events are those of the plane through V
                    // and the receiver edge, which the vertex-edge events cut (the building of
                    // bench/scenes.py at obstructed_tol 1e-3: 22 of 152 881 F change, by at most
                    // 7e-6 of the unobstructed F; their largest error against clipping at 1e-10
                    // 2.3e-5 -> 1.6e-5 of it)
                    if [e.0, e.1].iter().any(|x| x.distance(f.0) <= tol || x.distance(f.1) <= tol) {
                        continue;
                    }
                    for r in 0..rec.len() {
                        // (no line from the receiver edge meets both edges: nothing to trace)
                        if let (Some(ae), Some(af)) = (&arcs[ii][ei][r], &arcs[jj][fi][r]) {
                            if !ae.meets(af) {
                                continue;
                            }
                        }
                        let (r0, r1) = (rec[r], rec[(r + 1) % rec.len()]);
                        let mut prev: Option<Vec3> = None;
                        for k in 0..=GAP_STEPS {
                            let p = r0 + (r1 - r0) * (k as f64 / GAP_STEPS as f64);
                            let x = trace(p, e, f);
                            if let (Some(x0), Some(x1)) = (prev, x) {
                                if x0.distance(x1) > 1e3 * tol && over_source(x0, x1) {
                                    out.push((x0, x1));
                                }
                            }
                            prev = x;
                        }
                    }
                }
            }
        }
    }
}

/// The directions about an axis (a receiver edge's line) in which a segment lies: a line from
/// a point of the axis that meets two segments meets both in one half-plane bounded by the axis
/// (on one ray from that point), so the segments' arcs of directions overlap. An arc is the
/// angle of the segment's first end about the axis and the signed sweep to its second, less
/// than pi, widened by ARC_MARGIN at both ends for the rounding and the 1e-9 of its length by
/// which [`meets_both`] extends it.
struct Arc {
    start: f64,
    sweep: f64,
}

/// Radians by which an [`Arc`] is widened at each end.
const ARC_MARGIN: f64 = 1e-6;

/// Least distance of a segment from the axis, in its lengths, for which [`Axis::arc`] gives
/// an arc: nearer, 1e-9 of its length turns it by up to 1e-6 rad, and one touching the axis
/// lies in every direction.
const ARC_CLEARANCE: f64 = 1e-3;

/// The line through a0 (direction a1 - a0) about which [`Arc`]s are taken, with two unit vectors
/// across it.
struct Axis {
    a0: Vec3,
    u: Vec3,
    w: Vec3,
}

impl Axis {
    /// None if a1 = a0.
    fn new(a0: Vec3, a1: Vec3) -> Option<Axis> {
        let d = (a1 - a0).normalize_or_zero();
        if d == Vec3::ZERO {
            return None;
        }
        let (u, w) = d.any_orthonormal_pair();
        Some(Axis { a0, u, w })
    }

    /// The arc of the segment `e` about the axis, None if it comes within ARC_CLEARANCE of its
    /// length of the axis.
    fn arc(&self, e: (Vec3, Vec3)) -> Option<Arc> {
        let flat = |x: Vec3| {
            let v = x - self.a0;
            [v.dot(self.u), v.dot(self.w)]
        };
        let (p, q) = (flat(e.0), flat(e.1));
        // the segment's distance from the axis: from the origin to the segment pq in 2-D
        let pq = [q[0] - p[0], q[1] - p[1]];
        let len2 = pq[0] * pq[0] + pq[1] * pq[1];
        let s = if len2 > 0.0 { (-(p[0] * pq[0] + p[1] * pq[1]) / len2).clamp(0.0, 1.0) } else { 0.0 };
        let near = (p[0] + s * pq[0]).hypot(p[1] + s * pq[1]);
        if !(near > ARC_CLEARANCE * e.0.distance(e.1)) {
            return None;
        }
        let (ap, aq) = (p[1].atan2(p[0]), q[1].atan2(q[0]));
        let sweep = (aq - ap + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        let (start, sweep) = if sweep >= 0.0 { (ap, sweep) } else { (aq, -sweep) };
        Some(Arc { start: start - ARC_MARGIN, sweep: sweep + 2.0 * ARC_MARGIN })
    }
}

impl Arc {
    /// True if the two arcs share a direction.
    fn meets(&self, other: &Arc) -> bool {
        let within = |x: f64, a: &Arc| (x - a.start).rem_euclid(std::f64::consts::TAU) <= a.sweep;
        within(other.start, self) || within(self.start, other)
    }
}

/// One blocker's traces on the source's plane, row r for receiver vertex r, column k for the
/// blocker's vertex k (see `trace` in [`kink_planes`]).
type Traces = Vec<Vec<std::result::Result<Vec3, i8>>>;

/// The kink planes of a pair (see [`split_at_kinks`]), most important first, with the
/// length tolerance under which a vertex counts as on a plane (for the events and the cuts).
struct Kinks {
    planes: Vec<(Vec3, Vec3)>,
    /// stretches of curved kinks, chord by chord: each cuts only the pieces it meets
    chords: Vec<(Vec3, Vec3)>,
    tol: f64,
}

/// Share of the pair's size, and of the source's width, within which a point counts as on a
/// kink plane ([`Kinks::tol`]): far above the rounding of the coordinates, so that a vertex
/// shared with the source, or an event set by rounding, is classed alike wherever the scene
/// lies. Of the width too: a needle 1e-8 wide, the plane of a blocker (a kink plane) passing
/// through its vertex and at most 1e-12 off its long edge, lay within 1e-9 of the pair's size
/// of that edge and was not cut; the layer between, where the blocker hides most of the
/// point F, held 2e-4 of F, which the integral then missed or chased until it ran out of
/// evaluations, by where the scene lay and which other blockers it held (long-run seed 61,
/// tests/test_properties.py). The building of bench/scenes.py: the same work units within
/// 1e-5 at obstructed_tol 1e-3 (27 780 860 -> 27 781 024) and at the default.
const KINK_TOL: f64 = 1e-9;

/// Floor of [`Kinks::tol`] in ulps of the largest coordinate of the pair (a thin source's width
/// share would otherwise come down to the rounding it guards against).
const KINK_TOL_ULPS: f64 = 1e4;

fn kink_planes(a: &Polygon, receiver: &Polygon, blockers: &[&Polygon], casting: &[usize]) -> Kinks {
    let scale = a.radius() + receiver.radius() + a.centroid().distance(receiver.centroid());
    let coords = a.vertices().iter().chain(receiver.vertices()).fold(0.0_f64, |m, x| m.max(x.abs().max_element()));
    let tol = (KINK_TOL * scale.min(width(a))).max(KINK_TOL_ULPS * f64::EPSILON * coords);
    let mut planes: Vec<(Vec3, Vec3)> = Vec::new();
    let mut add = |q: Vec3, n: Vec3| {
        let len = n.length();
        if !(len > 0.0) || !len.is_finite() {
            return;
        }
        let n = n / len;
        // [methods] one work unit per 64 planes compared (a comparison costs about a
        // hundredth of a ray test; O(planes^2): 10 000 small blockers give 0.7 s of them);
        // over budget or cancelled, no more (the result is discarded)
        if !crate::work::spend(planes.len() as u64 / 64) {
            return;
        }
        if planes.iter().any(|(q2, n2)| n.cross(*n2).length() < 1e-12 && n2.dot(q - *q2).abs() < tol) {
            return;
        }
        planes.push((q, n));
    };
    let (ca, na) = (a.centroid(), a.normal());
    let (rec, src) = (receiver.vertices(), a.vertices());
    // Where the line from receiver vertex r through blocker vertex q meets the source's plane
    // beyond q (an event's end seen from the source): Err(-1) if q is behind that plane,
    // Err(1) if the line never gets there. One table per blocker, rows = receiver vertices.
    // Distances within `tol` of a plane count as on it (0), so that a vertex shared with the
    // source is classed alike wherever the scene lies (the rounding of its distance, 0 or
    // +-1e-16, depends on the coordinates' magnitude); likewise a line within `tol` of parallel
    // to the plane counts as parallel (Err(1)): rounding put such a trace 1e15 sizes away or
    // nowhere depending on where the scene lay, and so cut the source or not.
    let snap = |d: f64| if d.abs() <= tol { 0.0 } else { d };
    let dist = |x: Vec3| snap(na.dot(x - ca));
    let trace = |r: Vec3, q: Vec3| -> std::result::Result<Vec3, i8> {
        let (dr, dq) = (dist(r), dist(q));
        if dq <= 0.0 {
            Err(-1)
        } else if dq >= dr - tol {
            Err(1)
        } else {
            Ok(r + (q - r) * (dr / (dr - dq)))
        }
    };
    let traces: Vec<Traces> = blockers
        .iter()
        .map(|b| rec.iter().map(|&r| b.vertices().iter().map(|&q| trace(r, q)).collect()).collect())
        .collect();
    // Whether an event of the plane (q, n) whose ends on the source's plane are `ends` crosses
    // the source: their stretch along the plane's trace direction meets the source's chord
    // there. Unbounded events (an end that never reaches the plane, or no ends given) are
    // kept. Some(how far the event runs over the source: the overlap of its stretch and the
    // chord, all of the chord if unbounded) if it crosses, for the order of the cuts.
    let reach = |q: Vec3, n: Vec3, ends: &[std::result::Result<Vec3, i8>]| -> Option<f64> {
        let u = n.cross(na);
        if !(u.length() > 0.0) {
            return Some(0.0);
        }
        let (u, n) = (u.normalize(), n.normalize());
        let (mut slo, mut shi) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..src.len() {
            let (x, y) = (src[k], src[(k + 1) % src.len()]);
            let (dx, dy) = (snap(n.dot(x - q)), snap(n.dot(y - q)));
            if (dx <= 0.0) != (dy <= 0.0) {
                let s = u.dot(x + (y - x) * (dx / (dx - dy)));
                slo = slo.min(s);
                shi = shi.max(s);
            }
        }
        if ends.is_empty() || ends.iter().any(|e| e.is_err()) {
            return Some((shi - slo).max(0.0));
        }
        let (lo, hi) = ends
            .iter()
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(u.dot(*x)), hi.max(u.dot(*x))));
        (hi > slo + tol && lo < shi - tol).then(|| hi.min(shi) - lo.max(slo))
    };
    // kink planes (q, n), each with how far it runs over the source (see `reach`)
    type Events = Vec<(f64, Vec3, Vec3)>;
    let next = |k: usize, len: usize| (k + 1) % len;
    // A vertex and an edge that both lie in the receiver's plane (an edge of a blocker cut to
    // the slab runs along it) span that plane, which no source point in front of it crosses:
    // no event. Its normal is set by rounding when the vertex lies close to the edge's line,
    // and tilted by that, it cut the source or not as the scene was moved, and so decided
    // which later events were cut before MAX_KINK_PIECES (5.9e-6 of F apart,
    // tests/test_properties.py).
    let (cr, nr) = (receiver.centroid(), receiver.normal());
    let in_receiver_plane = |x: &[Vec3]| x.iter().all(|x| nr.dot(*x - cr).abs() <= tol);
    // A blocker's own plane, and the planes through a receiver edge and a parallel edge of it.
    let own = |b: &Polygon, t: &Traces, out: &mut Events| {
        let bv = b.vertices();
        if let Some(r) = reach(bv[0], b.normal(), &[]) {
            out.push((r, bv[0], b.normal()));
        }
        for k in 0..bv.len() {
            let (k1, g) = (next(k, bv.len()), bv[next(k, bv.len())] - bv[k]);
            for e in 0..rec.len() {
                let (e1, d) = (next(e, rec.len()), rec[next(e, rec.len())] - rec[e]);
                if d.cross(g).length() > 1e-9 * d.length() * g.length() || in_receiver_plane(&[bv[k], bv[k1]]) {
                    continue;
                }
                // the shadow of the blocker edge slides over the receiver edge only for source
                // points between the traces of the four endpoint pairs
                let n = d.cross(bv[k] - rec[e]);
                // (edges on one line, within `tol`: the shadow's edge stays on the receiver's)
                if n.length() > tol * d.length() {
                    if let Some(r) = reach(rec[e], n, &[t[e][k], t[e][k1], t[e1][k], t[e1][k1]]) {
                        out.push((r, rec[e], n));
                    }
                }
            }
        }
    };
    // Vertex-edge events: a blocker vertex's shadow crosses a receiver edge, or a blocker
    // edge's shadow crosses a receiver vertex. The visible region's F has a jump in its second
    // derivative there, which for nearly parallel edges happens over so short a stretch of the
    // source that it acts as a kink. Each event happens along a segment of the source's plane
    // (the trace of the edge, seen through the vertex): only events whose segment crosses the
    // source count; none where both ends lie behind the source or both out of reach. Nor where
    // the vertex lies within `tol` of the edge's line (`n` is the cross product of the vertex's
    // offsets from the edge's ends, `edge` the edge): the shadow then stays within about that
    // distance of where it would cross, so the kink is of that size, but the plane through them
    // is set by rounding. Kept, such planes took the place of real ones under
    // MAX_KINK_PIECES: a blocker vertex 1e-10 off a receiver edge cost 2.4e-6 of F
    // (`test_replay_tiny_coordinates_moved_scene`).
    let event = |q: Vec3, n: Vec3, edge: Vec3, ends: [std::result::Result<Vec3, i8>; 2]| {
        let hopeless = matches!(ends, [Err(x), Err(y)] if x == y);
        let kept = !hopeless && n.length() > tol * edge.length();
        kept.then(|| reach(q, n, &ends)).flatten()
    };
    let vertex_edge = |b: &Polygon, t: &Traces, out: &mut Events| {
        let bv = b.vertices();
        for k in 0..bv.len() {
            let k1 = next(k, bv.len());
            if in_receiver_plane(&[bv[k], bv[k1]]) {
                continue;
            }
            for (e, &r) in rec.iter().enumerate() {
                let n = (bv[k] - r).cross(bv[k1] - r);
                if let Some(reach) = event(r, n, bv[k1] - bv[k], [t[e][k], t[e][k1]]) {
                    out.push((reach, r, n));
                }
            }
        }
        for e in 0..rec.len() {
            let e1 = next(e, rec.len());
            for (k, &q) in bv.iter().enumerate() {
                if in_receiver_plane(&[q]) {
                    continue;
                }
                let n = (rec[e] - q).cross(rec[e1] - q);
                if let Some(reach) = event(q, n, rec[e1] - rec[e], [t[e][k], t[e1][k]]) {
                    out.push((reach, q, n));
                }
            }
        }
    };
    // Vertex-edge events between two blockers: where a vertex of one lines up with an edge of
    // another as seen from the source point, their shadows' union changes its outline, and
    // the visible F has a kink there as at the events above. Kept where the plane through them
    // passes through both the receiver and the source (a five-face pair was 2.25 x tol off at
    // the default without them, 0.00 x with; tests/test_properties.py). Their number grows
    // as the square of the blockers': only up to MAX_PAIRWISE_BLOCKERS casting ones (beyond,
    // the events above fill MAX_KINK_PIECES anyway; 10 000 blockers would take minutes here).
    let separates = |p: &[Vec3], q: Vec3, n: Vec3| crosses_plane(p, q, n, tol);
    let pairwise = |add: &mut dyn FnMut(Vec3, Vec3)| {
        if casting.len() > MAX_PAIRWISE_BLOCKERS {
            return;
        }
        for &i in casting {
            for &j in casting {
                if i == j {
                    continue;
                }
                let bv = blockers[j].vertices();
                for &q in blockers[i].vertices() {
                    for k in 0..bv.len() {
                        let (e0, e1) = (bv[k], bv[next(k, bv.len())]);
                        if in_receiver_plane(&[q, e0, e1]) {
                            continue;
                        }
                        let n = (e0 - q).cross(e1 - q);
                        let len = n.length();
                        if len > tol * e0.distance(e1) && separates(rec, q, n / len) && separates(src, q, n / len) {
                            add(q, n);
                        }
                    }
                }
            }
        }
    };
    // the source's and the receiver's triangles, triangulated once: x (in the plane) within
    // `tol` of the polygon
    let (src_triangles, rec_triangles) = ((triangles_of(a), a.normal()), (triangles_of(receiver), nr));
    let on = |(tris, n): &(Vec<[Vec3; 3]>, Vec3), x: Vec3| within_triangles(tris, *n, x, tol);
    let mut chords: Vec<(Vec3, Vec3)> = Vec::new();
    // Edge-edge-edge events at a pierce point: where a blocker's edge pierces the source's
    // plane at a point V of the source (a vertex of the blocker as cut to the slab, on the
    // plane), lines from source points near V can meet that edge, a second edge and a third
    // (of another casting blocker or of the receiver): there one shadow's edge crosses
    // another's on the receiver, or ends on the receiver's edge, and the point F has a kink.
    // The lines meeting three lines form a quadric, whose trace on the source's plane is a
    // conic through V. It is no plane and cannot be cut along; but near V it is its tangent,
    // the trace of the plane spanned by the pierced edge and the transversal through V (the
    // tangent plane of the quadric at V holds both lines of it through V). Near V the F
    // depends on the direction from V alone, and a kink in a narrow sector of directions is
    // missed on every corner piece at V alike (each a scaled copy of its parent): a source
    // triangle at such a V converged to 7.3e-5 of its unobstructed G off at every tol from
    // 1e-8 down (`kinks_through_a_pierce_point_are_cut_along_their_tangents`). With the
    // tangents cut it converged to 4e-8 off: the conic bends away from its tangent and hugs
    // the cut within the samples' margin. So the conic is cut along chords too, between its
    // points from the pierced edge's points 1/16, 1/8, .., 1 of the way from V: each chord
    // cuts only the pieces it meets (a whole-source cut per chord cost the building 19 % more
    // work units instead of 7 %). Only for transversals that meet both edges (not only their
    // lines) and go on to the receiver, and up to MAX_PAIRWISE_BLOCKERS casting blockers.
    let mut pierce_events = |add: &mut dyn FnMut(Vec3, Vec3)| {
        if casting.len() > MAX_PAIRWISE_BLOCKERS {
            return;
        }
        let mut edges: Vec<(usize, Vec3, Vec3)> = Vec::new(); // (owner: blockers.len() for the receiver, ends)
        for e in 0..rec.len() {
            edges.push((blockers.len(), rec[e], rec[next(e, rec.len())]));
        }
        for &i in casting {
            let bv = blockers[i].vertices();
            for k in 0..bv.len() {
                edges.push((i, bv[k], bv[next(k, bv.len())]));
            }
        }
        for &i in casting {
            let bv = blockers[i].vertices();
            for (k, &v) in bv.iter().enumerate() {
                if dist(v) != 0.0 || !on(&src_triangles, v) {
                    continue;
                }
                for w in [bv[next(k, bv.len())], bv[(k + bv.len() - 1) % bv.len()]] {
                    if dist(w) == 0.0 {
                        continue; // an edge in the source's plane: its trace is cut already
                    }
                    let l = w - v;
                    // [methods] one work unit per 128 pairs of edges tried (each a few cross
                    // products); over budget or cancelled, no more (the result is discarded)
                    if !crate::work::spend((edges.len() * edges.len() / 256) as u64) {
                        return;
                    }
                    for (m, &(oa, a0, a1)) in edges.iter().enumerate() {
                        if oa == i {
                            continue;
                        }
                        let n1 = (a0 - v).cross(a1 - v);
                        for &(ob, b0, b1) in &edges[m + 1..] {
                            if ob == i || ob == oa {
                                continue;
                            }
                            let n2 = (b0 - v).cross(b1 - v);
                            let t = n1.cross(n2);
                            let len = t.length();
                            if !(len > tol * n1.length().max(n2.length())) {
                                continue;
                            }
                            let t = t / len;
                            // the transversal meets both edges (not only their lines), on one
                            // side of V, in front of the source, and goes on to the receiver:
                            // it ends on the receiver's edge or meets the receiver beyond both
                            let Some((sa, sb)) = meets_both(v, t, (a0, a1), (b0, b1)) else {
                                continue;
                            };
                            let ahead = sa * sb > 0.0 && dist(v + t * sa) > 0.0;
                            let (sa, sb) = (sa.abs(), sb.abs());
                            // The two edges cross where the transversal meets them, at X (a cut
                            // blocker's edge in the receiver's plane crossing the receiver's
                            // edge): the lines from the pierced edge through X are the event,
                            // a plane (vertex X, edge l), and rounding alone says which edge the
                            // transversal meets first (it put the event in or out as the scene
                            // was moved: 5.9e-6 of F apart, tests/test_properties.py).
                            let crossing = (sa - sb).abs() <= tol;
                            let t = if dist(v + t) > 0.0 { t } else { -t };
                            // (the receiver's edges come first in `edges`)
                            let reaches = if oa == blockers.len() {
                                sb < sa || crossing
                            } else {
                                let sr = nr.dot(cr - v) / nr.dot(t);
                                sr > sa.max(sb) && on(&rec_triangles, v + t * sr)
                            };
                            if ahead && reaches {
                                add(v, l.cross(t));
                                if !crossing {
                                    conic_chords(v, l, (a0, a1), (b0, b1), (ca, na), tol, &mut chords);
                                }
                            }
                        }
                    }
                }
            }
        }
    };
    // The casting blockers' events first, then the others' (whose shadows lie inside those of
    // the casting ones: they only cut the start finer), so that MAX_KINK_PIECES keeps the
    // events that shape the shadows: a building pair whose split reached that limit was 1.29 x
    // tol off at the default, 0.07 x with this order. Counting all blockers against
    // MAX_PAIRWISE_BLOCKERS (as before) gave no blocker-blocker events at all to pairs with
    // more than 16 candidates however few cast: a building pair with 20 (15-19 casting, light
    // through the stair opening) was 1.85 x tol off at obstructed_tol 1e-7 and 2.6 x at 1e-8,
    // now 0.003 x and 0. (bench/obstructed_calibration.py, 500 pairs: pairs above tol at
    // 1e-6/1e-7/1e-8 1/1/4 -> 0/1/3, the same number of evaluations.)
    // Within each kind, the events that run furthest over the source come first: a kink left
    // uncut past MAX_KINK_PIECES misleads the rule along all of its length, while every cut
    // adds a piece per piece it crosses. In blocker order, a stair's risers cut the building's
    // floor into 37 strips along events that happen within 0.09 of its edge only (their
    // shadows slide over the receiver's edges there), and the strips used up the split before
    // the side walls' events that bound the shadow across all of it: start pieces whose
    // samples all missed where the hidden F falls 20-fold, 4 x tol at obstructed_tol 1e-3
    // (`kink_cuts_that_run_over_the_source_come_first`).
    let mut events: Events = Vec::new();
    let by_reach = |events: &mut Events, add: &mut dyn FnMut(Vec3, Vec3)| {
        events.sort_by(|a, b| b.0.total_cmp(&a.0));
        for (_, q, n) in events.drain(..) {
            add(q, n);
        }
    };
    let is_casting: Vec<bool> = (0..blockers.len()).map(|k| casting.contains(&k)).collect();
    for round in [true, false] {
        let members: Vec<usize> = (0..blockers.len()).filter(|&k| is_casting[k] == round).collect();
        for &k in &members {
            own(blockers[k], &traces[k], &mut events);
        }
        by_reach(&mut events, &mut add);
        for &k in &members {
            vertex_edge(blockers[k], &traces[k], &mut events);
        }
        by_reach(&mut events, &mut add);
        if round {
            pairwise(&mut add);
            pierce_events(&mut add);
        }
    }
    // (after the pierce points' chords)
    gap_chords(a, rec, blockers, casting, tol, &mut chords);
    Kinks { planes, chords, tol }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The arcs of two segments about an axis meet wherever a line from a point of the axis
    /// meets both segments on one ray (as `gap_chords` traces them), and they do not meet for
    /// segments on opposite sides of it. Random segments and axes, points along the axis; the
    /// segments include ones passing close to the axis, where no arc is given.
    #[test]
    fn arcs_about_an_axis_meet_where_a_line_from_it_meets_both_segments() {
        use crate::sampling::hash_unit;
        let point =
            |k: u64, i: u64| Vec3::new(hash_unit(k, &[i, 0]), hash_unit(k, &[i, 1]), hash_unit(k, &[i, 2])) * 2.0 - 1.0;
        let (mut found, mut culled) = (0, 0);
        for k in 0..20_000 {
            let (a0, a1) = (point(k, 0), point(k, 1));
            let e = (point(k, 2), point(k, 3));
            // every tenth f starts on the line through e's end and a point of the axis: a line
            // from that point meets both (near-misses are what a margin is for)
            let f0 = if k % 10 == 0 { a0 + (e.1 - a0) * (1.0 + hash_unit(k, &[9])) } else { point(k, 4) };
            let f = (f0, point(k, 5));
            let axis = Axis::new(a0, a1).unwrap();
            let meet = match (&axis.arc(e), &axis.arc(f)) {
                (Some(x), Some(y)) => x.meets(y),
                _ => true,
            };
            culled += usize::from(!meet);
            for s in 0..=16 {
                let p = a0 + (a1 - a0) * (s as f64 / 16.0);
                if let Some((se, sf)) = meets_both(p, transversal(p, e, f), e, f) {
                    if se * sf > 0.0 {
                        found += 1;
                        assert!(meet, "case {k}: a line from the axis meets both, the arcs do not");
                    }
                }
            }
        }
        // (the test says something: both outcomes occur often)
        assert!(found > 1000 && culled > 1000, "{found} lines found, {culled} pairs culled");
        // segments on opposite sides of the z axis: no common direction
        let z = Axis::new(Vec3::ZERO, Vec3::Z).unwrap();
        let (left, right) = (
            (Vec3::new(-1.0, -0.5, 0.0), Vec3::new(-1.0, 0.5, 0.3)),
            (Vec3::new(1.0, -0.5, 0.2), Vec3::new(1.0, 0.5, 0.0)),
        );
        assert!(!z.arc(left).unwrap().meets(&z.arc(right).unwrap()));
        // a segment through the axis has no arc
        assert!(z.arc((Vec3::new(-1.0, 0.0, 0.5), Vec3::new(1.0, 0.0, 0.5))).is_none());
    }

    /// A needle 1 long and 1e-3 wide at its base, the receiver touching the base's corner: cut
    /// across at 1e-3, 2e-3, 4e-3, ... from that corner into pieces that cover it (their areas
    /// add up to its own), each no longer than twice its distance from the corner plus the
    /// first step. Left whole: a triangle of aspect below SLIVER_ASPECT, the needle with the
    /// receiver along its whole length, and with the receiver far away.
    #[test]
    fn a_sliver_near_the_receiver_is_cut_in_graded_pieces() {
        let needle = [Vec3::ZERO, Vec3::new(0.0, 1e-3, 0.0), Vec3::new(1.0, 0.0, 0.0)];
        let square = |q: [f64; 4]| {
            Polygon::new(vec![
                Vec3::new(q[0], q[1], -1.0),
                Vec3::new(q[0], q[1], 1.0),
                Vec3::new(q[2], q[3], 1.0),
                Vec3::new(q[2], q[3], -1.0),
            ])
            .unwrap()
        };
        // (a wall through the base's corner, across the needle)
        let (pieces, flags) = grade_slivers(vec![needle], vec![true], &square([0.0, 0.0, -1.0, -1.0]));
        let area: f64 = pieces.iter().map(area3).sum();
        assert!((area - area3(&needle)).abs() <= 1e-12 * area3(&needle), "{area:e}");
        assert!(flags.iter().all(|&k| k) && (16..=30).contains(&pieces.len()), "{}", pieces.len());
        for p in &pieces {
            let (near, far) = p.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| (lo.min(v.x), hi.max(v.x)));
            assert!(far - near <= 2.0 * near + 1.01e-3, "{near:e} .. {far:e}");
        }
        let whole = |t: [Vec3; 3], receiver: &Polygon| grade_slivers(vec![t], vec![false], receiver).0 == vec![t];
        let stubby = [Vec3::ZERO, Vec3::new(0.0, 0.1, 0.0), Vec3::new(1.0, 0.0, 0.0)];
        assert!(whole(stubby, &square([0.0, 0.0, -1.0, -1.0])));
        assert!(whole(needle, &square([-1.0, 0.0, 2.0, 0.0])));
        assert!(whole(needle, &square([0.0, 5.0, -1.0, 5.0])));
    }

    /// A source with a vertex 1e-6 above the receiver's plane and a blocker crossing both
    /// planes (found by the property tests): the split of the parts in front of each other
    /// must give the same pieces at every scale, vertex for vertex. Clipped with a tolerance
    /// of 0, scaled by 0.1 or 1e-3 one quad's fan took the other diagonal.
    #[test]
    fn the_split_is_the_same_at_every_scale() {
        let raw = [
            [[0.0, -0.18359375, 0.09765625], [0.09476491635586348, 0.0, 1e-06], [0.0, -0.9375, -0.5]],
            [[0.0, 0.0, 0.0], [-0.421875, 0.0, 0.0], [0.859375, -0.6015625, 0.0]],
            [[0.0, -0.408203125, 0.5], [0.0, -0.1879407936051012, -0.375], [0.306640625, 0.2265625, 0.9375]],
        ];
        let scaled = |s: f64| -> Vec<Polygon> {
            raw.iter().map(|p| Polygon::new(p.iter().map(|&v| Vec3::from_array(v) * s).collect()).unwrap()).collect()
        };
        // as a pair computes it: each polygon's part in front of the other
        let split = |s: f64| {
            let p = scaled(s);
            let (a, b) = crate::geometry::clip_pair(&p[0], &p[1]).unwrap();
            let (a, b) = (Polygon::new(a).unwrap(), Polygon::new(b).unwrap());
            split_at_kinks(&a, &b, &[&p[2]], &[0], false).0
        };
        let unit = split(1.0);
        assert!(unit.len() > 10, "{} pieces", unit.len());
        for s in [1e6, 0.1, 3e-3, 1e-3, 1e-9] {
            let pieces = split(s);
            assert_eq!(pieces.len(), unit.len(), "scale {s}");
            for (t, u) in pieces.iter().zip(&unit) {
                for (x, y) in t.iter().zip(u) {
                    assert!((*x / s).distance(*y) <= 1e-12, "scale {s}: {x:?} / s vs {y:?}");
                }
            }
        }
    }

    /// Two small squares side by side between unit plates, one higher than the other: from
    /// source points on the line where the upper square's near edge hides the lower one's
    /// corner, the shadows' union changes outline. That plane (through a vertex of one
    /// blocker and an edge of the other) is among the kink planes, and the split cuts the
    /// source along it; no other event plane holds both.
    #[test]
    fn a_vertex_of_one_blocker_and_an_edge_of_another_make_a_kink() {
        use crate::unobstructed::far_field::tests::square;
        let (src, rec) = (square(-0.5, -0.5, 1.0, 0.0, true), square(-0.5, -0.5, 1.0, 1.0, false));
        let (low, high) = (square(-0.25, -0.1, 0.2, 0.3, true), square(0.05, -0.05, 0.2, 0.6, true));
        let kinks = kink_planes(&src, &rec, &[&low, &high], &[0, 1]);
        // the plane through the low square's corner (-0.05, 0.1, 0.3) and the high square's
        // edge x = 0.05 at z = 0.6 (direction y)
        let (q, e0, e1) = (Vec3::new(-0.05, 0.1, 0.3), Vec3::new(0.05, -0.05, 0.6), Vec3::new(0.05, 0.15, 0.6));
        let n = (e0 - q).cross(e1 - q).normalize();
        let found = kinks.planes.iter().any(|&(p, m)| m.cross(n).length() < 1e-12 && m.dot(q - p).abs() < 1e-12);
        assert!(found, "{} planes", kinks.planes.len());
        let (pieces, _) = split_at_kinks(&src, &rec, &[&low, &high], &[0, 1], false);
        // some piece has an edge in that plane
        let on = |x: Vec3| n.dot(x - q).abs() < 1e-12;
        assert!(pieces.iter().any(|t| (0..3).any(|k| on(t[k]) && on(t[(k + 1) % 3]))));
    }

    /// The same two squares with 18 small ones stacked just above the higher square, inside the
    /// shadow it casts from every source point: 20 candidates, 2 of them casting. Their
    /// blocker-blocker event is still a kink plane (counted against all 20 candidates, none
    /// was), and it comes before every event of the hidden squares.
    #[test]
    fn blockers_hidden_behind_others_leave_the_casting_ones_their_events() {
        use crate::unobstructed::far_field::tests::square;
        let (src, rec) = (square(-0.5, -0.5, 1.0, 0.0, true), square(-0.5, -0.5, 1.0, 1.0, false));
        let mut blockers = vec![square(-0.25, -0.1, 0.2, 0.3, true), square(0.05, -0.05, 0.2, 0.6, true)];
        blockers.extend((0..18).map(|k| square(0.14, 0.04, 0.02, 0.61 + 0.002 * k as f64, true)));
        let all: Vec<&Polygon> = blockers.iter().collect();
        // (independent of the engine: a segment from z = 0 to a point of a small square crosses
        // z = 0.6 within 0.06 of that point horizontally, inside the higher square)
        let casting = super::super::casting(&src, &all, 0.0);
        assert_eq!(casting, vec![0, 1]);
        let kinks = kink_planes(&src, &rec, &all, &casting);
        let (q, e0, e1) = (Vec3::new(-0.05, 0.1, 0.3), Vec3::new(0.05, -0.05, 0.6), Vec3::new(0.05, 0.15, 0.6));
        let n = (e0 - q).cross(e1 - q).normalize();
        let at = kinks.planes.iter().position(|&(p, m)| m.cross(n).length() < 1e-12 && m.dot(q - p).abs() < 1e-12);
        let at = at.expect("the blocker-blocker event of the casting squares");
        let hidden =
            |p: Vec3, m: Vec3| blockers[2..].iter().any(|b| b.vertices().iter().any(|v| m.dot(*v - p).abs() < 1e-12));
        let first_hidden = kinks.planes.iter().position(|&(p, m)| hidden(p, m)).expect("events of the hidden squares");
        assert!(at < first_hidden, "{at} vs {first_hidden}");
    }

    /// The split marks the pieces that a kink left uncut past MAX_KINK_PIECES crosses, and only
    /// those: none when every event was cut (two squares), some when 20 scattered squares fill
    /// the split: exactly the pieces a kink plane crosses.
    #[test]
    fn pieces_crossed_by_kinks_past_the_limit_are_marked() {
        use crate::unobstructed::far_field::tests::square;
        let (src, rec) = (square(-0.5, -0.5, 1.0, 0.0, true), square(-0.5, -0.5, 1.0, 1.0, false));
        let two = [square(-0.25, -0.1, 0.2, 0.3, true), square(0.05, -0.05, 0.2, 0.6, true)];
        let (pieces, kinked) = split_at_kinks(&src, &rec, &[&two[0], &two[1]], &[0, 1], true);
        assert_eq!(pieces.len(), kinked.len());
        assert!(!kinked.iter().any(|&k| k));
        let many: Vec<Polygon> = (0..20)
            .map(|k| square(-0.45 + 0.043 * k as f64, -0.4 + 0.037 * k as f64, 0.05, 0.2 + 0.03 * k as f64, true))
            .collect();
        let all: Vec<&Polygon> = many.iter().collect();
        let every: Vec<usize> = (0..all.len()).collect();
        let (pieces, kinked) = split_at_kinks(&src, &rec, &all, &every, true);
        assert_eq!(pieces.len(), kinked.len());
        let marked = kinked.iter().filter(|&&k| k).count();
        assert!(marked > 0 && marked < pieces.len(), "{marked} of {}", pieces.len());
        // (a plane that was cut along crosses no piece, and these squares pierce nothing: no
        // chords)
        let kinks = kink_planes(&src, &rec, &all, &every);
        assert!(kinks.chords.is_empty());
        for (t, &k) in pieces.iter().zip(&kinked) {
            assert_eq!(k, kinks.planes.iter().any(|&(q, n)| crosses_plane(t, q, n, kinks.tol)));
        }
    }
}
