"""Scenes shipped with nusselt: the Cornell box, in millimetres, after the Cornell Program of
Computer Graphics' "Cornell Box Data" (https://www.graphics.cornell.edu/online/box/data.html).

>>> from nusselt.data import bundled, cornell_box
>>> box = cornell_box()                       # Scene: five walls, the light and the two blocks
>>> bundled("cornell_empty.vs3")              # the path of a file, for a reader or the command line

``cornell_box.obj``: the box with its two blocks (one OBJ object per wall and per block face).
``cornell_empty.obj`` and ``cornell_empty.vs3``: the same box without the blocks, as OBJ and as
View3D input (docs/formats/obj.md, docs/formats/view3d-input.md).
"""

from __future__ import annotations

from importlib import resources
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..scene import Scene

#: The scene files shipped in this package.
FILES: tuple[str, ...] = tuple(
    sorted(p.name for p in resources.files(__name__).iterdir() if p.name.endswith((".obj", ".vs3")))
)


def bundled(name: str) -> str:
    """The path of the bundled scene file ``name`` (one of :data:`FILES`)."""
    if name not in FILES:
        raise ValueError(f"no bundled scene file {name!r}; the bundled ones are {', '.join(FILES)}")
    return str(resources.files(__name__) / name)


def cornell_box() -> Scene:
    """The Cornell box with its two blocks (20 polygons, 16 named surfaces, millimetres)."""
    from ..scene import Scene

    return Scene.from_file(bundled("cornell_box.obj"))


def cornell_empty(format: str = "obj") -> Scene:
    """The Cornell box without the blocks, read from its ``"obj"`` or its ``"vs3"`` file."""
    from ..scene import Scene

    if format not in ("obj", "vs3"):
        raise ValueError(f"format must be 'obj' or 'vs3', got {format!r}")
    return Scene.from_file(bundled(f"cornell_empty.{format}"))


__all__ = ["FILES", "bundled", "cornell_box", "cornell_empty"]
