"""The plain container every scene reader returns (``Scene`` is built from it)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass, field

import numpy as np


class NusseltWarning(UserWarning):
    """Base of the warnings nusselt gives about a scene, a file or a result."""


class SkippedCellsWarning(NusseltWarning):
    """A mesh file held cells that are not surfaces (lines, points, volumes, unknown types);
    they were skipped and counted."""


def parse_error(source: str, where: str | None, problem: str) -> ValueError:
    """A one-line ``ValueError``: ``"<file>, <where>: <problem>"``.

    Every reader raises through this so that messages look alike, e.g.
    ``scene.vs3, line 12: surface 4 refers to vertex 9, but only 8 vertices are defined``."""
    problem = " ".join(str(problem).split())  # one line, whatever the cause said
    head = f"{source}, {where}" if where else str(source)
    return ValueError(f"{head}: {problem}")


def check_readable(path: str) -> None:
    """Raise ``OSError`` (missing, a directory, unreadable) or ``ValueError`` (empty file)
    with a one-line message naming the file."""
    if not os.path.exists(path):
        raise FileNotFoundError(f"{path}: no such file")
    if os.path.isdir(path):
        raise IsADirectoryError(f"{path}: is a directory, not a scene file")
    if not os.access(path, os.R_OK):
        raise PermissionError(f"{path}: permission denied")
    if os.path.getsize(path) == 0:
        raise parse_error(path, None, "the file is empty")


#: The longest line a text reader accepts (16 MiB: a face of over a million vertices). A longer
#: one is damage or not a scene file, refused before it is held in memory.
MAX_LINE_BYTES = 1 << 24


def text_lines(path: str, kind: str) -> Iterator[tuple[int, str]]:
    """(line number, text) of a text file, read line by line (the file is never held whole)
    and decoded as UTF-8 (bad bytes replaced, a leading byte-order mark dropped); a NUL byte
    (a binary file) or a line longer than :data:`MAX_LINE_BYTES` is refused with a ValueError
    naming the file and line. Every hand-written text reader (OBJ, View3D, IDF, CSV) reads
    through this."""
    with open(path, "rb") as fh:
        no = 0
        while raw := fh.readline(MAX_LINE_BYTES + 1):
            if len(raw) > MAX_LINE_BYTES and not raw.endswith(b"\n"):
                raise parse_error(
                    path, f"line {no + 1}", f"longer than {MAX_LINE_BYTES >> 20} MiB: damaged, or not a {kind} file"
                )
            if b"\0" in raw:
                raise parse_error(path, f"line {no + 1}", f"this is a binary file, not a {kind} file (a NUL byte)")
            if no == 0 and raw.startswith(b"\xef\xbb\xbf"):
                raw = raw[3:]
            for line in raw.decode("utf-8", errors="replace").splitlines() or [""]:
                no += 1  # splitlines: CR-only line ends count too, as for str.splitlines
                yield no, line


def csv_rows(path: str, kind: str) -> Iterator[tuple[int, list[str]]]:
    """(line number, fields) of each record of a CSV file, read through :func:`text_lines`
    (so with its line cap); a malformed record is a ValueError naming the file and line."""
    import csv

    lines = text_lines(path, kind)
    reader = csv.reader(text + "\n" for _, text in lines)
    while True:
        try:
            row = next(reader)
        except StopIteration:
            return
        except csv.Error as e:
            raise parse_error(path, f"line {reader.line_num}", f"bad CSV: {e}") from None
        yield reader.line_num, row


#: The largest JSON file a reader accepts (256 MiB). JSON is parsed whole, into Python objects
#: several times its size, so a larger file is refused before it is read.
MAX_JSON_BYTES = 1 << 28


def read_json(path: str, kind: str, advice: str = ""):
    """The parsed JSON document of a file no larger than :data:`MAX_JSON_BYTES`; a larger one,
    or invalid JSON, is refused with a ValueError naming the file (and the line)."""
    size = os.path.getsize(path)
    if size > MAX_JSON_BYTES:
        raise parse_error(
            path,
            None,
            f"{size / (1 << 20):.0f} MiB is larger than the {MAX_JSON_BYTES >> 20} MiB a {kind} file may have "
            f"(JSON is read whole){'; ' + advice if advice else ''}",
        )
    import json

    with open(path, "rb") as fh:
        text = fh.read().decode("utf-8-sig", errors="replace")
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise parse_error(path, f"line {e.lineno}", f"not valid JSON: {e.msg}") from None


def starts_with(path: str, char: bytes) -> bool:
    """Whether the first character of a file after white space (and a byte-order mark) is
    ``char``, read a block at a time so that leading blank space is never held whole."""
    with open(path, "rb") as fh:
        head = True
        while block := fh.read(1 << 16):
            if head and block.startswith(b"\xef\xbb\xbf"):
                block = block[3:]
            head = False
            block = block.lstrip()
            if block:
                return block[:1] == char
    return False


def first_bad_face(faces: list[np.ndarray], nv: int) -> int | None:
    """The first of ``faces`` (1-D integer arrays) with fewer than 3 vertices or a vertex
    index outside ``0 .. nv - 1``, or None: all faces checked at once."""
    sizes = np.fromiter(map(len, faces), dtype=np.int64, count=len(faces))
    bad = sizes < 3
    flat = np.concatenate(faces) if len(faces) else np.zeros(0, dtype=np.int64)
    outside = (flat < 0) | (flat >= nv)
    if outside.any():
        bad[np.repeat(np.arange(len(faces)), sizes)[outside]] = True
    return int(np.argmax(bad)) if bad.any() else None


@dataclass(kw_only=True)
class SceneData:
    """Polygons with named surfaces, as read from a file.

    Attributes
    ----------
    vertices : (V, 3) float64
    faces : list of int64 arrays
        Vertex indices of each polygon (n >= 3), counter-clockwise seen from the front.
    surface : (F,) int64
        Index into ``names`` of each polygon's named surface.
    names : list of str
        Surface names, unique.
    obstruction : (F,) bool
        Polygons that block radiation but get no row or column (default: none).
    emissivity : (len(names),) float64 or None
        Per named surface (NaN where the file gives none, e.g. obstruction-only surfaces);
        None (the default) when the format has none.
    origin : list of str
        Where each polygon came from, for error messages ("line 17", "cell 42").
    source : str
        The file path.
    meta : dict
        Format-specific extras (View3D: title, controls such as ``encl`` and ``emit``,
        the per-surface records; meshes: where the names came from ...).
    """

    vertices: np.ndarray
    faces: list
    surface: np.ndarray
    names: list
    origin: list
    source: str
    obstruction: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    emissivity: np.ndarray | None = None
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        # Structural consistency only; geometry (planarity, simplicity) is the core's job.
        src = self.source
        self.vertices = np.asarray(self.vertices, dtype=np.float64).reshape(-1, 3)
        self.faces = [np.asarray(f, dtype=np.int64).ravel() for f in self.faces]
        nf, nv = len(self.faces), len(self.vertices)
        if nf == 0:
            raise parse_error(src, None, "the file defines no polygons")
        self.surface = np.asarray(self.surface, dtype=np.int64).ravel()
        self.obstruction = np.asarray(self.obstruction, dtype=bool).ravel()
        if not self.obstruction.size:  # not given (the default): nothing is obstruction-only
            self.obstruction = np.zeros(nf, dtype=bool)
        self.names = [str(n) for n in self.names]
        self.origin = [str(o) for o in self.origin]
        if self.surface.shape != (nf,) or self.obstruction.shape != (nf,) or len(self.origin) != nf:
            raise ValueError(f"{src}: internal reader error: per-polygon arrays do not match {nf} polygons")
        if len(set(self.names)) != len(self.names):
            raise ValueError(f"{src}: internal reader error: surface names are not unique")
        if nf and (self.surface.min() < 0 or self.surface.max() >= len(self.names)):
            raise ValueError(f"{src}: internal reader error: surface index out of range")
        bad = np.flatnonzero(~np.isfinite(self.vertices).all(axis=1))
        if bad.size:
            raise parse_error(src, f"vertex {bad[0] + 1}", "NaN or infinite coordinate")
        k = first_bad_face(self.faces, nv)
        if k is not None:
            f = self.faces[k]
            if f.size < 3:
                raise parse_error(src, self.origin[k], f"a polygon needs at least 3 vertices, this one has {f.size}")
            raise parse_error(
                src,
                self.origin[k],
                f"polygon refers to vertex {int(f.max()) + 1}, but only {nv} vertices are defined",
            )
        if self.emissivity is not None:
            self.emissivity = np.asarray(self.emissivity, dtype=np.float64).ravel()
            if self.emissivity.shape != (len(self.names),):
                raise ValueError(f"{src}: internal reader error: emissivity has the wrong length")

    @property
    def polygons(self) -> list[np.ndarray]:
        """Each polygon as an (n, 3) array of coordinates."""
        return [self.vertices[f] for f in self.faces]

    def __repr__(self) -> str:
        return (
            f"SceneData({self.source!r}: {len(self.faces)} polygons, {len(self.names)} surfaces, "
            f"{int(self.obstruction.sum())} obstruction-only)"
        )
