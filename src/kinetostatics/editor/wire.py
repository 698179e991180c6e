"""A document with NumPy arrays as strict JSON, fast: the rule of
:func:`~kinetostatics.base.files.json_text` (no ``NaN`` or ``Infinity``: each is null,
and named under ``non_finite``), with an array named once for all its non-finite entries
(``{"curves.effort.series[1].y": "NaN at 99 of 360"}``) and written by :mod:`json`'s C
encoder instead of number by number (``json_text(..., whole=True)``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..base.files import json_text

__all__ = ["wire_text"]


def wire_text(data: Mapping[str, Any]) -> str:
    """``data`` (a mapping) as strict JSON text (module docstring)."""
    return json_text(data, None, whole=True, ensure_ascii=False, separators=(",", ":"))
