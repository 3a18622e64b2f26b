"""Mesh topology of a polygon soup, in numpy: area vectors, degenerate faces, closed shells
and their orientation.

A *shell* is a set of faces connected through shared edges (vertices are welded by exact
coordinates first, since STL and many exporters repeat vertices per face). A shell is
*closed and consistent* when every edge is used exactly twice, in opposite directions; its
signed volume V = 1/3 sum_f a_f . p_f (a_f the face's area vector, p_f any of its points,
divergence theorem) is then positive when the faces' fronts point out of the enclosed volume
and negative when they point into it.

This module does not import the compiled core, so readers can use it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

ORIENTS = ("auto", "inward", "outward", "as-is")


def _flat(faces: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(flat vertex indices, index of each one's successor in its face, face offsets)."""
    sizes = np.array([len(f) for f in faces], dtype=np.int64)
    offsets = np.zeros(len(faces) + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    flat = np.concatenate(faces) if faces else np.zeros(0, np.int64)
    pos = np.arange(len(flat))
    start = np.repeat(offsets[:-1], sizes)
    nxt = start + (pos - start + 1) % np.repeat(sizes, sizes)
    return flat, nxt, offsets


def area_vectors(vertices: np.ndarray, faces: list[np.ndarray]) -> np.ndarray:
    """(F, 3) Newell area vectors, a_f = 1/2 sum_i p_i x p_{i+1} (|a_f| = area, along the
    front normal), computed relative to each face's first vertex for accuracy."""
    flat, nxt, offsets = _flat(faces)
    first = np.repeat(vertices[flat[offsets[:-1]]], np.diff(offsets), axis=0)
    p = vertices[flat] - first
    q = vertices[flat[nxt]] - first
    return 0.5 * np.add.reduceat(np.cross(p, q), offsets[:-1], axis=0) if len(faces) else np.zeros((0, 3))


def degenerate_faces(vertices: np.ndarray, faces: list[np.ndarray]) -> np.ndarray:
    """Faces with zero area (collinear or coincident vertices), by the core's own test:
    twice the area at most 1e-14 of the squared diameter of the face's bounding box."""
    flat, _, offsets = _flat(faces)
    p = vertices[flat]
    lo = np.minimum.reduceat(p, offsets[:-1], axis=0)
    hi = np.maximum.reduceat(p, offsets[:-1], axis=0)
    scale2 = ((hi - lo) ** 2).sum(axis=1)
    twice = 2.0 * np.linalg.norm(area_vectors(vertices, faces), axis=1)
    return ~(twice > 1e-14 * scale2)


@dataclass
class Shells:
    """Shells of a polygon soup: ``label[f]`` is face f's shell; per shell, ``closed``
    (closed and consistently oriented) and ``volume`` (signed, > 0: fronts point out)."""

    label: np.ndarray
    closed: np.ndarray
    volume: np.ndarray
    manifold: np.ndarray  # per shell: every edge used exactly twice (whatever the directions)

    @property
    def count(self) -> int:
        return len(self.closed)


def shells(vertices: np.ndarray, faces: list[np.ndarray]) -> Shells:
    nf = len(faces)
    weld = _weld(vertices)
    flat, nxt, offsets = _flat(faces)
    a, b = weld[flat], weld[flat[nxt]]
    face_of_edge = np.repeat(np.arange(nf), np.diff(offsets))
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    # one int64 key per undirected edge (1-D unique is much faster than unique on rows)
    keys, key_of_edge, count = np.unique(lo * (int(weld.max()) + 1) + hi, return_inverse=True, return_counts=True)
    key_of_edge = key_of_edge.ravel()
    nk = len(keys)
    # consistent: each edge twice, once each way (a < b once, a > b once)
    forward = np.bincount(key_of_edge, weights=(a < b).astype(float), minlength=nk)
    edge_ok = (count == 2) & (forward == 1)
    # faces and edges as one graph: a face is joined to its edges
    g = sp.coo_matrix((np.ones(len(flat)), (face_of_edge, nf + key_of_edge)), shape=(nf + nk, nf + nk))
    from scipy.sparse.csgraph import connected_components  # on first use: it imports scipy.linalg

    _, lab = connected_components(g, directed=False)
    face_lab = lab[:nf]
    _, face_lab = np.unique(face_lab, return_inverse=True)
    ns = int(face_lab.max()) + 1 if nf else 0
    bad = np.bincount(face_lab[face_of_edge], weights=(~edge_ok[key_of_edge]).astype(float), minlength=ns)
    open_edges = np.bincount(face_lab[face_of_edge], weights=(count[key_of_edge] != 2).astype(float), minlength=ns)
    av = area_vectors(vertices, faces)
    p0 = vertices[flat[offsets[:-1]]] if nf else np.zeros((0, 3))
    # shift to the scene's centre so the volume sum does not cancel far from the origin
    centre = 0.5 * (vertices.min(axis=0) + vertices.max(axis=0)) if len(vertices) else np.zeros(3)
    vol = np.bincount(face_lab, weights=np.einsum("ij,ij->i", av, p0 - centre) / 3.0, minlength=ns)
    return Shells(face_lab, bad == 0, vol, open_edges == 0)


def _consistent_flips(vertices: np.ndarray, faces: list[np.ndarray], members: np.ndarray) -> np.ndarray | None:
    """Faces of a shell (``members``, every edge used twice) to reverse so that each edge is
    used once each way: a breadth-first walk over shared edges (a neighbour that runs a
    shared edge the same way must be reversed relative to its predecessor), keeping the
    orientation of the majority of faces. None if the shell cannot be oriented (a Moebius
    strip, a Klein bottle)."""
    sub = [faces[k] for k in members]
    nf = len(sub)
    weld = _weld(vertices)
    flat, nxt, offsets = _flat(sub)
    a, b = weld[flat], weld[flat[nxt]]
    face_of_edge = np.repeat(np.arange(nf), np.diff(offsets))
    key = np.minimum(a, b) * (int(weld.max()) + 1) + np.maximum(a, b)
    order = np.argsort(key, kind="stable")
    e1, e2 = order[0::2], order[1::2]
    if len(e1) != len(e2) or np.any(key[e1] != key[e2]):
        return None
    f1, f2 = face_of_edge[e1], face_of_edge[e2]
    fwd = a < b
    parity = (fwd[e1] == fwd[e2]).astype(np.int8)  # 1: the two must differ in flip
    g = sp.coo_matrix((parity.astype(float) + 1.0, (f1, f2)), shape=(nf, nf)).tocsr()
    g = (g + g.T).tocsr()
    flip = np.zeros(nf, dtype=bool)
    seen = np.zeros(nf, dtype=bool)
    for root in range(nf):
        if seen[root]:
            continue
        from scipy.sparse.csgraph import breadth_first_order

        bfs, pred = breadth_first_order(g, root, directed=False, return_predecessors=True)
        seen[bfs] = True
        for node in bfs[1:]:
            p = pred[node]
            flip[node] = flip[p] ^ (g[p, node] > 1.5)
    d = fwd ^ flip[face_of_edge]
    if np.any(d[e1] == d[e2]):
        return None
    if flip.sum() * 2 > nf:
        flip = ~flip  # keep the orientation most faces had
    return members[flip]


def _encloses_volume(
    vertices: np.ndarray, faces: list[np.ndarray], av: np.ndarray, members: np.ndarray, flips: np.ndarray
) -> bool:
    """Whether a shell made consistent by reversing ``flips`` encloses a volume: two coincident
    faces (a face duplicated, both fronts one way) use each edge twice and "close" into a
    shell of no volume; reversing one of them would hide the duplicate from the overlap check
    (the two then face opposite ways, as a two-sided wall does)."""
    sign = np.where(np.isin(members, flips), -1.0, 1.0)
    p0 = np.array([vertices[faces[k][0]] for k in members])
    p0 = p0 - p0.mean(axis=0)
    vol = abs(float(np.sum(sign * np.einsum("ij,ij->i", av[members], p0)))) / 3.0
    area = float(np.linalg.norm(av[members], axis=1).sum())
    return vol > 1e-12 * area**1.5


def _weld(vertices: np.ndarray) -> np.ndarray:
    """Index of each vertex among the distinct coordinates (exactly equal ones share one)."""
    order = np.lexsort((vertices[:, 2], vertices[:, 1], vertices[:, 0]))
    sv = vertices[order]
    new = np.ones(len(sv), dtype=bool)
    new[1:] = (sv[1:] != sv[:-1]).any(axis=1)
    out = np.empty(len(sv), dtype=np.int64)
    out[order] = np.cumsum(new) - 1
    return out


def _winding(points: np.ndarray, vertices: np.ndarray, faces: list[np.ndarray]) -> np.ndarray:
    """Winding number of a closed surface about each point: the sum of the signed solid
    angles of its faces (fan triangles; Van Oosterom and Strackee's formula) over 4 pi;
    +-1 inside, 0 outside."""
    tris = [np.stack([np.full(len(f) - 2, f[0]), f[1:-1], f[2:]], axis=1) for f in faces]
    t = np.concatenate(tris)
    out = np.zeros(len(points))
    for k, x in enumerate(points):
        r = vertices[t] - x  # (T, 3, 3)
        la, lb, lc = (np.linalg.norm(r[:, i], axis=1) for i in range(3))
        num = np.einsum("ij,ij->i", r[:, 0], np.cross(r[:, 1], r[:, 2]))
        den = (
            la * lb * lc
            + np.einsum("ij,ij->i", r[:, 0], r[:, 1]) * lc
            + np.einsum("ij,ij->i", r[:, 0], r[:, 2]) * lb
            + np.einsum("ij,ij->i", r[:, 1], r[:, 2]) * la
        )
        out[k] = 2.0 * np.arctan2(num, den).sum() / (4.0 * np.pi)
    return out


def _encloses_all(s: int, sh: Shells, vertices: np.ndarray, faces: list[np.ndarray], bounds: np.ndarray) -> bool:
    """Whether closed shell ``s`` holds every other face of the scene inside it: bounding
    box first, then the winding number about the centre of up to 64 other shells."""
    mine = np.flatnonzero(sh.label == s)
    vm = np.unique(np.concatenate([faces[k] for k in mine]))
    lo, hi = vertices[vm].min(axis=0), vertices[vm].max(axis=0)
    tol = 1e-9 * float(np.linalg.norm(hi - lo))
    if (bounds[0] < lo - tol).any() or (bounds[1] > hi + tol).any():
        return False
    others = [o for o in range(sh.count) if o != s]
    if not others:
        return True
    pick = np.unique(np.linspace(0, len(others) - 1, min(64, len(others))).astype(int))
    centres = []
    for o in (others[i] for i in pick):
        idx = np.concatenate([faces[k] for k in np.flatnonzero(sh.label == o)])
        centres.append(vertices[idx].mean(axis=0))
    w = _winding(np.array(centres), vertices, [faces[k] for k in mine])
    return bool(np.all(np.abs(w) > 0.5))


def orient_faces(vertices: np.ndarray, faces: list[np.ndarray], orient: str = "auto"):
    """Faces oriented as asked, and a report.

    ``orient``:

    * ``"as-is"``: unchanged.
    * ``"inward"`` / ``"outward"``: every closed, consistently oriented shell is turned so
      that its fronts face into / out of the volume it encloses (rooms are seen from inside,
      solids from outside); other faces are left as they are (the report counts them).
    * ``"auto"``: a closed shell whose fronts face outward while it holds every other face
      of the scene inside it (or is alone) is a room exported as a solid (Blender, trimesh,
      pyvista and EnergyPlus list a zone's walls counter-clockwise from outside): its
      fronts would see nothing, so it is turned inward. Everything else is left as it is,
      so closed solids inside a room or in an urban scene stay seen from outside.

    Except for ``"as-is"``, a shell whose edges are each used twice but not once each way
    (some faces of a closed mesh reversed, as broken exports have) is first made consistent,
    keeping the orientation of most of its faces (``report["consistent"]``); with
    ``"as-is"``, ``report["inconsistent"]`` lists the faces that would be reversed.

    Returns ``(faces, report)``; ``report`` holds ``flipped`` (indices of the reversed
    faces), ``open`` (faces in shells that are not closed and consistent), ``shells``
    and, for ``"as-is"``, ``outward_enclosure`` (faces of a shell ``"auto"`` would turn).
    """
    if orient not in ORIENTS:
        raise ValueError(f"orient must be one of {', '.join(map(repr, ORIENTS))}, got {orient!r}")
    faces = list(faces)
    report: dict = {"orient": orient, "flipped": np.zeros(0, np.int64), "open": np.zeros(0, np.int64)}
    if not faces:
        return faces, report
    sh = shells(vertices, faces)
    made_consistent = np.zeros(0, np.int64)
    fixed = []
    av = area_vectors(vertices, faces)
    for sidx in np.flatnonzero(sh.manifold & ~sh.closed):
        members = np.flatnonzero(sh.label == sidx)
        flips = _consistent_flips(vertices, faces, members)
        if flips is not None and _encloses_volume(vertices, faces, av, members, flips):
            fixed.append(flips)
    if orient == "as-is":
        report["inconsistent"] = np.concatenate(fixed) if fixed else np.zeros(0, np.int64)
    else:
        if fixed:
            made_consistent = np.concatenate(fixed)
            for k in made_consistent:
                faces[k] = faces[k][::-1].copy()
            sh = shells(vertices, faces)
    report["consistent"] = made_consistent
    report["shells"] = sh.count
    report["open"] = np.flatnonzero(~sh.closed[sh.label])
    flip_shell = np.zeros(sh.count, dtype=bool)
    if orient in ("inward", "outward"):
        want = -1.0 if orient == "inward" else 1.0
        flip_shell = sh.closed & (sh.volume * want < 0)
    else:
        cand = np.flatnonzero(sh.closed & (sh.volume > 0))
        used = np.unique(np.concatenate(faces))
        bounds = np.stack([vertices[used].min(axis=0), vertices[used].max(axis=0)])  # of the scene's faces
        enclosing = [s for s in cand if _encloses_all(int(s), sh, vertices, faces, bounds)]
        if orient == "auto":
            flip_shell[enclosing] = True
        else:
            report["outward_enclosure"] = np.flatnonzero(np.isin(sh.label, enclosing))
    turned = np.flatnonzero(flip_shell[sh.label])
    for k in turned:
        faces[k] = faces[k][::-1].copy()
    # a face reversed twice (made consistent, then its shell turned) is back as given
    report["flipped"] = np.setxor1d(turned, made_consistent)
    return faces, report
