"""Exceptions and source locations.

Every user-caused problem is a :class:`KinetostaticsError`.  Model problems
carry a :class:`Location` (file, line, column, key path) and are collected by
:class:`Collector`, which raises them together as one :class:`ModelError`.
Solver problems (:class:`AssemblyError`, :class:`SelfLockingError`) name the
group, the driver coordinate and the reason.  Each class also subclasses a
built-in exception so ``except ValueError`` keeps working.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

__all__ = [
    "Location",
    "KinetostaticsError",
    "ModelError",
    "StructureError",
    "AssemblyError",
    "SingularConfigurationError",
    "SelfLockingError",
    "NonFiniteResultError",
    "LostInertiaError",
    "NearSingularWarning",
    "JointWarning",
    "ElementWarning",
    "SingularEquilibriumWarning",
    "Collector",
    "did_you_mean",
    "OutputError",
    "output_error",
    "printable",
]


@dataclass(frozen=True)
class Location:
    """Where a value came from: ``file:line:col: key.path`` (line, col 1-based)."""

    file: str = "<model>"
    line: int | None = None
    col: int | None = None
    path: str = ""

    def child(self, key: object, line: int | None = None, col: int | None = None) -> Location:
        """The location of ``key`` below this one (list indices as ``[k]``)."""
        path = (
            f"{self.path}[{key}]"
            if isinstance(key, int)
            else (f"{self.path}.{key}" if self.path else str(key))
        )
        return Location(
            self.file,
            line if line is not None else self.line,
            col if col is not None else self.col,
            path,
        )

    def __str__(self) -> str:
        where = self.file
        if self.line is not None:
            where += f":{self.line}:{self.col or 1}"
        return f"{where}: {self.path}" if self.path else where


def printable(text: str) -> str:
    """``text`` with every character that is not printable escaped as in Python
    (``\\n``, ``\\x1b``, ``\\u2028``, bidirectional overrides, unassigned code points):
    a message quoting what a file holds stays on one line and cannot move the cursor,
    colour the terminal or reorder the text it is printed in.

    >>> printable("r1\\nx\\x1b[31m")
    'r1\\\\nx\\\\x1b[31m'
    """
    if text.isprintable():
        return text
    return "".join(ch if ch.isprintable() else ascii(ch)[1:-1] for ch in text)


class KinetostaticsError(Exception):
    """Base class of every user-caused error.

    Parameters
    ----------
    *args : object
        The message (one ``str``), as for :class:`Exception`.

    See Also
    --------
    ModelError : A problem in a mechanism file or model.

    Examples
    --------
    >>> import kinetostatics as ks
    >>> try:
    ...     ks.load("no/such/file.yaml")
    ... except ks.KinetostaticsError as e:
    ...     print(type(e).__name__)
    ModelError
    """

    def __init__(self, *args: object) -> None:
        super().__init__(*args)


class ModelError(KinetostaticsError, ValueError):
    """One or more problems in a model, each with where it was written.

    The message has one line per problem, ``FILE:LINE:COL: key.path: message``.

    Parameters
    ----------
    problems : iterable of (Location, str)
        Each problem's place in the file and its message; kept as the list
        ``problems``, the first place as ``location``.

    Examples
    --------
    >>> from kinetostatics import ModelError
    >>> from kinetostatics.errors import Location
    >>> e = ModelError([(Location("m.yaml", 3, 5, "links.rod.mass"), "must be positive")])
    >>> print(e)
    m.yaml:3:5: links.rod.mass: must be positive
    >>> e.location.line
    3
    """

    def __init__(self, problems: Iterable[tuple[Location, str]]) -> None:
        self.problems = list(problems)
        self.location = self.problems[0][0] if self.problems else Location()
        super().__init__("\n".join(printable(f"{loc}: {msg}") for loc, msg in self.problems))


class StructureError(ModelError):
    """The topology does not match the drivers or the listed loops.

    Parameters
    ----------
    problems : iterable of (Location, str)
        As for :class:`ModelError`.

    Examples
    --------
    >>> import kinetostatics as ks
    >>> issubclass(ks.StructureError, ks.ModelError)
    True
    """


class AssemblyError(KinetostaticsError, RuntimeError):
    """A group cannot be assembled at a driver coordinate.

    Parameters
    ----------
    group : str
        The Assur group (its label, e.g. ``"RRR(rod, rocker)"``).
    coordinate : str
        The driver coordinate, as text with its unit.
    reason : str
        Why (no solution, a limit position).

    Examples
    --------
    >>> import kinetostatics as ks
    >>> print(ks.AssemblyError("RRR(rod, rocker)", "crank = 90 deg", "no solution"))
    RRR(rod, rocker) cannot assemble at crank = 90 deg: no solution
    """

    def __init__(self, group: str, coordinate: str, reason: str) -> None:
        self.group, self.coordinate, self.reason = group, coordinate, reason
        super().__init__(f"{group} cannot assemble at {coordinate}: {reason}")


class SingularConfigurationError(AssemblyError):
    """The motion cannot be continued through a singular position.

    Parameters
    ----------
    group : str
        The Assur group.
    coordinate : str
        The driver coordinate, as text with its unit.
    reason : str
        Why the motion cannot go on.

    Examples
    --------
    >>> import kinetostatics as ks
    >>> issubclass(ks.SingularConfigurationError, ks.AssemblyError)
    True
    """


class SelfLockingError(KinetostaticsError, RuntimeError):
    """The consistent friction solution does not exist (the mechanism self-locks).

    Parameters
    ----------
    *args : object
        The message (one ``str``).

    Examples
    --------
    >>> import kinetostatics as ks
    >>> issubclass(ks.SelfLockingError, (ks.KinetostaticsError, RuntimeError))
    True
    """


class NonFiniteResultError(KinetostaticsError, RuntimeError):
    """An analysis produced a NaN or infinite value that no status explains.

    Not a self-locked friction solution, not a singular position: the numbers of the
    model overflow.

    Parameters
    ----------
    column : str
        The result column that holds the value (kept as ``column``).
    row : int
        Its row, 0-based (kept as ``row``).
    message : str
        The message.

    Examples
    --------
    >>> import kinetostatics as ks
    >>> e = ks.NonFiniteResultError("rod.omega", 4, "rod.omega is inf at row 4")
    >>> e.column, e.row
    ('rod.omega', 4)
    """

    def __init__(self, column: str, row: int, message: str) -> None:
        self.column, self.row = column, row
        super().__init__(message)


class LostInertiaError(KinetostaticsError, RuntimeError):
    """The equations of motion cannot be solved at a state.

    The free coordinates' inertia is lost to round-off against the other terms (a
    spring, a load or a speed far larger than the masses can balance in double
    precision).

    Parameters
    ----------
    *args : object
        The message (one ``str``).

    Examples
    --------
    >>> import kinetostatics as ks
    >>> issubclass(ks.LostInertiaError, RuntimeError)
    True
    """


class OutputError(KinetostaticsError, RuntimeError):
    """An output cannot be written or a batch's machinery failed.

    An ``--out`` that is a file, a folder without write permission, a full disk, a
    lost Dask scheduler.  The message is one line naming the path (or the scheduler).

    Parameters
    ----------
    *args : object
        The message (one ``str``).

    Examples
    --------
    >>> import kinetostatics as ks
    >>> print(ks.OutputError("--out out: is a file, not a folder"))
    --out out: is a file, not a folder
    """


def output_error(exc: OSError, what: str) -> OutputError:
    """An :class:`OutputError` for an ``OSError`` met writing ``what`` (e.g.
    ``"--out out"``): ``what: cannot write PATH: reason``."""
    path = exc.filename if exc.filename is not None else ""
    reason = exc.strerror or str(exc) or type(exc).__name__
    return OutputError(f"{what}: cannot write {path}: {reason}" if path else f"{what}: {reason}")


class MissingPackageError(KinetostaticsError, ImportError):
    """An optional third-party package that a feature needs is not installed; the
    message names the feature and the ``pip install`` line that adds it."""


class NearSingularWarning(UserWarning):
    """A group is near a singular position (large condition number).

    Parameters
    ----------
    *args : object
        The message (one ``str``), as for :class:`UserWarning`.

    Examples
    --------
    >>> import warnings
    >>> import kinetostatics as ks
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     warnings.warn("RRR(rod, rocker) near a singular position", ks.NearSingularWarning)
    >>> caught[0].category.__name__
    'NearSingularWarning'
    """

    def __init__(self, *args: object) -> None:
        super().__init__(*args)


class JointWarning(UserWarning):
    """A joint type's own warning about a result: a cam follower that would leave
    its cam (the contact force would pull), naming the cam angles."""


class ElementWarning(UserWarning):
    """An element's warning about a result: a spring or damper whose two points meet
    (its length reaches zero: its direction, so its force, is undefined there), naming
    the driver positions."""


class SingularEquilibriumWarning(NearSingularWarning):
    """No finite driver effort balances the loads at some positions (a dead centre
    for the joint that carries the effort); those rows are NaN."""


def did_you_mean(word: str, choices: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the closest choice, or an empty string."""
    import difflib  # on the error path only

    close = difflib.get_close_matches(str(word), [str(c) for c in choices], n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


class Collector:
    """Gathers model problems and raises them together.

    >>> c = Collector()
    >>> c.add(Location("m.yaml", 3, 5, "links.rod.mass"), "must be positive, got -1")
    >>> c.raise_if_any()
    Traceback (most recent call last):
    ...
    kinetostatics.errors.ModelError: m.yaml:3:5: links.rod.mass: must be positive, got -1
    """

    def __init__(self) -> None:
        self.problems: list[tuple[Location, str]] = []

    def add(self, where: Location, message: str) -> None:
        self.problems.append((where, message))

    def raise_if_any(self, cls: type[ModelError] = ModelError) -> None:
        if self.problems:
            problems, self.problems = self.problems, []
            raise cls(problems)
