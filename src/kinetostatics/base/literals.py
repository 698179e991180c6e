"""Numbers written plainly in a file (``12``, ``-0.5``, ``1.5e3``): read by ``float``
instead of a parse of their expression (:mod:`.expressions`), most numbers of a file
being written so."""

from __future__ import annotations

import math
import re

from .expressions import MAX_EXPRESSION_LENGTH

__all__ = ["plain_number"]

_PLAIN_NUMBER = re.compile(
    r"-?(?:(?:0|[1-9][0-9]*)(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?", re.ASCII
)


def plain_number(text: str) -> float | None:
    """The value of ``text`` when it is a number written plainly (ASCII digits, no
    leading zero, no ``_``, at most a minus sign) that is finite and not zero: the value
    :func:`~.expressions.evaluate` gives it (Python's literals and ``float`` round alike,
    and the sign of a nonzero number is the literal's), without parsing it.  None for
    anything else, which ``evaluate`` reads (a zero too: ``-0`` evaluates to +0.0).

    >>> plain_number("-1.5e3"), plain_number("007"), plain_number("2*pi")
    (-1500.0, None, None)
    """
    if len(text) > MAX_EXPRESSION_LENGTH or _PLAIN_NUMBER.fullmatch(text) is None:
        return None
    value = float(text)
    return value if value != 0.0 and math.isfinite(value) else None
