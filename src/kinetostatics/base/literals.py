"""The numbers of a file written without names: read by ``float`` where they are written
plainly (``12``, ``-0.5``, ``1.5e3``: most numbers of a file) instead of a parse of their
expression (:mod:`.expressions`), and kept by their text (the same in every reading)."""

from __future__ import annotations

import math
import re

import numpy as np
import yaml

from .expressions import MAX_EXPRESSION_LENGTH
from .limits import MAGNITUDE

__all__ = ["KNOWN", "known_vector", "plain_number", "remember"]

KNOWN: dict[str, float] = {}
"""Text -> value of each number written without names read so far (at most 4,096)."""


def remember(text: str, value: float) -> float:
    """Keep ``value`` as the value of the number written ``text``; return it."""
    if len(KNOWN) >= 4096:
        KNOWN.clear()
    KNOWN[text] = value
    return value


def known_vector(node: yaml.Node, n: int, scale: float, bound: str | None) -> np.ndarray | None:
    """The ``n`` numbers of a list ``node`` whose items are all numbers in :data:`KNOWN`,
    times ``scale``, when each is within :data:`~.limits.MAGNITUDE` of ``bound``: what
    :meth:`~.spec.Entry.vector` reads item by item, without an entry per item.  None
    otherwise (the items are read one by one, and any problem reported as usual)."""
    if not isinstance(node, yaml.SequenceNode) or len(node.value) != n:
        return None
    lower, upper = MAGNITUDE[bound]
    values = []
    for item in node.value:
        value = KNOWN.get(item.value) if isinstance(item, yaml.ScalarNode) else None
        if value is None:
            return None
        value *= scale
        size = abs(value)
        if not (size <= upper and (size == 0.0 or size >= lower)):
            return None
        values.append(value)
    return np.array(values, dtype=float)


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
