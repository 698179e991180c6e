"""The pictures, at their old import path: see :mod:`kinetostatics.outputs.plotting`."""

from .outputs.plotting import *  # noqa: F403
from .outputs.plotting import __all__, _active_spans  # noqa: F401
