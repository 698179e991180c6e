"""How the golden files are compared: every number on the scale of its unit.

One rule, used by ``tests/architecture/test_golden.py`` (which fails on a difference) and by
``audit.py`` (which prints the worst ratio), so that a golden file means the same on
every CPU — NumPy's SIMD loops (AVX-512 or not) and the order of a sum move the last
bits of a result, and a comparison has to be blind to exactly that and nothing more.

- **CSV** (``results.csv``, ``simulation.csv``): the first line names each column's
  unit.  A unit's scale is the largest finite |value| of all the golden columns of that
  unit (a fixed pivot's speed of 1e-18 m/s is round-off of the links' metres per
  second, not of its own column of zeros).  An empty cell is a number, NaN: a cell
  empty on one side only is a difference.
- **summary.json**: a number's unit is the one the file gives it — the column's unit
  (``column_units``) under ``extremes.<column>``, the ``unit`` key of the record it
  sits in (``drivers``, ``reaction_peaks``) — and its scale is that unit's scale in
  ``results.csv``; a number the file gives no unit is compared with the largest
  |number| beside it in its record.  Where a quantity peaks (``at_max``, ``at_min``)
  may move to any row where the golden column is as large within round-off of its
  unit: a column of round-off, or a constant one, peaks anywhere.  A self-check
  (``checks.<name>``) whose golden value is round-off (below 1e-3 of its tolerance)
  must stay so; its value and where it peaks are not compared.
- **geometry.json** (the drawing data): every coordinate against the largest
  |number| of the drawing.
- **check.txt** (a text): its words must be equal, line by line; each number in a line
  is compared with the largest |number| of that golden line, as a number without a unit
  in summary.json is.  The self-checks' line prints round-off (``constraints 2e-16 ·
  sketch 5.7e-14 mm · cond ≤ 15``): on a CPU that fuses a multiply and an add (FMA) the
  constraints' residual printed 1e-16 where the golden file has 2e-16.

Everything else (names, counts, flags) must be equal.
"""

from __future__ import annotations

import csv
import io
import json
import math
import re

CHECK_ROUND_OFF = 1e-3  # a self-check's value below this share of its tolerance is round-off


def _cell(text: str) -> float | str:
    if text == "":
        return math.nan
    try:
        return float(text)
    except ValueError:
        return text


def _table(text: str) -> tuple[list[str], list[str], list[list[float | str]]]:
    rows = list(csv.reader(io.StringIO(text)))
    units = [u.replace("# units: ", "") for u in rows[0]]
    return units, rows[1], [[_cell(c) for c in r] for r in rows[2:]]


def _columns(csv_text: str) -> dict[str, list[float | str]]:
    _, names, body = _table(csv_text)
    return {n: [r[j] for r in body] for j, n in enumerate(names)}


def unit_scales(csv_text: str) -> dict[str, float]:
    """The largest finite |value| of each unit's columns."""
    units, _, body = _table(csv_text)
    scale: dict[str, float] = {}
    for row in body:
        for u, v in zip(units, row):
            if isinstance(v, float) and math.isfinite(v):
                scale[u] = max(scale.get(u, 0.0), abs(v))
    return scale


def _differs(a, b, tol: float) -> bool:
    if isinstance(a, float) and isinstance(b, float):
        if math.isnan(a) or math.isnan(b):
            return not (math.isnan(a) and math.isnan(b))
        return not (a == b or abs(a - b) <= tol)
    return a != b


def compare_csv(new: str, old: str, rel: float) -> list[tuple[float, str]]:
    """``(ratio, message)`` for every column that differs: the ratio is the worst
    |difference| over its unit's scale (inf for a changed kind or text)."""
    units, names, body_b = _table(old)
    u_a, names_a, body_a = _table(new)
    if (u_a, names_a) != (units, names) or len(body_a) != len(body_b):
        return [
            (math.inf, f"header or row count differs ({len(body_a)} rows, golden {len(body_b)})")
        ]
    scale = unit_scales(old)
    out = []
    for j, (name, unit) in enumerate(zip(names, units)):
        s = scale.get(unit, 0.0)
        worst, where = 0.0, None
        for k, (ra, rb) in enumerate(zip(body_a, body_b)):
            a, b = ra[j], rb[j]
            if not _differs(a, b, rel * s):
                continue
            numeric = (
                isinstance(a, float)
                and isinstance(b, float)
                and not (math.isnan(a) or math.isnan(b))
            )
            r = abs(a - b) / s if numeric and s > 0 else math.inf
            if r > worst or where is None:
                worst, where = r, f"{name} [{unit}] row {k}: {a!r} (golden {b!r})"
        if where is not None:
            out.append((worst, where))
    return out


def _numbers(x) -> list[float]:
    if isinstance(x, dict):
        return [v for y in x.values() for v in _numbers(y)]
    if isinstance(x, list):
        return [v for y in x for v in _numbers(y)]
    if isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x):
        return [abs(float(x))]
    return []


class _Walk:
    def __init__(self, rel: float, scales: dict[str, float], column_units: dict[str, str]):
        self.rel, self.scales, self.column_units = rel, scales, column_units
        self.out: list[tuple[float, str]] = []

    def differ(self, where: str, a, b, scale: float) -> None:
        numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (a, b))
        if numeric:
            a, b = float(a), float(b)
        if not _differs(a, b, self.rel * scale if numeric else 0.0):
            return
        ok = numeric and scale > 0 and math.isfinite(a) and math.isfinite(b)
        self.out.append((abs(a - b) / scale if ok else math.inf, f"{where}: {a!r} (golden {b!r})"))

    def walk(self, a, b, where: str, scale: float | None, beside: float = 0.0) -> None:
        """Compare ``a`` with golden ``b``.  ``scale`` is the scale of the unit the file
        gives (None where it gives none); ``beside``, the largest |number| beside ``b``."""
        if isinstance(b, dict):
            if not isinstance(a, dict) or list(a) != list(b):
                self.out.append((math.inf, f"{where}: keys differ"))
                return
            if "unit" in b:
                scale = self.scales.get(b["unit"], scale)
            near = max(
                _numbers([v for v in b.values() if not isinstance(v, (dict, list))]), default=0.0
            )
            for k in b:
                self.walk(a[k], b[k], f"{where}.{k}", scale, near)
        elif isinstance(b, list):
            if not isinstance(a, list) or len(a) != len(b):
                self.out.append((math.inf, f"{where}: length differs"))
                return
            near = max(_numbers([v for v in b if not isinstance(v, (dict, list))]), default=0.0)
            for k, (x, y) in enumerate(zip(a, b)):
                self.walk(x, y, f"{where}[{k}]", scale, near)
        else:
            s = scale if scale is not None else max([beside, *_numbers(b)])
            self.differ(where, a, b, s)

    def extremes(self, a: dict, b: dict, table: dict[str, list[float]]) -> None:
        """``at_max``/``at_min`` may name another row where the golden column is as
        large within round-off of its unit (a constant column peaks anywhere)."""
        angles = table.get("angle", [])
        for column, rec in b.items():
            unit = self.column_units.get(column)
            s = self.scales.get(unit, 0.0)
            new = a.get(column, {})
            if list(new) != list(rec):
                self.out.append((math.inf, f"extremes.{column}: keys differ"))
                continue
            for key, value in rec.items():
                where = f"extremes.{column}.{key}"
                peak, values = rec.get(key[3:]), table.get(column)
                if key.startswith("at_") and values and new[key] in angles:
                    there = values[angles.index(new[key])]
                    if not _differs(float(there), float(peak), self.rel * s):
                        continue
                self.differ(where, new[key], value, 360.0 if key.startswith("at_") else s)

    def checks(self, a: dict, b: dict) -> None:
        if list(a) != list(b):
            self.out.append((math.inf, "checks: keys differ"))
            return
        for name, rec in b.items():
            new = a[name]
            if not isinstance(rec, dict) or not isinstance(new, dict) or list(new) != list(rec):
                self.walk(new, rec, f"checks.{name}", None)
                continue
            tol, value = rec.get("tolerance"), rec.get("value")
            keys = list(rec)
            if (
                isinstance(tol, (int, float))
                and isinstance(value, (int, float))
                and (abs(value) <= CHECK_ROUND_OFF * tol)
            ):
                if not abs(new["value"]) <= CHECK_ROUND_OFF * tol:
                    self.out.append(
                        (
                            math.inf,
                            f"checks.{name}.value: {new['value']!r} is no "
                            f"longer round-off of its tolerance {tol!r}",
                        )
                    )
                keys = [k for k in keys if k not in ("value", "where")]
            for k in keys:  # each number on its own magnitude: a tolerance is no scale
                self.walk(new[k], rec[k], f"checks.{name}.{k}", None)


def compare_summary(new: str, old: str, results_csv: str, rel: float) -> list[tuple[float, str]]:
    """``(ratio, message)`` for every number of summary.json that differs."""
    a, b = json.loads(new), json.loads(old)
    w = _Walk(rel, unit_scales(results_csv), b.get("column_units", {}))
    if list(a) != list(b):
        return [(math.inf, "keys differ")]
    for key in b:
        if key == "extremes":
            w.extremes(a[key], b[key], _columns(results_csv))
        elif key == "checks":
            w.checks(a[key], b[key])
        else:
            w.walk(a[key], b[key], key, None)
    return w.out


def compare_drawing(new: str, old: str, rel: float) -> list[tuple[float, str]]:
    """``(ratio, message)`` for the drawing data: every number against the drawing's size."""
    a, b = json.loads(new), json.loads(old)
    w = _Walk(rel, {}, {})
    w.walk(a, b, "geometry", max(_numbers(b), default=0.0))
    return w.out


NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")  # a number in a text


def compare_text(new: str, old: str, rel: float) -> list[tuple[float, str]]:
    """``(ratio, message)`` for a text: its words line by line, each number against the
    largest |number| of its golden line."""
    a, b = new.splitlines(), old.splitlines()
    if len(a) != len(b):
        return [(math.inf, f"{len(a)} lines, the golden file has {len(b)}")]
    out = []
    for k, (x, y) in enumerate(zip(a, b), 1):
        if NUMBER.split(x) != NUMBER.split(y):
            out.append((math.inf, f"line {k} differs: {x!r}, golden {y!r}"))
            continue
        nx, ny = [float(v) for v in NUMBER.findall(x)], [float(v) for v in NUMBER.findall(y)]
        scale = max(map(abs, ny), default=0.0)
        for u, v in zip(nx, ny):
            if _differs(u, v, rel * scale):
                ratio = abs(u - v) / scale if scale else math.inf
                out.append((ratio, f"line {k}: {u!r}, golden {v!r}"))
    return out


def compare(produced: dict[str, str], golden: dict[str, str], rel: dict[str, float]):
    """Every difference between the files produced and the golden ones, as
    ``(ratio, "file: message")``; ``rel[name]`` is each file's tolerance (a share of
    the unit's scale)."""
    out = []
    for name, text in produced.items():
        old = golden[name]
        r = rel.get(name, rel["*"])
        if name.endswith(".csv"):
            found = compare_csv(text, old, r)
        elif name == "summary.json":
            found = compare_summary(text, old, golden["results.csv"], r)
        elif name.endswith(".json"):
            found = compare_drawing(text, old, r)
        else:
            found = compare_text(text, old, r)
        out += [(ratio, f"{name}: {m}") for ratio, m in found]
    return out
