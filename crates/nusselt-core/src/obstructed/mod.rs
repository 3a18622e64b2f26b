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
//! from the sampled integrand where the blocked region lies away from the shared edge or
//! vertex. Where the largest kernel sample is blocked (the shared part is hidden), the same
//! samples give the visible part directly instead (`sampled::Parts::with_free`).

mod clipping;
mod kinks;
mod options;
mod rules;
mod sampled;
mod subdivision;

use crate::error::{Error, Result};
use crate::geometry::{Polygon, Vec3};
use crate::quadrature::AreaRule;
use crate::sampling::PolygonSampler;
use crate::unobstructed::analytic;
use crate::unobstructed::method::{self, Method, RuleCache};
use crate::visibility::shadow::{hides_whole, hides_whole_together, point_visible_view_factor};
use crate::visibility::{Occluders, Visibility};
use rules::area_source_points;
use sampled::{
    cut_at_blocker_planes, kernel, montecarlo, pair_order, quadrature, rqmc_estimates, stratum_samples, Replicates,
    RQMC_REPS,
};
use subdivision::{adaptive_point, subdivide_at_blockers, uniform_point};

pub use clipping::MAX_SOURCE_EVALS;
pub use options::{
    AdaptiveOptions, ClippingOptions, Estimate, Estimator, MonteCarloOptions, QuadratureOptions, SubdivisionOptions,
};

/// What the estimators need of a scene: its polygons, its occluders with visibility over
/// them (ids in `vis` are occluder ids), cached area rules, and the accuracy of the
/// unobstructed G they compute themselves (`auto`'s `tol`, see [`Known::free`]).
pub struct Context<'a> {
    pub polygons: &'a [Polygon],
    pub occluders: &'a Occluders,
    pub vis: &'a dyn Visibility,
    pub rules: Option<&'a RuleCache>,
    pub exact_tol: f64,
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

/// What the caller of [`pair_with`] already knows of a pair (scene rows compute these for
/// whole rows at once).
#[derive(Debug, Clone, Copy, Default)]
pub struct Known<'a> {
    /// The unobstructed G as [`method::area_factor`] with `auto` at [`Context::exact_tol`]
    /// gives it.
    pub free: Option<f64>,
    /// A superset of the pair's candidate blockers, sorted (see
    /// [`Visibility::candidates_among`]).
    pub among: Option<&'a [u32]>,
}

/// G_ij = A_i F_ij between polygons i and j of the scene, with visibility.
pub fn pair(ctx: &Context, i: usize, j: usize, m: &Estimator) -> Result<Estimate> {
    pair_with(ctx, i, j, m, Known::default())
}

/// True when `m` computes a pair with nothing in between by the exact kernel (so a caller
/// may compute such pairs itself, and [`Known::free`] is the answer for them).
pub fn exact_when_unobstructed(m: &Estimator) -> bool {
    match m {
        Estimator::Quadrature(o) => o.control_variate,
        Estimator::MonteCarlo(o) => o.control_variate,
        _ => true,
    }
}

/// [`pair`], using what the caller knows of the pair instead of computing it again.
pub fn pair_with(ctx: &Context, i: usize, j: usize, m: &Estimator, known: Known) -> Result<Estimate> {
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
            let opts = method::Options { tol: ctx.exact_tol, ..Default::default() };
            method::area_factor(a, b, Method::Auto, &opts, ctx.rules.map(|r| (r, i, j)))
        }
    };
    if cand.is_empty() {
        // Nothing can block: every method reduces to the unobstructed integral.
        return Ok(match m {
            Estimator::MonteCarlo(o) if !o.control_variate => {
                montecarlo(a, b, None, &[], o, i, j).estimate(exact()?, false)
            }
            Estimator::Quadrature(o) if !o.control_variate => {
                Estimate::exact(quadrature(a, b, None, &[], o.order).visible)
            }
            _ => Estimate::exact(exact()?),
        });
    }
    let blockers = ctx.blockers(&cand);
    let band = hidden_band(m);
    if hidden_whole(sa.vertices(), sb.vertices(), &blockers, band) {
        return Ok(Estimate::exact(0.0));
    }
    let visible = |x: Vec3, y: Vec3| !ctx.vis.occluded(x, y, &ignore);
    Ok(match *m {
        Estimator::Quadrature(o) => {
            // the order of this pair from its unobstructed F and the absolute target `tol`
            let free = exact()?;
            let n = pair_order(free, a, b, &o);
            let parts = quadrature(a, b, Some(&visible), &blockers, n);
            Estimate::exact(if o.control_variate { parts.with_free(free) } else { parts.visible })
        }
        Estimator::MonteCarlo(o) => {
            let reps = montecarlo(a, b, Some(&visible), &blockers, &o, i, j);
            reps.estimate(exact()?, o.control_variate)
        }
        Estimator::Subdivision(o) => {
            let pieces = subdivide_at_blockers(b, &blockers, o.divisions);
            let f = |x: Vec3| uniform_point(x, a.normal(), &pieces, &|y| visible(x, y));
            Estimate::exact(over_source(sa, sb, &blockers, o.source, f))
        }
        Estimator::Adaptive(o) => {
            let f = |x: Vec3| adaptive_point(x, a.normal(), b, &|y| visible(x, y), &o);
            Estimate::exact(over_source(sa, sb, &blockers, o.source, f))
        }
        Estimator::Clipping(o) => {
            let casting = casting(sa, &blockers, band);
            clipping::pair(a, b, sa, sb, &blockers, &casting, exact()?, &o)
        }
    })
}

/// The band of [`hides_whole_together`] for estimator `m`: segments within 1e-9 of the
/// outlines' sizes are not followed (at most ~1e-8 of the unobstructed F, where a joint lets
/// light through at all) for relative targets from [`BAND_FROM_TOL`] on and for the sampled
/// estimators; tighter `clipping` targets take the strict test, which never claims a pair
/// touching a wall's plane. In the 391-surface building (closed: floors and walls touch the
/// partitions and slabs between rooms) the test with the band finds 9 320 entries of F hidden
/// that no single blocker hides (the strict one 2 168), on which the source integration spent
/// a third of the run at obstructed_tol 1e-3 to find 0 or leaks of up to 2.3e-5 in F along
/// the joints (0 by `clipping` at tol 1e-9).
fn hidden_band(m: &Estimator) -> f64 {
    match m {
        Estimator::Clipping(o) if o.tol < BAND_FROM_TOL => 0.0,
        _ => 1e-9,
    }
}

/// True if the blockers hide all of `target` from all of `source` (vertex lists): one of them
/// alone ([`hides_whole`]) or several together ([`hides_whole_together`] with `band`, see
/// [`hidden_band`]).
fn hidden_whole(source: &[Vec3], target: &[Vec3], blockers: &[&Polygon], band: f64) -> bool {
    blockers.iter().any(|k| hides_whole(source, target, k)) || hides_whole_together(source, target, blockers, band)
}

/// The indices of the blockers that cast a shadow of their own from the source part `sa`:
/// those that the others still kept do not hide from all of it ([`hidden_whole`]). A blocker
/// hidden from the whole source hides nothing from any point of it (nor from the receiver's
/// side: each segment through it meets the others between the source and it) that the others
/// do not, so its shadow adds nothing to theirs; every blocker so dropped leaves its shadow to
/// one that stays. From 3 blockers on (the test costs a few boolean operations per blocker):
/// the far faces of partitions, the treads behind a step. In the 391-surface building at
/// obstructed_tol 1e-3 18.2 -> 15.3 s of one core's CPU, the largest row error the same
/// (2.093e-4).
fn casting(sa: &Polygon, blockers: &[&Polygon], band: f64) -> Vec<usize> {
    let mut keep = vec![true; blockers.len()];
    if blockers.len() >= 3 {
        let mut others = Vec::with_capacity(blockers.len());
        for k in 0..blockers.len() {
            others.clear();
            others.extend((0..blockers.len()).filter(|&q| q != k && keep[q]).map(|q| blockers[q]));
            keep[k] = !hidden_whole(sa.vertices(), blockers[k].vertices(), &others, band);
        }
    }
    (0..blockers.len()).filter(|&k| keep[k]).collect()
}

/// The least relative `clipping` target for which [`hidden_band`] lets the joints' band go.
const BAND_FROM_TOL: f64 = 1e-7;

/// Sum of w f(x) over the source points (x, w) of `sa` for the receiver's part `b` in front
/// of it (see [`area_source_points`]): the dA -> A_j methods' outer integral.
fn over_source(
    sa: &Polygon,
    b: &Polygon,
    blockers: &[&Polygon],
    source: Option<usize>,
    f: impl Fn(Vec3) -> f64,
) -> f64 {
    let mut g = 0.0;
    for (x, w) in area_source_points(sa, b, blockers, source) {
        // [methods] stop at cancellation or when the pair's work budget is spent
        if !crate::work::go_on() {
            break;
        }
        g += w * f(x);
    }
    g
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

/// A point (p, unit n) as the source polygon of a candidate-blocker test: a triangle 1e-9 of
/// `size` (the scene's or the receiver's) around p in its tangent plane, but no smaller than
/// 1e-9 of p's coordinates: smaller, rounding bends it out of its plane or collapses it (a
/// scene 1e-6 across at x = 7 had the candidate test then find no blocker: F unobstructed,
/// 0.125 for 0.101).
/// Larger only adds candidates, each then tested from p itself.
pub(crate) fn point_source(p: Vec3, n: Vec3, size: f64) -> Result<Polygon> {
    let (t, s) = crate::geometry::tangent_frame(n);
    let eps = 1e-9 * size.max(p.abs().max_element());
    Polygon::new(vec![p + eps * t, p + eps * s, p - eps * (t + s)])
        .map_err(|err| Error::InvalidArgument(format!("point {p:?}, normal {n:?}: {err}")))
}

/// F from a differential area (p, unit n) to polygon j of the scene, with visibility.
/// Nothing coplanar with the receiver blocks (see [`Occluders`]).
pub fn point(ctx: &Context, p: Vec3, n: Vec3, j: usize, m: &Estimator) -> Result<Estimate> {
    let b = &ctx.polygons[j];
    let ignore = &ctx.ignore([j]);
    let src = point_source(p, n, b.radius().max(p.distance(b.centroid())))?;
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
    Ok(match *m {
        Estimator::Quadrature(o) => {
            let pieces = subdivide_at_blockers(b, &blockers, o.panels);
            let sum = |pred: &dyn Fn(Vec3) -> bool| -> f64 {
                let mut total = 0.0;
                // a rule per piece as it comes (up to 8 192 pieces of 1 024 points each)
                for t in pieces.iter().filter_map(|t| Polygon::new(t.to_vec()).ok()) {
                    // [methods] stop at cancellation or over budget (the result is discarded)
                    if !crate::work::go_on() {
                        break;
                    }
                    let r = AreaRule::new(&t, o.order);
                    for (y, w) in r.points.iter().zip(&r.weights) {
                        if pred(*y) {
                            total += w * kernel(p, n, *y, b.normal());
                        }
                    }
                }
                total
            };
            if o.control_variate {
                Estimate::exact(lambert - sum(&|y| !visible(y)))
            } else {
                Estimate::exact(sum(&visible))
            }
        }
        Estimator::MonteCarlo(o) => {
            // strata: the receiver's pieces cut along the blockers' planes, as in the pair form
            let per = (o.samples / RQMC_REPS).max(1);
            let strata: Vec<(PolygonSampler, f64, usize)> = cut_at_blocker_planes(b, &blockers)
                .iter()
                .map(|q| (PolygonSampler::new(q), q.area(), stratum_samples(per, q.area() / b.area())))
                .collect();
            let sizes: Vec<(f64, usize)> = strata.iter().map(|s| (s.1, s.2)).collect();
            let est = rqmc_estimates::<2>(o.seed, [j as u64, u64::MAX], &sizes, |s, u| {
                let y = strata[s].0.sample([u[0], u[1]]);
                let w = kernel(p, n, y, b.normal());
                // (the visible and the blocked part; every sample's visibility is tested, and
                // pays by its ray)
                (if visible(y) { [w, 0.0] } else { [0.0, w] }, true)
            });
            // control variate: the unblocked integral is exact, the blocked part sampled
            Replicates::new(est, false).estimate(lambert, o.control_variate)
        }
        Estimator::Subdivision(o) => {
            Estimate::exact(uniform_point(p, n, &subdivide_at_blockers(b, &blockers, o.divisions), &visible))
        }
        Estimator::Adaptive(o) => Estimate::exact(adaptive_point(p, n, b, &visible, &o)),
        Estimator::Clipping(_) => Estimate::exact(point_visible_view_factor(p, n, b, &blockers)),
    })
}
