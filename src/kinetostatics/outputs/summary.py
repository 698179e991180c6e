"""summary.json: the summary's formatter under its documented path.

The formatter is :func:`~kinetostatics.analysis.summary.summarize`, in ``analysis/``
beside the result it formats (``Result.summary()`` calls it without an upward import);
the cycle's records it formats are computed by the caller
(:func:`~kinetostatics.dynamics.stages.cycle_stage`).  Nothing here solves.
"""

from __future__ import annotations

from ..analysis.summary import ROUND_OFF, summarize

__all__ = ["summarize", "ROUND_OFF"]
