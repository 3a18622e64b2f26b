//! Form factors with partial obstruction: the area methods of the lecture notes and the exact
//! visible-region method, all behind one entry point per pair and per point.
//!
//! Every estimator here first asks the visibility engine for the pair's candidate blockers
//! (a conservative shaft test). A pair with none is unobstructed and costs nothing extra.
//!
//! With `control_variate` (the default) the area-sampling estimators compute only the
//! *blocked* part by sampling and subtract it from the exact unobstructed value:
//!   A_i F_ij = G_exact - integral K (1 - V),
//! which is exact for unblocked pairs and removes the 1/r^2 singularity of touching pairs
//! from the sampled integrand (the blocked region lies away from shared edges).

use crate::analytic;
use crate::error::{Error, Result};
use crate::geometry::{clip_to_halfspace, Polygon, Vec3};
use crate::method::{self, Method, RuleCache};
use crate::quadrature::AreaRule;
use crate::sampling::{hash_seed, sobol4, PolygonSampler};
use crate::visibility::shadow::{hides_whole, point_free_and_shadowed, point_shadowed_view_factor, point_visible_view_factor};
use crate::visibility::{Occluders, Visibility};
use std::f64::consts::PI;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VisMethod {
    /// Exact kernel where nothing is in between, `Clipping` where something may block.
    Auto,
    /// Gauss rules on both areas with point-pair visibility.
    Quadrature,
    /// Area-to-area quasi-Monte Carlo with Owen-scrambled Sobol points.
    MonteCarlo,
    /// dA -> A_j by uniform subdivision of the receiver, summed over source points.
    Subdivision,
    /// dA -> A_j by adaptive subdivision of the receiver, summed over source points.
    Adaptive,
    /// Exact visible region per source point, adaptive over the source.
    Clipping,
}

impl std::str::FromStr for VisMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        Ok(match s {
            "auto" => VisMethod::Auto,
            "quadrature" => VisMethod::Quadrature,
            "montecarlo" => VisMethod::MonteCarlo,
            "subdivision" => VisMethod::Subdivision,
            "adaptive" => VisMethod::Adaptive,
            "clipping" => VisMethod::Clipping,
            _ => return Err(Error::InvalidArgument(format!("unknown method {s:?}"))),
        })
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct VisOptions {
    /// Unobstructed accuracy target of `auto` (relative), see [`method::Options::tol`].
    pub exact_tol: f64,
    /// `clipping` and obstructed pairs of `auto`: error target on F relative to the pair's
    /// unobstructed F (so also an absolute bound on F, and row sums in a scene are within
    /// tol times the unobstructed row sum). `adaptive`: absolute F per leaf piece.
    pub tol: f64,
    /// `quadrature`: Gauss order per direction on each polygon.
    pub order: usize,
    /// `quadrature`, point form only: the receiver's triangles are split into panels^2 pieces,
    /// each with the order rule. A single area integral keeps the visibility step sharp, so
    /// it needs a composite rule; the pair form's second integral smooths the step.
    pub panels: usize,
    /// `montecarlo`: point pairs per form factor.
    pub samples: usize,
    pub seed: u64,
    /// `subdivision`: each receiver triangle is split into divisions^2 pieces.
    pub divisions: usize,
    /// `subdivision` / `adaptive`: source points. None (default): the source is cut along
    /// its kink lines (see [`split_at_kinks`]) and each piece gets Radon's 7-point rule;
    /// Some(0) is the centroid alone, Some(k) a k x k Gauss rule per source triangle or quad
    /// (always a normalised weighted sum).
    pub source_points: Option<usize>,
    /// `clipping` (and obstructed pairs of `auto`): None integrates the shadowed F over the
    /// source adaptively to `tol`; Some(0) uses the centroid alone, Some(k) a k x k Gauss rule,
    /// for the visible fraction of the point F that scales the exact unobstructed value.
    pub clip_source: Option<usize>,
    /// `quadrature` / `montecarlo`: sample only the blocked part (see module docs).
    pub control_variate: bool,
    /// `adaptive` / `clipping`: deepest refinement level.
    pub max_depth: usize,
    /// `clipping`: most point evaluations of one adaptive source integral (reaching it ends
    /// the refinement before `tol` is met; default [`MAX_SOURCE_EVALS`]).
    pub max_evals: usize,
}

impl Default for VisOptions {
    fn default() -> Self {
        VisOptions {
            exact_tol: 1e-10,
            tol: 1e-7,
            order: 24,
            panels: 4,
            samples: 16384,
            seed: 0,
            divisions: 48,
            source_points: None,
            clip_source: None,
            control_variate: true,
            max_depth: 12,
            max_evals: MAX_SOURCE_EVALS,
        }
    }
}

impl VisOptions {
    pub fn check(&self) -> Result<()> {
        let bad = |what: &str| Err(Error::InvalidArgument(what.to_string()));
        if !(self.exact_tol >= 1e-15 && self.exact_tol <= 0.1) {
            return bad("tol must be in [1e-15, 0.1]");
        }
        if !(self.tol >= 1e-14 && self.tol <= 0.1) {
            return bad("tol must be in [1e-14, 0.1]");
        }
        if !(1..=32).contains(&self.order) {
            return bad("order must be in 1..=32");
        }
        if !(1..=64).contains(&self.panels) {
            return bad("panels must be in 1..=64");
        }
        if !(8..=1 << 24).contains(&self.samples) {
            return bad("samples must be in 8..=16777216");
        }
        if !(1..=256).contains(&self.divisions) {
            return bad("divisions must be in 1..=256");
        }
        if self.source_points.is_some_and(|k| k > 16) || self.clip_source.is_some_and(|k| k > 16) {
            return bad("source must be 'centre' or a Gauss order in 1..=16");
        }
        if !(1..=16).contains(&self.max_depth) {
            return bad("max_depth must be in 1..=16");
        }
        if self.max_evals < 1 {
            return bad("max_evals must be at least 1");
        }
        Ok(())
    }
}

/// An estimate of G = A_i F_ij (pair) or F (point) with its standard error (0 when the method
/// is deterministic).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub value: f64,
    pub std_err: f64,
}

impl Estimate {
    fn exact(value: f64) -> Self {
        Estimate { value, std_err: 0.0 }
    }
}

/// What the estimators need of a scene: its polygons, its occluders with visibility over
/// them (ids in `vis` are occluder ids), and cached area rules.
pub struct Context<'a> {
    pub polygons: &'a [Polygon],
    pub occluders: &'a Occluders,
    pub vis: &'a dyn Visibility,
    pub rules: Option<&'a RuleCache>,
}

impl Context<'_> {
    /// The occluders of the scene polygons `ids` (which cannot block their own pair).
    fn ignore<const N: usize>(&self, ids: [usize; N]) -> [u32; N] {
        ids.map(|k| self.occluders.owner[k])
    }

    fn blockers(&self, cand: &[u32]) -> Vec<&Polygon> {
        cand.iter().map(|&k| &self.occluders.polygons[k as usize]).collect()
    }
}

/// The kernel cos_i cos_j / (pi r^2) between x (normal nx) and y (normal ny), 0 behind.
#[inline]
fn kernel(x: Vec3, nx: Vec3, y: Vec3, ny: Vec3) -> f64 {
    let r = y - x;
    let r2 = r.length_squared();
    let ci = r.dot(nx);
    let cj = -r.dot(ny);
    if ci <= 0.0 || cj <= 0.0 || r2 == 0.0 {
        0.0
    } else {
        ci * cj / (PI * r2 * r2)
    }
}

/// What the caller of [`pair_with`] already knows of a pair (scene rows compute these for
/// whole rows at once).
#[derive(Debug, Clone, Copy, Default)]
pub struct Known<'a> {
    /// The unobstructed G as [`method::area_factor`] with `auto` at `exact_tol` gives it.
    pub free: Option<f64>,
    /// A superset of the pair's candidate blockers, sorted (see
    /// [`Visibility::candidates_among`]).
    pub among: Option<&'a [u32]>,
}

/// G_ij = A_i F_ij between polygons i and j of the scene, with visibility.
pub fn pair(ctx: &Context, i: usize, j: usize, m: VisMethod, o: &VisOptions) -> Result<Estimate> {
    pair_with(ctx, i, j, m, o, Known::default())
}

/// True when `m` computes a pair with nothing in between by the exact kernel (so a caller
/// may compute such pairs itself, and [`Known::free`] is the answer for them).
pub fn exact_when_unobstructed(m: VisMethod, o: &VisOptions) -> bool {
    o.control_variate || !matches!(m, VisMethod::Quadrature | VisMethod::MonteCarlo)
}

/// [`pair`], using what the caller knows of the pair instead of computing it again.
pub fn pair_with(ctx: &Context, i: usize, j: usize, m: VisMethod, o: &VisOptions, known: Known) -> Result<Estimate> {
    let (a, b) = (&ctx.polygons[i], &ctx.polygons[j]);
    if method::facing(a, b) == method::Facing::None {
        return Ok(Estimate::exact(0.0));
    }
    let ignore = ctx.ignore([i, j]);
    // Only the part of each polygon in front of the other exchanges radiation: the shaft and
    // the source integration use those parts (a source point behind the receiver's plane
    // sees nothing, and a thin strip of such points would escape a sampling rule).
    let (ca, cb) = match clip_pair_polygons(a, b) {
        Some(c) => c,
        None => return Ok(Estimate::exact(0.0)),
    };
    let (sa, sb) = (ca.as_ref().unwrap_or(a), cb.as_ref().unwrap_or(b));
    let mut cand = Vec::new();
    match known.among {
        Some(among) => ctx.vis.candidates_among(sa, sb, &ignore, among, &mut cand),
        None => ctx.vis.candidates_between(sa, sb, &ignore, &mut cand),
    }
    let exact = || match known.free {
        Some(g) => Ok(g),
        None => {
            let opts = method::Options { tol: o.exact_tol, ..Default::default() };
            method::area_factor(a, b, Method::Auto, &opts, ctx.rules.map(|r| (r, i, j)))
        }
    };
    if cand.is_empty() {
        // Nothing can block: every method reduces to the unobstructed integral.
        return Ok(match m {
            _ if exact_when_unobstructed(m, o) => Estimate::exact(exact()?),
            VisMethod::MonteCarlo => montecarlo(a, b, None, &[], o, i, j),
            _ => Estimate::exact(quadrature(a, b, None, &[], o)),
        });
    }
    let blockers = ctx.blockers(&cand);
    if blockers.iter().any(|k| hides_whole(sa.vertices(), sb.vertices(), k)) {
        return Ok(Estimate::exact(0.0));
    }
    let visible = |x: Vec3, y: Vec3| !ctx.vis.occluded(x, y, &ignore);
    Ok(match m {
        VisMethod::Quadrature => {
            if o.control_variate {
                Estimate::exact(exact()? - quadrature(a, b, Some(&|x, y| !visible(x, y)), &blockers, o))
            } else {
                Estimate::exact(quadrature(a, b, Some(&visible), &blockers, o))
            }
        }
        VisMethod::MonteCarlo => {
            if o.control_variate {
                let e = montecarlo(a, b, Some(&|x, y| !visible(x, y)), &blockers, o, i, j);
                Estimate { value: exact()? - e.value, std_err: e.std_err }
            } else {
                montecarlo(a, b, Some(&visible), &blockers, o, i, j)
            }
        }
        VisMethod::Subdivision | VisMethod::Adaptive => {
            let pieces = if m == VisMethod::Subdivision { Some(subdivide_at_blockers(b, &blockers, o.divisions)) } else { None };
            let mut g = 0.0;
            let points = match o.source_points {
                Some(k) => source_points(sa, k),
                None => {
                    let r7 = radon7();
                    split_at_kinks(sa, b, &blockers).iter().flat_map(|t| rule_points(&r7, t)).collect()
                }
            };
            for (x, w) in points {
                let f = match &pieces {
                    Some(p) => uniform_point(x, a.normal(), p, &|y| visible(x, y)),
                    None => adaptive_point(x, a.normal(), b, &|y| visible(x, y), o),
                };
                g += w * f;
            }
            Estimate::exact(g)
        }
        VisMethod::Clipping | VisMethod::Auto => {
            match o.clip_source {
                None => {
                    // G = G_free - (integral of the shadowed part): the exact kernel handles
                    // touching pairs, the adaptive rule refines along shadows only.
                    // Relative target: blocked F <= unobstructed F, so an error of tol * G_free
                    // is also within tol absolute, and small (distant) pairs cost little.
                    let free = exact()?;
                    if free <= 0.0 {
                        return Ok(Estimate::exact(0.0));
                    }
                    // G is symmetric: integrate over the side the blockers keep farther from
                    // (a blocker close above the source makes the shadowed F peak beneath it)
                    let (src, rec, src_part, rec_part) =
                        if clearance(a, &blockers) < clearance(b, &blockers) { (b, a, sb, sa) } else { (a, b, sa, sb) };
                    let shadowed = |x: Vec3, bl: &[&Polygon]| point_shadowed_view_factor(x, src.normal(), rec, bl);
                    let start = split_at_kinks(src_part, rec, &blockers);
                    let test = ShadowTest::new(rec_part, &blockers);
                    let hidden = adaptive_over_source(&start, &blockers, &shadowed, &test, o.tol * free, o);
                    Estimate::exact((free - hidden).clamp(0.0, free))
                }
                Some(k) => {
                    // Ratio estimator: the exact unobstructed G times the rule's visible
                    // fraction of the point F. Exact for pairs fully hidden or not hidden at
                    // all; a touching pair's steep kernel cancels in the ratio.
                    let free = exact()?;
                    let (mut vis, mut all) = (0.0, 0.0);
                    for (x, w) in source_points(sa, k) {
                        let (f_free, f_hidden) = point_free_and_shadowed(x, a.normal(), b, &blockers);
                        vis += w * (f_free - f_hidden);
                        all += w * f_free;
                    }
                    Estimate::exact(if all > 0.0 { (free * vis / all).clamp(0.0, free) } else { free })
                }
            }
        }
    })
}

/// How far the blockers keep from the plane of `p`, relative to p's size: the least height of
/// a blocker vertex in front of it, 0 for a blocker that crosses the plane.
fn clearance(p: &Polygon, blockers: &[&Polygon]) -> f64 {
    let (c, n) = (p.centroid(), p.normal());
    let mut least = f64::INFINITY;
    for b in blockers {
        let (mut above, mut below) = (f64::INFINITY, false);
        for v in b.vertices() {
            let h = n.dot(*v - c);
            if h > 0.0 {
                above = above.min(h);
            }
            below |= h < 0.0;
        }
        if below && above < f64::INFINITY {
            return 0.0;
        }
        least = least.min(above);
    }
    least / p.radius()
}

/// The parts of a and b in front of each other, as polygons; `None` inside when a polygon is
/// whole (nothing clipped), outer `None` when they exchange nothing.
fn clip_pair_polygons(a: &Polygon, b: &Polygon) -> Option<(Option<Polygon>, Option<Polygon>)> {
    let (va, vb) = crate::geometry::clip_pair(a, b)?;
    let keep = |orig: &Polygon, v: Vec<Vec3>| {
        if v.len() == orig.vertices().len() && v.iter().zip(orig.vertices()).all(|(p, q)| p == q) {
            None
        } else {
            // a clipped sliver may fail validation (zero area); the whole polygon then serves,
            // its points behind the plane contributing nothing
            Polygon::with_tolerance(v, 1e-6).ok()
        }
    };
    Some((keep(a, va), keep(b, vb)))
}

/// F from a differential area (p, unit n) to polygon j of the scene, with visibility.
/// Nothing coplanar with the receiver blocks (see [`Occluders`]).
pub fn point(ctx: &Context, p: Vec3, n: Vec3, j: usize, m: VisMethod, o: &VisOptions) -> Result<Estimate> {
    let b = &ctx.polygons[j];
    let ignore = &ctx.ignore([j]);
    // Candidate blockers: a point is a degenerate source polygon, so test against a tiny
    // triangle around p in its tangent plane.
    let (t, s) = crate::geometry::tangent_frame(n);
    let eps = 1e-9 * b.radius().max(p.distance(b.centroid()));
    let src = match Polygon::new(vec![p + eps * t, p + eps * s, p - eps * (t + s)]) {
        Ok(poly) => poly,
        Err(_) => return Err(Error::InvalidArgument("point and normal must be finite".into())),
    };
    let mut cand = Vec::new();
    ctx.vis.candidates_between(&src, b, ignore, &mut cand);
    let lambert = analytic::point_polygon(p, n, b.vertices());
    if cand.is_empty() {
        return Ok(Estimate::exact(lambert));
    }
    let blockers = ctx.blockers(&cand);
    if blockers.iter().any(|k| hides_whole(&[p], b.vertices(), k)) {
        return Ok(Estimate::exact(0.0));
    }
    let visible = |y: Vec3| !ctx.vis.occluded(p, y, ignore);
    Ok(match m {
        VisMethod::Quadrature => {
            let rules: Vec<AreaRule> = subdivide_at_blockers(b, &blockers, o.panels)
                .into_iter()
                .filter_map(|t| Polygon::new(t.to_vec()).ok())
                .map(|t| AreaRule::new(&t, o.order))
                .collect();
            let sum = |pred: &dyn Fn(Vec3) -> bool| -> f64 {
                rules
                    .iter()
                    .flat_map(|r| r.points.iter().zip(&r.weights))
                    .filter(|(y, _)| pred(**y))
                    .map(|(y, w)| w * kernel(p, n, *y, b.normal()))
                    .sum()
            };
            if o.control_variate {
                Estimate::exact(lambert - sum(&|y| !visible(y)))
            } else {
                Estimate::exact(sum(&visible))
            }
        }
        VisMethod::MonteCarlo => {
            // strata: the receiver's pieces cut along the blockers' planes, as in the pair form
            let reps = 8usize;
            let per = (o.samples / reps).max(1);
            let strata: Vec<(PolygonSampler, f64, usize)> = cut_at_blocker_planes(b, &blockers)
                .iter()
                .map(|q| (PolygonSampler::new(q), q.area(), stratum_samples(per, q.area() / b.area())))
                .collect();
            let mut est = Vec::with_capacity(reps);
            for r in 0..reps {
                let mut mean = 0.0;
                for (s, (sampler, area, count)) in strata.iter().enumerate() {
                    let seed = stratum_seed(o.seed, [j as u64, u64::MAX, r as u64], s, strata.len());
                    let mut acc = 0.0;
                    for k in 0..*count {
                        let u = sobol4(k as u32, seed);
                        let y = sampler.sample([u[0], u[1]]);
                        let blocked = !visible(y);
                        let w = kernel(p, n, y, b.normal());
                        acc += if o.control_variate { if blocked { w } else { 0.0 } } else if blocked { 0.0 } else { w };
                    }
                    mean += area * acc / *count as f64;
                }
                est.push(if o.control_variate { lambert - mean } else { mean });
            }
            mean_and_error(&est)
        }
        VisMethod::Subdivision => Estimate::exact(uniform_point(p, n, &subdivide_at_blockers(b, &blockers, o.divisions), &visible)),
        VisMethod::Adaptive => Estimate::exact(adaptive_point(p, n, b, &visible, o)),
        VisMethod::Clipping | VisMethod::Auto => Estimate::exact(point_visible_view_factor(p, n, b, &blockers)),
    })
}

/// Double Gauss rule: sum w_k w_l K(x_k, y_l) [pred(x_k, y_l)] (pred None = always 1),
/// composite over the pieces of both polygons cut along the blockers' planes (see
/// [`cut_at_blocker_planes`]), a piece of a fraction f of its polygon's area getting order
/// ceil(order sqrt f): about order^2 points per polygon however it is cut.
fn quadrature(a: &Polygon, b: &Polygon, pred: Option<&dyn Fn(Vec3, Vec3) -> bool>, blockers: &[&Polygon], o: &VisOptions) -> f64 {
    let rules = |p: &Polygon| -> Vec<AreaRule> {
        cut_at_blocker_planes(p, blockers)
            .iter()
            .map(|q| AreaRule::new(q, per_direction(o.order, q.area() / p.area()).clamp(2.min(o.order), o.order)))
            .collect()
    };
    let (ra, rb) = (rules(a), rules(b));
    let mut g = 0.0;
    for ra in &ra {
        for rb in &rb {
            for (x, wx) in ra.points.iter().zip(&ra.weights) {
                for (y, wy) in rb.points.iter().zip(&rb.weights) {
                    let k = kernel(*x, a.normal(), *y, b.normal());
                    if k > 0.0 && pred.map_or(true, |p| p(*x, *y)) {
                        g += wx * wy * k;
                    }
                }
            }
        }
    }
    g
}

/// Most pieces [`cut_at_blocker_planes`] cuts a polygon into.
const MAX_QUADRATURE_PIECES: usize = 8;

/// `p` cut along the planes of the blockers that pass through it, into at most
/// [`MAX_QUADRATURE_PIECES`] convex pieces (p itself when none does). A blocker that touches
/// or pierces a polygon (a partition between two plates, a fin standing on a floor) hides
/// from each side of its plane much of the other side: a step along the plane, which a Gauss
/// rule over the whole polygon resolves only to O(1/order) (5.2e-3 at order 24 for a
/// partition spanning two parallel unit plates at x = 0.13; 2.4e-9 with the cut).
fn cut_at_blocker_planes(p: &Polygon, blockers: &[&Polygon]) -> Vec<Polygon> {
    let tol = 1e-9 * p.radius();
    let mut pieces = vec![p.vertices().to_vec()];
    let (mut lo, mut hi) = (Vec::new(), Vec::new());
    for b in blockers {
        if pieces.len() >= MAX_QUADRATURE_PIECES {
            break;
        }
        let (q, n) = (b.vertices()[0], b.normal());
        let mut next = Vec::with_capacity(pieces.len() + 1);
        for piece in pieces {
            let side = |x: &Vec3| n.dot(*x - q);
            if !(piece.iter().any(|x| side(x) > tol) && piece.iter().any(|x| side(x) < -tol)) {
                next.push(piece);
                continue;
            }
            clip_to_halfspace(&piece, q, n, 0.0, &mut hi);
            clip_to_halfspace(&piece, q, -n, 0.0, &mut lo);
            next.extend([&hi, &lo].into_iter().filter(|v| v.len() >= 3).cloned());
        }
        pieces = next;
    }
    if pieces.len() == 1 {
        return vec![p.clone()];
    }
    // a sliver too thin to be a valid polygon carries no weight worth a rule
    pieces.into_iter().filter_map(|v| Polygon::new(v).ok()).collect()
}

/// A count per direction (Gauss order, divisions) for a piece holding `fraction` of its
/// polygon's area: about as many points per unit area as `n` gives the whole.
fn per_direction(n: usize, fraction: f64) -> usize {
    (n as f64 * fraction.sqrt()).ceil() as usize
}

/// Samples of a stratum holding `fraction` of the whole's `n` (at least 8).
fn stratum_samples(n: usize, fraction: f64) -> usize {
    ((n as f64 * fraction).round() as usize).max(8)
}

/// The scrambling seed of stratum `s` (of `strata`) for `key`: the key's own seed when there
/// is one stratum, so unstratified results stay as they were.
fn stratum_seed(seed: u64, key: [u64; 3], s: usize, strata: usize) -> u64 {
    let k = [key[0], key[1], key[2], s as u64];
    hash_seed(seed, &k[..if strata == 1 { 3 } else { 4 }])
}

/// Area-to-area RQMC: 8 independent Owen scramblings of a 4-D Sobol sequence; the spread of
/// the 8 estimates gives the standard error.
fn montecarlo(a: &Polygon, b: &Polygon, pred: Option<&dyn Fn(Vec3, Vec3) -> bool>, blockers: &[&Polygon], o: &VisOptions, i: usize, j: usize) -> Estimate {
    // strata: the pairs of pieces of the two polygons cut along the blockers' planes (see
    // [`cut_at_blocker_planes`]), each with its share of the samples: behind a partition the
    // hidden part is then a whole stratum, sampled without the visibility step
    let (pa, pb) = (cut_at_blocker_planes(a, blockers), cut_at_blocker_planes(b, blockers));
    let reps = 8usize;
    let per = (o.samples / reps).max(1);
    let strata: Vec<(PolygonSampler, PolygonSampler, f64, usize)> = pa
        .iter()
        .flat_map(|x| pb.iter().map(move |y| (x, y)))
        .map(|(x, y)| {
            let share = x.area() * y.area() / (a.area() * b.area());
            (PolygonSampler::new(x), PolygonSampler::new(y), x.area() * y.area(), stratum_samples(per, share))
        })
        .collect();
    let mut est = Vec::with_capacity(reps);
    for r in 0..reps {
        let mut total = 0.0;
        for (s, (sa, sb, area, n)) in strata.iter().enumerate() {
            // every pair gets its own scrambling: results do not depend on the order of pairs
            let seed = stratum_seed(o.seed, [i as u64, j as u64, r as u64], s, strata.len());
            let mut acc = 0.0;
            for k in 0..*n {
                let u = sobol4(k as u32, seed);
                let x = sa.sample([u[0], u[1]]);
                let y = sb.sample([u[2], u[3]]);
                let kv = kernel(x, a.normal(), y, b.normal());
                if kv > 0.0 && pred.map_or(true, |p| p(x, y)) {
                    acc += kv;
                }
            }
            total += area * acc / *n as f64;
        }
        est.push(total);
    }
    mean_and_error(&est)
}

fn mean_and_error(est: &[f64]) -> Estimate {
    let n = est.len() as f64;
    let mean = est.iter().sum::<f64>() / n;
    let var = est.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / (n - 1.0);
    Estimate { value: mean, std_err: (var / n).sqrt() }
}

/// Source points and weights (summing to the polygon's area): the centroid alone, or a
/// k x k Gauss rule.
fn source_points(a: &Polygon, k: usize) -> Vec<(Vec3, f64)> {
    if k == 0 {
        return vec![(a.centroid(), a.area())];
    }
    let r = AreaRule::new(a, k);
    r.points.into_iter().zip(r.weights).collect()
}

/// The receiver's triangles, each split uniformly into d^2 sub-triangles.
fn subdivide(b: &Polygon, d: usize) -> Vec<[Vec3; 3]> {
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
fn subdivide_at_blockers(b: &Polygon, blockers: &[&Polygon], d: usize) -> Vec<[Vec3; 3]> {
    let parts = cut_at_blocker_planes(b, blockers);
    if parts.len() == 1 {
        return subdivide(b, d);
    }
    parts.iter().flat_map(|q| subdivide(q, per_direction(d, q.area() / b.area()).max(1))).collect()
}

fn centroid3(t: &[Vec3; 3]) -> Vec3 {
    (t[0] + t[1] + t[2]) / 3.0
}

fn area3(t: &[Vec3; 3]) -> f64 {
    0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()
}

/// Uniform subdivision: sum over pieces of Lambert's exact F to the piece times the piece's
/// visibility at its centre (Wallace et al.'s better leaf estimator, algorithms.md 6.1).
fn uniform_point(x: Vec3, n: Vec3, pieces: &[[Vec3; 3]], visible: &dyn Fn(Vec3) -> bool) -> f64 {
    pieces
        .iter()
        .map(|t| {
            let f = analytic::point_polygon(x, n, t);
            if f > 0.0 && visible(centroid3(t)) { f } else { 0.0 }
        })
        .sum()
}

/// Adaptive subdivision: a piece is split in four while visibility differs among its seven
/// samples (corners pulled 1 % inwards, edge midpoints, centre) and its exact unobstructed
/// contribution (Lambert) exceeds `tol`, down to `max_depth`; there the visible fraction of
/// the samples weights it. Pieces whose samples agree are still refined to `MIN_DEPTH`
/// levels, so that a shadow smaller than a first-level piece is not missed between samples.
fn adaptive_point(x: Vec3, n: Vec3, b: &Polygon, visible: &dyn Fn(Vec3) -> bool, o: &VisOptions) -> f64 {
    const MIN_DEPTH: usize = 4;
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

/// Radon's 7-point degree-5 rule on a triangle (barycentric points, weights summing to 1).
fn radon7() -> [([f64; 3], f64); 7] {
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

/// A triangle rule (barycentric points, weights summing to 1) mapped onto `t`: points and
/// weights summing to its area.
fn rule_points<'r>(rule: &'r [([f64; 3], f64)], t: &[Vec3; 3]) -> impl Iterator<Item = (Vec3, f64)> + 'r {
    let (t, area) = (*t, area3(t));
    rule.iter().map(move |(b, w)| (t[0] * b[0] + t[1] * b[1] + t[2] * b[2], area * w))
}

fn rule_integral(rule: &[([f64; 3], f64)], t: &[Vec3; 3], f: &dyn Fn(Vec3) -> f64) -> f64 {
    rule_points(rule, t).map(|(x, w)| w * f(x)).sum()
}

/// Relative targets from which the adaptive source integration computes a start piece's
/// children only when the piece needs refining; until then its error estimate is twice the
/// difference between the rule and the centroid rule (4 evaluations instead of 15). 300
/// obstructed room pairs (`obstructed_schemes`, 9/15/21 quads per wall edge) at tol 1e-2:
/// largest error 1.0e-4/1.7e-4/4.1e-5 of the unobstructed F in 41/25/17 us per pair, against
/// 8.7e-6/1.6e-5/4.3e-6 in 114/65/42 us with the full start.
const COARSE_START_TOL: f64 = 1e-2;

/// Relative targets from which the adaptive source integration uses Strang and Fix's
/// interior 3-point rule (degree 2) instead of Radon's 7 points (degree 5). The source is cut
/// at its kinks and vertex-edge events first, so the integrand is smooth on every piece and
/// degree 2 meets such targets with fewer evaluations (300 obstructed room pairs,
/// `obstructed_schemes`, 9/15/21 quads per wall edge, at tol 1e-4: largest error
/// 8.7e-6/1.6e-5/4.3e-6 of the unobstructed F in 115/65/43 us per pair, against
/// 6.5e-8/2.2e-7/7.2e-8 in 242/137/90 us with Radon's rule). On those small pairs it also
/// met 1e-6 (2.2e-7 at most, 20-40 % faster), but on the unit squares of bench/obstructed.py
/// (a centred square blocker) it needed 2.6 instead of 0.56 ms at 1e-6: it stops at 1e-4.
const LOW_DEGREE_TOL: f64 = 1e-4;

/// The triangle rule of the adaptive source integration for a relative target `tol`.
fn source_rule(tol: f64) -> Vec<([f64; 3], f64)> {
    if tol >= LOW_DEGREE_TOL {
        let (a, b) = (2.0 / 3.0, 1.0 / 6.0);
        vec![([a, b, b], 1.0 / 3.0), ([b, a, b], 1.0 / 3.0), ([b, b, a], 1.0 / 3.0)]
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
    /// blocker triangles, their normals and the index of their blocker
    triangles: Vec<([Vec3; 3], Vec3, usize)>,
    max_abs: f64,
}

impl<'a> ShadowTest<'a> {
    fn new(receiver: &'a Polygon, blockers: &[&Polygon]) -> Self {
        let mut triangles = Vec::new();
        let mut max_abs: f64 = 0.0;
        for (k, b) in blockers.iter().enumerate() {
            let v = b.vertices();
            for x in v {
                max_abs = max_abs.max(x.abs().max_element());
            }
            for t in b.triangulate() {
                triangles.push(([v[t[0]], v[t[1]], v[t[2]]], b.normal(), k));
            }
        }
        ShadowTest { receiver, triangles, max_abs }
    }

    /// The blockers among `within` (sorted indices) that meet the shaft of `t` and the
    /// receiver, sorted, into `out` (all of `within` if t is too thin to be a polygon).
    fn active(&self, t: &[Vec3; 3], within: &[usize], out: &mut Vec<usize>) {
        out.clear();
        let Ok(piece) = Polygon::new(t.to_vec()) else {
            out.extend_from_slice(within);
            return;
        };
        let shaft = crate::visibility::bvh::Shaft::new(&piece, self.receiver, self.max_abs);
        for (v, n, k) in &self.triangles {
            if out.last() != Some(k) && within.binary_search(k).is_ok() && shaft.may_meet_triangle(v, *n) {
                out.push(*k);
            }
        }
    }
}

/// Most pieces the kink split may cut a source into.
const MAX_KINK_PIECES: usize = 64;

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
fn split_at_kinks(a: &Polygon, receiver: &Polygon, blockers: &[&Polygon]) -> Vec<[Vec3; 3]> {
    let kinks = kink_planes(a, receiver, blockers);
    let v = a.vertices();
    let mut pieces: Vec<Vec<Vec3>> = a.triangulate().iter().map(|t| vec![v[t[0]], v[t[1]], v[t[2]]]).collect();
    let (mut lo, mut hi) = (Vec::new(), Vec::new());
    for &(q, n) in &kinks.planes {
        if pieces.len() >= MAX_KINK_PIECES {
            break;
        }
        let mut next = Vec::with_capacity(pieces.len() + 4);
        for piece in pieces {
            if !kinks.cuts(&piece, q, n) {
                next.push(piece);
                continue;
            }
            clip_to_halfspace(&piece, q, n, 0.0, &mut hi);
            clip_to_halfspace(&piece, q, -n, 0.0, &mut lo);
            for part in [&hi, &lo] {
                if part.len() >= 3 {
                    next.push(part.clone());
                }
            }
        }
        pieces = next;
    }
    // Every piece is convex (a triangle cut by planes): fan triangulation.
    fan_triangles(&pieces, 1e-12 * a.area())
}

/// Fan triangles of convex pieces. Slivers from cuts through a vertex carry no area but would
/// put sample points on a kink line: those below `min_area` are left out.
fn fan_triangles(pieces: &[Vec<Vec3>], min_area: f64) -> Vec<[Vec3; 3]> {
    pieces
        .iter()
        .filter(|p| p.len() >= 3)
        .flat_map(|p| (1..p.len() - 1).map(move |k| [p[0], p[k], p[k + 1]]))
        .filter(|t| area3(t) > min_area)
        .collect()
}

/// The kink planes of a pair (see [`split_at_kinks`]), most important first, with the
/// length tolerance under which a plane is taken not to cut a piece.
struct Kinks {
    planes: Vec<(Vec3, Vec3)>,
    tol: f64,
}

impl Kinks {
    /// True if the plane (point q, unit normal n) passes through the piece's interior.
    fn cuts(&self, piece: &[Vec3], q: Vec3, n: Vec3) -> bool {
        let side = |x: &Vec3| n.dot(*x - q);
        piece.iter().any(|x| side(x) > self.tol) && piece.iter().any(|x| side(x) < -self.tol)
    }
}

fn kink_planes(a: &Polygon, receiver: &Polygon, blockers: &[&Polygon]) -> Kinks {
    let scale = a.radius() + receiver.radius() + a.centroid().distance(receiver.centroid());
    let tol = 1e-9 * scale;
    let mut planes: Vec<(Vec3, Vec3)> = Vec::new();
    let mut add = |q: Vec3, n: Vec3| {
        let len = n.length();
        if !(len > 0.0) || !len.is_finite() {
            return;
        }
        let n = n / len;
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
    let dist = |x: Vec3| na.dot(x - ca);
    let trace = |r: Vec3, q: Vec3| -> std::result::Result<Vec3, i8> {
        let (dr, dq) = (dist(r), dist(q));
        if dq <= 0.0 {
            Err(-1)
        } else if dq >= dr {
            Err(1)
        } else {
            Ok(r + (q - r) * (dr / (dr - dq)))
        }
    };
    let traces: Vec<Vec<Vec<std::result::Result<Vec3, i8>>>> =
        blockers.iter().map(|b| rec.iter().map(|&r| b.vertices().iter().map(|&q| trace(r, q)).collect()).collect()).collect();
    // Whether an event of the plane (q, n) whose ends on the source's plane are `ends` crosses
    // the source: their stretch along the plane's trace direction meets the source's chord
    // there. Unbounded events (an end that never reaches the plane) are kept.
    let crosses = |q: Vec3, n: Vec3, ends: &[std::result::Result<Vec3, i8>]| -> bool {
        let u = n.cross(na);
        if !(u.length() > 0.0) || ends.iter().any(|e| e.is_err()) {
            return true;
        }
        let u = u.normalize();
        let (lo, hi) = ends.iter().flatten().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(u.dot(*x)), hi.max(u.dot(*x))));
        let (mut slo, mut shi) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..src.len() {
            let (x, y) = (src[k], src[(k + 1) % src.len()]);
            let (dx, dy) = (n.dot(x - q), n.dot(y - q));
            if (dx <= 0.0) != (dy <= 0.0) {
                let s = u.dot(x + (y - x) * (dx / (dx - dy)));
                slo = slo.min(s);
                shi = shi.max(s);
            }
        }
        hi > slo + tol && lo < shi - tol
    };
    let next = |k: usize, len: usize| (k + 1) % len;
    for (b, t) in blockers.iter().zip(&traces) {
        let bv = b.vertices();
        add(bv[0], b.normal());
        for k in 0..bv.len() {
            let (k1, g) = (next(k, bv.len()), bv[next(k, bv.len())] - bv[k]);
            for e in 0..rec.len() {
                let (e1, d) = (next(e, rec.len()), rec[next(e, rec.len())] - rec[e]);
                if d.cross(g).length() > 1e-9 * d.length() * g.length() {
                    continue;
                }
                // the shadow of the blocker edge slides over the receiver edge only for source
                // points between the traces of the four endpoint pairs
                let n = d.cross(bv[k] - rec[e]);
                if crosses(rec[e], n, &[t[e][k], t[e][k1], t[e1][k], t[e1][k1]]) {
                    add(rec[e], n);
                }
            }
        }
    }
    // Vertex-edge events: a blocker vertex's shadow crosses a receiver edge, or a blocker
    // edge's shadow crosses a receiver vertex. The visible region's F has a jump in its second
    // derivative there, which for nearly parallel edges happens over so short a stretch of the
    // source that it acts as a kink. Each event happens along a segment of the source's plane
    // (the trace of the edge, seen through the vertex): only events whose segment crosses the
    // source count; none where both ends lie behind the source or both out of reach.
    let mut event = |q: Vec3, n: Vec3, ends: [std::result::Result<Vec3, i8>; 2]| {
        let hopeless = matches!(ends, [Err(x), Err(y)] if x == y);
        if !hopeless && crosses(q, n, &ends) {
            add(q, n);
        }
    };
    for (b, t) in blockers.iter().zip(&traces) {
        let bv = b.vertices();
        for k in 0..bv.len() {
            let k1 = next(k, bv.len());
            for (e, &r) in rec.iter().enumerate() {
                event(r, (bv[k] - r).cross(bv[k1] - r), [t[e][k], t[e][k1]]);
            }
        }
        for e in 0..rec.len() {
            let e1 = next(e, rec.len());
            for (k, &q) in bv.iter().enumerate() {
                event(q, (rec[e] - q).cross(rec[e1] - q), [t[e][k], t[e1][k]]);
            }
        }
    }
    Kinks { planes, tol }
}

/// Most integrand evaluations one adaptive source integral may spend (about 0.1-1 s).
pub const MAX_SOURCE_EVALS: usize = 60_000;

/// Integral of f over the source polygon by globally adaptive triangle subdivision: every
/// leaf triangle carries its value by the rule of [`source_rule`] (degree 5, or 2 for loose
/// targets), the sum over its four children and the difference of the two as error
/// estimate (f is given only the blockers that meet the leaf's shaft). The leaf with the
/// largest estimate is split until the estimates add up to `goal` (an error bound on
/// G = A_i F), the depth limit or the evaluation budget is reached. The visible-region F is continuous but has kinks along
/// shadow lines: a global criterion spends the refinement along those lines only as far
/// as the total error needs it (a local criterion would refine them without end).
fn adaptive_over_source(
    start: &[[Vec3; 3]],
    blockers: &[&Polygon],
    f: &dyn Fn(Vec3, &[&Polygon]) -> f64,
    test: &ShadowTest,
    goal: f64,
    o: &VisOptions,
) -> f64 {
    use std::cmp::Ordering;
    use std::collections::BinaryHeap;
    struct Leaf {
        t: [Vec3; 3],
        /// the rule's value on t
        whole: f64,
        /// the rule's values on the four children, once computed (the returned value)
        kids: Option<[f64; 4]>,
        err: f64,
        depth: usize,
        /// the blockers that may cast a shadow from this leaf (indices into `blockers`)
        active: Vec<usize>,
    }
    impl Leaf {
        fn value(&self) -> f64 {
            self.kids.map_or(self.whole, |k| k.iter().sum())
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
    let split = |t: &[Vec3; 3]| {
        let m01 = 0.5 * (t[0] + t[1]);
        let m12 = 0.5 * (t[1] + t[2]);
        let m20 = 0.5 * (t[2] + t[0]);
        [[t[0], m01, m20], [m01, t[1], m12], [m20, m12, t[2]], [m01, m12, m20]]
    };
    let rule = source_rule(o.tol);
    let evals = std::cell::Cell::new(0usize);
    let pick = |active: &[usize]| active.iter().map(|&k| blockers[k]).collect::<Vec<&Polygon>>();
    // the leaf's children values and error estimate
    let refine = |l: &mut Leaf| {
        let bl = pick(&l.active);
        let (zero, lit) = (std::cell::Cell::new(false), std::cell::Cell::new(false));
        let g = |x: Vec3| {
            let v = f(x, &bl);
            if v == 0.0 { zero.set(true) } else { lit.set(true) }
            v
        };
        let k = split(&l.t);
        let kids = [0, 1, 2, 3].map(|i| rule_integral(&rule, &k[i], &g));
        evals.set(evals.get() + 4 * rule.len());
        // |kids - whole| bounds the coarse value's error; the kids' sum (what is returned) is
        // better by 2^6 on smooth pieces and by 2^3 next to an unsplit kink: count a quarter.
        // A leaf whose samples are partly 0 holds the edge of the region the shadow reaches,
        // where the shadowed F starts without a smooth transition and a small shadow may be
        // caught by few samples: count the whole difference there (300 room pairs at tol 1e-5:
        // largest error 4.7e-5 -> 8.1e-6 of the unobstructed F, 3 % more evaluations).
        let weight = if zero.get() && lit.get() { 1.0 } else { 0.25 };
        l.err = weight * (kids.iter().sum::<f64>() - l.whole).abs();
        l.kids = Some(kids);
    };
    let mut heap = BinaryHeap::new();
    let all: Vec<usize> = (0..blockers.len()).collect();
    let coarse_start = o.tol >= COARSE_START_TOL;
    for &t in start {
        let mut active = Vec::new();
        test.active(&t, &all, &mut active);
        if active.is_empty() {
            continue;
        }
        let bl = pick(&active);
        let whole = rule_integral(&rule, &t, &|x| f(x, &bl));
        evals.set(evals.get() + rule.len());
        let mut l = Leaf { t, whole, kids: None, err: 0.0, depth: 0, active };
        if coarse_start {
            // children only where needed (see COARSE_START_TOL)
            l.err = 2.0 * (whole - area3(&t) * f(centroid3(&t), &bl)).abs();
            evals.set(evals.get() + 1);
        } else {
            refine(&mut l);
        }
        heap.push(l);
    }
    let mut total_err: f64 = heap.iter().map(|l| l.err).sum();
    let mut done = Vec::new(); // leaves at the depth limit
    while total_err > goal && evals.get() < o.max_evals {
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
        for (k, whole) in split(&worst.t).into_iter().zip(kids) {
            let mut active = Vec::new();
            test.active(&k, &worst.active, &mut active);
            if active.is_empty() {
                continue; // exactly 0 there (its whole value is 0 up to rounding)
            }
            let mut l = Leaf { t: k, whole, kids: None, err: 0.0, depth: worst.depth + 1, active };
            refine(&mut l);
            total_err += l.err;
            heap.push(l);
        }
        // guard against drift of the running sum
        total_err = total_err.max(0.0);
    }
    heap.iter().chain(done.iter()).map(Leaf::value).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::visibility::Bvh;

    /// G of the pair (i, j) of `polys` by `clipping`, every other polygon a blocker.
    fn clipping(polys: &[Polygon], i: usize, j: usize, o: &VisOptions) -> f64 {
        let occ = Occluders::new(polys);
        let bvh = Bvh::new(&occ.polygons).unwrap();
        let ctx = Context { polygons: polys, occluders: &occ, vis: &bvh, rules: None };
        pair(&ctx, i, j, VisMethod::Clipping, o).unwrap().value
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
        let plate = |z: f64, up: bool| facing_quad(vec![Vec3::new(0.0, 0.0, z), Vec3::new(1.0, 0.0, z), Vec3::new(1.0, 1.0, z), Vec3::new(0.0, 1.0, z)], if up { Vec3::Z } else { -Vec3::Z });
        let blocker = facing_quad(vec![Vec3::new(0.3, -0.2, -0.1), Vec3::new(0.6, -0.2, 0.5), Vec3::new(0.6, 0.7, 0.5), Vec3::new(0.3, 0.7, -0.1)], Vec3::new(-2.0, 0.0, 1.0));
        let polys = vec![plate(0.0, true), plate(1.0, false), blocker];
        assert!(clearance(&polys[0], &[&polys[2]]) < clearance(&polys[1], &[&polys[2]]));
        let o = VisOptions { tol: 1e-5, exact_tol: 1e-12, ..Default::default() };
        let (g01, g10) = (clipping(&polys, 0, 1, &o), clipping(&polys, 1, 0, &o));
        assert_eq!(g01.to_bits(), g10.to_bits());
        let reference = clipping(&polys, 0, 1, &VisOptions { tol: 1e-10, max_evals: 2_000_000, ..o.clone() });
        let free = method::area_factor(&polys[0], &polys[1], Method::Analytic, &Default::default(), None).unwrap();
        assert!(reference < 0.9 * free && reference > 0.1 * free, "hidden fraction {}", 1.0 - reference / free);
        assert!((g01 - reference).abs() <= 1e-5 * free, "error {:.2e} of the unobstructed G", (g01 - reference).abs() / free);
    }

    /// A wall tile and a ceiling tile on either side of a crate's vertical edge: the edge's
    /// shadow crosses the ceiling tile nearly parallel to one of its edges (3.6 degrees), so
    /// the shadowed F turns from linear to 0 within 3 % of the source's width (a near-kink that
    /// only the vertex-edge cuts expose; without them the error at tol 1e-4 was 2.2e-4 of
    /// the unobstructed F). Each target is met against the result at tol 1e-10.
    #[test]
    fn nearly_parallel_edges_meet_the_target() {
        let (y0, y1, z0) = (5.0 / 7.0, 6.0 / 7.0, 6.0 / 7.0);
        let source = facing_quad(vec![Vec3::new(0.0, y0, z0), Vec3::new(0.0, y1, z0), Vec3::new(0.0, y1, 1.0), Vec3::new(0.0, y0, 1.0)], Vec3::X);
        let (x0, y2) = (20.0 / 7.0, 4.0 / 7.0);
        let receiver = facing_quad(vec![Vec3::new(x0, y0, 3.0), Vec3::new(3.0, y0, 3.0), Vec3::new(3.0, y2, 3.0), Vec3::new(x0, y2, 3.0)], -Vec3::Z);
        let mut polys = vec![source, receiver];
        polys.extend(box_faces(Vec3::new(0.8, 0.7, 1.1), Vec3::new(1.8, 1.7, 2.1)));
        let value = |tol: f64| clipping(&polys, 0, 1, &VisOptions { tol, exact_tol: 1e-12, ..Default::default() });
        let free = method::area_factor(&polys[0], &polys[1], Method::Analytic, &Default::default(), None).unwrap();
        let reference = value(1e-10);
        assert!(reference > 0.05 * free && reference < 0.15 * free, "visible fraction {}", reference / free);
        for tol in [1e-2, 1e-3, 1e-4, 1e-5, 1e-6] {
            let err = (value(tol) - reference).abs() / free;
            assert!(err <= tol, "tol {tol:e}: error {err:.2e} of the unobstructed F");
        }
    }
}
