"""YAML with file locations: the reader that every section reader is built on.

A text is composed (:mod:`.document`: PyYAML's safe composer, libyaml's where it can,
no tags, no object construction; size, depth, node count and keys checked); every node
keeps its line and column, so that every problem is reported as
``FILE:LINE:COL: key.path: message`` (an entry makes its location when it is first asked
for).  An :class:`Entry` is a node with its
location; its typed readers (numbers with units and parameter expressions,
vectors, names) report problems to the collector of its :class:`_Context` and
return ``None``.  Problems are raised together as one
:class:`~kinetostatics.errors.ModelError`.
"""

from __future__ import annotations

import threading
from collections.abc import Iterable

import numpy as np
import yaml

from ..errors import Collector, Location, did_you_mean
from . import expressions, units
from .keys import Keys
from .limits import MAGNITUDE
from .literals import KNOWN, known_vector, plain_number, remember
from .names import is_name, suggestion

__all__ = [
    "Entry",
    "RESERVED",
    "describe_node",
    "expression_message",
    "name_problem",
]

RESERVED = frozenset({"time", "angle", "stroke", "travel", "power", "friction", "shaking"})


def name_problem(what: str, name: str, *, expression: bool = False) -> str | None:
    """The message for a ``what`` (link, point, parameter, …) named ``name`` that is not a
    valid name (:mod:`.names`), with a valid one to use instead; None for a valid name.
    With ``expression`` (a parameter) the name must also be usable in an expression."""
    if is_name(name, expression=expression):
        return None
    if is_name(name):
        return (
            f"{what} name '{name}' is a Python keyword and cannot be used in an expression "
            f"(e.g. '{suggestion(name)}')"
        )
    return (
        f"{what} name '{name}' is not a valid name: use letters, digits and _, not starting "
        f"with a digit (e.g. '{suggestion(name)}')"
    )


class _Problems(Collector):
    """A collector that drops exact repeats (a missing key seen by two readers)."""

    def add(self, where: Location, message: str) -> None:
        if (where, message) not in self.problems:
            super().add(where, message)


class _Context:
    def __init__(self, file: str):
        self.file = file
        self.problems = _Problems()
        self.notes: list[tuple[Location, str]] = []  # what is allowed but implausible
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


_ABSENT = object()  # a key looked up and not there
_NONE: dict = {}  # an entry's tables before their first entry (never written)

# A tree is read by one builder at a time: its entries are kept from one reading to the
# next and carry the reading's context (Entry.rebuilt).
READING = threading.RLock()


def _where_of(
    pnode: yaml.Node, pwhere: Location, key: str | int, node: yaml.Node | None, kind: str
) -> Location:
    """The location of ``node`` (a key's value, or with ``kind="_ks_key"`` the key itself;
    None: absent) at ``key`` below the node ``pnode`` written at ``pwhere``, kept on
    ``pnode`` for the next variant.  Kept by the parent location's identity: a tree is
    re-read with the same locations, and a node reached through an alias has other ones."""
    cache = pnode.__dict__.get(kind)
    if cache is None:
        cache = pnode.__dict__[kind] = {}
    hit = cache.get((id(pwhere), key))
    if hit is not None and hit[0] is pwhere:
        return hit[1]
    if node is None:
        where = pwhere.child(key)
    else:
        m = node.start_mark
        where = pwhere.child(key, m.line + 1, m.column + 1)
    cache[(id(pwhere), key)] = (pwhere, where)  # holds the parent: its id stays
    return where


def _located(node: yaml.Node, up: tuple) -> Location:
    """The location of ``node`` from ``up``: (its parent's node, the parent's location or
    its own ``up``, its key); iterative."""
    chain = [(node, up)]
    while not isinstance(chain[-1][1][1], Location):
        pnode, pup, _ = chain[-1][1]
        chain.append((pnode, pup))
    where = None
    for n, (pnode, pwhere, key) in reversed(chain):
        where = _where_of(pnode, where if where is not None else pwhere, key, n, "_ks_where")
    return where


class Entry:
    """A YAML node with its location; typed readers report problems and return ``None``."""

    # slots: a file makes an entry for most of its nodes (about 1,200 for a 61-link chain)
    __slots__ = ("node", "_where", "ctx", "_up", "_kids", "_keys_at", "_vectors", "_keyed", "_root")

    def __init__(
        self,
        node: yaml.Node,
        where: Location | None,
        ctx: _Context,
        parent: Entry | None = None,
        key: str | int | None = None,
    ):
        # ``where`` None: the location below ``parent`` at ``key``, made when it is first
        # asked for (most entries of a file that reads well are never asked); the entry
        # keeps the parent's node and its location, or what makes it (no reference to
        # the parent: no cycle)
        self.node, self._where, self.ctx = node, where, ctx
        self._up = None if parent is None else (parent.node, parent._where or parent._up, key)
        # made when first written (most entries are scalars that keep none of them):
        self._kids: dict = _NONE  # key -> child entry (or _ABSENT), kept for the next build
        self._keys_at: dict[str, Location] = _NONE  # key -> where the key is written
        self._vectors: dict[tuple, np.ndarray] = _NONE  # a vector of numbers without names
        self._keyed: dict | None = None  # the node's _index(), once asked for

    def rebuilt(self, ctx: _Context) -> Entry:
        """This entry for another reading of the tree (a batch's next variant): an entry
        kept for that, whose children are kept as they are met and take ``ctx`` as they are
        reached through it — one reading at a time (:data:`READING`)."""
        root = getattr(self, "_root", None)  # the slot is empty until the first rebuild
        if root is None:
            root = self._root = Entry(self.node, self.where, ctx)
        root.ctx = ctx
        return root

    @property
    def where(self) -> Location:
        """Where the entry is written: ``file:line:col: key.path``."""
        where = self._where
        if where is None:
            where = self._where = _located(self.node, self._up)
            self._up = None
        return where

    # -- structure ----------------------------------------------------------
    def error(self, message: str) -> None:
        self.ctx.problems.add(self.where, message)

    def note(self, message: str) -> None:
        """A value allowed but implausible: a warning naming the key and its line."""
        self.ctx.notes.append((self.where, message))

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
        kid = self._kids.get(key)
        if kid is None or kid is _ABSENT or kid.node is not node:
            if self._kids is _NONE:
                self._kids = {}
            kid = self._kids[key] = Entry(node, None, self.ctx, self, key)
        else:
            kid.ctx = self.ctx
        return kid

    def _where_of(self, key: str | int, node: yaml.Node | None, kind: str) -> Location:
        """The location of ``node`` (a key's value, or with ``kind="_ks_key"`` the key
        itself; None: absent) below this entry (:func:`_where_of`)."""
        return _where_of(self.node, self.where, key, node, kind)

    def _index(self) -> dict[str, tuple[yaml.Node, yaml.Node]]:
        """Key -> (key node, value node) of a mapping (its first, as ``_pairs`` runs)."""
        index = self.node.__dict__.get("_ks_index")
        if index is None:
            index = {}
            for k, knode, v in self._pairs():
                index.setdefault(k, (knode, v))
            self.node._ks_index = index
        return index

    def key_where(self, key: str) -> Location:
        """The location of ``key`` itself (not of its value)."""
        where = self._keys_at.get(key)
        if where is None:
            found = self._index().get(key) if self.is_mapping else None
            where = self._where_of(key, None if found is None else found[0], "_ks_key")
            if self._keys_at is _NONE:
                self._keys_at = {}
            self._keys_at[key] = where
        return where

    def get(self, key: str) -> Entry | None:
        kid = self._kids.get(key)
        if kid is not None:
            if kid is _ABSENT:
                return None
            kid.ctx = self.ctx
            return kid
        index = self._keyed
        if index is None:  # the node's index, kept on the entry: the readers ask often
            index = self._keyed = self._index() if self.is_mapping else _NONE
        found = index.get(key)
        if found is None:
            if self._kids is _NONE:
                self._kids = {}
            self._kids[key] = _ABSENT
            return None
        return self._child(key, found[1])

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
        required, optional = tuple(required), tuple(optional)
        passed = self.node.__dict__.get("_ks_checked")
        if passed is not None and (required, optional) in passed:
            return True  # the keys are the node's own: a tree re-read passes again
        if not self.mapping():
            return False
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
        if ok:
            self.node.__dict__.setdefault("_ks_checked", set()).add((required, optional))
        return ok

    def check(self, keys: Keys) -> bool:
        """:meth:`check_keys` against a key table (:mod:`.keys`), the one the JSON Schema
        of a mechanism file is made from."""
        return self.check_keys(required=keys.required, optional=keys.names)

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

    def coefficient(self) -> float | None:
        """A friction coefficient: dimensionless, zero or positive; one above
        :data:`PLAUSIBLE_COEFFICIENT` is read, and noted as implausible."""
        value = self.number(None, minimum=0.0)
        if value is not None and value > PLAUSIBLE_COEFFICIENT:
            self.note(
                f"a friction coefficient of {value:g} is implausible (metal pairs, dry or "
                f"lubricated: 0.05-0.8); a percentage? {value:g} % is {value / 100:g}"
            )
        return value

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
        value = KNOWN.get(text)
        if value is not None:
            return value
        value = plain_number(text)  # most numbers of a file: no parse
        if value is not None:
            return remember(text, value)
        try:
            used = expressions.names_in(text)
        except expressions.ExpressionError as exc:
            self.error(expression_message(exc))
            return None
        if not used:  # a number (or an expression of numbers): the same in every build
            try:
                value = expressions.evaluate(text, {})
            except expressions.ExpressionError as exc:
                self.error(expression_message(exc))
                return None
            return remember(text, value)
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
        key = (kind, n, bound, self.ctx.units[kind] if kind else 1.0)
        kept = self._vectors.get(key)
        if kept is not None:
            return kept.copy()
        out = known_vector(self.node, n, key[3], bound or kind)
        if out is not None:  # numbers read before, within their limits: no entry per number
            if self._vectors is _NONE:
                self._vectors = {}
            self._vectors[key] = out.copy()
            return out
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
        if any(v is None for v in values):
            return None
        out = np.array(values, dtype=float)
        if all(e.node.value in KNOWN for e in items):  # the same in every build
            if self._vectors is _NONE:
                self._vectors = {}
            self._vectors[key] = out.copy()
        return out

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
        nodes = self.node.value
        if len(nodes) == n and all(isinstance(x, yaml.ScalarNode) and x.value for x in nodes):
            return [str(x.value) for x in nodes]  # what text() reads, without an entry each
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


PLAUSIBLE_COEFFICIENT = 1.0
"""Friction coefficients above this are read, and noted as implausible (a warning)."""


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

    def note(self, message: str) -> None:
        pass

    def mapping(self) -> bool:
        return False

    def check_keys(self, required: Iterable[str] = (), optional: Iterable[str] = ()) -> bool:
        return False

    def require(self, key: str) -> Entry:
        return _Missing(self, key)

    def check(self, keys: Keys) -> bool:
        return False

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
