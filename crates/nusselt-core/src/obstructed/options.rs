//! The obstructed methods' options, the estimator that pairs one with its options, and the
//! estimate type.

use super::MAX_SOURCE_EVALS;
use crate::error::{Error, Result};
use crate::registry::method_options;

method_options! {
    /// Options of `quadrature`.
    pub struct QuadratureOptions for "quadrature" {
        /// Most Gauss points per direction on each polygon (the order of pairs nothing can block).
        order: usize,
        /// Absolute target on F from which an obstructed pair's order is chosen
        /// (`sampled::pair_order`).
        tol: f64,
        /// Point form only: the receiver's triangles are split into panels^2 pieces, each with
        /// the order rule. A single area integral keeps the visibility step sharp, so it needs a
        /// composite rule; the pair form's second integral smooths the step.
        panels: usize,
        /// Subtract the blocked part from the exact unobstructed G, or take the visible part
        /// where the largest kernel sample is blocked (see module docs).
        control_variate: bool,
    }
}

method_options! {
    /// Options of `montecarlo`.
    pub struct MonteCarloOptions for "montecarlo" {
        /// Point pairs per form factor.
        samples: usize,
        seed: u64,
        /// As `quadrature`'s (see module docs).
        control_variate: bool,
    }
}

method_options! {
    /// Options of `subdivision`.
    pub struct SubdivisionOptions for "subdivision" {
        /// Each receiver triangle is split into divisions^2 pieces.
        divisions: usize,
        /// Source points: None (default) cuts the source along its kink lines (see
        /// `kinks::split_at_kinks`), each piece gets its centroid and the largest Radon's 7-point
        /// rule, at most 64 points beyond one per piece (`rules::area_source_points`); Some(0) is
        /// the centroid alone, Some(k) a k x k Gauss rule per source triangle or quad (always a
        /// normalised weighted sum).
        source: Option<usize>,
    }
}

method_options! {
    /// Options of `adaptive`.
    pub struct AdaptiveOptions for "adaptive" {
        /// Pieces whose exact unobstructed F is below this are not refined (absolute F).
        tol: f64,
        /// Deepest refinement level.
        max_depth: usize,
        /// Source points, as [`SubdivisionOptions::source`].
        source: Option<usize>,
    }
}

method_options! {
    /// Options of `clipping`, and of the obstructed pairs of `auto`, `analytic` and `contour`
    /// (their `obstructed_tol` is `tol` here, the rest at `clipping`'s defaults).
    pub struct ClippingOptions for "clipping" {
        /// Error target on F relative to the pair's unobstructed F (so also an absolute bound on
        /// F, and row sums in a scene are within tol times the unobstructed row sum).
        tol: f64,
        /// Deepest refinement of the source.
        max_depth: usize,
        /// None integrates the shadowed F over the source adaptively to `tol`; Some(0) uses the
        /// centroid alone, Some(k) a k x k Gauss rule, for the visible fraction of the point F
        /// that scales the exact unobstructed value.
        source: Option<usize>,
    }
    fixed {
        /// Most point evaluations of one adaptive source integral (reaching it ends the
        /// refinement before `tol` is met; default [`MAX_SOURCE_EVALS`]).
        max_evals: usize = MAX_SOURCE_EVALS,
    }
    check(o) {
        if o.max_evals < 1 {
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
