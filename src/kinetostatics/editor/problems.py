"""The problems and warnings of a mechanism's text, as ``kinetostatics check`` gives them.

:func:`check_text` reads the text with the public loader and builds its system (what
``check`` does); every :class:`~kinetostatics.errors.KinetostaticsError` becomes one
:class:`Problem` per line of its message, with the line and column of the file where the
message names them, and the warnings raised on the way (a forgotten ``units:``, an
implausible magnitude) are collected as text.
"""

from __future__ import annotations

import re
import warnings
from dataclasses import dataclass

from ..errors import KinetostaticsError, printable
from ..io.plausible import magnitude_warnings, units_note
from ..outputs.loading import loads
from ..structure.system import build_system

__all__ = ["Problem", "Checked", "check_text", "problems_of"]

_WHERE = re.compile(r"^(?P<file>.*?):(?P<line>\d+):(?P<col>\d+): (?P<message>.*)$")


@dataclass(frozen=True)
class Problem:
    """One line of the CLI's message: ``text`` as printed, its ``line`` and ``col`` in the
    file (1-based; None where the message names no place) and the ``message`` after them."""

    text: str
    message: str
    line: int | None = None
    col: int | None = None

    def to_dict(self) -> dict:
        return {"text": self.text, "message": self.message, "line": self.line, "col": self.col}


@dataclass(frozen=True)
class Checked:
    """What :func:`check_text` found: the model and its system (None with problems), the
    problems, and the warnings as the CLI prints them (without its ``kinetostatics:``)."""

    model: object
    system: object
    problems: tuple[Problem, ...]
    warnings: tuple[str, ...]


def problems_of(exc: KinetostaticsError, file: str) -> tuple[Problem, ...]:
    """The lines of ``exc``'s message as problems, each with its place where it names one
    (``FILE:LINE:COL: key.path: message``, as ``kinetostatics check`` prints it)."""
    out = []
    for raw in str(exc).splitlines():
        text = printable(raw)
        m = _WHERE.match(text)
        if m and m.group("file") == file:
            line, col = int(m.group("line")), int(m.group("col"))
            out.append(Problem(text, m.group("message"), line, col))
        else:
            out.append(Problem(text if text.startswith(file) else f"kinetostatics: {text}", text))
    return tuple(out)


def check_text(text: str, file: str) -> Checked:
    """Read ``text`` as the mechanism file ``file`` and build its system, as ``kinetostatics
    check`` does: its problems, or its model and system with the warnings of the way."""
    said: list[str] = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            model = loads(text, file=file)
            system = build_system(model)
        except KinetostaticsError as exc:
            return Checked(None, None, problems_of(exc, file), ())
        if note := units_note(model):
            said.append(note)
        said += [f"warning: {line}" for line in magnitude_warnings(model)]
    said += [f"warning: {printable(str(w.message))}" for w in caught]
    return Checked(model, system, (), tuple(dict.fromkeys(said)))
