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


TOL = Option(float, 1e-10, "relative accuracy target per pair", 1e-15, 0.1)
NODES = Option(int, 8, "Gauss-Legendre nodes per edge panel", 1, 64)

METHODS: dict[str, Method] = {
    "auto": Method(
        "auto",
        "the fastest method that meets the accuracy target `tol` for each pair: Gauss area "
        "quadrature of an order chosen by separation for distant pairs, the exact closed form "
        "for close or touching ones",
        obstructed=False,
        options={"tol": TOL},
    ),
    "analytic": Method(
        "analytic",
        "closed form: Lambert's formula for a point, Narayanaswamy's edge-pair formula "
        "(with exact limits for touching edges) for two polygons",
        obstructed=False,
    ),
    "contour": Method(
        "contour",
        "double contour (Stokes) integral: exact inner line integral, Gauss-Legendre outer "
        "integral on graded panels, exact closed form where edges touch",
        obstructed=False,
        options={"nodes": NODES},
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
