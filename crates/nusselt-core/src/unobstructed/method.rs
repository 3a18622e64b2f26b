//! Method selection for one pair or one point, unobstructed.
//!
//! `auto` picks per pair, from the pair's relative separation, the cheapest rule whose
//! calibrated relative error stays below `tol` ([`far_field::FarPlan`]): a Gauss area rule
//! or a moment rule ([`crate::unobstructed::moments`]: second order, or fourth order for pairs of
//! parallelograms) when the polygons are far apart compared with their size (the kernel is
//! smooth there), the exact closed form when the pair is close, touching or straddles a plane.

use super::far_field::{self, FarPlan, FarRule, PackedRule};
use crate::error::{Error, Result};
use crate::geometry::{Polygon, Vec3};
use crate::quadrature::AreaRule;
use crate::registry::{method_options, OptionField};
use crate::unobstructed::analytic;
use crate::unobstructed::contour;
use crate::unobstructed::moments::{moment4_pair, moment_pair, Moments};
use std::sync::OnceLock;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    Auto,
    Analytic,
    Contour,
}

method_options! {
    /// Options of `auto`.
    pub struct AutoOptions for "auto" {
        /// Relative accuracy target per unobstructed pair.
        tol: f64,
        /// The `tol` of the pairs something may block (computed by `clipping`).
        obstructed_tol: f64,
    }
}

method_options! {
    /// Options of `analytic`.
    pub struct AnalyticOptions for "analytic" {
        /// The `tol` of the pairs something may block (computed by `clipping`).
        obstructed_tol: f64,
    }
}

method_options! {
    /// Options of `contour`.
    pub struct ContourOptions for "contour" {
        /// Gauss-Legendre nodes per edge panel.
        nodes: usize,
        /// The `tol` of the pairs something may block (computed by `clipping`).
        obstructed_tol: f64,
    }
}

/// What the unobstructed kernels read (each the field it documents): `auto`'s `tol` and
/// `contour`'s `nodes`, at their methods' defaults unless a caller sets them.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// `auto`: relative accuracy target per pair.
    pub tol: f64,
    /// `contour`: Gauss-Legendre nodes per edge panel.
    pub nodes: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options { tol: AutoOptions::default().tol, nodes: ContourOptions::default().nodes }
    }
}

impl Options {
    pub fn check(&self) -> Result<()> {
        OptionField::check(&self.tol, AutoOptions::METHOD, "tol")?;
        OptionField::check(&self.nodes, ContourOptions::METHOD, "nodes")
    }
}

/// Largest Gauss order `auto` uses before it falls back to the exact kernel.
pub const MAX_AUTO_ORDER: usize = 8;

/// Area rules of one polygon, built on first use per order, and its second moments (shared
/// across threads).
pub struct RuleCache {
    rules: Vec<OnceLock<PackedRule>>,
    moments: Vec<OnceLock<Moments>>,
}

impl RuleCache {
    pub fn new(n_polygons: usize) -> Self {
        RuleCache {
            rules: (0..n_polygons * MAX_AUTO_ORDER).map(|_| OnceLock::new()).collect(),
            moments: (0..n_polygons).map(|_| OnceLock::new()).collect(),
        }
    }
    fn get<'a>(&'a self, id: usize, poly: &Polygon, order: usize) -> &'a PackedRule {
        self.rules[id * MAX_AUTO_ORDER + order - 1].get_or_init(|| PackedRule::new(&AreaRule::new(poly, order), poly))
    }
    pub fn moments<'a>(&'a self, id: usize, poly: &Polygon) -> &'a Moments {
        self.moments[id].get_or_init(|| Moments::new(poly))
    }
}

/// Relation of two polygons' planes, decided with a scale-relative tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Facing {
    /// Nothing of either polygon lies strictly in front of the other: no exchange.
    None,
    /// Each lies entirely in the other's closed front half-space.
    Full,
    /// At least one crosses the other's plane: clipping is needed.
    Partial,
}

pub fn facing(a: &Polygon, b: &Polygon) -> Facing {
    // q's vertices against p's plane, within 1e-12 of q's own size (never of the pair's:
    // pairs of very different size keep the small one) above the rounding across p
    let d = a.centroid().distance(b.centroid());
    let side = |p: &Polygon, q: &Polygon| {
        let tol = 1e-2 * crate::geometry::plane_tol(q.radius(), p.radius() + d);
        // bounding-sphere test first: most pairs of a scene are decided without the vertices
        let h = (q.centroid() - p.centroid()).dot(p.normal());
        if h - q.radius() > tol {
            return (true, false);
        }
        if h + q.radius() < -tol {
            return (false, true);
        }
        let (mut pos, mut neg) = (false, false);
        for v in q.vertices() {
            let d = (*v - p.centroid()).dot(p.normal());
            pos |= d > tol;
            neg |= d < -tol;
        }
        (pos, neg)
    };
    let (ap, an) = side(a, b);
    let (bp, bn) = side(b, a);
    if !ap || !bp {
        Facing::None
    } else if an || bn {
        Facing::Partial
    } else {
        Facing::Full
    }
}

/// A_a F_ab (= A_b F_ba) for an unobstructed pair. With `cache`, `ia`/`ib` index its rules.
pub fn area_factor(
    a: &Polygon,
    b: &Polygon,
    method: Method,
    opts: &Options,
    cache: Option<(&RuleCache, usize, usize)>,
) -> Result<f64> {
    let f = if method == Method::Auto { facing(a, b) } else { Facing::Partial };
    area_factor_facing(a, b, f, method, opts, cache)
}

/// [`area_factor`] when the caller already knows `facing(a, b)` (scene loops test it first).
pub fn area_factor_facing(
    a: &Polygon,
    b: &Polygon,
    f: Facing,
    method: Method,
    opts: &Options,
    cache: Option<(&RuleCache, usize, usize)>,
) -> Result<f64> {
    match method {
        Method::Analytic => Ok(analytic::polygon_pair(a, b)),
        Method::Contour => contour::polygon_pair(a, b, opts.nodes),
        Method::Auto => {
            let regular = far_field::is_regular_quad(a) && far_field::is_regular_quad(b);
            Ok(auto_pair(a, b, f, &FarPlan::cached(opts.tol), regular, cache))
        }
    }
}

/// `auto` for an unobstructed pair whose facing `f` is known, with the plan of its tolerance
/// and whether both are regular quads (scene loops know both once for all pairs).
pub fn auto_pair(
    a: &Polygon,
    b: &Polygon,
    f: Facing,
    plan: &FarPlan,
    regular: bool,
    cache: Option<(&RuleCache, usize, usize)>,
) -> f64 {
    match f {
        Facing::None => 0.0,
        Facing::Partial => analytic::polygon_pair_within(a, b, plan.tol()),
        Facing::Full => {
            let (d, rsum) = (b.centroid() - a.centroid(), a.radius() + b.radius());
            full_facing_pair(a, b, plan.rule_sq(d.dot(d), rsum * rsum, regular), plan.tol(), cache)
        }
    }
}

/// A_a F_ab of a fully facing, unobstructed pair by `rule` (from a [`FarPlan`] for `tol`).
pub fn full_facing_pair(
    a: &Polygon,
    b: &Polygon,
    rule: FarRule,
    tol: f64,
    cache: Option<(&RuleCache, usize, usize)>,
) -> f64 {
    match rule {
        FarRule::Gauss(order) if order <= MAX_AUTO_ORDER => match cache {
            Some((c, ia, ib)) => far_field::far_pair(c.get(ia, a, order), a.normal(), c.get(ib, b, order), b.normal()),
            None => far_field::far_pair(
                &PackedRule::new(&AreaRule::new(a, order), a),
                a.normal(),
                &PackedRule::new(&AreaRule::new(b, order), b),
                b.normal(),
            ),
        },
        FarRule::Moment | FarRule::Moment4 => {
            let pair = if rule == FarRule::Moment { moment_pair } else { moment4_pair };
            match cache {
                Some((c, ia, ib)) => pair(c.moments(ia, a), c.moments(ib, b)),
                None => pair(&Moments::new(a), &Moments::new(b)),
            }
        }
        FarRule::Gauss(_) | FarRule::Exact => analytic::polygon_pair_within(a, b, tol),
    }
}

/// F from a differential area (p, unit n) to polygon b, unobstructed. Every unobstructed
/// method evaluates Lambert's closed form here: it is exact and a single contour sum.
pub fn point_factor(p: Vec3, n: Vec3, b: &Polygon, _method: Method, opts: &Options) -> Result<f64> {
    opts.check()?;
    if !p.is_finite() || !n.is_finite() || (n.length() - 1.0).abs() > 1e-6 {
        return Err(Error::InvalidArgument("point and unit normal must be finite".into()));
    }
    Ok(analytic::point_polygon(p, n, b.vertices()))
}
