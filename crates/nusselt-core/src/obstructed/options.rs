//! The obstructed methods' names, options and estimate type.

use super::MAX_SOURCE_EVALS;
use crate::error::{Error, Result};

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

#[derive(Debug, Clone, PartialEq)]
pub struct VisOptions {
    /// Unobstructed accuracy target of `auto` (relative), see [`method::Options::tol`].
    pub exact_tol: f64,
    /// `clipping` and obstructed pairs of `auto`: error target on F relative to the pair's
    /// unobstructed F (so also an absolute bound on F, and row sums in a scene are within
    /// tol times the unobstructed row sum). `adaptive`: absolute F per leaf piece.
    /// `quadrature`: absolute target on F from which an obstructed pair's order is chosen
    /// (`sampled::pair_order`).
    pub tol: f64,
    /// `quadrature`: most Gauss points per direction on each polygon (the order of pairs
    /// nothing can block).
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
    /// its kink lines (see [`split_at_kinks`]), each piece gets its centroid and the largest
    /// Radon's 7-point rule, at most 64 points beyond one per piece (`rules::area_source_points`);
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
            samples: 8192,
            seed: 0,
            divisions: 10,
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
    pub(super) fn exact(value: f64) -> Self {
        Estimate { value, std_err: 0.0 }
    }
}
