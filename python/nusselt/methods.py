"""The methods users can select, their options, defaults and valid ranges.

This table is the single source of the option names the public API accepts; the Rust core
checks the values again (it is the authority on ranges), this layer gives the friendlier
message and the documentation.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Option:
    kind: type
    default: object
    doc: str
    lo: float | None = None
    hi: float | None = None
    choices: tuple | None = None

    def check(self, method: str, name: str, value):
        if self.choices is not None:
            if value not in self.choices:
                raise ValueError(f"method {method!r}: option {name}={value!r} must be one of {self.choices}")
            return value
        if self.kind is object:  # source: a keyword or a non-negative integer
            if isinstance(value, str) or (isinstance(value, int) and not isinstance(value, bool) and 0 <= value <= 16):
                return value
            raise ValueError(f"method {method!r}: option {name}={value!r} must be {self.doc}")
        if self.kind is bool:
            if not isinstance(value, bool):
                raise TypeError(f"method {method!r}: option {name} must be True or False, got {value!r}")
            return value
        try:
            v = self.kind(value)
        except (TypeError, ValueError):
            raise TypeError(f"method {method!r}: option {name} must be {self.kind.__name__}, got {value!r}") from None
        if self.kind is int and v != value:
            raise TypeError(f"method {method!r}: option {name} must be an integer, got {value!r}")
        if self.kind is float and not (v == v and abs(v) != float("inf")):
            raise ValueError(f"method {method!r}: option {name} must be finite, got {value!r}")
        if (self.lo is not None and v < self.lo) or (self.hi is not None and v > self.hi):
            raise ValueError(f"method {method!r}: option {name}={value!r} is outside [{self.lo}, {self.hi}]")
        return v


@dataclass(frozen=True)
class Method:
    name: str
    doc: str
    obstructed: bool
    options: dict = field(default_factory=dict)
    #: "pairs": computes A_i F_ij once per unordered pair; "rows": samples whole rows F_i.
    kind: str = "pairs"


TOL = Option(float, 1e-10, "relative accuracy target per unobstructed pair", 1e-15, 0.1)
NODES = Option(int, 16, "Gauss-Legendre nodes per edge panel", 1, 64)
SEED = Option(int, 0, "seed of the scrambled low-discrepancy points (results are reproducible)", 0, 2**63)
SOURCE_AREA = Option(
    object, "auto", "source points on A_i: 'auto' (the source cut along the lines where the visible F has "
    "a kink, 7 points per piece), 'centre', or k for a k x k Gauss rule (always a normalised weighted sum)"
)
SOURCE_ROW = Option(
    object, "auto", "source points on each patch: 'auto' (by patch size), 'centre', or k for a k x k Gauss rule"
)
ROTATE = Option(bool, True, "random rotation about the normal per sample point (aliasing becomes noise)")

METHODS: dict[str, Method] = {
    "auto": Method(
        "auto",
        "the fastest method that meets the accuracy targets for each pair: for pairs with nothing in "
        "between, a moment rule (fourth order for parallelograms) or Gauss area quadrature of an order chosen by separation "
        "(distant pairs) or the exact closed form (close, touching, piercing pairs); for pairs a polygon may block, the exact "
        "visible region (`clipping`) to `obstructed_tol`",
        obstructed=True,
        options={
            "tol": TOL,
            "obstructed_tol": Option(
                float, 1e-6, "accuracy target for obstructed pairs, relative to the pair's unobstructed F "
                "(so also absolute on F; row sums within it in enclosures)", 1e-14, 0.1),
        },
    ),
    "analytic": Method(
        "analytic",
        "closed form: Lambert's formula for a point, Narayanaswamy's edge-pair formula (exact limits "
        "for touching edges) for two polygons; where the edge-pair terms cancel by more than 2e3 (slivers, "
        "pairs far apart) an area route with terms of one sign (Gauss on both areas, or Lambert integrated "
        "over the smaller polygon) to 1e-14; assumes nothing is in between",
        obstructed=False,
    ),
    "contour": Method(
        "contour",
        "double contour (Stokes) integral: exact inner line integral, Gauss-Legendre outer integral on "
        "graded panels, exact closed form where edges touch; sums that cancel by more than 2e3 take the same "
        "area route as analytic; assumes nothing is in between",
        obstructed=False,
        options={"nodes": NODES},
    ),
    "quadrature": Method(
        "quadrature",
        "Gauss rules on both areas (the double area integral) with point-pair visibility by ray casting; "
        "each polygon is first cut along the planes of blockers that pass through it (a partition or a fin "
        "standing on it), where visibility steps",
        obstructed=True,
        options={
            "order": Option(int, 24, "Gauss order per direction on each polygon (a piece cut off a fraction f of "
                            "it gets ceil(order sqrt f))", 1, 32),
            "panels": Option(int, 4, "point form: the receiver is split into panels^2 pieces per triangle, "
                             "each with the order rule (composite rule for the sharp visibility step)", 1, 64),
            "control_variate": Option(
                bool, True, "compute the unblocked integral exactly and sample only the blocked part"
            ),
        },
    ),
    "montecarlo": Method(
        "montecarlo",
        "area-to-area quasi-Monte Carlo with Owen-scrambled Sobol points, stratified over the pieces of both "
        "polygons cut along the planes of blockers through them; standard error from 8 independent scramblings",
        obstructed=True,
        options={
            "samples": Option(int, 16384, "point pairs per form factor", 8, 2**24),
            "seed": SEED,
            "control_variate": Option(
                bool, True, "compute the unblocked integral exactly and sample only the blocked part"
            ),
        },
    ),
    "subdivision": Method(
        "subdivision",
        "dA -> A_j by uniform subdivision of the receiver (exact Lambert per piece times the piece's "
        "visibility; the receiver is first cut along the planes of blockers through it), summed over source points",
        obstructed=True,
        options={"divisions": Option(int, 48, "each receiver triangle is split into divisions^2", 1, 256),
                 "source": SOURCE_AREA},
    ),
    "adaptive": Method(
        "adaptive",
        "dA -> A_j by adaptive subdivision of the receiver where visibility changes, summed over "
        "source points",
        obstructed=True,
        options={
            "tol": Option(float, 1e-5, "pieces contributing less than this to F are not refined", 1e-14, 0.1),
            "max_depth": Option(int, 8, "deepest refinement level", 1, 16),
            "source": SOURCE_AREA,
        },
    ),
    "clipping": Method(
        "clipping",
        "exact visible region per source point (shadows projected onto the receiver, subtracted by "
        "polygon clipping, Lambert on the rest), integrated adaptively over the source",
        obstructed=True,
        options={
            "tol": Option(float, 1e-7, "accuracy target on F, relative to the pair's unobstructed F (so also absolute)",
                          1e-14, 0.1),
            "max_depth": Option(int, 12, "deepest refinement of the source", 1, 16),
            "source": Option(object, "adaptive", "'adaptive' (to tol), or 'centre' / k for a fixed k x k Gauss "
                             "rule whose visible fraction of the point F scales the exact unobstructed F"),
        },
    ),
    "hemicube": Method(
        "hemicube",
        "hemicube with z-buffer and item buffer per face, exact delta form factors per cell",
        obstructed=True,
        kind="rows",
        options={
            "resolution": Option(int, 128, "cells along the top face (even)", 4, 4096),
            "source": SOURCE_ROW,
            "random_rotation": ROTATE,
            "seed": SEED,
        },
    ),
    "single-plane": Method(
        "single-plane",
        "Sillion's single plane above the patch with Warnock area subdivision; the horizon band it "
        "misses is reported per row (`lost`)",
        obstructed=True,
        kind="rows",
        options={
            "half_width": Option(float, 14.0, "half-width of the plane at height 1", 0.5, 1000.0),
            "min_cell": Option(float, 1 / 128, "smallest Warnock window (relative to height 1)", 1e-5, 1.0),
            "source": SOURCE_ROW,
            "random_rotation": ROTATE,
            "seed": SEED,
        },
    ),
    "raytrace": Method(
        "raytrace",
        "cosine-distributed rays (reverse Nusselt analogy) from area-uniform points, first hit by the "
        "BVH; binomial standard error per entry",
        obstructed=True,
        kind="rows",
        options={"rays": Option(int, 4096, "rays per patch", 1, 2**26), "seed": SEED},
    ),
    "nusselt": Method(
        "nusselt",
        "Nusselt analog: equal-area cells of the unit disk lifted to the hemisphere, each resolved "
        "to the visible patch; F = covered disk area / pi",
        obstructed=True,
        kind="rows",
        options={
            "cells": Option(int, 4096, "disk cells (rounded to a square number)", 1, 2**24),
            "source": SOURCE_ROW,
            "jitter": Option(bool, True, "a random point per cell instead of its centre"),
            "random_rotation": ROTATE,
            "seed": SEED,
        },
    ),
}


def resolve(method: str, options: dict, *, obstructed: bool = False) -> tuple[Method, dict]:
    """Validates a method name and its options; returns the method and the full option set."""
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of: {', '.join(METHODS)}")
    m = METHODS[method]
    unknown = set(options) - set(m.options)
    if unknown:
        allowed = ", ".join(m.options) or "none"
        raise TypeError(f"method {method!r} has no option {', '.join(sorted(unknown))} (options: {allowed})")
    if obstructed and not m.obstructed:
        raise ValueError(
            f"method {method!r} does not handle obstacles; use a method with visibility "
            f"({', '.join(k for k, v in METHODS.items() if v.obstructed) or 'none available yet'})"
        )
    full = {k: o.check(method, k, options.get(k, o.default)) for k, o in m.options.items()}
    return m, full
