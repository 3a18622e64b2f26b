//! The obstructed methods' names, options and estimate type.

use super::MAX_SOURCE_EVALS;
use crate::error::{Error, Result};
use crate::registry::{check_field, default_bool, default_f64, default_source, default_u64, Value};

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

/// Options of `quadrature`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadratureOptions {
    /// Most Gauss points per direction on each polygon (the order of pairs nothing can block).
    pub order: usize,
    /// Absolute target on F from which an obstructed pair's order is chosen
    /// (`sampled::pair_order`).
    pub tol: f64,
    /// Point form only: the receiver's triangles are split into panels^2 pieces, each with
    /// the order rule. A single area integral keeps the visibility step sharp, so it needs a
    /// composite rule; the pair form's second integral smooths the step.
    pub panels: usize,
    /// Sample only the blocked part (see module docs).
    pub control_variate: bool,
}

/// Options of `montecarlo`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MonteCarloOptions {
    /// Point pairs per form factor.
    pub samples: usize,
    pub seed: u64,
    /// Sample only the blocked part (see module docs).
    pub control_variate: bool,
}

/// Options of `subdivision`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubdivisionOptions {
    /// Each receiver triangle is split into divisions^2 pieces.
    pub divisions: usize,
    /// Source points: None (default) cuts the source along its kink lines (see
    /// `kinks::split_at_kinks`), each piece gets its centroid and the largest Radon's 7-point
    /// rule, at most 64 points beyond one per piece (`rules::area_source_points`); Some(0) is
    /// the centroid alone, Some(k) a k x k Gauss rule per source triangle or quad (always a
    /// normalised weighted sum).
    pub source: Option<usize>,
}

/// Options of `adaptive`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveOptions {
    /// Pieces whose exact unobstructed F is below this are not refined (absolute F).
    pub tol: f64,
    /// Deepest refinement level.
    pub max_depth: usize,
    /// Source points, as [`SubdivisionOptions::source`].
    pub source: Option<usize>,
}

/// Options of `clipping`, and of the obstructed pairs of `auto`, `analytic` and `contour`
/// (their `obstructed_tol` is `tol` here, the rest at `clipping`'s defaults).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClippingOptions {
    /// Error target on F relative to the pair's unobstructed F (so also an absolute bound on
    /// F, and row sums in a scene are within tol times the unobstructed row sum).
    pub tol: f64,
    /// Deepest refinement of the source.
    pub max_depth: usize,
    /// None integrates the shadowed F over the source adaptively to `tol`; Some(0) uses the
    /// centroid alone, Some(k) a k x k Gauss rule, for the visible fraction of the point F
    /// that scales the exact unobstructed value.
    pub source: Option<usize>,
    /// Most point evaluations of one adaptive source integral (reaching it ends the
    /// refinement before `tol` is met; default [`MAX_SOURCE_EVALS`]).
    pub max_evals: usize,
}

impl Default for QuadratureOptions {
    fn default() -> Self {
        QuadratureOptions {
            order: default_u64("quadrature", "order") as usize,
            tol: default_f64("quadrature", "tol"),
            panels: default_u64("quadrature", "panels") as usize,
            control_variate: default_bool("quadrature", "control_variate"),
        }
    }
}

impl Default for MonteCarloOptions {
    fn default() -> Self {
        MonteCarloOptions {
            samples: default_u64("montecarlo", "samples") as usize,
            seed: default_u64("montecarlo", "seed"),
            control_variate: default_bool("montecarlo", "control_variate"),
        }
    }
}

impl Default for SubdivisionOptions {
    fn default() -> Self {
        SubdivisionOptions {
            divisions: default_u64("subdivision", "divisions") as usize,
            source: default_source("subdivision").1,
        }
    }
}

impl Default for AdaptiveOptions {
    fn default() -> Self {
        AdaptiveOptions {
            tol: default_f64("adaptive", "tol"),
            max_depth: default_u64("adaptive", "max_depth") as usize,
            source: default_source("adaptive").1,
        }
    }
}

impl Default for ClippingOptions {
    fn default() -> Self {
        ClippingOptions {
            tol: default_f64("clipping", "tol"),
            max_depth: default_u64("clipping", "max_depth") as usize,
            source: default_source("clipping").1,
            max_evals: MAX_SOURCE_EVALS,
        }
    }
}

fn int(x: usize) -> Value {
    Value::Int(x as u64)
}

/// Checks an `Option<usize>` source against method `m`'s `source` range.
fn check_source(m: &str, source: Option<usize>) -> Result<()> {
    source.map_or(Ok(()), |k| check_field(m, "source", int(k)))
}

impl QuadratureOptions {
    pub fn check(&self) -> Result<()> {
        check_field("quadrature", "order", int(self.order))?;
        check_field("quadrature", "tol", Value::Float(self.tol))?;
        check_field("quadrature", "panels", int(self.panels))
    }
}

impl MonteCarloOptions {
    pub fn check(&self) -> Result<()> {
        check_field("montecarlo", "samples", int(self.samples))?;
        check_field("montecarlo", "seed", Value::Int(self.seed))
    }
}

impl SubdivisionOptions {
    pub fn check(&self) -> Result<()> {
        check_field("subdivision", "divisions", int(self.divisions))?;
        check_source("subdivision", self.source)
    }
}

impl AdaptiveOptions {
    pub fn check(&self) -> Result<()> {
        check_field("adaptive", "tol", Value::Float(self.tol))?;
        check_field("adaptive", "max_depth", int(self.max_depth))?;
        check_source("adaptive", self.source)
    }
}

impl ClippingOptions {
    pub fn check(&self) -> Result<()> {
        check_field("clipping", "tol", Value::Float(self.tol))?;
        check_field("clipping", "max_depth", int(self.max_depth))?;
        check_source("clipping", self.source)?;
        if self.max_evals < 1 {
            return Err(Error::InvalidArgument("max_evals must be at least 1".into()));
        }
        Ok(())
    }
}

/// A pair method with visibility and its options: what [`super::pair_with`] and
/// [`super::point`] run (`auto`, `analytic` and `contour` run `Clipping` on the pairs
/// something may block).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Estimator {
    Quadrature(QuadratureOptions),
    MonteCarlo(MonteCarloOptions),
    Subdivision(SubdivisionOptions),
    Adaptive(AdaptiveOptions),
    Clipping(ClippingOptions),
}

impl Estimator {
    pub fn check(&self) -> Result<()> {
        match self {
            Estimator::Quadrature(o) => o.check(),
            Estimator::MonteCarlo(o) => o.check(),
            Estimator::Subdivision(o) => o.check(),
            Estimator::Adaptive(o) => o.check(),
            Estimator::Clipping(o) => o.check(),
        }
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
    pub fn exact(value: f64) -> Self {
        Estimate { value, std_err: 0.0 }
    }
}
