"""A YAML text → the root :class:`~.spec.Entry` of a file: read with a size limit,
composed with PyYAML's safe composer (no tags, no object construction), and its depth,
node count and keys checked before any section is read.

The tree is composed by libyaml's composer (``yaml.CSafeLoader``) where PyYAML has it,
about ten times faster than PyYAML's own (its nodes have the same tags, values and
start marks); a text it refuses, or whose tree is deeper than :data:`MAX_DEPTH` or
larger than :data:`MAX_NODES`, is composed again by PyYAML's composer, whose messages
(and line and column) are the ones a user reads, so every refusal is the same with or
without libyaml.  libyaml's own nesting limit (1,000) keeps its recursive composer off
the C stack's end."""

from __future__ import annotations

import functools
import operator
import re
from pathlib import Path

import yaml

from ..errors import Collector, Location, ModelError
from .limits import MAX_DEPTH, MAX_FILE_BYTES, MAX_NODES
from .spec import Entry, _Context, describe_node

__all__ = ["compose", "read_text"]


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


_TAGS_MAX = 4096  # the tags of this many (kind, text, implicit) kept

if hasattr(yaml, "CSafeLoader"):

    class _CLoader(yaml.CSafeLoader):
        """libyaml's composer, which calls three resolver methods for every node it makes:
        without path resolvers (PyYAML's default) the first two do nothing and a node's
        tag depends on its kind and text alone, so they are C callables here — nothing
        done, the tags looked up in a table of the process — instead of a Python call
        each (~10 % of reading a file).  With path resolvers added, every tag is resolved
        as PyYAML does."""

        def __init__(self, stream):
            super().__init__(stream)
            if not self.yaml_path_resolvers:
                self.descend_resolver = operator.is_  # (parent, index): nothing to do
                self.ascend_resolver = tuple  # (): nothing to do
                self.resolve = _tag

    @functools.lru_cache(maxsize=_TAGS_MAX)
    def _tag(kind, value, implicit) -> str:
        """PyYAML's tag of a node without path resolvers (its implicit ones a class's)."""
        return yaml.resolver.BaseResolver.resolve(_PROBE, kind, value, implicit)

    _PROBE = yaml.CSafeLoader("")  # a resolver of the class's implicit resolvers

else:  # PyYAML without libyaml
    _CLoader = None
_PLAIN_RANGES = (
    (0x0A, 0x0A),
    (0x20, 0x3E),
    (0x40, 0x7E),
    (0xA0, 0xD7FF),
    (0xF900, 0xFEFE),
    (0xFF00, 0xFFFD),
)
"""The characters libyaml is given: where the two composers differ (tabs, carriage
returns, the other line breaks, a byte-order mark, control and private characters,
characters beyond the BMP, and ``?``, which libyaml accepts inside a flow mapping's
plain key where PyYAML refuses it) PyYAML's composer reads the text.  A text that is
not ASCII is checked character by distinct character: a pattern of these wide ranges
costs ``re`` 1.5–3 ms to compile, which every command reading such a file paid."""
_ASCII_NOT_PLAIN = re.compile("[\x00-\x09\x0b-\x1f\x3f\x7f]")  # the same, for ASCII


def _plain_text(text: str) -> bool:
    """Whether ``text`` has only characters of :data:`_PLAIN_RANGES`."""
    if text.isascii():
        return _ASCII_NOT_PLAIN.search(text) is None
    for ch in set(text):
        code = ord(ch)
        if not any(lo <= code <= hi for lo, hi in _PLAIN_RANGES):
            return False
    return True


def _within_limits(root: yaml.Node) -> bool:
    """Whether a composed tree is within :data:`MAX_NODES` (aliases counted each time)
    and no list or mapping is nested deeper than :data:`MAX_DEPTH` (counted as
    :class:`_Loader` counts it, an alias's levels included: a stricter count, so that a
    tree this passes is one that :class:`_Loader` accepts), and it has no empty scalar
    (libyaml marks an empty value in a flow mapping one column later).  Iterative; the
    scalars of a list or mapping are looked at in place, never stacked."""
    if isinstance(root, yaml.ScalarNode):
        return bool(root.value)
    count, stack = 1, [(root, 1)]
    scalar, mapping = yaml.ScalarNode, yaml.MappingNode
    while stack:
        n, depth = stack.pop()
        if depth > MAX_DEPTH:
            return False
        children = [c for pair in n.value for c in pair] if isinstance(n, mapping) else n.value
        count += len(children)
        if count > MAX_NODES:
            return False
        for c in children:
            if isinstance(c, scalar):
                if not c.value:
                    return False
            else:
                stack.append((c, depth + 1))
    return True


def _compose_fast(text: str) -> tuple[bool, yaml.Node | None]:
    """``(True, root)`` composed by libyaml when it is there, accepts the text and the
    tree is within the limits; ``(False, None)`` when PyYAML's composer must do it."""
    if _CLoader is None or not _plain_text(text):
        return False, None
    try:
        root = yaml.compose(text, Loader=_CLoader)
    except Exception:  # noqa: BLE001 (any refusal: PyYAML's composer says why)
        return False, None
    if root is not None and not _within_limits(root):
        return False, None
    return True, root


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


def _path(chain) -> str:
    """The key path of a chain ``(parent chain, key)`` (``None`` for the top): ``a.b[2].c``."""
    keys = []
    while chain is not None:
        chain, key = chain
        keys.append(key)
    text = ""
    for key in reversed(keys):
        if isinstance(key, int):
            text += f"[{key}]"
        else:
            text = f"{text}.{key}" if text else key
    return text


def _check_keys_and_duplicates(root: yaml.Node, file: str, problems: Collector) -> None:
    """Every mapping key must be a plain scalar and appear once; no application tags
    (``!!python/...``).  Iterative: no recursion; a node's key path is written out only
    for a problem."""
    stack: list[tuple[yaml.Node, object]] = [(root, None)]
    visited: set[int] = set()
    plain, mapping, sequence = _PLAIN_TAGS, yaml.MappingNode, yaml.SequenceNode
    scalar = yaml.ScalarNode
    while stack:
        node, chain = stack.pop()
        if id(node) in visited:  # an alias: its node was checked already
            continue
        visited.add(id(node))
        if node.tag not in plain:
            m = node.start_mark
            tag = str(node.tag).replace("tag:yaml.org,2002:", "!!", 1)
            problems.add(
                Location(file, m.line + 1, m.column + 1, _path(chain)),
                f"YAML tags such as '{tag}' are not allowed",
            )
            continue
        if isinstance(node, mapping):
            seen: dict[str, yaml.Node] = {}  # key -> its node (its line made for a message)
            children = []  # (a scalar of a plain tag has nothing to check)
            for k, v in node.value:
                if not isinstance(k, scalar):
                    m = k.start_mark
                    problems.add(
                        Location(file, m.line + 1, m.column + 1, _path(chain)),
                        f"a key must be a plain name, got {describe_node(k)}",
                    )
                    continue
                key = str(k.value)
                if key in seen:
                    m = k.start_mark
                    problems.add(
                        Location(file, m.line + 1, m.column + 1, _path((chain, key))),
                        f"duplicate key '{key}' (first given at line "
                        f"{seen[key].start_mark.line + 1})",
                    )
                else:
                    seen[key] = k
                if v.tag not in plain or not isinstance(v, scalar):
                    children.append((v, (chain, key)))
            stack.extend(reversed(children))
        elif isinstance(node, sequence):
            stack.extend(
                reversed(
                    [
                        (v, (chain, k))
                        for k, v in enumerate(node.value)
                        if v.tag not in plain or not isinstance(v, scalar)
                    ]
                )
            )


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
    fast, root = _compose_fast(text)
    try:
        if not fast:
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
    if not fast and _count_nodes(root, MAX_NODES) > MAX_NODES:
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
