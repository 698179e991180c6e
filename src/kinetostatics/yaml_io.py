"""YAML text -> :class:`~kinetostatics.model.Model`.

The file is composed with PyYAML's safe composer (no tags, no object
construction); every node keeps its line and column, so every problem is
reported as ``FILE:LINE:COL: key.path: message``.  Problems are collected and
raised together as one :class:`~kinetostatics.errors.ModelError`.  The schema
is documented in ``docs/yaml.md``.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from . import expressions, units
from .errors import Collector, KinetostaticsError, Location, ModelError, did_you_mean
from .joints import JOINT_TYPES, Joint
from .model import (
    Analysis,
    Condition,
    Driver,
    EffortLaw,
    FlywheelSpec,
    Link,
    Load,
    Model,
    MotionLaw,
)
from .motion import HarmonicLaw, PolynomialLaw, TableLaw

__all__ = ["load", "loads", "Entry", "MAX_FILE_BYTES", "MAX_NODES", "dump"]

MAX_FILE_BYTES = 1_000_000
MAX_NODES = 100_000
MAX_DEPTH = 100
MAX_LINKS = 200
MAX_POSITIONS = 10_000_000
MAX_TURNS = 100  # analysis.sweep of a revolute driver, in turns
MAX_TRAVEL = 1000  # a prismatic driver's sweep (and at - start): x the largest link
SPEED_RANGE = (1e-9, 1e9)  # |speed| of a motion driver, rad/s or m/s
MAX_LAW_ACCELERATION = 1e18  # |second derivative| of a motion law, rad/s^2 or m/s^2
MAGNITUDE = {  # SI: |value| <= upper, and a value that is not 0 has |value| >= lower
    "length": (1e-30, 1e9),  # m
    "mass": (1e-30, 1e12),  # kg
    "inertia": (1e-30, 1e30),  # kg*m^2 (mass limit x length limit^2)
    "force": (1e-30, 1e24),  # N (mass limit x gravity limit)
    "torque": (1e-30, 1e33),  # N*m (force limit x length limit)
    "acceleration": (1e-30, 1e12),  # m/s^2: gravity
    "time": (1e-30, 1e9),  # s
    "speed": (1e-30, 1e9),  # rad/s or m/s (a motion driver: SPEED_RANGE)
    "angle": (0.0, 1e6),  # rad
    None: (1e-30, 1e18),  # dimensionless: friction coefficients, directions, ratios
}
"""Bounds on every number of a file, by quantity kind, in SI.  The products the
analysis forms from them (m*omega^2*L, J*omega^2, m*g*L, F*L, power F*v; with a
driver speed of at most 1e9 and a law's acceleration of at most 1e18 in SI) stay
below 1e60, and their squares (norms) below 1e120: far from overflow (1.8e308).  A
non-zero value below the lower bound (1e-300 kg) is refused as well: it only
arises by mistake, and its products underflow."""
OWN_LIMITS = {
    "analysis.sweep": "MAX_TURNS (revolute driver; start + sweep within ±MAX_TURNS turns of "
    "0), MAX_TRAVEL (prismatic driver)",
    "analysis.at[]": "within ±MAX_TURNS turns of 0 (revolute driver), MAX_TRAVEL from "
    "analysis.start (prismatic driver)",
    "drivers.*.motion.speed": "SPEED_RANGE",
    "drivers.*.motion.coefficients[]": "finite in SI; the law's SPEED_RANGE, "
    "MAX_LAW_ACCELERATION, MAGNITUDE of its coordinate, "
    "MAX_TURNS or MAX_TRAVEL of its path",
}
"""The numbers of a file that are bounded by a limit of their own instead of (or besides)
:data:`MAGNITUDE`: key pattern (names as ``*``, indices as ``[]``) -> the limit.  Every other
number is read through :meth:`Entry.number` and bounded by :data:`MAGNITUDE`
(``tests/test_hostile_keys.py`` walks the loader to check it)."""
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
RESERVED = frozenset({"time", "angle", "stroke", "travel", "power", "friction", "shaking"})
TOP_KEYS = (
    "name",
    "units",
    "parameters",
    "gravity",
    "ground",
    "links",
    "joints",
    "loops",
    "drivers",
    "loads",
    "sketch",
    "analysis",
    "flywheel",
    "sweep",
    "clearance",
)


class _TooDeep(Exception):
    def __init__(self, mark):
        self.mark = mark


class _TooMany(_TooDeep):
    pass


class _Loader(yaml.SafeLoader):
    """The safe composer, refusing nesting deeper than :data:`MAX_DEPTH` (before
    Python's recursion limit is reached)."""

    def __init__(self, stream):
        super().__init__(stream)
        self._depth = 0
        self._nodes = 0

    def compose_node(self, parent, index):
        # A level is a list or a mapping (a scalar inside the 100th level is fine); the
        # nodes are counted as they are composed, so that a long flat list is refused
        # before all of it is built (aliases are counted expanded after composing).
        self._depth += 1
        self._nodes += 1
        try:
            if self._nodes > MAX_NODES:
                raise _TooMany(self.peek_event().start_mark)
            if self._depth > MAX_DEPTH and self.check_event(
                yaml.SequenceStartEvent, yaml.MappingStartEvent
            ):
                raise _TooDeep(self.peek_event().start_mark)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1


class _Problems(Collector):
    """A collector that drops exact repeats (a missing key seen by two readers)."""

    def add(self, where: Location, message: str) -> None:
        if (where, message) not in self.problems:
            super().add(where, message)


class _Context:
    def __init__(self, file: str):
        self.file = file
        self.problems = _Problems()
        self.env: dict[str, float] = {}
        self.units: dict[str, float] = units.unit_table(None)
        self.unit_names: dict[str, str] = {}
        self.broken_parameters: set[str] = set()  # declared, but in error (already reported)
        self.overrides: dict[str, float] = {}  # parameter values given from outside


_EXPRESSION_HINT = (
    "; an expression may use numbers, parameter names, + - * / // % **, "
    "parentheses and functions such as sqrt, sind, atan2"
)


def _expression_message(exc: Exception) -> str:
    """An expression error, with what is allowed when a construct was refused."""
    message = str(exc)
    if message.endswith("not allowed") or message.startswith("only calls"):
        message += _EXPRESSION_HINT
    return message


class Entry:
    """A YAML node with its location; typed readers report problems and return ``None``."""

    def __init__(self, node: yaml.Node, where: Location, ctx: _Context):
        self.node, self.where, self.ctx = node, where, ctx

    # -- structure ----------------------------------------------------------
    def error(self, message: str) -> None:
        self.ctx.problems.add(self.where, message)

    @property
    def is_mapping(self) -> bool:
        return isinstance(self.node, yaml.MappingNode)

    def _pairs(self) -> list[tuple[str, yaml.Node, yaml.Node]]:
        if not self.is_mapping:
            return []
        pairs = self.node.__dict__.get("_ks_pairs")  # a tree is built once per variant:
        if pairs is None:  # keep what does not change on it
            pairs = self.node._ks_pairs = [(str(k.value), k, v) for k, v in self.node.value]
        return pairs

    def mapping(self) -> bool:
        if not self.is_mapping:
            self.error(f"expected a mapping of keys, got {_describe(self.node)}")
            return False
        return True

    def items(self) -> list[tuple[str, Entry]]:
        return [(key, self._child(key, v)) for key, _, v in self._pairs()]

    def keys(self) -> list[str]:
        return [key for key, _, _ in self._pairs()]

    def _child(self, key: str | int, node: yaml.Node) -> Entry:
        cache = self.node.__dict__.setdefault("_ks_where", {})
        where = cache.get((self.where, key))
        if where is None:
            m = node.start_mark
            where = cache[(self.where, key)] = self.where.child(key, m.line + 1, m.column + 1)
        return Entry(node, where, self.ctx)

    def key_where(self, key: str) -> Location:
        """The location of ``key`` itself (not of its value)."""
        for k, knode, _ in self._pairs():
            if k == key:
                m = knode.start_mark
                return self.where.child(key, m.line + 1, m.column + 1)
        return self.where.child(key)

    def get(self, key: str) -> Entry | None:
        for k, _, v in self._pairs():
            if k == key:
                return self._child(k, v)
        return None

    def __getitem__(self, key: str) -> Entry:
        entry = self.get(key)
        if entry is None:
            raise KeyError(key)
        return entry

    def require(self, key: str) -> Entry:
        """The child ``key``; when it is absent, report it and return a falsy
        placeholder whose readers all return ``None`` without reporting again."""
        entry = self.get(key)
        if entry is None:
            if self.mapping():
                self.error(f"missing required key '{key}'")
            return _Missing(self, key)
        return entry

    def check_keys(self, required: Iterable[str] = (), optional: Iterable[str] = ()) -> bool:
        """Report unknown keys (with a suggestion) and missing required keys."""
        if not self.mapping():
            return False
        required, optional = tuple(required), tuple(optional)
        allowed = (
            optional
            if set(required) <= set(optional)
            else tuple(dict.fromkeys(required + optional))
        )
        ok = True
        for key, knode, _ in self._pairs():
            if key not in allowed:
                m = knode.start_mark
                self.ctx.problems.add(
                    self.where.child(key, m.line + 1, m.column + 1),
                    f"unknown key '{key}'{did_you_mean(key, allowed)}; "
                    f"expected one of: {', '.join(allowed)}",
                )
                ok = False
        present = set(self.keys())
        for key in required:
            if key not in present:
                self.error(f"missing required key '{key}'")
                ok = False
        return ok

    def seq(self) -> list[Entry] | None:
        if not isinstance(self.node, yaml.SequenceNode):
            self.error(f"expected a list, got {_describe(self.node)}")
            return None
        return [self._child(k, n) for k, n in enumerate(self.node.value)]

    # -- scalars ------------------------------------------------------------
    def text(self) -> str | None:
        if not isinstance(self.node, yaml.ScalarNode) or self.node.value == "":
            self.error(f"expected a name, got {_describe(self.node)}")
            return None
        return str(self.node.value)

    def boolean(self) -> bool | None:
        value = self.node.value if isinstance(self.node, yaml.ScalarNode) else None
        if isinstance(value, str) and value.lower() in ("true", "yes", "on", "false", "no", "off"):
            return value.lower() in ("true", "yes", "on")
        self.error(f"expected true or false, got {_describe(self.node)}")
        return None

    def number(
        self,
        kind: str | None,
        *,
        minimum: float | None = None,
        strict: bool = False,
        bounded: bool = True,
    ) -> float | None:
        """The scalar's value (a number or a parameter expression) times the
        file's unit factor for ``kind`` (``None``: dimensionless), within
        :data:`MAGNITUDE` (``bounded=False``: the caller applies its own limit)."""
        value = self.raw_number()
        if value is None:
            return None
        if minimum is not None and (value < minimum or (strict and value == minimum)):
            if minimum == 0:
                self.error(f"must be {'positive' if strict else 'zero or positive'}, got {value:g}")
            else:
                self.error(
                    f"must be {'greater than' if strict else 'at least'} {minimum:g}, got {value:g}"
                )
            return None
        scale = self.ctx.units[kind] if kind else 1.0
        if bounded and not self.within(value * scale, kind, value):
            return None
        return value * scale

    def within(
        self, value: float, kind: str | None, written: float | None = None, unit: str | None = None
    ) -> bool:
        """Whether ``value`` (SI) is within :data:`MAGNITUDE` of ``kind``; if not, report it
        (``written``: the value in the file's ``unit``) and return False."""
        lower, upper = MAGNITUDE[kind]
        size = abs(value)
        if size <= upper and (size == 0.0 or size >= lower):
            return True
        si = units.SI_UNITS.get(kind, "") if kind not in ("acceleration",) else "m/s^2"
        if kind is None:
            text, limit = f"{value:g}", ""
        else:
            unit = unit or self.ctx.unit_names.get(kind, si)
            text = f"{written if written is not None else value:g} {unit}".rstrip()
            if unit != si:
                text += f" ({value:g} {si})"
            limit = f" {si}"
        what = f"{'an' if kind[0] in 'aeiou' else 'a'} {kind}" if kind else "a dimensionless number"
        if size > upper:
            self.error(
                f"{text} is too large: the magnitude of {what} must be at most "
                f"{upper:g}{limit} (larger values overflow in the analysis)"
            )
        else:
            self.error(
                f"{text} is too small: the magnitude of {what} must be 0 or at least "
                f"{lower:g}{limit} (smaller values underflow in the analysis)"
            )
        return False

    def raw_number(self) -> float | None:
        """The scalar's value as written (no unit conversion)."""
        if not isinstance(self.node, yaml.ScalarNode) or self.node.value == "":
            self.error(f"expected a number or an expression, got {_describe(self.node)}")
            return None
        text = self.node.value
        try:
            used = expressions.names_in(text)
        except expressions.ExpressionError as exc:
            self.error(_expression_message(exc))
            return None
        env = self.ctx.env
        if used & self.ctx.broken_parameters:
            return None  # that parameter's problem is already reported
        for name in sorted(used):
            if name not in env and name not in expressions.CONSTANTS:
                self.error(f"undefined parameter '{name}'{did_you_mean(name, env)}")
                return None
        try:
            return expressions.evaluate(text, env)
        except expressions.ExpressionError as exc:
            self.error(_expression_message(exc))
            return None

    def vector(self, kind: str | None, n: int = 2, bound: str | None = None) -> np.ndarray | None:
        """``n`` numbers of ``kind``; ``bound``: the :data:`MAGNITUDE` entry that limits them
        when it is not ``kind``'s (gravity: numbers in m/s², bounded as an acceleration)."""
        shape = "[x, y]" if n == 2 else f"a list of {n} numbers"
        if not isinstance(self.node, yaml.SequenceNode):
            self.error(f"expected {shape}, got {_describe(self.node)}")
            return None
        items = self.seq() or []
        if len(items) != n:
            self.error(
                f"expected {shape} ({n} numbers), got {len(items)} "
                f"number{'s' if len(items) != 1 else ''}"
            )
            return None
        values = [e.number(kind, bounded=bound is None) for e in items]
        if bound is not None:
            values = [v if v is None or e.within(v, bound) else None for e, v in zip(items, values)]
        return None if any(v is None for v in values) else np.array(values, dtype=float)

    def unit(self, v: np.ndarray) -> np.ndarray | None:
        norm = float(np.hypot(*v))
        if not norm > 0.0:
            self.error(f"the direction [{self._raw_list()}] has zero length")
            return None
        return v / norm

    def _raw_list(self) -> str:
        if isinstance(self.node, yaml.SequenceNode):
            return ", ".join(str(getattr(n, "value", "?")) for n in self.node.value)
        return str(getattr(self.node, "value", ""))

    def names(self, n: int) -> list[str | None]:
        """A name (n = 1) or a list of exactly n names; ``None`` for each name
        that could not be read (the problem is reported)."""
        if n == 1 and isinstance(self.node, yaml.ScalarNode):
            return [self.text()]
        if n == 1:
            self.error(f"expected a name, got {_describe(self.node)}")
            return [None]
        if not isinstance(self.node, yaml.SequenceNode):
            self.error(f"expected a list of {n} names, got {_describe(self.node)}")
            return [None] * n
        items = self.seq() or []
        if len(items) != n:
            self.error(f"expected a list of {n} names, got {len(items)}")
            return [None] * n
        return [e.text() for e in items]

    def point(
        self,
        link: str,
        name: str | None,
        points: dict[str, dict[str, np.ndarray]],
        key: str,
        index: int | None = None,
    ) -> np.ndarray | None:
        """Local point ``name`` of ``link``; errors point at ``key[index]`` (or at this entry)."""
        where = self.get(key) or self
        if (
            index is not None
            and isinstance(where.node, yaml.SequenceNode)
            and index < len(where.node.value)
        ):
            where = where._child(index, where.node.value[index])
        if name is None or link not in points:
            return None
        if name not in points[link]:
            where.error(
                f"unknown point '{name}' on link '{link}'"
                f"{did_you_mean(name, points[link])}; "
                f"it has: {', '.join(points[link]) or 'no points'}"
            )
            return None
        return points[link][name]


class _Missing(Entry):
    """Stands for a required key that is absent (already reported): falsy, and
    every reader returns ``None`` (``names``: a list of ``None``) silently."""

    def __init__(self, parent: Entry, key: str):
        super().__init__(
            yaml.ScalarNode("tag:yaml.org,2002:null", ""), parent.where.child(key), parent.ctx
        )

    def __bool__(self) -> bool:
        return False

    def error(self, message: str) -> None:
        pass

    def mapping(self) -> bool:
        return False

    def check_keys(self, required: Iterable[str] = (), optional: Iterable[str] = ()) -> bool:
        return False

    def require(self, key: str) -> Entry:
        return _Missing(self, key)

    def seq(self) -> None:
        return None

    def text(self) -> None:
        return None

    def boolean(self) -> None:
        return None

    def raw_number(self) -> None:
        return None

    def vector(self, kind: str | None, n: int = 2, bound: str | None = None) -> None:
        return None

    def names(self, n: int) -> list[None]:
        return [None] * n


def _describe(node: yaml.Node) -> str:
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return "a list"
    return f"'{node.value}'" if node.value != "" else "nothing"


def _count_nodes(node: yaml.Node, limit: int) -> int:
    """Number of nodes reached (aliases counted each time), stopping past ``limit``."""
    count, stack = 0, [node]
    while stack and count <= limit:
        n = stack.pop()
        count += 1
        if isinstance(n, yaml.MappingNode):
            for k, v in n.value:
                stack.extend((k, v))
        elif isinstance(n, yaml.SequenceNode):
            stack.extend(n.value)
    return count


_PLAIN_TAGS = frozenset(
    f"tag:yaml.org,2002:{t}"
    for t in ("str", "int", "float", "bool", "null", "seq", "map", "merge", "timestamp", "value")
)


def _check_keys_and_duplicates(root: yaml.Node, file: str, problems: Collector) -> None:
    """Every mapping key must be a plain scalar and appear once; no application tags
    (``!!python/...``).  Iterative: no recursion."""
    stack: list[tuple[yaml.Node, str]] = [(root, "")]
    visited: set[int] = set()
    while stack:
        node, path = stack.pop()
        if id(node) in visited:  # an alias: its node was checked already
            continue
        visited.add(id(node))
        if node.tag not in _PLAIN_TAGS:
            m = node.start_mark
            tag = str(node.tag).replace("tag:yaml.org,2002:", "!!", 1)
            problems.add(
                Location(file, m.line + 1, m.column + 1, path),
                f"YAML tags such as '{tag}' are not allowed",
            )
            continue
        if isinstance(node, yaml.MappingNode):
            seen: dict[str, int] = {}
            children = []
            for k, v in node.value:
                m = k.start_mark
                if not isinstance(k, yaml.ScalarNode):
                    problems.add(
                        Location(file, m.line + 1, m.column + 1, path),
                        f"a key must be a plain name, got {_describe(k)}",
                    )
                    continue
                key = str(k.value)
                sub = f"{path}.{key}" if path else key
                if key in seen:
                    problems.add(
                        Location(file, m.line + 1, m.column + 1, sub),
                        f"duplicate key '{key}' (first given at line {seen[key]})",
                    )
                else:
                    seen[key] = m.line + 1
                children.append((v, sub))
            stack.extend(reversed(children))
        elif isinstance(node, yaml.SequenceNode):
            stack.extend(reversed([(v, f"{path}[{k}]") for k, v in enumerate(node.value)]))


# ---------------------------------------------------------------------------
def load(path: str | Path, parameters: Mapping[str, float] | None = None) -> Model:
    """Read a mechanism from a YAML file.

    Raises :class:`~kinetostatics.errors.ModelError` listing every problem
    as ``FILE:LINE:COL: key.path: message``.
    """
    return loads(read_text(path), file=str(path), parameters=parameters)


def read_text(path: str | Path) -> str:
    """A mechanism file's text, with the size cap and UTF-8 checked (``ModelError``)."""
    path = Path(path)
    try:
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise ModelError(
                [
                    (
                        Location(str(path)),
                        f"the file is {size} bytes, more than the limit of "
                        f"{MAX_FILE_BYTES} bytes; refused",
                    )
                ]
            )
        with path.open("rb") as f:  # the file may grow between stat and read
            data = f.read(MAX_FILE_BYTES + 1)
        if len(data) > MAX_FILE_BYTES:
            raise ModelError(
                [
                    (
                        Location(str(path)),
                        f"the file is more than the limit of {MAX_FILE_BYTES} bytes; refused",
                    )
                ]
            )
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        col = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise ModelError(
            [
                (
                    Location(str(path), line, col),
                    f"the file is not UTF-8 text (byte 0x{data[exc.start]:02x}); save it as UTF-8",
                )
            ]
        ) from None
    except OSError as exc:
        reason = exc.strerror or str(exc)
        raise ModelError([(Location(str(path)), f"cannot read the file: {reason}")]) from None
    return text


def loads(
    text: str, file: str = "<string>", parameters: Mapping[str, float] | None = None
) -> Model:
    """Read a mechanism from YAML text (see :func:`load`)."""
    return build(compose(text, file), parameters)


def compose(text: str, file: str = "<string>") -> Entry:
    """The checked YAML tree of a mechanism (syntax, size, keys), not yet built.

    :func:`build` turns it into a model; a batch builds one tree many times
    with other parameter values.
    """
    if len(text.encode("utf-8", "replace")) > MAX_FILE_BYTES:
        raise ModelError(
            [
                (
                    Location(file),
                    f"the text is more than the limit of {MAX_FILE_BYTES} bytes; refused",
                )
            ]
        )
    try:
        root = yaml.compose(text, Loader=_Loader)
    except yaml.YAMLError as exc:
        raise ModelError([_syntax_problem(exc, file)]) from None
    except _TooMany as exc:
        raise ModelError(
            [
                (
                    Location(file, exc.mark.line + 1, exc.mark.column + 1),
                    f"more than {MAX_NODES} YAML nodes; refused",
                )
            ]
        ) from None
    except _TooDeep as exc:
        raise ModelError(
            [
                (
                    Location(file, exc.mark.line + 1, exc.mark.column + 1),
                    f"lists and mappings nested more than {MAX_DEPTH} deep; refused",
                )
            ]
        ) from None
    except RecursionError:
        raise ModelError(
            [(Location(file, 1, 1), "lists and mappings nested too deeply; refused")]
        ) from None
    if root is None:
        raise ModelError(
            [
                (
                    Location(file, 1, 1),
                    "the file has no content (only comments or "
                    "blank lines); expected a mapping with at "
                    "least links and joints",
                )
            ]
        )
    start = Location(file, root.start_mark.line + 1, root.start_mark.column + 1, "")
    if _count_nodes(root, MAX_NODES) > MAX_NODES:
        raise ModelError(
            [
                (
                    start,
                    f"more than {MAX_NODES} YAML nodes once aliases are expanded "
                    "(an alias bomb?); refused",
                )
            ]
        )
    ctx = _Context(file)
    _check_keys_and_duplicates(root, file, ctx.problems)
    ctx.problems.raise_if_any()
    top = Entry(root, start, ctx)
    if not top.is_mapping:
        raise ModelError(
            [
                (
                    top.where,
                    "the file must be a mapping of keys (name, units, links, "
                    f"joints, ...), got {_describe(root)}",
                )
            ]
        )
    return top


def build(top: Entry, parameters: Mapping[str, float] | None = None) -> Model:
    """The model of a composed tree, with ``parameters`` replacing the values of
    the file's parameters of those names (numbers in the file's units; the
    parameters computed from them follow).  Raises :class:`ModelError`."""
    ctx = _Context(top.ctx.file)
    ctx.overrides = dict(parameters or {})
    return _Builder(Entry(top.node, top.where, ctx), ctx).build()


def _syntax_problem(exc: yaml.YAMLError, file: str) -> tuple[Location, str]:
    """``(location, message)`` of a PyYAML error, with the construct it was reading."""
    mark = getattr(exc, "problem_mark", None)
    problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
    loc = Location(file, mark.line + 1, mark.column + 1) if mark else Location(file)
    context, cmark = getattr(exc, "context", None), getattr(exc, "context_mark", None)
    message = f"YAML syntax error: {problem}"
    if problem.startswith("found character '\\t'"):
        return loc, "YAML syntax error: a tab character; indent with spaces"
    if context and not context.startswith("while "):
        message = f"YAML syntax error: {context}, {problem}"
    elif (
        context
        and cmark is not None
        and (mark is None or cmark.line != mark.line or cmark.column != mark.column)
    ):
        context = (
            context.removeprefix("while ")
            .replace("parsing ", "in ", 1)
            .replace("scanning ", "in ", 1)
        )
        message += f" ({context} that starts at line {cmark.line + 1}, column {cmark.column + 1})"
    return loc, message


class _Builder:
    """Reads the top-level sections in dependency order.

    A declared item that cannot be built (its problem reported) is remembered
    in ``broken``; later references to it stay silent, so one mistake gives
    one line rather than a cascade.
    """

    def __init__(self, top: Entry, ctx: _Context):
        self.top, self.ctx, self.problems = top, ctx, ctx.problems
        self.names: dict[str, tuple[str, Location]] = {}  # name -> (what, where first named)
        self.broken: dict[str, set[str]] = {
            "link": set(),
            "joint": set(),
            "driver": set(),
            "load": set(),
        }
        self.ground: str | None = None
        self.lost: set[str] = set()  # kinds whose whole section is missing or unreadable
        self.sketch_where: dict[str, Location] = {}  # sketch key -> where written
        self.pins: dict[str, list[str]] = {}  # pin -> the revolutes it expands to
        self.generated: dict[str, tuple[str, str, str]] = {}  # revolute -> (pin, hub, link)

    def build(self) -> Model:
        top = self.top
        top.check_keys(required=("links", "joints"), optional=TOP_KEYS)
        name = top["name"].text() if top.get("name") else "mechanism"
        unit_names = self._units()
        self._parameters()
        gravity = np.array([0.0, -9.81])
        if (g := top.get("gravity")) is not None:
            gravity = g.vector(None, bound="acceleration")
            if gravity is None:
                gravity = np.array([0.0, -9.81])
        links = self._links(gravity)
        points = {link.name: dict(link.points) for link in links}
        joints = self._joints(links, points)
        drivers = self._drivers(links, joints, points)
        loads_ = self._loads(links, joints, points, drivers)
        sketch = self._sketch(links, joints)
        analysis = self._analysis(joints, drivers, links)
        loops = self._loops(joints)
        flywheel = self._flywheel()
        clearances = self._clearances(joints)
        self.problems.raise_if_any()
        model = Model(
            name=name or "mechanism",
            links=tuple(links),
            joints=tuple(joints),
            drivers=tuple(drivers),
            loads=tuple(loads_),
            gravity=gravity,
            sketch=sketch,
            analysis=analysis,
            loops=loops,
            parameters=dict(self.ctx.env),
            units=unit_names,
            source=self.ctx.file,
            flywheel=flywheel,
            sketch_where=self.sketch_where,
        )
        if clearances:
            from .clearance import expand

            model = expand(model, clearances)
        return model

    def _clearances(self, joints) -> list:
        """The ``clearance:`` section: {joint: {size, model, speed, acceleration,
        angle, contact}} (docs/clearance.md)."""
        from .clearance import Clearance
        from .contact import read_contact

        section = self.top.get("clearance")
        if section is None or not section.mapping():
            return []
        by_name = {j.name: j for j in joints}
        out = []
        for name, e in section.items():
            if not e.mapping():
                continue
            if name not in by_name:
                if not self._broken("joint", name):
                    section.error(self._not_a("joint", name, by_name))
                continue
            if by_name[name].kind != "revolute":
                e.error(f"clearance applies to a revolute; '{name}' is {by_name[name].kind}")
                continue
            e.check_keys(
                required=("size",), optional=("model", "speed", "acceleration", "angle", "contact")
            )
            size = e.require("size").number("length", minimum=0.0)
            kind = e["model"].text() if e.get("model") is not None else "prescribed"
            if kind not in (None, "prescribed", "contact"):
                e["model"].error(
                    f"unknown clearance model '{kind}'"
                    f"{did_you_mean(kind, ('prescribed', 'contact'))}; "
                    "known: contact, prescribed"
                )
                continue
            rates = {}
            for key in ("speed", "acceleration"):  # the angle unit per s, per s²
                rates[key] = e[key].number("angle") if e.get(key) is not None else 0.0
            angle = e["angle"].number("angle") if e.get("angle") is not None else None
            contact = None
            if kind == "contact":
                contact = read_contact(e.require("contact"))
            elif e.get("contact") is not None:
                e["contact"].error("contact applies to model: contact")
            if (
                size is None
                or kind is None
                or None in rates.values()
                or (kind == "contact" and contact is None)
            ):
                continue
            out.append(
                Clearance(
                    name, size, kind, rates["speed"], rates["acceleration"], angle, contact, e.where
                )
            )
        return out

    # -- names ----------------------------------------------------------------
    def _claim(self, section: Entry, name: str, what: str) -> bool:
        """Register ``name`` (a key of ``section``) as a ``what``; report a bad name."""
        where = section.key_where(name)
        if not NAME.match(name):
            fixed = re.sub(r"[^A-Za-z0-9_]", "_", name) or "_"
            fixed = "_" + fixed if fixed[0].isdigit() else fixed
            self.problems.add(
                where,
                f"{what} name '{name}' is not a valid name: use letters, "
                f"digits and _, not starting with a digit (e.g. '{fixed}')",
            )
        elif name in RESERVED:
            self.problems.add(
                where,
                f"'{name}' is a reserved name (a results column); "
                f"reserved: {', '.join(sorted(RESERVED))}",
            )
        elif name in self.names:
            other, first = self.names[name]
            if name in self.generated:
                pin, hub, link = self.generated[name]
                self.problems.add(
                    where,
                    f"duplicate name '{name}': the pin '{pin}' at line "
                    f"{first.line} names its revolute {hub}-{link} so; "
                    "rename one",
                )
            else:
                self.problems.add(
                    where,
                    f"duplicate name '{name}': the {other} at line "
                    f"{first.line} has it already; names must be unique "
                    "across links, joints, drivers and loads",
                )
        else:
            self.names[name] = (what, where)
            return True
        self.broken[what].add(name)
        return False

    def _broken(self, what: str, name: str) -> bool:
        """Whether ``name`` was declared as a ``what`` but is in error (already reported)."""
        return what in self.lost or name in self.broken[what]

    def _what(self, name: str) -> str | None:
        """What a name names (link, joint, driver, load), if anything."""
        return self.names[name][0] if name in self.names else None

    @staticmethod
    def _unknown(what: str, name: str, known: Iterable[str]) -> str:
        """``unknown link 'x' (did you mean 'y'?)``, or the list of choices when none is close."""
        known = list(known)
        hint = did_you_mean(name, known)
        if not hint:
            hint = f"; the {what}s are: {', '.join(known)}" if known else f"; there are no {what}s"
        return f"unknown {what} '{name}'{hint}"

    def _not_a(self, what: str, name: str, known: Iterable[str], links=()) -> str:
        """Why ``name`` is not a ``what``: it names something else, or nothing."""
        other = self._what(name)
        known = list(known)
        listing = f"; the {what}s are: {', '.join(known)}" if known else ""
        if what == "joint" and name in self.pins:
            return (
                f"'{name}' is a pin shared by {len(self.pins[name]) + 1} links, not one joint: "
                f"name one of its revolutes ({', '.join(self.pins[name])})"
            )
        if other is not None and other != what:
            return f"'{name}' is a {other}, not a {what}{listing}"
        owners = [link.name for link in links if name in link.points]
        if what == "link" and owners:
            return f"'{name}' is a point of link '{owners[0]}', not a link{listing}"
        return self._unknown(what, name, known)

    # -- sections ---------------------------------------------------------------
    def _units(self) -> dict[str, str]:
        spec: dict[str, str] = {}
        u = self.top.get("units")
        if u is None or not u.mapping():
            return spec
        for kind, e in u.items():
            if kind not in units.QUANTITY_KINDS:
                self.problems.add(
                    u.key_where(kind),
                    f"unknown quantity kind '{kind}'"
                    f"{did_you_mean(kind, units.QUANTITY_KINDS)}; "
                    f"known: {', '.join(units.QUANTITY_KINDS)}",
                )
                continue
            unit = e.text()
            if unit is None:
                continue
            try:
                self.ctx.units[kind] = units.factor(kind, unit)
            except units.UnitError as exc:
                e.error(str(exc))
                continue
            spec[kind] = self.ctx.unit_names[kind] = unit
        return spec

    def _parameters(self) -> None:
        """Evaluate the parameters in dependency order, each problem reported at its
        parameter; a parameter that uses a broken one is skipped silently."""
        p = self.top.get("parameters")
        overrides = self.ctx.overrides
        if p is None or not p.mapping():
            if overrides:
                self._unknown_overrides([])
            return
        broken = self.ctx.broken_parameters
        declared = p.keys()
        self._unknown_overrides(declared)
        pending: dict[str, tuple[Entry, str, list[str]]] = {}
        for key, e in p.items():
            where = p.key_where(key)
            if not NAME.match(key):
                self.problems.add(
                    where,
                    f"parameter name '{key}' is not a valid name: use "
                    "letters, digits and _, not starting with a digit",
                )
            elif key in expressions.FUNCTIONS:
                self.problems.add(
                    where, f"'{key}' is the name of a function; choose another parameter name"
                )
            elif not isinstance(e.node, yaml.ScalarNode) or e.node.value == "":
                e.error(f"expected a number or an expression, got {_describe(e.node)}")
            else:
                try:
                    used = sorted(expressions.names_in(e.node.value))
                except expressions.ExpressionError as exc:
                    e.error(_expression_message(exc))
                else:
                    if key in overrides:
                        pending[key] = (e, repr(float(overrides[key])), [])
                        continue
                    pending[key] = (e, e.node.value, [n for n in used if n in declared])
                    undefined = [
                        n for n in used if n not in declared and n not in expressions.CONSTANTS
                    ]
                    if not undefined:
                        continue
                    others = [k for k in declared if k != key]
                    e.error(
                        f"undefined parameter '{undefined[0]}'{did_you_mean(undefined[0], others)}"
                    )
                    del pending[key]
            broken.add(key)
        env: dict[str, float] = {}
        progress = True
        while pending and progress:
            progress = False
            for key, (e, text, deps) in list(pending.items()):
                if any(d in broken for d in deps):
                    broken.add(key)  # silent: the cause is reported
                elif all(d in env for d in deps):
                    try:
                        env[key] = expressions.evaluate(text, env)
                    except expressions.ExpressionError as exc:
                        e.error(_expression_message(exc))
                        broken.add(key)
                else:
                    continue
                del pending[key]
                progress = True
        reported: set[str] = set()
        for key in list(pending):  # what is left depends on a cycle
            if key in reported:
                continue
            path, node = [key], key
            while True:
                node = next(d for d in pending[node][2] if d in pending)
                if node in path:
                    cycle = path[path.index(node) :] + [node]
                    break
                path.append(node)
            if not reported & set(cycle):
                pending[cycle[0]][0].error(f"the parameters form a cycle: {' -> '.join(cycle)}")
            reported |= set(cycle)
        broken |= set(pending)
        self.ctx.env.update((k, env[k]) for k in declared if k in env)

    def _unknown_overrides(self, declared: list[str]) -> None:
        for key in self.ctx.overrides:
            if key not in declared:
                known = ", ".join(declared) or "none"
                self.problems.add(
                    Location(self.ctx.file, path="parameters"),
                    f"a variant sets the parameter '{key}', which the file does not "
                    f"declare{did_you_mean(key, declared)}; its parameters: {known}",
                )

    def _links(self, gravity: np.ndarray) -> list[Link]:
        section = self.top.get("links")
        if section is None or not section.mapping():
            self.lost.add("link")
            return []
        keys = section.keys()
        where = self.top.key_where("links")
        if not keys:
            self.problems.add(where, "no links: give the ground and the moving links")
            return []
        if len(keys) > MAX_LINKS:
            self.problems.add(where, f"{len(keys)} links; the limit is {MAX_LINKS}")
            return []
        if (g := self.top.get("ground")) is not None:
            name = g.text()
            if name is not None and name not in keys:
                g.error(
                    f"the ground link '{name}' is not among the links"
                    f"{did_you_mean(name, keys)}; the links are: {', '.join(keys)}"
                )
            elif name is not None:
                self.ground = name
        elif "ground" in keys:
            self.ground = "ground"
        else:
            self.problems.add(
                where,
                "no ground link: name a link 'ground', or give the "
                "top-level key 'ground: <link>' naming the frame",
            )
        links = []
        for name, e in section.items():
            link = None
            if self._claim(section, name, "link") and e.check_keys(
                optional=("points", "mass", "weight", "com", "inertia")
            ):
                link = self._link(name, e, gravity, section.key_where(name))
            if link is None:
                self.broken["link"].add(name)
            else:
                links.append(link)
        return links

    def _link(self, name: str, e: Entry, gravity: np.ndarray, where: Location) -> Link | None:
        is_ground = name == self.ground
        com = e["com"].vector("length") if e.get("com") is not None else np.zeros(2)
        raw: dict[str, np.ndarray] = {}
        ok = True
        if (pts := e.get("points")) is not None and pts.mapping():
            for pname, pe in pts.items():
                if not NAME.match(pname):
                    self.problems.add(
                        pts.key_where(pname),
                        f"point name '{pname}' is not a valid name: use letters, "
                        "digits and _, not starting with a digit",
                    )
                    ok = False
                    continue
                v = pe.vector("length")
                if v is None:
                    ok = False
                else:
                    raw[pname] = v
        elif pts is not None:
            ok = False
        mass = inertia = 0.0
        if e.get("mass") is not None and e.get("weight") is not None:
            e["weight"].error("give either mass or weight, not both")
            mass = None
        elif e.get("mass") is not None:
            mass = e["mass"].number("mass", minimum=0.0)
        elif e.get("weight") is not None:
            w = e["weight"].number("force", minimum=0.0)
            g = float(np.hypot(*gravity))
            if w is not None and w > 0 and g == 0.0:
                e["weight"].error(
                    "a weight needs a non-zero gravity to give a mass "
                    "(gravity is [0, 0]); give the mass instead"
                )
                w = None
            mass = None if w is None else (w / g if w else 0.0)
            if mass and not MAGNITUDE["mass"][0] <= mass <= MAGNITUDE["mass"][1]:
                e["weight"].error(
                    f"a weight of {w:g} N with |gravity| = {g:g} m/s^2 gives a mass "
                    f"of {mass:g} kg; the mass must be from "
                    f"{MAGNITUDE['mass'][0]:g} to {MAGNITUDE['mass'][1]:g} kg"
                )
                mass = None
        if e.get("inertia") is not None:
            inertia = e["inertia"].number("inertia", minimum=0.0)
        if is_ground and (mass or inertia):
            e.error("the ground link takes no mass or inertia")
        if com is None or mass is None or inertia is None or not ok:
            return None
        return Link(
            name,
            {k: v - com for k, v in raw.items()},
            float(mass),
            float(inertia),
            com,
            is_ground,
            where,
        )

    def _joints(self, links: list[Link], points) -> list[Joint]:
        section = self.top.get("joints")
        if section is None or not section.mapping():
            self.lost.add("joint")
            return []
        link_names = [link.name for link in links]
        joints = []
        for name, e in section.items():
            joint = None
            if self._claim(section, name, "joint") and e.mapping():
                if _is_pin(e):
                    pin = self._pin(name, e, links, link_names, points)
                    joints += pin or []
                    if pin is None:
                        self.broken["joint"].add(name)
                    continue
                joint = self._joint(name, e, links, link_names, points)
            if joint is None:
                self.broken["joint"].add(name)
            else:
                joints.append(joint)
        return joints

    def _joint(self, name: str, e: Entry, links, link_names, points) -> Joint | None:
        t = e.require("type")
        kind = t.text()
        if kind is None:
            return None
        if kind not in JOINT_TYPES:
            t.error(
                f"unknown joint type '{kind}'{did_you_mean(kind, JOINT_TYPES)}; "
                f"known: {', '.join(sorted(JOINT_TYPES))}"
            )
            return None
        le = e.require("links")
        pair = le.names(2)
        if None in pair:
            return None
        bad = False
        for k, ln in enumerate(pair):
            if ln not in link_names:
                if not self._broken("link", ln):
                    le._child(k, le.node.value[k]).error(self._not_a("link", ln, link_names, links))
                bad = True
        if bad:
            return None
        if pair[0] == pair[1]:
            le.error(f"both links are '{pair[0]}'; a joint connects two different links")
            return None
        try:
            return JOINT_TYPES[kind].from_spec(name, e, tuple(pair), points)
        except KinetostaticsError:
            raise
        except Exception as exc:  # a joint type's reader must not crash the loader
            e.error(
                f"cannot read this {kind} joint ({type(exc).__name__}: {exc}); "
                "this is a bug in the joint type, please report it"
            )
            return None

    def _pin(self, name: str, e: Entry, links, link_names, points) -> list[Joint] | None:
        """A pin shared by the links of ``links: [hub, a, b, ...]``: the revolutes
        ``<name>_a`` = [hub, a], ``<name>_b`` = [hub, b], ... at the points of
        ``points`` (default: the point ``<name>`` on each link), each with the
        pin's ``friction`` (docs/yaml.md, "Pins shared by three or more links")."""
        from .joints import Revolute

        e.check_keys(required=("type", "links"), optional=("points", "friction"))
        le = e["links"]
        items = le.seq() or []
        if len(items) < 2:
            le.error(
                f"a revolute connects two links, or three or more that share one pin; "
                f"got {len(items)}"
            )
            return None
        names = [x.text() for x in items]
        if None in names:
            return None
        bad = False
        for k, ln in enumerate(names):
            if ln not in link_names:
                if not self._broken("link", ln):
                    items[k].error(self._not_a("link", ln, link_names, links))
                bad = True
            elif ln in names[:k]:
                items[k].error(f"link '{ln}' is listed twice; each link of a pin once")
                bad = True
        pts = e["points"].names(len(names)) if e.get("points") is not None else [name] * len(names)
        rho = Revolute.friction_radius(e)
        if bad or None in pts or rho is None:
            return None
        hub = names[0]
        p_hub = e.point(hub, pts[0], points, key="points", index=0)
        out, gens = [], []
        for k in range(1, len(names)):
            gen = f"{name}_{names[k]}"
            p_k = e.point(names[k], pts[k], points, key="points", index=k)
            if gen in self.names:
                other, first = self.names[gen]
                self.problems.add(
                    self.top["joints"].key_where(name),
                    f"the pin's revolute {hub}-{names[k]} is named '{gen}', but the "
                    f"{other} at line {first.line} has that name; rename one",
                )
                bad = True
                continue
            self.names[gen] = ("joint", e.where)
            self.generated[gen] = (name, hub, names[k])
            gens.append(gen)
            if p_hub is not None and p_k is not None:
                out.append(
                    Revolute(
                        gen, (hub, names[k]), e.where, p_hub, p_k, (pts[0], pts[k]), float(rho)
                    )
                )
        self.pins[name] = gens
        if bad or len(out) != len(names) - 1:
            self.broken["joint"].update(gens)
            return None
        return out

    def _drivers(self, links, joints, points) -> list[Driver]:
        section = self.top.get("drivers")
        if section is not None and not section.mapping():
            self.lost.add("driver")
        if section is None or not section.mapping():
            return []
        drivers = []
        for name, e in section.items():
            driver = None
            if self._claim(section, name, "driver") and e.check_keys(
                required=("joint",), optional=("motion", "effort", "points", "balance_at")
            ):
                driver = self._driver(name, e, links, joints, points, section.key_where(name))
            if driver is None:
                self.broken["driver"].add(name)
            else:
                drivers.append(driver)
        return drivers

    def _driver(self, name: str, e: Entry, links, joints, points, where: Location) -> Driver | None:
        by_name = {j.name: j for j in joints}
        jname = e["joint"].text()
        joint = by_name.get(jname)
        if joint is None:
            if jname is not None and not self._broken("joint", jname):
                e["joint"].error(self._not_a("joint", jname, by_name))
            return None
        m, f = e.get("motion"), e.get("effort")
        if m is not None and f is not None:
            e.error(
                "give either motion (a prescribed coordinate) or effort (an applied "
                "torque or force), not both"
            )
            return None
        if m is None and f is None:
            e.error("give motion (a prescribed coordinate) or effort (an applied torque or force)")
            return None
        motion = effort = None
        if m is not None and m.is_mapping and m.get("law") is not None:
            motion = self._motion_law(m, joint, links)
            if motion is None:
                return None
        elif m is not None:
            if not m.check_keys(required=("speed",)):
                return None
            motion = self._constant_speed(m, joint)
            if motion is None:
                return None
        else:
            effort = self._effort(f, joint)
            if effort is None:
                return None
        pts: tuple[str | None, str | None] = (None, None)
        offset = 0.0
        if joint.angular:
            pts, offset = self._driver_offset(e, joint, joints, points)
            if offset is None:
                return None
        elif e.get("points") is not None:
            e["points"].error("points apply to a revolute driver only")
        balance = None
        if (b := e.get("balance_at")) is not None:
            balance = b.text()
            if balance is None:
                return None
            if balance not in by_name:
                if not self._broken("joint", balance):
                    b.error(self._not_a("joint", balance, by_name))
                return None
            if motion is None:
                b.error("balance_at needs a motion driver")
                return None
        return Driver(name, joint.name, motion, effort, offset, pts, balance, where)

    def _constant_speed(self, m: Entry, joint: Joint) -> MotionLaw | None:
        """``motion: {speed: v}``: constant speed, signed (rad/s or m/s)."""
        s = m["speed"]
        unit = self.ctx.unit_names.get("speed")
        if unit and units.is_angular_speed(unit) != joint.angular:
            if joint.angular:
                s.error(
                    f"the speed unit '{unit}' (units.speed) is linear, but joint "
                    f"'{joint.name}' is {joint.kind}: give units.speed as rpm, "
                    "rad/s, deg/s or rev/s"
                )
            else:
                s.error(
                    f"the speed unit '{unit}' (units.speed) is angular, but joint "
                    f"'{joint.name}' is {joint.kind}: give units.speed as m/s, "
                    "mm/s or cm/s"
                )
            return None
        v = s.number("speed", bounded=False)  # SPEED_RANGE below
        if v is not None and v == 0.0:
            s.error("the speed must not be zero (its sign gives the sense of motion)")
            return None
        if v is not None and not SPEED_RANGE[0] <= abs(v) <= SPEED_RANGE[1]:
            si = "rad/s" if joint.angular else "m/s"
            given = self.ctx.unit_names.get("speed", si)
            written = f"{v / self.ctx.units['speed']:g} {given}" + (
                f" ({v:g} {si})" if given != si else ""
            )
            s.error(
                f"the speed is {written}; its magnitude must be from "
                f"{SPEED_RANGE[0]:g} to {SPEED_RANGE[1]:g} {si}"
            )
            return None
        if v is None:
            return None
        return MotionLaw(v)

    def _motion_law(self, m: Entry, joint: Joint, links=()):
        """``motion: {law: constant | harmonic | polynomial | table, ...}`` (see docs/yaml.md)."""
        law = m["law"].text()
        keys = {
            "constant": (("speed",), ()),
            "harmonic": (("centre", "amplitude", "period"), ("phase",)),
            "polynomial": (("coefficients", "duration"), ()),
            "table": (("time", "value"), ("periodic",)),
        }
        if law not in keys:
            if law is not None:
                m["law"].error(
                    f"unknown motion law '{law}'{did_you_mean(law, keys)}; "
                    f"expected one of: {', '.join(keys)}"
                )
            return None
        required, optional = keys[law]
        if not m.check_keys(required=required, optional=("law",) + required + optional):
            return None
        if law == "constant":
            return self._constant_speed(m, joint)
        made = self._law(m, law, joint)
        return None if made is None or not self._law_in_range(m, made, joint, links) else made

    def _law_in_range(self, m: Entry, law, joint: Joint, links=()) -> bool:
        """A motion law's coordinate within :data:`MAGNITUDE`, its peak speed within
        :data:`SPEED_RANGE` (sampled over its duration), as for a constant speed, and the
        path it makes the driver travel within the sweep limits of a constant-speed driver
        (:data:`MAX_TURNS`, :data:`MAX_TRAVEL`): the positions are followed along it."""
        kind, si = ("angle", "rad/s") if joint.angular else ("length", "m/s")
        t = np.linspace(0.0, law.duration, 4097)
        with np.errstate(all="ignore"):
            psi, psi_d, psi_dd = (np.asarray(a, dtype=float) for a in law.value(0.0, t))
            peak = float(np.max(np.abs(psi_d)))
        if (
            not (
                np.all(np.isfinite(psi))
                and np.all(np.isfinite(psi_d))
                and np.all(np.isfinite(psi_dd))
            )
            or not SPEED_RANGE[0] <= peak <= SPEED_RANGE[1]
        ):
            m.error(
                f"the {law.kind} law reaches a speed of {peak:g} {si}; its peak speed must "
                f"be from {SPEED_RANGE[0]:g} to {SPEED_RANGE[1]:g} {si}"
            )
            return False
        if float(np.max(np.abs(psi_dd))) > MAX_LAW_ACCELERATION:
            m.error(
                f"the {law.kind} law reaches an acceleration of "
                f"{float(np.max(np.abs(psi_dd))):g} {si}^2; its magnitude must be at most "
                f"{MAX_LAW_ACCELERATION:g} {si}^2"
            )
            return False
        worst = float(np.max(np.abs(psi)))
        if joint.angular and worst > MAX_TURNS * 2 * np.pi:
            scale = self.ctx.units["angle"]
            unit = self.ctx.unit_names.get("angle", "rad")
            m.error(
                f"the {law.kind} law reaches {worst / scale:g} {unit}; a revolute driver's "
                f"coordinate must stay within ±{MAX_TURNS} turns "
                f"(±{MAX_TURNS * 2 * np.pi / scale:g} {unit}) of 0 (farther, the positions "
                "lose the precision they are solved to)"
            )
            return False
        if worst > MAGNITUDE[kind][1]:
            m.error(
                f"the {law.kind} law reaches {worst:g} {'rad' if joint.angular else 'm'}; "
                f"the magnitude of a driver coordinate must be at most {MAGNITUDE[kind][1]:g}"
            )
            return False
        path = float(np.sum(np.abs(np.diff(psi))))  # the travel, back and forth
        unit = self.ctx.unit_names.get(kind, units.SI_UNITS[kind])
        if problem := self._too_far(path / self.ctx.units[kind], kind, unit, links):
            m.error(
                f"the {law.kind} law moves the driver {path / self.ctx.units[kind]:g} "
                f"{unit} over its {'period' if law.cyclic else 'duration'}, {problem}"
            )
            return False
        return True

    def _law(self, m: Entry, law: str, joint: Joint):
        """The harmonic, polynomial or table law of ``motion:`` (its keys checked)."""
        kind = "angle" if joint.angular else "length"
        si = "rad" if joint.angular else "m"
        if law == "harmonic":
            centre, amplitude = m["centre"].number(kind), m["amplitude"].number(kind)
            period = m["period"].number("time", minimum=0.0, strict=True)
            phase = m["phase"].number("angle") if m.get("phase") is not None else 0.0
            if amplitude is not None and amplitude == 0.0:
                m["amplitude"].error("the amplitude must not be zero (the driver would not move)")
                return None
            if None in (centre, amplitude, period, phase):
                return None
            return HarmonicLaw(centre, amplitude, period, phase)
        if law == "polynomial":
            items = m["coefficients"].seq()
            duration = m["duration"].number("time", minimum=0.0, strict=True)
            if items is None or duration is None:
                return None
            if not 2 <= len(items) <= 11:
                m["coefficients"].error(
                    f"give from 2 to 11 coefficients c0, c1, … (ψ = c0 + c1·t + "
                    f"c2·t² + …), got {len(items)}"
                )
                return None
            raw = [x.raw_number() for x in items]
            if any(v is None for v in raw):
                return None
            scale, tscale = self.ctx.units[kind], self.ctx.units["time"]
            with np.errstate(all="ignore"):
                coef = tuple(
                    float(np.float64(v) * scale / np.float64(tscale) ** k)
                    for k, v in enumerate(raw)
                )
            for k, (x, c) in enumerate(zip(items, coef)):
                if not np.isfinite(c):  # the law's limits below bound the rest
                    x.error(
                        f"c{k} = {raw[k]:g} is too large: it overflows once converted "
                        f"to SI ({si}/s^{k})"
                    )
                    return None
            if not any(coef[1:]):
                m["coefficients"].error(
                    "the coefficients c1, c2, … are all zero: the driver would not move"
                )
                return None
            return PolynomialLaw(coef, duration)
        t_items, v_items = m["time"].seq(), m["value"].seq()
        periodic = m["periodic"].boolean() if m.get("periodic") is not None else False
        if t_items is None or v_items is None or periodic is None:
            return None
        if len(t_items) != len(v_items) or len(t_items) < 3:
            m.error(
                f"time and value need the same number of entries, at least 3 "
                f"(got {len(t_items)} and {len(v_items)})"
            )
            return None
        times = [x.number("time") for x in t_items]
        values = [x.number(kind) for x in v_items]
        if any(v is None for v in times + values):
            return None
        if np.any(np.diff(times) <= 0):
            m["time"].error("the times must increase")
            return None
        if periodic and abs(values[-1] - values[0]) > 1e-12 * max(map(abs, values)):
            m["value"].error(
                f"a periodic table must end where it starts: first value "
                f"{values[0]:g} {si}, last {values[-1]:g} {si} (SI)"
            )
            return None
        if periodic:
            values[-1] = values[0]  # equal to round-off (the unit conversion): made exact
        if np.ptp(values) == 0.0:
            m["value"].error("all values are equal: the driver would not move")
            return None
        try:
            return TableLaw(tuple(times), tuple(values), bool(periodic))
        except ValueError as exc:  # the spline refuses the points
            m.error(f"the table cannot be interpolated: {exc}")
            return None

    def _effort(self, f: Entry, joint: Joint) -> float | EffortLaw | None:
        """``effort:`` a number (constant), or one of ``{table: {at, value}}`` (over the
        driver coordinate), ``{motor: {torque, speed, slip}}`` (the linear motor curve
        τ(ω) = torque·[1 + (speed − ω)/(slip·speed)]) or ``{curve: {speed, torque}}``
        (τ tabulated over the driver speed)."""
        unit = "torque" if joint.angular else "force"
        if not f.is_mapping:
            return f.number(unit)
        kinds = ("table", "motor", "curve")
        if not f.check_keys(optional=kinds):
            return None
        given = [k for k in kinds if f.get(k) is not None]
        if len(given) != 1:
            f.error(
                "give a number, or exactly one of table (over the driver coordinate), "
                "motor (a linear motor curve) or curve (effort over the driver speed)"
            )
            return None
        e = f[given[0]]
        speed_kind = "speed"
        sunit = self.ctx.unit_names.get("speed")
        if (
            given[0] in ("motor", "curve")
            and sunit
            and units.is_angular_speed(sunit) != joint.angular
        ):
            e.error(
                f"the speed unit '{sunit}' (units.speed) does not suit {joint.kind} joint "
                f"'{joint.name}'"
            )
            return None
        if given[0] == "motor":
            if not e.check_keys(required=("torque", "speed", "slip")):
                return None
            torque, speed = e["torque"].number(unit), e["speed"].number(speed_kind)
            slip = e["slip"].number(None, minimum=0.0, strict=True)
            if speed is not None and speed == 0.0:
                e["speed"].error("the rated speed must not be zero (its sign gives the sense)")
                return None
            if None in (torque, speed, slip):
                return None
            return EffortLaw("motor", value=torque, speed=speed, slip=slip)
        keys = ("at", "value") if given[0] == "table" else ("speed", "torque")
        if not e.check_keys(required=keys):
            return None
        xs, ys = e[keys[0]].seq(), e[keys[1]].seq()
        if xs is None or ys is None:
            return None
        if len(xs) != len(ys) or len(xs) < 2:
            e.error(
                f"{keys[0]} and {keys[1]} need the same number of entries, at least 2 "
                f"(got {len(xs)} and {len(ys)})"
            )
            return None
        xkind = ("angle" if joint.angular else "length") if given[0] == "table" else speed_kind
        x = [v.number(xkind) for v in xs]
        y = [v.number(unit) for v in ys]
        if any(v is None for v in x + y):
            return None
        if np.any(np.diff(x) <= 0):
            e[keys[0]].error(f"the {keys[0]} values must increase")
            return None
        return EffortLaw(given[0], at=tuple(x), values=tuple(y))

    def _flywheel(self) -> FlywheelSpec | None:
        """``flywheel: {delta, ratio, friction}``: size a flywheel for δ (see docs/dynamics.md)."""
        f = self.top.get("flywheel")
        if f is None or not f.check_keys(
            required=("delta",), optional=("delta", "ratio", "friction")
        ):
            return None
        delta = f["delta"].number(None, minimum=0.0, strict=True)
        if delta is not None and not delta < 1.0:
            f["delta"].error(f"the coefficient of speed fluctuation must be below 1, got {delta:g}")
            delta = None
        ratio = None
        if f.get("ratio") is not None:
            ratio = f["ratio"].number(None, minimum=0.0, strict=True)
            if ratio is None:
                return None
        friction = f["friction"].boolean() if f.get("friction") is not None else False
        if delta is None or friction is None:
            return None
        return FlywheelSpec(delta, ratio, bool(friction), f.where)

    def _driver_offset(self, e: Entry, joint: Joint, joints, points):
        """(P_i, P_j) names and the offset α_j − α_i of the driver coordinate."""
        i, j = joint.links
        if self.ground is None:  # reported with the links
            return (None, None), None
        chosen: list[str | None] = [None, None]
        if (pe := e.get("points")) is not None:
            names = pe.names(2)
            if None in names:
                return (None, None), None
            chosen = [None if n in ("", "x", "+x") else n for n in names]
        angles = []
        for k, link in enumerate((i, j)):
            pname = chosen[k]
            if pname is None:
                if link == self.ground and k == 0:
                    angles.append(0.0)  # the global +x axis
                    continue
                others = [o for o in joints if link in o.links and o.name != joint.name]
                if len(others) != 1:
                    if not self.broken["joint"] and "joint" not in self.lost:
                        e.error(
                            f"cannot choose the driver's reference point on link '{link}' "
                            f"(it has {len(others)} other joints): give points: [P_i, P_j]"
                        )
                    return (None, None), None
                other = others[0]
                pname = _joint_point(other, link)
                chosen[k] = pname
            c = _joint_point_vec(joint, link)
            p = e.point(link, pname, points, key="points", index=k)
            if p is None or c is None:
                return (None, None), None
            d = p - c
            if not np.hypot(*d) > 0:
                e.error(
                    f"the driver's reference point '{pname}' on link '{link}' "
                    "coincides with the joint centre"
                )
                return (None, None), None
            angles.append(float(np.arctan2(d[1], d[0])))
        return (chosen[0], chosen[1]), angles[1] - angles[0]

    def _loads(self, links, joints, points, drivers) -> list[Load]:
        section = self.top.get("loads")
        if section is None or not section.mapping():
            return []
        out = []
        for name, e in section.items():
            load = None
            if self._claim(section, name, "load") and e.check_keys(
                required=("type", "link"), optional=("value", "table", "point", "axis", "active")
            ):
                load = self._load(name, e, links, joints, points, drivers, section.key_where(name))
            if load is None:
                self.broken["load"].add(name)
            else:
                out.append(load)
        return out

    def _load(
        self, name: str, e: Entry, links, joints, points, drivers, where: Location
    ) -> Load | None:
        link_names = {link.name: link for link in links}
        kinds = ("force", "torque", "resistance")
        kind = e["type"].text()
        if kind not in kinds:
            if kind is not None:
                e["type"].error(
                    f"unknown load type '{kind}'{did_you_mean(kind, kinds)}; "
                    "known: force, resistance, torque"
                )
            return None
        link = e["link"].text()
        if link not in link_names:
            if link is not None and not self._broken("link", link):
                e["link"].error(self._not_a("link", link, link_names, links))
            return None
        if link_names[link].ground:
            e["link"].error(
                f"a load on the ground link '{link}' does nothing; put it on a moving link"
            )
            return None
        point = None
        if (pe := e.get("point")) is not None:
            point = pe.text()
            if e.point(link, point, points, key="point") is None:
                return None
        if (e.get("value") is None) == (e.get("table") is None):
            e.error(
                "give exactly one of value (a constant) or table (values over the driver "
                "coordinate)"
            )
            return None
        table = None
        if e.get("value") is not None:
            value = (
                e["value"].vector("force")
                if kind == "force"
                else e["value"].number("torque" if kind == "torque" else "force")
            )
        else:
            table = self._table(e["table"], kind, joints, drivers)
            value = None if table is None else np.zeros(2 if kind == "force" else ())
        axis = None
        if kind == "resistance":
            if (ae := e.get("axis")) is None:
                e.error(
                    "a resistance needs axis: [x, y], the line along which it opposes "
                    "the point's velocity"
                )
                return None
            axis = ae.vector(None)
            axis = None if axis is None else ae.unit(axis)
            if axis is None:
                return None
        elif e.get("axis") is not None:
            e["axis"].error("axis applies to a resistance only")
        if kind == "torque" and point is not None:
            e["point"].error("a torque acts on the link, not at a point")
        conditions = self._conditions(e, link, point, points, drivers)
        if value is None or conditions is None:
            return None
        return Load(
            name,
            kind,
            link,
            np.asarray(value, dtype=float),
            point,
            axis,
            tuple(conditions),
            where,
            table,
        )

    def _table(self, e: Entry, kind: str, joints, drivers) -> tuple[np.ndarray, np.ndarray] | None:
        """``table: {at: [driver coordinates], value: [values]}``, sorted by coordinate."""
        if not e.check_keys(required=("at", "value")):
            return None
        motion = [d for d in drivers if d.motion is not None]
        joints = {j.name: j for j in joints}
        angular = not motion or joints[motion[0].joint].angular
        at_items, val_items = e["at"].seq(), e["value"].seq()
        if at_items is None or val_items is None:
            return None
        if len(at_items) != len(val_items) or len(at_items) < 2:
            e.error(
                f"at and value need the same number of entries, at least 2 "
                f"(got {len(at_items)} and {len(val_items)})"
            )
            return None
        at = [x.number("angle" if angular else "length") for x in at_items]
        unit = "force" if kind != "torque" else "torque"
        vals = [x.vector(unit) if kind == "force" else x.number(unit) for x in val_items]
        if any(v is None for v in at) or any(v is None for v in vals):
            return None
        at_arr = np.array(at, dtype=float)
        if np.any(np.diff(at_arr) <= 0):
            e["at"].error("the coordinates must increase")
            return None
        return at_arr, np.array(vals, dtype=float)

    def _point_ref(self, e: Entry, ref: str, points, allow_link: bool = False) -> bool:
        """Check ``link.point`` (or ``link`` alone when ``allow_link``); report a bad one."""
        link, dot, pname = ref.partition(".")
        if link not in points:
            if not self._broken("link", link):
                e.error(f"{self._not_a('link', link, points)} (in '{ref}', written link.point)")
            return False
        if not dot and not allow_link:
            e.error(f"'{ref}' is a link; write link.point")
            return False
        if dot and pname not in points[link]:
            e.error(
                f"link '{link}' has no point '{pname}'{did_you_mean(pname, points[link])}; "
                f"it has: {', '.join(points[link]) or 'no points'}"
            )
            return False
        return True

    def _conditions(
        self, e: Entry, link: str, point: str | None, points, drivers
    ) -> list[Condition] | None:
        ae = e.get("active")
        if ae is None:
            return []
        items = ae.seq()
        if items is None:
            return None
        out = []
        for c in items:
            if not c.check_keys(optional=("moving", "travel", "along", "angle", "point")):
                return None
            kinds = [k for k in ("moving", "travel", "angle") if c.get(k) is not None]
            if not kinds:
                c.error("a condition needs one of: moving, travel, angle")
                return None
            if len(kinds) > 1:
                c.error(
                    f"a condition takes exactly one of moving, travel, angle; this one has "
                    f"{' and '.join(kinds)} (write each condition as its own list item)"
                )
                return None
            kind = kinds[0]
            plink, pname = link, point
            if (pe := c.get("point")) is not None:
                ref = pe.text()
                if ref is None or not self._point_ref(pe, ref, points, allow_link=True):
                    return None
                plink, _, pname = ref.partition(".")
                pname = pname or None
            if kind == "moving":
                axis = c["moving"].vector(None)
                axis = None if axis is None else c["moving"].unit(axis)
                if axis is None:
                    return None
                out.append(Condition("moving", plink, pname, axis, None, c.where))
            elif kind == "travel":
                if c.get("along") is None:
                    c.error("travel needs along: [x, y], the direction of travel")
                    return None
                axis = c["along"].vector(None)
                axis = None if axis is None else c["along"].unit(axis)
                b = c["travel"].vector("length")
                if axis is None or b is None:
                    return None
                if not b[0] < b[1]:
                    scale = self.ctx.units["length"]
                    unit = self.ctx.unit_names.get("length", "m")
                    c["travel"].error(
                        f"the travel band [{b[0] / scale:g}, {b[1] / scale:g}] "
                        f"{unit} is empty: give [from, to] with from < to"
                    )
                    return None
                out.append(Condition("travel", plink, pname, axis, (b[0], b[1]), c.where))
            else:
                b = c["angle"].vector("angle")
                if b is None:
                    return None
                if not [d for d in drivers if d.motion is not None]:
                    if not self.broken["driver"] and "driver" not in self.lost:
                        c["angle"].error("an angle condition needs a motion driver")
                    return None
                first = next(d for d in drivers if d.motion is not None)
                if not isinstance(first.motion, MotionLaw):
                    c["angle"].error(
                        f"an angle condition needs a constant-speed driver; "
                        f"'{first.name}' follows a {first.motion.kind} law (use a "
                        "travel or moving condition)"
                    )
                    return None
                out.append(Condition("angle", bounds=(b[0], b[1]), where=c.where))
        return out

    def _sketch(self, links, joints) -> dict[str, np.ndarray]:
        section = self.top.get("sketch")
        if section is None or not section.mapping():
            return {}
        out = {}
        by_joint = [j.name for j in joints]
        pts = {link.name: link.points for link in links}
        for ref, e in section.items():
            where = section.key_where(ref)
            if "." in ref:
                if not self._point_ref(Entry(e.node, where, self.ctx), ref, pts):
                    continue
            elif ref in self.pins:  # a pin places all its revolutes
                v = e.vector("length")
                for gen in self.pins[ref] if v is not None else ():
                    out[gen] = v
                    self.sketch_where[gen] = where
                continue
            elif ref not in by_joint:
                if self._broken("joint", ref):
                    continue
                what = self._what(ref)
                head = (
                    f"'{ref}' is a {what}, not a joint"
                    if what and what != "joint"
                    else f"unknown joint '{ref}'{did_you_mean(ref, by_joint)}"
                )
                self.problems.add(
                    where,
                    f"{head}: a sketch key is a joint name ({', '.join(by_joint)}) or link.point",
                )
                continue
            v = e.vector("length")
            if v is not None:
                out[ref] = v
                self.sketch_where[ref] = where
        return out

    def _analysis(self, joints, drivers, links=()) -> Analysis:
        a = self.top.get("analysis")
        motion = [d for d in drivers if d.motion is not None]
        if motion and not isinstance(motion[0].motion, MotionLaw):
            return self._law_analysis(a, motion[0])
        if a is None or not a.check_keys(optional=("start", "sweep", "positions", "at", "events")):
            return Analysis()
        by_name = {j.name: j for j in joints}
        kind = "angle" if not motion or by_name[motion[0].joint].angular else "length"
        unit = self.ctx.unit_names.get(kind, units.SI_UNITS[kind])
        start = a["start"].number(kind) if a.get("start") is not None else 0.0
        sweep = None if kind == "length" else 2 * np.pi
        if (se := a.get("sweep")) is not None:
            raw = se.raw_number()
            sweep = None if raw is None else raw * self.ctx.units[kind]
            if raw is not None and not raw > 0:
                se.error(
                    f"the sweep must be positive, got {raw:g} {unit} (it is measured in "
                    "the sense of motion, which the sign of the driver's speed gives)"
                )
                sweep = None
            elif raw is not None and (problem := self._too_far(raw, kind, unit, links)):
                se.error(f"the sweep is {raw:g} {unit}, {problem}")
                sweep = None
        elif kind == "length":
            a.error("a prismatic driver needs analysis.sweep (the travel to analyse)")
        if kind == "angle" and start is not None:
            start = self._within_turns(
                a["start"] if a.get("start") is not None else a, start, "the start", unit
            )
            sense = np.sign(motion[0].motion.speed) if motion else 1.0
            if (
                start is not None
                and sweep is not None
                and (se := a.get("sweep")) is not None
                and self._within_turns(
                    se, start + sense * sweep, "the end of the sweep (start + sweep)", unit
                )
                is None
            ):
                sweep = None
        n = self._positions(a)
        at: tuple[float, ...] = ()
        if (ae := a.get("at")) is not None and (items := ae.seq()) is not None:
            vals = [e.number(kind, bounded=kind == "angle") for e in items]  # lengths: below
            if kind == "angle":
                vals = [
                    None if v is None else self._within_turns(e, v, "the position", unit)
                    for e, v in zip(items, vals)
                ]
            if kind == "length" and start is not None:
                for e, v in zip(items, vals):
                    scale = self.ctx.units[kind]
                    if v is not None and (
                        problem := self._too_far((v - start) / scale, kind, unit, links)
                    ):
                        e.error(
                            f"{v / scale:g} {unit} is {abs(v - start) / scale:g} {unit} "
                            f"from analysis.start ({start / scale:g} {unit}), {problem}"
                        )
            at = tuple(v for v in vals if v is not None)
        events = a["events"].boolean() if a.get("events") is not None else False
        return Analysis(start or 0.0, sweep or 2 * np.pi, n, at, bool(events))

    def _within_turns(self, e: Entry, value: float, what: str, unit: str) -> float | None:
        """``value`` (rad), a revolute driver's coordinate in a run, if within ±MAX_TURNS
        turns of 0: farther, its rounding (|value| × 2.2e-16) approaches the tolerance of the
        position solver (1e-12) and the positions no longer converge."""
        limit = MAX_TURNS * 2 * np.pi
        if abs(value) <= limit * (1 + 1e-12):
            return value
        scale = self.ctx.units["angle"]
        e.error(
            f"{what} is {value / scale:g} {unit}; a revolute driver's coordinate must stay "
            f"within ±{MAX_TURNS} turns (±{limit / scale:g} {unit}) of 0 over the run "
            "(farther, the positions lose the precision they are solved to)"
        )
        return None

    def _positions(self, a: Entry) -> int:
        """``analysis.positions`` (default 360)."""
        if (pe := a.get("positions")) is not None:
            v = pe.number(None)
            if v is not None and (v != int(v) or not 1 <= v <= MAX_POSITIONS):
                pe.error(f"positions must be a whole number from 1 to {MAX_POSITIONS}, got {v:g}")
            elif v is not None:
                return int(v)
        return 360

    def _law_analysis(self, a: Entry | None, driver: Driver) -> Analysis:
        """``analysis`` when the first driver follows a motion law: the law fixes where the run
        starts and what it covers, so only ``positions`` and ``events`` apply."""
        if a is None or not a.check_keys(optional=("start", "sweep", "positions", "at", "events")):
            return Analysis(driver.motion.start)
        for key in ("start", "sweep", "at"):
            if a.get(key) is not None:
                self.ctx.problems.add(
                    a.key_where(key),
                    f"{key} does not apply: driver '{driver.name}' follows a "
                    f"{driver.motion.kind} motion law, which gives the coordinate at every time "
                    f"(the run covers {'one period' if driver.motion.cyclic else 'its duration'}; "
                    "set analysis.positions, or analyze(..., times=...))",
                )
        n = self._positions(a)
        events = a["events"].boolean() if a.get("events") is not None else False
        return Analysis(driver.motion.start, 2 * np.pi, n, (), bool(events))

    def _too_far(self, raw: float, kind: str, unit: str, links) -> str | None:
        """Why a driver-coordinate range ``raw`` (file units) is too long to analyse, if it is:
        the path is followed in steps of 30 degrees, or of 30 degrees x the largest link."""
        span = abs(raw) * self.ctx.units[kind]
        if kind == "angle":
            if span > MAX_TURNS * 2 * np.pi:
                return (
                    f"more than the limit of {MAX_TURNS} turns "
                    f"({MAX_TURNS * 2 * np.pi / self.ctx.units[kind]:g} {unit})"
                )
            return None
        spans = [
            float(np.hypot(*np.ptp(np.array(list(link.points.values())), axis=0)))
            for link in links
            if len(link.points) > 1
        ]
        size = max(spans, default=0.0)
        if size == 0.0:
            return (
                "but no link has two points: the mechanism has no size to measure the "
                "travel of a prismatic driver by"
            )
        if span > MAX_TRAVEL * size:
            scale = self.ctx.units[kind]
            return (
                f"more than the limit of {MAX_TRAVEL} times the largest link "
                f"({size / scale:g} {unit})"
            )
        return None

    def _loops(self, joints):
        section = self.top.get("loops")
        if section is None or (items := section.seq()) is None:
            return None
        names = [j.name for j in joints]
        loops = []
        for e in items:
            seq = e.seq()
            if seq is None:
                continue
            loop = []
            for x in seq:
                t = x.text()
                if t is not None and t not in names and not self._broken("joint", t):
                    x.error(self._not_a("joint", t, names))
                loop.append(t)
            loops.append(tuple(loop))
        return tuple(loops)


def _is_pin(e: Entry) -> bool:
    """Whether a joint entry is a revolute whose ``links`` is not a pair (a pin shared
    by three or more links, or a list too short, reported by ``_pin``)."""
    t, links_ = e.get("type"), e.get("links")
    return (
        t is not None
        and isinstance(t.node, yaml.ScalarNode)
        and t.node.value == "revolute"
        and links_ is not None
        and isinstance(links_.node, yaml.SequenceNode)
        and len(links_.node.value) != 2
    )


def _joint_point(joint: Joint, link: str) -> str:
    names = getattr(joint, "point_names", None)
    if names:
        return names[joint.links.index(link)]
    axis = getattr(joint, "axis_names", None)
    if axis and axis[0] and link == joint.links[0]:  # a prismatic's axis is on link i
        return axis[0]
    return getattr(joint, "point_name", joint.name)


def _joint_point_vec(joint: Joint, link: str) -> np.ndarray | None:
    if hasattr(joint, "p_i"):
        return joint.p_i if link == joint.links[0] else joint.p_j
    return None


def _effort_spec(law: EffortLaw) -> dict[str, Any]:
    if law.kind == "constant":
        return law.value
    if law.kind == "motor":
        return {"motor": {"torque": law.value, "speed": law.speed, "slip": law.slip}}
    keys = ("at", "value") if law.kind == "table" else ("speed", "torque")
    return {law.kind: {keys[0]: list(law.at), keys[1]: list(law.values)}}


def dump(model: Model) -> str:
    """The model as YAML text in SI (a round trip through :func:`loads` gives an equal model).

    A model expanded with clearances is written as its ideal model plus the
    ``clearance:`` section that expands it again.
    """
    if model.ideal is not None:
        doc = yaml.safe_load(dump(model.ideal))
        doc["clearance"] = {}
        for c in model.clearances:
            spec = {
                "size": c.size,
                "model": c.model,
                "speed": c.speed,
                "acceleration": c.acceleration,
            }
            if c.angle is not None:
                spec["angle"] = c.angle
            if c.contact is not None:
                law = c.contact
                spec["contact"] = {
                    "journal_radius": law.journal_radius,
                    "young": list(law.young),
                    "poisson": list(law.poisson),
                    "restitution": law.restitution,
                    "floor": law.floor,
                    **({"stiffness": law.stiffness} if law.stiffness else {}),
                }
            doc["clearance"][c.joint] = spec
        return yaml.safe_dump(doc, sort_keys=False)
    doc: dict[str, Any] = {
        "name": model.name,
        "gravity": [float(g) for g in model.gravity],
        "ground": model.ground.name,
        "links": {},
        "joints": {},
    }
    for link in model.links:
        spec: dict[str, Any] = {
            "points": {k: [float(c) for c in v + link.com] for k, v in link.points.items()}
        }
        if not link.ground:
            spec.update(mass=link.mass, inertia=link.inertia, com=[float(c) for c in link.com])
        doc["links"][link.name] = spec
    for j in model.joints:
        doc["joints"][j.name] = {"type": j.kind, "links": list(j.links), **j.to_spec()}
    if model.drivers:
        doc["drivers"] = {}
        for d in model.drivers:
            spec = {"joint": d.joint}
            if d.motion is not None:
                spec["motion"] = (
                    {"speed": d.motion.speed}
                    if isinstance(d.motion, MotionLaw)
                    else d.motion.to_spec()
                )
            if isinstance(d.effort, EffortLaw):
                spec["effort"] = _effort_spec(d.effort)
            elif d.effort is not None:
                spec["effort"] = d.effort
            if d.points != (None, None):
                spec["points"] = [p or "x" for p in d.points]
            if d.balance_at:
                spec["balance_at"] = d.balance_at
            doc["drivers"][d.name] = spec
    if model.sketch:
        doc["sketch"] = {k: [float(c) for c in v] for k, v in model.sketch.items()}
    a = model.analysis
    motion = [d for d in model.drivers if d.motion is not None]
    if motion and not isinstance(motion[0].motion, MotionLaw):  # the law fixes start and span
        doc["analysis"] = {"positions": a.positions, "events": a.events}
    else:
        doc["analysis"] = {
            "start": a.start,
            "sweep": a.sweep,
            "positions": a.positions,
            "at": list(a.at),
            "events": a.events,
        }
    if model.flywheel is not None:
        f = model.flywheel
        doc["flywheel"] = {
            "delta": f.delta,
            "friction": f.friction,
            **({"ratio": f.ratio} if f.ratio is not None else {}),
        }
    return yaml.safe_dump(doc, sort_keys=False)
