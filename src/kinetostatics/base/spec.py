"""YAML with file locations: the reader that every section reader is built on.

A text is composed with PyYAML's safe composer (no tags, no object construction)
and its size, depth, node count and keys are checked (:func:`compose`); every node
keeps its line and column, so that every problem is reported as
``FILE:LINE:COL: key.path: message``.  An :class:`Entry` is a node with its
location; its typed readers (numbers with units and parameter expressions,
vectors, names) report problems to the collector of its :class:`_Context` and
return ``None``.  Problems are raised together as one
:class:`~kinetostatics.errors.ModelError`.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import yaml

from ..errors import Collector, Location, ModelError, did_you_mean
from . import expressions, units
from .limits import MAGNITUDE, MAX_DEPTH, MAX_FILE_BYTES, MAX_NODES

__all__ = [
    "Entry",
    "compose",
    "read_text",
    "NAME",
    "RESERVED",
    "describe_node",
    "expression_message",
]

NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
RESERVED = frozenset({"time", "angle", "stroke", "travel", "power", "friction", "shaking"})


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


def expression_message(exc: Exception) -> str:
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
            self.error(f"expected a mapping of keys, got {describe_node(self.node)}")
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
            self.error(f"expected a list, got {describe_node(self.node)}")
            return None
        return [self._child(k, n) for k, n in enumerate(self.node.value)]

    # -- scalars ------------------------------------------------------------
    def text(self) -> str | None:
        if not isinstance(self.node, yaml.ScalarNode) or self.node.value == "":
            self.error(f"expected a name, got {describe_node(self.node)}")
            return None
        return str(self.node.value)

    def boolean(self) -> bool | None:
        value = self.node.value if isinstance(self.node, yaml.ScalarNode) else None
        if isinstance(value, str) and value.lower() in ("true", "yes", "on", "false", "no", "off"):
            return value.lower() in ("true", "yes", "on")
        self.error(f"expected true or false, got {describe_node(self.node)}")
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
            self.error(f"expected a number or an expression, got {describe_node(self.node)}")
            return None
        text = self.node.value
        try:
            used = expressions.names_in(text)
        except expressions.ExpressionError as exc:
            self.error(expression_message(exc))
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
            self.error(expression_message(exc))
            return None

    def vector(self, kind: str | None, n: int = 2, bound: str | None = None) -> np.ndarray | None:
        """``n`` numbers of ``kind``; ``bound``: the :data:`MAGNITUDE` entry that limits them
        when it is not ``kind``'s (gravity: numbers in m/s², bounded as an acceleration)."""
        shape = "[x, y]" if n == 2 else f"a list of {n} numbers"
        if not isinstance(self.node, yaml.SequenceNode):
            self.error(f"expected {shape}, got {describe_node(self.node)}")
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
            self.error(f"expected a name, got {describe_node(self.node)}")
            return [None]
        if not isinstance(self.node, yaml.SequenceNode):
            self.error(f"expected a list of {n} names, got {describe_node(self.node)}")
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


def describe_node(node: yaml.Node) -> str:
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
                        f"a key must be a plain name, got {describe_node(k)}",
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


def compose(text: str, file: str = "<string>") -> Entry:
    """The checked YAML tree of a mechanism (syntax, size, keys), not yet built.

    :func:`kinetostatics.io.build` turns it into a model; a batch builds one tree many times
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
                    f"joints, ...), got {describe_node(root)}",
                )
            ]
        )
    return top


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
