"""Outputs of an analysis: summaries, reports and pictures (:mod:`.plotting`)."""
