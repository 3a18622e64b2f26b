"""The methods users can select, their options, defaults and valid ranges.

Everything here is read from the core's method registry (``crates/nusselt-core/src/registry.rs``,
through ``_core.methods()``): names, kinds, whether a method handles obstacles, and each
option's type, default, range and documentation are written once, there. This module gives
Python's view of that table (:data:`METHODS`), the friendlier checks with messages naming the
method and option (:func:`resolve`), and the text of ``nusselt methods``; the core checks the
values again against the same table.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

from . import _core

#: A method's name, for type checkers (``method: MethodName``): the registry's names, in its
#: order. A type must be written out, so tests/test_methods_registry.py checks it against
#: :data:`METHODS` (which is read from the core).
MethodName = Literal[
    "auto",
    "analytic",
    "contour",
    "quadrature",
    "montecarlo",
    "subdivision",
    "adaptive",
    "clipping",
    "hemicube",
    "single-plane",
    "raytrace",
    "nusselt",
]

#: Python type of each registry option type ("source" is a keyword or an integer k).
_TYPES: dict[str, type] = {"float": float, "int": int, "bool": bool, "source": object}


@dataclass(frozen=True)
class Option:
    """One option of a method: its type, default, inclusive range [lo, hi] (numbers, and the
    integer form of a ``source``), the keywords a ``source`` accepts, and its documentation."""

    kind: type
    default: object
    doc: str
    lo: float | None = None
    hi: float | None = None
    choices: tuple | None = None

    def check(self, method: str, name: str, value: Any) -> Any:
        """The value, converted to the option's type; TypeError/ValueError naming the method
        and option when it is of the wrong type or out of range."""
        if self.kind is object:  # source: a keyword or an integer in [lo, hi]
            if isinstance(value, str):
                if self.choices is not None and value not in self.choices:
                    raise ValueError(
                        f"method {method!r}: option {name}={value!r} must be one of {self.choices} "
                        f"or an integer in [{self.lo}, {self.hi}]"
                    )
                return value
            if isinstance(value, bool) or not isinstance(value, int):
                raise TypeError(f"method {method!r}: option {name} must be a keyword or an integer, got {value!r}")
            if not (self.lo is None or self.lo <= value) or not (self.hi is None or value <= self.hi):
                raise ValueError(f"method {method!r}: option {name}={value!r} is outside [{self.lo}, {self.hi}]")
            return int(value)
        if self.kind is bool:
            if not isinstance(value, bool):
                raise TypeError(f"method {method!r}: option {name} must be True or False, got {value!r}")
            return value
        if isinstance(value, bool):
            raise TypeError(f"method {method!r}: option {name} must be {self.kind.__name__}, got {value!r}")
        try:
            v = self.kind(value)
        except (TypeError, ValueError, OverflowError):
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
    options: dict[str, Option] = field(default_factory=dict)
    #: "pairs": computes A_i F_ij once per unordered pair; "rows": samples whole rows F_i.
    kind: str = "pairs"


def _from_registry() -> dict[str, Method]:
    methods: dict[str, Method] = {}
    for m in _core.methods():
        options = {
            o["name"]: Option(
                _TYPES[o["type"]],
                o["default"],
                o["doc"],
                o["lo"],
                o["hi"],
                tuple(o["keywords"]) if o["type"] == "source" else None,
            )
            for o in m["options"]
        }
        methods[m["name"]] = Method(m["name"], m["doc"], m["obstructed"], options, m["kind"])
    return methods


#: Every method by name, in the order ``nusselt methods`` lists them (from the core's registry).
METHODS: dict[str, Method] = _from_registry()


def resolve(method: str, options: dict) -> tuple[Method, dict]:
    """Validates a method name and its options; returns the method and the full option set."""
    if not isinstance(method, str) or method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of: {', '.join(METHODS)}")
    m = METHODS[method]
    unknown = set(options) - set(m.options)
    if unknown:
        allowed = ", ".join(m.options) or "none"
        raise TypeError(f"method {method!r} has no option {', '.join(sorted(unknown))} (options: {allowed})")
    full = {k: o.check(method, k, options.get(k, o.default)) for k, o in m.options.items()}
    return m, full


def describe() -> str:
    """The text of ``nusselt methods``: each method, its kind, and its options with default,
    range and documentation."""
    lines = []
    for m in METHODS.values():
        lines.append(f"{m.name:14s} [{m.kind}{', obstacles' if m.obstructed else ''}] {m.doc}")
        for k, o in m.options.items():
            if o.kind is bool:
                rng = ""
            elif o.kind is object:
                rng = f"  ({' | '.join(o.choices or ())} | integer in [{o.lo}, {o.hi}])"
            else:
                rng = f"  in [{o.lo}, {o.hi}]"
            lines.append(f"{'':16s}{k} = {o.default!r}{rng}  {o.doc}")
    return "\n".join(lines)
