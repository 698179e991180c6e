"""Tables as CSV files with a ``# units:`` line: ``results.csv``, ``simulation.csv``
and a batch's ``summary.csv``.

The layout (docs/conventions.md, *Results*): the line ``# units: u1,u2,…``
(one unit per column, in the order of the columns), the header of column names, one row per line.
"""

from __future__ import annotations

import csv
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TextIO

import numpy as np

__all__ = ["write_table", "write_columns"]


def write_table(
    out: TextIO,
    names: Sequence[str],
    units: Sequence[str],
    rows: Iterable[Sequence],
    *,
    header: bool = True,
    lineterminator: str = "\r\n",
) -> None:
    """Write to the open text stream ``out``: with ``header`` the ``# units:`` line and the
    column ``names``, then ``rows`` (sequences of cells, one per column) as CSV.

    The ``# units:`` line always ends with ``\\n``; the header and the rows end with
    ``lineterminator`` (the :mod:`csv` default ``\\r\\n`` unless told).  Without ``header``
    (rows appended to a table already written) ``names`` and ``units`` are not used.
    """
    if header:
        out.write("# units: " + ",".join(units) + "\n")
    w = csv.writer(out, lineterminator=lineterminator)
    if header:
        w.writerow(names)
    for row in rows:
        w.writerow(row)


def write_columns(
    path: str | Path,
    columns: Mapping[str, np.ndarray],
    units: Mapping[str, str],
    *,
    blank_nonfinite: bool = True,
) -> None:
    """Write the file ``path``: equally long numeric ``columns`` by name, with their
    ``units`` by name (:func:`write_table`).  Every value is written as ``repr(float)``,
    which reads back exactly; a value that is not finite as an empty cell
    (``blank_nonfinite``) or as ``nan``/``inf``.

    The text is what :func:`write_table` writes for rows of ``repr(float(v))`` cells,
    byte for byte, without its per-cell cost: each distinct value is formatted once,
    and the rows are joined directly (no cell needs quoting; the :mod:`csv` module's
    one exception, a row of a single empty cell written ``""``, is kept)."""
    names = list(columns)
    with open(path, "w", encoding="utf-8", newline="") as fh:
        write_table(fh, names, [units[n] for n in names], ())
        fh.writelines(_lines(columns, names, blank_nonfinite))


def _lines(columns: Mapping[str, np.ndarray], names: list[str], blank: bool) -> list[str]:
    """The rows of :func:`write_columns` as CSV lines ending with ``\\r\\n``."""
    data = np.ascontiguousarray(np.column_stack([columns[n] for n in names]), dtype=float)
    # distinct by bit pattern (0.0 and -0.0 are written apart), formatted once each
    distinct, where = np.unique(data.view(np.int64), return_inverse=True)
    text = np.array([repr(v) for v in distinct.view(np.float64).tolist()], dtype=object)
    cells = text[where.reshape(data.shape)]
    if blank:
        cells[~np.isfinite(data)] = ""
    lines = [",".join(row) + "\r\n" for row in cells.tolist()]
    if len(names) == 1:  # csv.writer writes a row of one empty cell as ""
        lines = [line if line != "\r\n" else '""\r\n' for line in lines]
    return lines
