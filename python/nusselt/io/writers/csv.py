"""The ``.csv`` output: a dense table of F (docs/formats/csv.md)."""

from __future__ import annotations

import csv
import os

from ._common import MAX_DENSE_ROWS, _atomic, _check_size, _dense_rows, _names, _square


def write_csv(path, matrix, names, *, precision: int | None = None, max_rows: int | None = MAX_DENSE_ROWS) -> None:
    """Dense table: a header row ``from \\ to, name1, name2, ...`` and one row per source
    starting with its name. Values are written exactly (shortest round-trip form) unless
    ``precision`` (significant digits) is given. Refuses more than ``max_rows`` rows."""
    path = os.fspath(path)
    n = _square(matrix)
    names = _names(names, n)
    _check_size(path, n, max_rows, "CSV table")
    fmt = repr if precision is None else (lambda x, p=int(precision): f"{x:.{p}g}")
    with _atomic(path, "w") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(["from \\ to"] + names)
        for name, row in zip(names, _dense_rows(matrix, n)):
            w.writerow([name] + list(map(fmt, row.tolist())))
