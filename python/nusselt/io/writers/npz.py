"""The ``.npz`` output, the complete result, and reading it back (docs/formats/npz.md)."""

from __future__ import annotations

import json
import os
from typing import IO, Any

import numpy as np

from ..._sparse import Csr, issparse
from ..atomic import atomic_path
from ..direct import CHUNK, MIN_BYTES, DirectWriter
from ..scenedata import check_readable, parse_error
from ._common import _areas, _csr, _names, _square, field, row_sums, stored_matrix

NPZ_FORMAT = "nusselt-form-factors"
NPZ_VERSION = 1


def write_npz(path, matrix, areas, names, *, compress: bool = False, **extra_arrays) -> None:
    """Store the form factors as a ``.npz`` (zip-deflated with ``compress=True``).

    Keys: ``format``, ``version``, ``shape``, ``indptr``, ``indices``, ``data`` (the CSR
    parts of F), ``areas``, ``names`` and every extra array under its own name. A sparse
    extra (e.g. ``std_err``) is stored as ``<name>.indptr`` / ``.indices`` / ``.data`` /
    ``.shape``; a dict or string extra as JSON text. Read it back with :func:`load_npz`.
    Index arrays are stored as int32 when they fit (else int64) and values as float32 or
    float64 as given, so the file is no larger than the matrix in memory.
    """
    path = os.fspath(path)
    n = _square(matrix)
    m = _csr(matrix)
    if not isinstance(m, Csr):
        m.sum_duplicates()
        m.sort_indices()
    arrays = {
        "format": np.array(NPZ_FORMAT),
        "version": np.array(NPZ_VERSION),
        "shape": np.array(m.shape, dtype=np.int64),
        "indptr": _index_array(m.indptr, m.nnz),
        "indices": _index_array(m.indices, n),
        "data": _value_array(m.data),
        "areas": _areas(areas, n),
        "names": np.array(_names(names, n), dtype=str),
    }
    for key, val in extra_arrays.items():
        if key in arrays or "." in key:
            raise ValueError(f"extra array name {key!r} is reserved or contains '.'")
        if val is None:
            continue
        if issparse(val):
            import scipy.sparse as sp

            e = sp.csr_array(val)
            arrays[f"{key}.shape"] = np.array(e.shape, dtype=np.int64)
            arrays[f"{key}.indptr"] = _index_array(e.indptr, e.nnz)
            arrays[f"{key}.indices"] = _index_array(e.indices, max(e.shape))
            arrays[f"{key}.data"] = _value_array(e.data)
        elif isinstance(val, dict):
            arrays[f"{key}.json"] = np.array(json.dumps(val, default=str))
        else:
            a = np.asarray(val)
            if a.dtype == object:
                a = np.array([str(x) for x in a.ravel()], dtype=str).reshape(a.shape)
            arrays[key] = a
    _save_npz(path, arrays, compress)


def _save_npz(path: str, arrays: dict[str, np.ndarray], compress: bool) -> None:
    """The file ``np.savez`` (``np.savez_compressed``) writes, a zip of ``.npy`` files, written
    atomically; each array's bytes go to the zip as they are (``np.savez`` copies every 16 MiB
    of them first), and a big file past the page cache (:mod:`nusselt.io.direct`)."""
    import zipfile

    big = sum(a.nbytes for a in arrays.values()) >= MIN_BYTES
    with atomic_path(path) as tmp:
        fh: IO[bytes] = DirectWriter(tmp) if big else open(tmp, "wb")  # type: ignore[assignment]
        mode = zipfile.ZIP_DEFLATED if compress else zipfile.ZIP_STORED
        with fh, zipfile.ZipFile(fh, "w", compression=mode, allowZip64=True) as zf:
            for key, a in arrays.items():
                with zf.open(key + ".npy", "w", force_zip64=True) as out:
                    _write_npy(out, a)


def _write_npy(out, a: np.ndarray) -> None:
    """One array as ``np.save`` writes it: the header, then its bytes in C order."""
    from numpy.lib import format as npy

    a = np.asarray(a)
    if not a.flags.c_contiguous:  # (np.ascontiguousarray would make a 0-d array 1-d)
        a = a.copy(order="C")
    header = npy.header_data_from_array_1_0(a)
    try:
        npy.write_array_header_1_0(out, header)
    except ValueError:  # a header longer than format 1.0 holds
        npy.write_array_header_2_0(out, header)
    flat = a.reshape(-1).view(np.uint8)
    for s in range(0, flat.size, CHUNK):
        out.write(flat[s : s + CHUNK])


def _index_array(a: np.ndarray, largest: int) -> np.ndarray:
    """int32 when every index (at most ``largest``) fits, else int64; no copy if already so."""
    dtype = np.int32 if largest <= np.iinfo(np.int32).max else np.int64
    return np.asarray(a, dtype=dtype)


def _value_array(a: np.ndarray) -> np.ndarray:
    return a if a.dtype in (np.float32, np.float64) else np.asarray(a, dtype=np.float64)


def load_npz(path) -> dict:
    """Load a result written by :func:`write_npz` (``nusselt matrix ... -o out.npz``).

    >>> r = nusselt.io.load_npz("out.npz")
    >>> F = r["matrix"]            # scipy.sparse.csr_array, F[i, j], row = source
    >>> r["areas"], r["names"]     # ndarray, list of str

    Extra arrays come back under their names (sparse ones as csr_array, JSON ones as dicts).
    """
    import scipy.sparse as sp

    path = os.fspath(path)
    check_readable(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            files = {k: z[k] for k in z.files}
    except Exception as e:
        raise parse_error(path, None, f"not a readable .npz file ({type(e).__name__}: {e})") from None
    if "format" not in files or str(files["format"]) != NPZ_FORMAT:
        raise parse_error(path, None, "not a nusselt form-factor file (no 'format' marker)")
    try:
        shape = tuple(int(x) for x in files.pop("shape"))
        matrix = sp.csr_array((files.pop("data"), files.pop("indices"), files.pop("indptr")), shape=shape)
    except Exception as e:
        raise parse_error(path, None, f"damaged matrix ({type(e).__name__}: {e})") from None
    out = {"matrix": matrix, "areas": files.pop("areas"), "names": [str(s) for s in files.pop("names")]}
    files.pop("format")
    out["version"] = int(files.pop("version"))
    groups: dict[str, dict] = {}
    for key, val in files.items():
        if "." in key:
            base, part = key.rsplit(".", 1)
            groups.setdefault(base, {})[part] = val
        else:
            out[key] = val
    for base, parts in groups.items():
        if "json" in parts:
            out[base] = json.loads(str(parts["json"]))
        else:
            out[base] = sp.csr_array(
                (parts["data"], parts["indices"], parts["indptr"]), shape=tuple(int(x) for x in parts["shape"])
            )
    return out


def write_result_npz(path: str, result, scene, *, compress: bool) -> None:
    """A result as :func:`write_npz` stores it, with its row sums, faces, surfaces, errors,
    method, info and the scene's source file (see :func:`nusselt.io.write_result`)."""
    extra: dict[str, Any] = {}
    matrix = stored_matrix(result)
    known = getattr(result, "row_sums", None) if not isinstance(result, dict) else None
    extra["row_sums"] = np.asarray(known if known is not None else row_sums(matrix), dtype=np.float64)
    for key in ("faces", "surface", "lost", "std_err"):
        v = field(result, key)
        if v is not None:
            extra[key] = v
    sn = field(result, "surface_names")
    if sn is not None:
        extra["surface_names"] = np.array([str(s) for s in sn], dtype=str)
    if field(result, "method") is not None:
        extra["method"] = np.array(str(field(result, "method")))
    info = field(result, "info")
    if info:
        extra["info"] = dict(info)
    if scene is not None and getattr(scene, "source", None):
        extra["scene"] = np.array(str(scene.source))
    write_npz(path, matrix, field(result, "areas"), field(result, "names"), compress=compress, **extra)
