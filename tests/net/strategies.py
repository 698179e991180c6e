"""Hypothesis strategies over the generated mechanisms (tests/net/generate.py)."""

from __future__ import annotations

from hypothesis import strategies as st

from . import generate as G

# the default seeds of the strategies below (a strategy is immutable: safe as a default)
SEEDS = st.integers(min_value=0, max_value=2**31 - 1)


@st.composite
def mechanisms(draw, seeds=SEEDS, features=()):
    """An accepted random mechanism (an SI YAML-like dict) and its seed; ``features``
    (names from ``generate.FEATURES``, e.g. ``("cam",)``) it has for sure."""
    seed = draw(seeds)
    return seed, G.generate(seed, features)


@st.composite
def mechanisms_in_units(draw, seeds=SEEDS, features=()):
    """A generated mechanism and the same one written in random length/angle/speed
    units: ``(seed, si_doc, doc_in_units)``."""
    seed, doc = draw(mechanisms(seeds, features))
    length = draw(st.sampled_from(sorted(G.LENGTH_UNITS)))
    angle = draw(st.sampled_from(sorted(G.ANGLE_UNITS)))
    speed = draw(st.sampled_from(sorted(G.SPEED_UNITS)))
    return seed, doc, G.in_units(doc, length, angle, speed)
