"""The relative motion of a pair's two links at its point, as textbook vector terms.

What a pair adds to a vector equation of velocities or accelerations (方向/大小: direction
and magnitude) between the point of link j at the pair and the point of link i that
coincides with it: nothing for a pin (the points coincide); the sliding velocity and
acceleration along a slide and, where the slide's guide turns, the Coriolis term
2ω_i×v_r; the normal acceleration of rolling for a toothed pair at its pitch point
(``_meshrelative.py``); a cam's equivalent lower pairs' terms (``_camrelative.py``).
``Joint.relative_motion`` returns a :class:`RelativeMotion` (``methods/vectors.py`` reads it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["RelativeTerm", "RelativeMotion"]


@dataclass(frozen=True)
class RelativeTerm:
    """One term of j's point relative to i's coincident point.

    ``symbol`` (e.g. ``v_A2A3``), ``vector`` (global, m/s or m/s², ``(2,)``), ``direction``
    and ``magnitude`` texts (the magnitude's formula; '' where it is an unknown rate of the
    pair's coordinate until its group is solved), ``rate``: the magnitude is that rate
    (the sliding speed or acceleration), not a product of velocities already known."""

    symbol: str
    vector: np.ndarray
    direction: str
    magnitude: str = ""
    rate: bool = True


@dataclass(frozen=True)
class RelativeMotion:
    """The pair's ``point`` (global, m, ``(2,)``) named ``name``, on link j; ``turns``:
    whether the pair lets its links turn relative to each other (a pin: ω_j is not ω_i);
    the ``velocity`` and ``acceleration`` terms of j's point relative to i's coincident
    point (a pin: none); ``acceleration`` None: not written for the pair's type (a
    toothed pair's rolling at its pitch point)."""

    point: np.ndarray
    name: str
    turns: bool
    velocity: tuple[RelativeTerm, ...] = ()
    acceleration: tuple[RelativeTerm, ...] | None = ()
