//! The one table of methods users can select: each method's name, kind, whether it handles
//! obstacles, and each option's name, type, default, valid range and documentation.
//!
//! Everything else reads this table: [`configure`] turns a method name and the options a
//! caller gave into the core's method and option structs (whose `Default` and `check` read
//! their defaults and ranges here too, `default_f64`, `check_field`), and the Python package builds
//! `nusselt.METHODS`, its validation and `nusselt methods` from it (through the binding's
//! `methods()`). An option name means one thing per method: `tol` of `auto` is the accuracy
//! of unobstructed pairs, `tol` of `adaptive` the leaf threshold, `tol` of `clipping` the
//! target on obstructed pairs; the mapping is spelled out per method in [`configure`].

use crate::error::{Error, Result};
use crate::hemisphere::nusselt_analog::MAX_CELLS;
use crate::hemisphere::raytrace::MAX_RAYS;
use crate::hemisphere::{SourcePoints, MAX_GAUSS_ORDER};
use crate::scene::AnyMethod;
use crate::unobstructed::contour::DEFAULT_NODES;
use crate::work::DEFAULT_BUDGET;

/// How a method computes a matrix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A_i F_ij once per unordered pair (symmetric G).
    Pairs,
    /// Whole rows F_i. by sampling the hemisphere above each patch.
    Rows,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::Pairs => "pairs",
            Kind::Rows => "rows",
        }
    }
}

/// The type of an option's value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OptionType {
    Float,
    Int,
    Bool,
    /// A keyword of [`OptionSpec::keywords`] or an integer in [lo, hi] (a Gauss order k,
    /// 0 meaning the centroid).
    Source,
}

impl OptionType {
    pub fn name(self) -> &'static str {
        match self {
            OptionType::Float => "float",
            OptionType::Int => "int",
            OptionType::Bool => "bool",
            OptionType::Source => "source",
        }
    }
}

/// An option's value (defaults in the table, and what a caller gives).
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Float(f64),
    Int(u64),
    Bool(bool),
    Keyword(String),
}

/// A default in the static table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Default {
    Float(f64),
    Int(u64),
    Bool(bool),
    Keyword(&'static str),
}

impl Default {
    pub fn value(self) -> Value {
        match self {
            Default::Float(x) => Value::Float(x),
            Default::Int(x) => Value::Int(x),
            Default::Bool(x) => Value::Bool(x),
            Default::Keyword(s) => Value::Keyword(s.to_string()),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OptionSpec {
    pub name: &'static str,
    pub ty: OptionType,
    pub default: Default,
    /// Inclusive range of a number (Float, Int, the integer form of Source); unused for Bool.
    pub lo: f64,
    pub hi: f64,
    /// Keywords a Source option accepts.
    pub keywords: &'static [&'static str],
    pub doc: &'static str,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MethodSpec {
    pub name: &'static str,
    pub kind: Kind,
    /// Handles polygons that block others (visibility).
    pub obstructed: bool,
    pub doc: &'static str,
    pub options: &'static [OptionSpec],
}

impl MethodSpec {
    pub fn option(&self, name: &str) -> Option<&'static OptionSpec> {
        self.options.iter().find(|o| o.name == name)
    }
}

const fn float(name: &'static str, default: f64, lo: f64, hi: f64, doc: &'static str) -> OptionSpec {
    OptionSpec { name, ty: OptionType::Float, default: Default::Float(default), lo, hi, keywords: &[], doc }
}
const fn int(name: &'static str, default: u64, lo: u64, hi: u64, doc: &'static str) -> OptionSpec {
    OptionSpec {
        name,
        ty: OptionType::Int,
        default: Default::Int(default),
        lo: lo as f64,
        hi: hi as f64,
        keywords: &[],
        doc,
    }
}
const fn flag(name: &'static str, default: bool, doc: &'static str) -> OptionSpec {
    OptionSpec { name, ty: OptionType::Bool, default: Default::Bool(default), lo: 0.0, hi: 1.0, keywords: &[], doc }
}
const fn source(default: &'static str, keywords: &'static [&'static str], doc: &'static str) -> OptionSpec {
    OptionSpec {
        name: "source",
        ty: OptionType::Source,
        default: Default::Keyword(default),
        lo: 0.0,
        hi: MAX_GAUSS_ORDER as f64,
        keywords,
        doc,
    }
}

/// Largest budget accepted (2^62 units: effectively none).
pub const MAX_BUDGET: u64 = 1 << 62;

const BUDGET: OptionSpec = int(
    "budget",
    DEFAULT_BUDGET,
    1,
    MAX_BUDGET,
    "most work units (visibility tests, cells or rays) one pair or row may take; more is a ValueError naming it",
);
/// `auto`, `analytic`, `contour`: the target of the pairs they compute by `clipping`.
const OBSTRUCTED_TOL: OptionSpec = float(
    "obstructed_tol",
    1e-6,
    1e-14,
    0.1,
    "accuracy target for obstructed pairs, relative to the pair's unobstructed F (so also absolute on F; row sums \
     within it in enclosures)",
);
const SEED: OptionSpec =
    int("seed", 0, 0, 1 << 63, "seed of the scrambled low-discrepancy points (results are reproducible)");
const ROTATE: OptionSpec =
    flag("random_rotation", true, "random rotation about the normal per sample point (aliasing becomes noise)");
const CONTROL_VARIATE: OptionSpec =
    flag("control_variate", true, "compute the unblocked integral exactly and sample only the blocked part");
const SOURCE_ROW: OptionSpec = source(
    "auto",
    &["auto", "centre", "center"],
    "source points on each patch: 'auto' (by patch size), 'centre', or k for a k x k Gauss rule",
);
const SOURCE_AREA: OptionSpec = source(
    "auto",
    &["auto", "centre", "center"],
    "source points on A_i: 'auto' (the source cut along the lines where the visible F has a kink, a centroid per \
     piece and Radon's 7 points on the largest, at most 64 points beyond one per piece), \
     'centre', or k for a k x k Gauss rule \
     (always a normalised weighted sum)",
);

/// Every method, in the order `nusselt methods` lists them.
pub static METHODS: &[MethodSpec] = &[
    MethodSpec {
        name: "auto",
        kind: Kind::Pairs,
        obstructed: true,
        doc: "the fastest method that meets the accuracy targets for each pair: for pairs with nothing in between, a moment \
              rule (fourth order for parallelograms) or Gauss area quadrature of an order chosen by separation (distant \
              pairs) or the exact closed form (close, touching, piercing pairs); for pairs a polygon may block, the exact \
              visible region (`clipping`) to `obstructed_tol`",
        options: &[
            float("tol", 1e-10, 1e-15, 0.1, "relative accuracy target per unobstructed pair"),
            OBSTRUCTED_TOL,
            BUDGET,
        ],
    },
    MethodSpec {
        name: "analytic",
        kind: Kind::Pairs,
        obstructed: true,
        doc: "closed form: Lambert's formula for a point, Narayanaswamy's edge-pair formula (exact limits for touching \
              edges) for two polygons; where the edge-pair terms cancel by more than 2e3 (slivers, pairs far apart) an area \
              route with terms of one sign (Gauss on both areas, or Lambert integrated over the smaller polygon) to 1e-14; \
              for pairs a polygon may block, the exact visible region (`clipping`) from this closed form, to \
              `obstructed_tol` (a point: Lambert's formula on the exact visible region)",
        options: &[OBSTRUCTED_TOL, BUDGET],
    },
    MethodSpec {
        name: "contour",
        kind: Kind::Pairs,
        obstructed: true,
        doc: "double contour (Stokes) integral: exact inner line integral, Gauss-Legendre outer integral on graded panels, \
              exact closed form where edges touch; sums that cancel by more than 2e3 take the same area route as analytic; \
              for pairs a polygon may block, the exact visible region (`clipping`) from this integral, to `obstructed_tol` \
              (a point: Lambert's formula on the exact visible region)",
        options: &[int("nodes", DEFAULT_NODES as u64, 1, 64, "Gauss-Legendre nodes per edge panel"), OBSTRUCTED_TOL, BUDGET],
    },
    MethodSpec {
        name: "quadrature",
        kind: Kind::Pairs,
        obstructed: true,
        doc: "Gauss rules on both areas (the double area integral) with point-pair visibility by ray casting; each polygon \
              is first cut along the planes of blockers that pass through it (a partition or a fin standing on it), where \
              visibility steps; a pair something may block gets its own order, the lowest whose bound on the visibility \
              step's error (a fraction of the pair's unobstructed F that falls like 1/order) meets `tol`, at most `order`",
        options: &[
            int(
                "order",
                24,
                1,
                32,
                "most Gauss points per direction on each polygon (a piece cut off a fraction f of it gets ceil(order \
                 sqrt f)); the order of pairs nothing can block",
            ),
            float(
                "tol",
                5e-4,
                1e-14,
                0.1,
                "absolute target on F (both directions) for pairs something may block: such a pair gets the lowest order \
                 n with 0.75 F_free / n <= tol (F_free: its unobstructed F), between 2 and `order`",
            ),
            int(
                "panels",
                4,
                1,
                64,
                "point form: the receiver is split into panels^2 pieces per triangle, each with the order rule (composite \
                 rule for the sharp visibility step)",
            ),
            CONTROL_VARIATE,
            BUDGET,
        ],
    },
    MethodSpec {
        name: "montecarlo",
        kind: Kind::Pairs,
        obstructed: true,
        doc: "area-to-area quasi-Monte Carlo with Owen-scrambled Sobol points, stratified over the pieces of both polygons \
              cut along the planes of blockers through them; standard error from 8 independent scramblings",
        options: &[int("samples", 16384, 8, 1 << 24, "point pairs per form factor"), SEED, CONTROL_VARIATE, BUDGET],
    },
    MethodSpec {
        name: "subdivision",
        kind: Kind::Pairs,
        obstructed: true,
        doc: "dA -> A_j by uniform subdivision of the receiver (exact Lambert per piece times the piece's visibility; the \
              receiver is first cut along the planes of blockers through it), summed over source points",
        options: &[int("divisions", 10, 1, 256, "each receiver triangle is split into divisions^2"), SOURCE_AREA, BUDGET],
    },
    MethodSpec {
        name: "adaptive",
        kind: Kind::Pairs,
        obstructed: true,
        doc: "dA -> A_j by adaptive subdivision of the receiver where visibility changes, summed over source points",
        options: &[
            float("tol", 1e-4, 1e-14, 0.1, "pieces contributing less than this to F are not refined"),
            int("max_depth", 8, 1, 16, "deepest refinement level"),
            SOURCE_AREA,
            BUDGET,
        ],
    },
    MethodSpec {
        name: "clipping",
        kind: Kind::Pairs,
        obstructed: true,
        doc: "exact visible region per source point (shadows projected onto the receiver, subtracted by polygon clipping, \
              Lambert on the rest), integrated adaptively over the source",
        options: &[
            float("tol", 1e-7, 1e-14, 0.1, "accuracy target on F, relative to the pair's unobstructed F (so also absolute)"),
            int("max_depth", 12, 1, 16, "deepest refinement of the source"),
            source(
                "adaptive",
                &["adaptive", "centre", "center"],
                "'adaptive' (to tol), or 'centre' / k for a fixed k x k Gauss rule whose visible fraction of the point F \
                 scales the exact unobstructed F",
            ),
            BUDGET,
        ],
    },
    MethodSpec {
        name: "hemicube",
        kind: Kind::Rows,
        obstructed: true,
        doc: "hemicube with z-buffer and item buffer per face, exact delta form factors per cell",
        options: &[
            int("resolution", 128, 4, 4096, "cells along the top face (even; with row_tol: the finest a row may use)"),
            float(
                "row_tol",
                0.0,
                0.0,
                0.5,
                "target aliasing error per entry: a row is rendered at 16, 24, 32, 48, 64, ... cells and stops at the \
                 first where every entry's estimated error (from the cells along its outline) is at most this and an \
                 entry no cell saw is below it (0: always `resolution`; needs random_rotation)",
            ),
            SOURCE_ROW,
            ROTATE,
            SEED,
            BUDGET,
        ],
    },
    MethodSpec {
        name: "single-plane",
        kind: Kind::Rows,
        obstructed: true,
        doc: "Sillion's single plane above the patch with Warnock area subdivision; the horizon band it misses is reported \
              per row (`lost`)",
        options: &[
            float("half_width", 14.0, 0.5, 1e4, "half-width of the plane at height 1"),
            float("min_cell", 1.0 / 128.0, 1e-4, 1.0, "smallest Warnock window (relative to height 1)"),
            SOURCE_ROW,
            ROTATE,
            SEED,
            BUDGET,
        ],
    },
    MethodSpec {
        name: "raytrace",
        kind: Kind::Rows,
        obstructed: true,
        doc: "cosine-distributed rays (reverse Nusselt analogy) from area-uniform points, first hit by the BVH; binomial \
              standard error per entry",
        options: &[
            int("rays", 4096, 1, MAX_RAYS as u64, "rays per patch (with row_tol: the most a row may cast)"),
            float(
                "row_tol",
                0.0,
                0.0,
                0.5,
                "target standard error per entry: a row stops at the first of 256, 512, 1024, ... rays where every \
                 entry's sqrt(F(1-F)/N) is at most this and N >= 3/row_tol (0: always cast `rays`)",
            ),
            SEED,
            BUDGET,
        ],
    },
    MethodSpec {
        name: "nusselt",
        kind: Kind::Rows,
        obstructed: true,
        doc: "Nusselt analog: equal-area cells of the unit disk lifted to the hemisphere, each resolved to the visible \
              patch; F = covered disk area / pi",
        options: &[
            int("cells", 4096, 1, MAX_CELLS as u64, "disk cells (rounded to a square number)"),
            SOURCE_ROW,
            flag("jitter", true, "a random point per cell instead of its centre"),
            ROTATE,
            SEED,
            BUDGET,
        ],
    },
];

/// The method called `name`.
pub fn find(name: &str) -> Result<&'static MethodSpec> {
    METHODS.iter().find(|m| m.name == name).ok_or_else(|| {
        let names: Vec<&str> = METHODS.iter().map(|m| m.name).collect();
        Error::InvalidArgument(format!("unknown method {name:?}; choose one of: {}", names.join(", ")))
    })
}

/// The spec of option `option` of method `method` (both listed in [`METHODS`]: a caller bug
/// otherwise, hence the panic).
fn spec_of(method: &str, option: &str) -> &'static OptionSpec {
    find(method).ok().and_then(|m| m.option(option)).unwrap_or_else(|| panic!("{method:?} has no option {option}"))
}

/// Checks one field of an option struct against the range of option `option` of `method` in
/// [`METHODS`] (the `check` of the option structs, so that ranges are written once).
pub(crate) fn check_field(method: &str, option: &str, v: Value) -> Result<()> {
    check(method, spec_of(method, option), &v)
}

/// Checks `v` against `spec`; the message names the method and the option.
pub fn check(method: &str, spec: &OptionSpec, v: &Value) -> Result<()> {
    let bad = |why: String| Err(Error::InvalidArgument(format!("method {method:?}: option {}={v:?} {why}", spec.name)));
    let in_range = |x: f64| x >= spec.lo && x <= spec.hi;
    match (spec.ty, v) {
        (OptionType::Float, Value::Float(x)) if !x.is_finite() => bad("must be finite".into()),
        (OptionType::Float, Value::Float(x)) => {
            if in_range(*x) {
                Ok(())
            } else {
                bad(format!("is outside [{:e}, {:e}]", spec.lo, spec.hi))
            }
        }
        (OptionType::Int | OptionType::Source, Value::Int(x)) => {
            // integer comparison: above 2^53 an f64 cannot tell x from x + 1
            if *x >= spec.lo as u64 && *x <= spec.hi as u64 {
                Ok(())
            } else {
                bad(format!("is outside [{}, {}]", spec.lo as u64, spec.hi as u64))
            }
        }
        (OptionType::Bool, Value::Bool(_)) => Ok(()),
        (OptionType::Source, Value::Keyword(s)) => {
            if spec.keywords.contains(&s.as_str()) {
                Ok(())
            } else {
                bad(format!(
                    "must be one of {:?} or an integer in [{}, {}]",
                    spec.keywords, spec.lo as u64, spec.hi as u64
                ))
            }
        }
        _ => bad(format!("must be of type {}", spec.ty.name())),
    }
}

/// A field of a method's options struct, read from and checked against the option of the
/// same name in [`METHODS`] (see [`method_options`]).
pub(crate) trait OptionField: Sized {
    fn from_value(v: &Value) -> Self;
    fn check(&self, method: &str, option: &str) -> Result<()>;
}

impl OptionField for f64 {
    fn from_value(v: &Value) -> Self {
        as_f64(v)
    }
    fn check(&self, method: &str, option: &str) -> Result<()> {
        check_field(method, option, Value::Float(*self))
    }
}

impl OptionField for u64 {
    fn from_value(v: &Value) -> Self {
        as_u64(v)
    }
    fn check(&self, method: &str, option: &str) -> Result<()> {
        check_field(method, option, Value::Int(*self))
    }
}

impl OptionField for u32 {
    fn from_value(v: &Value) -> Self {
        as_u64(v) as u32
    }
    fn check(&self, method: &str, option: &str) -> Result<()> {
        check_field(method, option, Value::Int((*self).into()))
    }
}

impl OptionField for usize {
    fn from_value(v: &Value) -> Self {
        as_u64(v) as usize
    }
    fn check(&self, method: &str, option: &str) -> Result<()> {
        check_field(method, option, Value::Int(*self as u64))
    }
}

impl OptionField for bool {
    fn from_value(v: &Value) -> Self {
        as_bool(v)
    }
    fn check(&self, _: &str, _: &str) -> Result<()> {
        Ok(())
    }
}

/// A row method's `source`.
impl OptionField for SourcePoints {
    fn from_value(v: &Value) -> Self {
        source_of(v).0
    }
    fn check(&self, method: &str, _: &str) -> Result<()> {
        SourcePoints::check(self, method)
    }
}

/// An area pair method's `source` (None: the method's own 'auto' / 'adaptive' rule).
impl OptionField for Option<usize> {
    fn from_value(v: &Value) -> Self {
        source_of(v).1
    }
    fn check(&self, method: &str, option: &str) -> Result<()> {
        self.map_or(Ok(()), |k| check_field(method, option, Value::Int(k as u64)))
    }
}

/// The default of option `option` of `method` in [`METHODS`].
pub(crate) fn default_of(method: &str, option: &str) -> Value {
    spec_of(method, option).default.value()
}

/// Declares the options struct of one method of [`METHODS`]: one field per option, named as
/// the option (its `Default` and range come from the table), then `fixed` fields that are
/// not options (with their value), then the method's own conditions beyond the table's
/// ranges (`check(o) { ... }`, a `Result<()>`). Every struct also gets the table's `budget`.
/// Generated: the struct, `Default`, `METHOD` (the name), `set` (one option from a checked
/// value, what [`configure`] calls) and `check`.
macro_rules! method_options {
    (
        $(#[$meta:meta])*
        pub struct $name:ident for $method:literal {
            $( $(#[$fmeta:meta])* $field:ident: $ty:ty, )*
        }
        $( fixed { $( $(#[$xmeta:meta])* $xfield:ident: $xty:ty = $xinit:expr, )* } )?
        $( check($o:ident) $extra:block )?
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct $name {
            $( $(#[$fmeta])* pub $field: $ty, )*
            $( $( $(#[$xmeta])* pub $xfield: $xty, )* )?
            /// Most work units one pair or row may take ([`crate::work`]; the caller meters it).
            pub budget: u64,
        }

        impl Default for $name {
            fn default() -> Self {
                use $crate::registry::{default_of, OptionField};
                $name {
                    $( $field: OptionField::from_value(&default_of($method, stringify!($field))), )*
                    $( $( $xfield: $xinit, )* )?
                    budget: OptionField::from_value(&default_of($method, "budget")),
                }
            }
        }

        impl $name {
            /// The method's name in [`crate::registry::METHODS`].
            pub const METHOD: &'static str = $method;

            /// [`Self::METHOD`].
            pub fn name(&self) -> &'static str {
                $method
            }

            /// Sets option `key` from `v` (already checked against the table); false when
            /// the method has no option `key`.
            pub(crate) fn set(&mut self, key: &str, v: &$crate::registry::Value) -> bool {
                use $crate::registry::OptionField;
                $( if key == stringify!($field) {
                    self.$field = OptionField::from_value(v);
                    return true;
                } )*
                if key == "budget" {
                    self.budget = OptionField::from_value(v);
                    return true;
                }
                false
            }

            /// Checks every option against its range in the table, then the method's own
            /// conditions; the message names the method and the option.
            pub fn check(&self) -> $crate::error::Result<()> {
                use $crate::registry::OptionField;
                $( OptionField::check(&self.$field, $method, stringify!($field))?; )*
                OptionField::check(&self.budget, $method, "budget")?;
                $( let $o = self; ($extra)?; )?
                Ok(())
            }
        }
    };
}
pub(crate) use method_options;

/// The method `name` with the options `given` (the others at their defaults in [`METHODS`]),
/// each checked against its range.
pub fn configure(name: &str, given: &[(String, Value)]) -> Result<AnyMethod> {
    let spec = find(name)?;
    let mut values: Vec<(&'static OptionSpec, Value)> = spec.options.iter().map(|o| (o, o.default.value())).collect();
    for (k, v) in given {
        let slot = values.iter_mut().find(|(o, _)| o.name == k).ok_or_else(|| {
            let names: Vec<&str> = spec.options.iter().map(|o| o.name).collect();
            Error::InvalidArgument(format!(
                "method {name:?} has no option {k} (options: {})",
                if names.is_empty() { "none".to_string() } else { names.join(", ") }
            ))
        })?;
        check(name, slot.0, v)?;
        slot.1 = v.clone();
    }
    let mut method = AnyMethod::from_name(name)
        .ok_or_else(|| Error::InvalidArgument(format!("method {name:?} is listed but not wired (internal error)")))?;
    for (spec_o, v) in &values {
        if !method.set(spec_o.name, v) {
            return Err(Error::InvalidArgument(format!(
                "method {name:?}: option {} is listed but not wired (internal error)",
                spec_o.name
            )));
        }
    }
    method.check()?;
    Ok(method)
}

fn as_f64(v: &Value) -> f64 {
    match *v {
        Value::Float(x) => x,
        Value::Int(x) => x as f64,
        _ => f64::NAN,
    }
}
fn as_u64(v: &Value) -> u64 {
    match *v {
        Value::Int(x) => x,
        _ => 0,
    }
}
fn as_bool(v: &Value) -> bool {
    matches!(v, Value::Bool(true))
}

/// Source points of a row method, and of the area pair methods (None = the method's own
/// 'auto' / 'adaptive' rule).
fn source_of(v: &Value) -> (SourcePoints, Option<usize>) {
    match v {
        Value::Keyword(s) if s == "centre" || s == "center" => (SourcePoints::Centre, Some(0)),
        Value::Int(0) => (SourcePoints::Centre, Some(0)),
        Value::Int(k) => (SourcePoints::Gauss(*k as u32), Some(*k as usize)),
        _ => (SourcePoints::Auto, None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_method_configures_at_its_defaults_and_at_each_range_end() {
        for m in METHODS {
            configure(m.name, &[]).unwrap_or_else(|e| panic!("{}: {e}", m.name));
            for o in m.options {
                let ends: Vec<Value> = match o.ty {
                    OptionType::Float => vec![Value::Float(o.lo), Value::Float(o.hi)],
                    OptionType::Int | OptionType::Source => vec![Value::Int(o.lo as u64), Value::Int(o.hi as u64)],
                    OptionType::Bool => vec![Value::Bool(false), Value::Bool(true)],
                };
                for v in ends {
                    let v = match (m.name, o.name, v) {
                        // the hemicube's resolution is even
                        ("hemicube", "resolution", Value::Int(r)) => Value::Int(r & !1),
                        (_, _, v) => v,
                    };
                    configure(m.name, &[(o.name.to_string(), v.clone())])
                        .unwrap_or_else(|e| panic!("{} {}={v:?}: {e}", m.name, o.name));
                }
            }
        }
    }

    #[test]
    fn out_of_range_and_unknown_options_are_refused_by_name() {
        let e = configure("single-plane", &[("min_cell".into(), Value::Float(1e-5))]).unwrap_err().to_string();
        assert!(e.contains("min_cell") && e.contains("single-plane"), "{e}");
        let e = configure("adaptive", &[("nodes".into(), Value::Int(3))]).unwrap_err().to_string();
        assert!(e.contains("no option nodes"), "{e}");
        assert!(configure("nope", &[]).is_err());
    }

    #[test]
    fn every_listed_method_is_wired_once_and_named_back() {
        let mut names = std::collections::HashSet::new();
        for m in METHODS {
            assert_eq!(configure(m.name, &[]).unwrap().name(), m.name);
            assert_eq!(AnyMethod::from_name(m.name).unwrap().name(), m.name);
            assert!(names.insert(m.name), "{} listed twice", m.name);
        }
        assert!(AnyMethod::from_name("nope").is_none());
    }

    #[test]
    fn option_structs_default_to_the_table_and_check_its_ranges() {
        use crate::hemisphere::{HemicubeOptions, NusseltOptions, RaytraceOptions, SinglePlaneOptions};
        // what a user gets at the defaults is what a Rust caller gets from Default
        let at = |m: &str| configure(m, &[]).unwrap();
        assert_eq!(at("hemicube"), AnyMethod::Hemicube(HemicubeOptions::default()));
        assert_eq!(at("single-plane"), AnyMethod::SinglePlane(SinglePlaneOptions::default()));
        assert_eq!(at("raytrace"), AnyMethod::Raytrace(RaytraceOptions::default()));
        assert_eq!(at("nusselt"), AnyMethod::Nusselt(NusseltOptions::default()));
        use crate::unobstructed::method::{AnalyticOptions, AutoOptions, ContourOptions, Options};
        assert_eq!(at("auto"), AnyMethod::Auto(AutoOptions::default()));
        assert_eq!(at("analytic"), AnyMethod::Analytic(AnalyticOptions::default()));
        assert_eq!(at("contour"), AnyMethod::Contour(ContourOptions::default()));
        assert_eq!(at("contour").exact(), Options::default());
        use crate::obstructed::SubdivisionOptions;
        use crate::obstructed::{AdaptiveOptions, ClippingOptions, MonteCarloOptions, QuadratureOptions};
        assert_eq!(at("quadrature"), AnyMethod::Quadrature(QuadratureOptions::default()));
        assert_eq!(at("montecarlo"), AnyMethod::MonteCarlo(MonteCarloOptions::default()));
        assert_eq!(at("subdivision"), AnyMethod::Subdivision(SubdivisionOptions::default()));
        assert_eq!(at("adaptive"), AnyMethod::Adaptive(AdaptiveOptions::default()));
        assert_eq!(at("clipping"), AnyMethod::Clipping(ClippingOptions::default()));
        // the budget of every method is the table's
        for m in METHODS {
            assert_eq!(at(m.name).budget(), DEFAULT_BUDGET, "{}", m.name);
        }
        // a struct filled by hand is held to the table's range, and the message says which
        let e =
            SinglePlaneOptions { min_cell: 1e-5, ..std::default::Default::default() }.check().unwrap_err().to_string();
        assert!(e.contains("single-plane") && e.contains("min_cell") && e.contains("outside"), "{e}");
        let hi = spec_of("raytrace", "rays").hi as u32;
        assert!(RaytraceOptions { rays: hi, ..std::default::Default::default() }.check().is_ok());
        assert!(RaytraceOptions { rays: hi + 1, ..std::default::Default::default() }.check().is_err());
        let e = HemicubeOptions { resolution: 130 + 1, ..std::default::Default::default() }
            .check()
            .unwrap_err()
            .to_string();
        assert!(e.contains("even"), "{e}");
        // a row method's Gauss source points are held to its `source` range
        let hi = spec_of("hemicube", "source").hi as u32;
        let gauss = |k| HemicubeOptions { source: SourcePoints::Gauss(k), ..std::default::Default::default() };
        assert!(gauss(hi).check().is_ok());
        let e = gauss(hi + 1).check().unwrap_err().to_string();
        assert!(e.contains("hemicube") && e.contains("source") && e.contains("outside"), "{e}");
        assert!(gauss(0).check().unwrap_err().to_string().contains("k >= 1"));
        let e = configure("hemicube", &[("resolution".into(), Value::Int(131))]).unwrap_err().to_string();
        assert!(e.contains("hemicube") && e.contains("even"), "{e}");
        let q = QuadratureOptions { order: 33, ..std::default::Default::default() };
        assert!(q.check().unwrap_err().to_string().contains("order"));
        let e = AdaptiveOptions { max_depth: 17, ..std::default::Default::default() }.check().unwrap_err().to_string();
        assert!(e.contains("adaptive") && e.contains("max_depth"), "{e}");
    }

    #[test]
    fn tol_means_what_each_method_documents() {
        use crate::obstructed::{ClippingOptions, Estimator};
        let m = configure("auto", &[("tol".into(), Value::Float(1e-6))]).unwrap();
        assert_eq!(m.exact().tol, 1e-6);
        for name in ["auto", "analytic", "contour"] {
            let m = configure(name, &[("obstructed_tol".into(), Value::Float(1e-4))]).unwrap();
            let want = ClippingOptions { tol: 1e-4, ..std::default::Default::default() };
            assert_eq!(m.estimator(), Some(Estimator::Clipping(want)), "{name}");
        }
        let m = configure("adaptive", &[("tol".into(), Value::Float(1e-3))]).unwrap();
        assert!(matches!(m, AnyMethod::Adaptive(o) if o.tol == 1e-3));
        assert_eq!(m.exact().tol, 1e-10);
    }
}
