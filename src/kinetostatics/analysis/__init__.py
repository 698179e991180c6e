"""Layer 6, analysis: the pipeline :func:`analyze` (:mod:`.pipeline`), its
:class:`~.results.Result`, the self-checks (:mod:`.checks`), the reachable-range recovery
(:mod:`.reachable`) and the stacked form over variants (:mod:`.vectorised`)."""

from .pipeline import (
    Event,
    Kinetics,
    Schedule,
    analyze,
    kinetics,
    numerical_mobility,
    travel_extremes,
    whole_motion,
)

__all__ = [
    "analyze",
    "kinetics",
    "Kinetics",
    "Schedule",
    "Event",
    "numerical_mobility",
    "travel_extremes",
    "whole_motion",
]
