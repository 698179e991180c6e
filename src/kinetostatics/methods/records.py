"""What the methods' records share: the positions asked for, and their JSON-safe numbers."""

from __future__ import annotations

import math

from ..analysis.results import Result

__all__ = ["asked_rows", "json_float"]


def json_float(x) -> float | None:
    """A JSON-safe float: None for NaN or ±inf (a singular position's rows)."""
    x = float(x)
    return x if math.isfinite(x) else None


def asked_rows(result: Result, rows) -> list[tuple[str, int]]:
    """``[(label, row)]`` of row indices (label empty) or ``(label, row)`` pairs, as
    ``course_positions(result)`` gives them; a row not among the result's raises
    ``IndexError``."""
    out = []
    for r in rows:
        label, k = (str(r[0]), int(r[1])) if isinstance(r, tuple) else ("", int(r))
        if not -len(result) <= k < len(result):
            raise IndexError(f"row {k} is not among the result's {len(result)} rows")
        out.append((label, k % len(result)))
    return out
