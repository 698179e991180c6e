"""base.tables.write_columns: the fast writer gives the text of the csv module's rows of
``repr(float(v))`` cells, byte for byte (results.csv, simulation.csv)."""

from __future__ import annotations

import csv
import io

import numpy as np
import pytest

from kinetostatics.base.tables import write_columns


def _reference(columns, units, blank):
    """The writer as it was: csv.writer over rows of repr(float(v)) (or "")."""
    names = list(columns)
    out = io.StringIO(newline="")
    out.write("# units: " + ",".join(units[n] for n in names) + "\n")
    w = csv.writer(out, lineterminator="\r\n")
    w.writerow(names)
    for row in np.column_stack([columns[n] for n in names]):
        w.writerow(["" if blank and not np.isfinite(v) else repr(float(v)) for v in row])
    return out.getvalue()


SPECIAL = [0.0, -0.0, np.nan, -np.nan, np.inf, -np.inf, 5e-324, -5e-324, 2.2250738585072014e-308,
           1.7976931348623157e308, 1e16, 1e15, 9999999999999998.0, 1e-4, 9.999999999999999e-05,
           0.1, 1 / 3, -2.5, 123456789.0, 1e22, 1e-7, 100.0]  # fmt: skip


@pytest.mark.parametrize("blank", [True, False])
@pytest.mark.parametrize("shape", [(0, 3), (1, 1), (len(SPECIAL), 1), (50, 4), (300, 9)])
def test_same_text_as_the_csv_module(tmp_path, blank, shape):
    rng = np.random.default_rng(sum(shape))
    n, m = shape
    data = rng.standard_normal((n, m)) * 10.0 ** rng.integers(-12, 12, (n, m))
    flat = data.reshape(-1)
    flat[: min(len(SPECIAL), flat.size)] = SPECIAL[: flat.size]
    data[n // 2 :, 0] = data[: n - n // 2, 0]  # repeated values
    columns = {f"c{k}": data[:, k] for k in range(m)}
    units = {name: "m" for name in columns}
    path = tmp_path / "t.csv"
    write_columns(path, columns, units, blank_nonfinite=blank)
    assert path.read_bytes() == _reference(columns, units, blank).encode()
    if blank and shape == (len(SPECIAL), 1):  # the csv module's row of one empty cell
        assert b'\r\n""\r\n' in path.read_bytes()


def test_integer_and_boolean_columns(tmp_path):
    columns = {"k": np.arange(5), "b": np.array([True, False, True, True, False])}
    units = {"k": "1", "b": "1"}
    path = tmp_path / "t.csv"
    write_columns(path, columns, units)
    assert path.read_bytes() == _reference(columns, units, True).encode()
