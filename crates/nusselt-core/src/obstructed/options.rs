//! The obstructed methods' names, options and estimate type.

use super::MAX_SOURCE_EVALS;
use crate::error::{Error, Result};
use crate::registry::{check_field, Value};

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
    /// Unobstructed accuracy target of `auto` (relative), see [`crate::unobstructed::method::Options::tol`].
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
    /// its kink lines (see `kinks::split_at_kinks`), each piece gets its centroid and the largest
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
        // Fields shared by several methods take the default of the method named first in
        // their doc (`configure` sets every field a method reads from its own row).
        use crate::registry::{default_bool, default_f64, default_source, default_u64};
        VisOptions {
            exact_tol: default_f64("auto", "tol"),
            tol: default_f64("clipping", "tol"),
            order: default_u64("quadrature", "order") as usize,
            panels: default_u64("quadrature", "panels") as usize,
            samples: default_u64("montecarlo", "samples") as usize,
            seed: default_u64("montecarlo", "seed"),
            divisions: default_u64("subdivision", "divisions") as usize,
            source_points: default_source("subdivision").1,
            clip_source: default_source("clipping").1,
            control_variate: default_bool("quadrature", "control_variate"),
            max_depth: default_u64("clipping", "max_depth") as usize,
            max_evals: MAX_SOURCE_EVALS,
        }
    }
}

impl VisOptions {
    pub fn check(&self) -> Result<()> {
        // the ranges of the registry rows these fields come from
        let int = |x: usize| Value::Int(x as u64);
        check_field("auto", "tol", Value::Float(self.exact_tol))?;
        check_field("clipping", "tol", Value::Float(self.tol))?;
        check_field("quadrature", "order", int(self.order))?;
        check_field("quadrature", "panels", int(self.panels))?;
        check_field("montecarlo", "samples", int(self.samples))?;
        check_field("subdivision", "divisions", int(self.divisions))?;
        if let Some(k) = self.source_points {
            check_field("subdivision", "source", int(k))?;
        }
        if let Some(k) = self.clip_source {
            check_field("clipping", "source", int(k))?;
        }
        check_field("clipping", "max_depth", int(self.max_depth))?;
        if self.max_evals < 1 {
            return Err(Error::InvalidArgument("max_evals must be at least 1".into()));
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
    pub fn exact(value: f64) -> Self {
        Estimate { value, std_err: 0.0 }
    }
}
