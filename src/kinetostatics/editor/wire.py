"""A document with NumPy arrays as strict JSON, fast: the rule of
:func:`~kinetostatics.base.files.json_text` (no ``NaN`` or ``Infinity``: each is null,
and named under ``non_finite``), with an array named once for all its non-finite entries
(``{"curves.effort.series[1].y": "NaN at 99 of 360"}``) and written by :mod:`json`'s C
encoder instead of number by number.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..base.files import NON_FINITE

__all__ = ["wire_text"]


def _what(a: np.ndarray) -> str:
    bad = ~np.isfinite(a)
    kinds = [
        w
        for w, m in (("NaN", np.isnan(a)), ("Infinity", a == np.inf), ("-Infinity", a == -np.inf))
        if m.any()
    ]
    return f"{'/'.join(kinds)} at {int(bad.sum())} of {a.size}"


def _clean(value: Any, path: str, found: dict[str, str]) -> Any:
    if isinstance(value, Mapping):
        return {k: _clean(v, f"{path}.{k}" if path else str(k), found) for k, v in value.items()}
    if isinstance(value, np.ndarray) and value.dtype.kind in "fc":
        a = np.asarray(value, float)
        if np.all(np.isfinite(a)):
            return a.tolist()
        found[path] = _what(a)
        return np.where(np.isfinite(a), a, None).tolist()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [_clean(v, f"{path}[{i}]", found) for i, v in enumerate(value)]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        x = float(value)
        if math.isfinite(x):
            return x
        found[path] = "NaN" if math.isnan(x) else ("Infinity" if x > 0 else "-Infinity")
        return None
    return value


def wire_text(data: Mapping[str, Any]) -> str:
    """``data`` (a mapping) as strict JSON text (module docstring)."""
    found: dict[str, str] = {}
    clean = _clean(data, "", found)
    if found:
        clean[NON_FINITE] = found
    return json.dumps(clean, allow_nan=False, ensure_ascii=False, separators=(",", ":"))
