"""Find the best variants of a batch: an objective, constraints, the top rows.

>>> rows = [{"variant": "1", "status": "ok", "T": "5.0", "p": "12"},
...         {"variant": "2", "status": "ok", "T": "7.0", "p": "8"},
...         {"variant": "3", "status": "failed", "T": "", "p": ""}]
>>> [r["variant"] for r in select(rows, "min T", ["p <= 10"], top=5)]
['2']
"""

from __future__ import annotations

import math
import operator
import re
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

from ..errors import KinetostaticsError, did_you_mean
from .table import read_summary

__all__ = ["BestError", "parse_objective", "parse_condition", "select", "best", "format_table"]

OPS = {
    "<=": operator.le,
    ">=": operator.ge,
    "==": operator.eq,
    "!=": operator.ne,
    "<": operator.lt,
    ">": operator.gt,
}
CONDITION = re.compile(r"^\s*(\S+?)\s*(<=|>=|==|!=|<|>)\s*(\S+)\s*$")


class BestError(KinetostaticsError, ValueError):
    """An objective or constraint that does not parse or names no column."""


def _column(name: str, columns: Sequence[str], what: str) -> str:
    if name not in columns:
        numeric = [c for c in columns if c not in ("variant", "status", "reason")]
        raise BestError(f"{what}: no column '{name}'{did_you_mean(name, numeric)}")
    return name


def parse_objective(text: str, columns: Sequence[str]) -> tuple[str, bool]:
    """``"min COLUMN"`` or ``"max COLUMN"`` → (column, minimise)."""
    parts = text.split()
    if len(parts) != 2 or parts[0] not in ("min", "max"):
        raise BestError(f"--best {text!r}: expected 'min COLUMN' or 'max COLUMN'")
    return _column(parts[1], columns, f"--best {text!r}"), parts[0] == "min"


def parse_condition(text: str, columns: Sequence[str]) -> tuple[str, str, float]:
    """``"COLUMN OP NUMBER"`` with OP one of <= >= < > == != → (column, op, value)."""
    m = CONDITION.match(text)
    if not m:
        raise BestError(
            f"--where {text!r}: expected 'COLUMN OP NUMBER', OP one of " + " ".join(OPS)
        )
    name, op, value = m.groups()
    try:
        number = float(value)
    except ValueError:
        raise BestError(f"--where {text!r}: '{value}' is not a number") from None
    return _column(name, columns, f"--where {text!r}"), op, number


def _number(cell: object) -> float:
    try:
        return float(cell)  # "" and text give nan
    except (TypeError, ValueError):
        return math.nan


def select(
    rows: Sequence[Mapping[str, str]], objective: str, where: Iterable[str] = (), top: int = 5
) -> list[Mapping[str, str]]:
    """The ``top`` rows with status ok that meet every condition, best first
    (rows with an empty objective value are left out)."""
    columns = list(rows[0]) if rows else []
    col, minimise = parse_objective(objective, columns)
    conditions = [parse_condition(c, columns) for c in where]
    keep = []
    for row in rows:
        if row.get("status", "ok") != "ok" or math.isnan(_number(row[col])):
            continue
        if all(OPS[op](_number(row[c]), v) for c, op, v in conditions):
            keep.append(row)
    keep.sort(key=lambda r: _number(r[col]) * (1 if minimise else -1))
    return keep[:top]


def format_table(rows: Sequence[Mapping[str, str]], columns: Sequence[str]) -> str:
    """A plain text table, numbers to 6 significant digits."""

    def fmt(cell: str) -> str:
        x = _number(cell)
        return cell if math.isnan(x) or cell.strip() in ("True", "False") else f"{x:.6g}"

    cells = [list(columns)] + [
        [r.get(c, "") if c == "variant" else fmt(r.get(c, "")) for c in columns] for r in rows
    ]
    widths = [max(len(row[k]) for row in cells) for k in range(len(columns))]
    return "\n".join("  ".join(c.rjust(w) for c, w in zip(row, widths)).rstrip() for row in cells)


def best(
    summary_csv: str | Path,
    objective: str,
    where: Iterable[str] = (),
    top: int = 5,
    params: Sequence[str] | None = None,
) -> str:
    """The top rows of a batch's summary table as a text table: the variant,
    its parameters (``params``, default those that vary), the objective and the constrained
    columns."""

    header, rows = read_summary(summary_csv)
    where = list(where)
    chosen = select(rows, objective, where, top)
    col, _ = parse_objective(objective, header)
    constrained = [parse_condition(c, header)[0] for c in where]
    if params is None:
        k = header.index("status") if "status" in header else 1
        params = [p for p in header[1:k] if len({r[p] for r in rows}) > 1]  # the swept ones
    columns = ["variant", *params, col, *[c for c in constrained if c != col]]
    if not chosen:
        return f"no variant with status ok meets {' and '.join(where) or 'the objective'}"
    return format_table(chosen, list(dict.fromkeys(columns)))
