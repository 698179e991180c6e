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

    Parameters
    ----------
    path : str or pathlib.Path
        The mechanism file (docs/yaml.md describes its keys).
    parameters : mapping of str to float, optional
        Values that replace the file's ``parameters:`` of the same names, in the
        file's units.

    Returns
    -------
    Model
        The mechanism in SI units, its clearances (if any) expanded into links.

    Raises
    ------
    ModelError
        Every problem of the file, one per line, as ``FILE:LINE:COL: key.path:
        message`` (a missing or unreadable file, a wrong key or value, a linkage that
        cannot be assembled at its start).

    See Also
    --------
    loads : The same from YAML text.
    analyze : Analyse the model.

    Examples
    --------
    >>> import kinetostatics as ks
    >>> model = ks.load("mechanisms/slider_crank.yaml")  # doctest: +SKIP
    >>> model.name  # doctest: +SKIP
    'offset slider-crank'
    """
    return _expanded(io.read(path, parameters))


def loads(
    text: str, file: str = "<string>", parameters: Mapping[str, float] | None = None
) -> Model:
    """Read a mechanism from YAML text.

    Parameters
    ----------
    text : str
        The mechanism as YAML (the keys of a mechanism file).
    file : str, optional
        The name the error messages give the text (default ``"<string>"``).
    parameters : mapping of str to float, optional
        Values that replace the text's ``parameters:`` of the same names.

    Returns
    -------
    Model
        The mechanism in SI units, its clearances (if any) expanded into links.

    Raises
    ------
    ModelError
        Every problem of the text, one per line, as ``FILE:LINE:COL: key.path:
        message``.

    See Also
    --------
    load : The same from a file.

    Examples
    --------
    >>> import kinetostatics as ks
    >>> try:
    ...     ks.loads("name: x\\nlinks: {}\\n", file="x.yaml")
    ... except ks.ModelError as e:
    ...     print(e)
    x.yaml:1:1: missing required key 'joints'
    x.yaml:2:1: links: no links: give the ground and the moving links
    """
    return _expanded(io.read_string(text, file=file, parameters=parameters))


def build(top: Entry, parameters: Mapping[str, float] | None = None) -> Model:
    """The model of a composed tree (:func:`kinetostatics.io.build`), expanded with
    its clearances.  Raises :class:`~kinetostatics.errors.ModelError`."""
    return _expanded(io.build(top, parameters))
