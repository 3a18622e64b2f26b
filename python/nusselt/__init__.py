"""nusselt: fast and exact form factors (view factors) between planar polygons.

>>> import nusselt
>>> nusselt.view_factor(square, other_square)            # exact, unobstructed
>>> scene = nusselt.Scene.from_file("room.obj")
>>> result = nusselt.form_factors(scene)                  # F[i, j], row = source
"""

import os as _os
import sys as _sys
from typing import TYPE_CHECKING, Any


def _is_the_command() -> bool:
    return _os.path.splitext(_os.path.basename(_sys.argv[0]))[0] == "nusselt"


# The `nusselt` command: numpy's OpenBLAS pool busy-waits about 0.1 s of CPU per idle thread
# after it loads (2^28 cycles by default), more than the rest of a short run's start-up.
# Idle threads sleeping at once (2^4 cycles) leaves dense solves as fast (docs/scale.md).
# The user's own setting wins, and a program importing nusselt keeps its environment.
if _is_the_command() and "numpy" not in _sys.modules:
    _os.environ.setdefault("OPENBLAS_THREAD_TIMEOUT", "4")

try:
    from . import io
    from ._core import __version__
    from .api import form_factors, point_view_factor, view_factor
    from .checks import ToleranceWarning, ZeroRowWarning
    from .io import read_scene
    from .methods import METHODS, MethodName
    from .result import FormFactors
    from .scene import NusseltWarning, OrientationWarning, RepairWarning, Scene
except KeyboardInterrupt:
    # Ctrl-C while the `nusselt` command starts (numpy, scipy and the core load before its
    # main() runs): a quiet exit with the code for SIGINT, as once the command runs. A
    # program importing nusselt gets its KeyboardInterrupt as usual.
    if _is_the_command():
        print("nusselt: interrupted", file=_sys.stderr)
        raise SystemExit(130) from None
    raise

if TYPE_CHECKING:
    from . import exchange, radiosity, sensors, sky
    from .io import load_npz
    from .sensors import point_view_factors

# Imported on first use: they pull in scipy.sparse.linalg and scipy.linalg, most of the
# import time, which reading a scene and computing its matrix never needs.
_LAZY_MODULES = ("exchange", "radiosity", "sensors", "sky")


def __getattr__(name: str) -> Any:
    import importlib

    if name in _LAZY_MODULES:
        return importlib.import_module(f".{name}", __name__)
    if name == "point_view_factors":
        return importlib.import_module(".sensors", __name__).point_view_factors
    if name == "load_npz":  # the writers load when first used (nusselt.io)
        return io.load_npz
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "Scene",
    "FormFactors",
    "METHODS",
    "MethodName",
    "form_factors",
    "view_factor",
    "point_view_factor",
    "point_view_factors",
    "sensors",
    "sky",
    "exchange",
    "radiosity",
    "load_npz",
    "read_scene",
    "io",
    "__version__",
    "NusseltWarning",
    "OrientationWarning",
    "RepairWarning",
    "ToleranceWarning",
    "ZeroRowWarning",
]
