"""Sizing: the bearings' life, the pins' stresses and the links' internal forces and
fatigue safety factors, from a Result's reactions (docs/sizing.md).

A stage between the analyses (``dynamics/``, ``methods/``) and the outputs: it reads a
Result's columns only and returns frozen records (:mod:`.records`), which ``run`` writes
to sizing.json and the report formats.
"""

from .records import BearingSizing, LinkSizing, PinSizing, Sizing
from .stage import sizing_stage

__all__ = ["BearingSizing", "LinkSizing", "PinSizing", "Sizing", "sizing_stage"]
