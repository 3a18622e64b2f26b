"""The scenes shipped in nusselt.data: every file is found, loads, and is what its name says."""

import os

import numpy as np
import pytest

import nusselt
from nusselt.data import FILES, bundled, cornell_box, cornell_empty


def test_every_bundled_file_is_listed_and_loads():
    assert set(FILES) == {"cornell_box.obj", "cornell_empty.obj", "cornell_empty.vs3"}
    for name in FILES:
        path = bundled(name)
        assert os.path.isfile(path) and os.path.basename(path) == name
        assert len(nusselt.Scene.from_file(path)) > 0


def test_cornell_scenes_are_the_files():
    box = cornell_box()
    assert isinstance(box, nusselt.Scene)
    assert box.surface_names[:6] == ["floor", "ceiling", "back", "green", "red", "light"]
    assert len(box.surface_names) == 16  # the walls, the light and five faces of each block
    again = nusselt.Scene.from_file(bundled("cornell_box.obj"))
    np.testing.assert_array_equal(box.vertices, again.vertices)
    obj, vs3 = cornell_empty(), cornell_empty("vs3")
    assert sorted(obj.surface_names) == sorted(vs3.surface_names)
    # the two files hold the same box: the same total area, to the float rounding of the sums
    assert abs(obj.areas.sum() - vs3.areas.sum()) < 1e-9 * obj.areas.sum()


def test_unknown_names_are_refused_with_the_list():
    with pytest.raises(ValueError, match="cornell_box.obj, cornell_empty.obj, cornell_empty.vs3"):
        bundled("cornell.obj")
    with pytest.raises(ValueError, match="'obj' or 'vs3'"):
        cornell_empty("stl")


def test_cli_keeps_its_bundled():
    import nusselt.cli

    assert nusselt.cli.bundled("cornell_box.obj") == bundled("cornell_box.obj")
