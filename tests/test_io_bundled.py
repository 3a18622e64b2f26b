"""The bundled Cornell boxes (python/nusselt/data) against the published geometry
(docs/algorithms.md §8.4: Cornell Program of Computer Graphics, "Cornell Box Data")."""

import importlib
import pathlib

import numpy as np
import pytest

import nusselt.io as nio

BUNDLED = pathlib.Path(nio.__file__).resolve().parents[1] / "data"
WALLS = ["floor", "ceiling", "back", "green", "red", "light"]
# Published areas (mm^2); the bundled ceiling has a hole for the light.
# The red wall's 306902.0 is the vector area of its non-planar quad;
# split into two planar triangles its true area is 306904.51 (8e-6 larger).
AREAS = {
    "floor": 308231.0,
    "ceiling": 310915.2 - 13650.0,
    "back": 303376.6,
    "green": 306889.0,
    "red": 306902.0,
    "light": 13650.0,
}
CENTRE = np.array([278.0, 274.4, 279.6])


def newell(p):
    return 0.5 * np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)


def per_surface(d):
    out = {}
    for s, p in zip(d.surface, d.polygons):
        out.setdefault(d.names[s], []).append(p)
    return out


def planar_deviation(p):
    n = newell(p)
    n /= np.linalg.norm(n)
    c = p.mean(axis=0)
    return np.max(np.abs((p - c) @ n)) / np.max(np.linalg.norm(p - c, axis=1))


@pytest.mark.parametrize("name", ["cornell_empty.obj", "cornell_box.obj"])
def test_cornell_walls(name):
    d = nio.read_scene(BUNDLED / name)
    polys = per_surface(d)
    assert d.names[:6] == WALLS
    for w in WALLS:
        a = sum(np.linalg.norm(newell(p)) for p in polys[w])
        assert a == (pytest.approx(AREAS[w], rel=1e-5) if w == "red" else pytest.approx(AREAS[w], abs=0.05)), (
            w
        )  # published to 0.1 mm^2
        for p in polys[w]:
            assert planar_deviation(p) < 1e-12, w  # the core's planarity check will accept them
            assert newell(p) @ (CENTRE - p.mean(axis=0)) > 0, w  # fronts face into the box
    assert len(polys["red"]) == 2 and all(len(p) == 3 for p in polys["red"])
    np.testing.assert_allclose(newell(polys["light"][0]) / AREAS["light"], [0, -1, 0])  # faces down


def test_cornell_blocks_are_closed_and_face_outward():
    d = nio.read_scene(BUNDLED / "cornell_box.obj")
    polys = per_surface(d)
    assert len(d.names) == 16 and len(d.faces) == 20
    for block in ("short", "tall"):
        faces = [polys[f"{block}_top"][0]] + [polys[f"{block}_side{k}"][0] for k in range(1, 5)]
        # A closed polyhedron's outward vector areas sum to zero; the missing bottom (on the
        # floor, outward normal -y) has the top's area, so the five faces sum to +A_top y.
        total = sum(newell(p) for p in faces)
        top = np.linalg.norm(newell(faces[0]))
        np.testing.assert_allclose(total, [0, top, 0], atol=1e-9 * top)
        centre = np.concatenate(faces).mean(axis=0)
        for p in faces:
            assert newell(p) @ (p.mean(axis=0) - centre) > 0
            assert planar_deviation(p) < 1e-12


def test_cornell_vs3_matches_the_obj():
    a = nio.read_scene(BUNDLED / "cornell_empty.vs3")
    b = nio.read_scene(BUNDLED / "cornell_empty.obj")
    assert a.names == b.names == WALLS
    assert a.surface.tolist() == b.surface.tolist()
    for pa, pb in zip(a.polygons, b.polygons):
        np.testing.assert_array_equal(pa, pb)
    np.testing.assert_array_equal(a.emissivity, np.full(6, 0.9))
    assert a.meta["encl"] == 0 and a.meta["surfaces"][8]["cmb"] == 8 and a.meta["surfaces"][4]["cmb"] == 2


def test_lazy_io_names_resolve_and_cover_the_public_ones():
    # nusselt.io names each reader and writer three times (typing imports, the lazy table,
    # __all__); a name missing from the table would only fail when a user first asks for it
    import nusselt.io as io

    for name, module in io._LAZY.items():
        assert getattr(importlib.import_module(f"nusselt.io.{module}"), name) is getattr(io, name)
    assert set(io.__all__) <= {"SceneData", "read_scene", *io._LAZY}
