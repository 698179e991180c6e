"""The public loader: a mechanism file read (:mod:`kinetostatics.io`) and expanded with
its clearances (:func:`kinetostatics.dynamics.clearance.expand`, which solves the linkage at
t = 0 to place each clearance link).  ``kinetostatics.load`` and ``loads`` are these."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path

from .. import io
from ..base.spec import Entry
from ..model import Model

__all__ = ["load", "loads", "build"]


def _expanded(model: Model) -> Model:
    """``model`` with its clearances (read as data by :mod:`kinetostatics.io`) expanded."""
    if not model.clearances:
        return model
    from ..dynamics.clearance import expand  # the dynamics layer only for a clearance

    return expand(replace(model, clearances=()), model.clearances)


def load(path: str | Path, parameters: Mapping[str, float] | None = None) -> Model:
    """Read a mechanism from a YAML file.

    Raises :class:`~kinetostatics.errors.ModelError` listing every problem
    as ``FILE:LINE:COL: key.path: message``.
    """
    return _expanded(io.read(path, parameters))


def loads(
    text: str, file: str = "<string>", parameters: Mapping[str, float] | None = None
) -> Model:
    """Read a mechanism from YAML text (see :func:`load`)."""
    return _expanded(io.read_string(text, file=file, parameters=parameters))


def build(top: Entry, parameters: Mapping[str, float] | None = None) -> Model:
    """The model of a composed tree (:func:`kinetostatics.io.build`), expanded with
    its clearances.  Raises :class:`~kinetostatics.errors.ModelError`."""
    return _expanded(io.build(top, parameters))
