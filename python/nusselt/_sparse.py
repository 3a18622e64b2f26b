"""scipy.sparse on demand: importing it costs more than numpy itself, and reading a scene or
asking for a dense result never needs it."""

from __future__ import annotations

import sys
from typing import Any


def issparse(m: Any) -> bool:
    """``scipy.sparse.issparse`` without importing scipy: nothing is sparse before it loads."""
    mod = sys.modules.get("scipy.sparse")
    return mod is not None and bool(mod.issparse(m))
