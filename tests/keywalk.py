"""Instrumenting the loader: which keys it accepts, which numbers it reads and how
each is bounded (used by tests/io/test_hostile_keys.py and tests/io/test_fuzz.py)."""

from __future__ import annotations

import re
from collections import defaultdict
from contextlib import contextmanager

from kinetostatics.base import spec

NAMED = (
    "parameters",
    "links",
    "joints",
    "drivers",
    "loads",
    "elements",
    "clearance",
    "sketch",
    "units",
)


def pattern(path: str) -> str:
    """A key path with its names and indices made generic: ``links.rod.points.B[0]`` ->
    ``links.*.points.*[]``."""
    path = re.sub(r"\[\d+\]", "[]", path)
    if path.startswith("sketch."):  # a sketch key may be link.point
        return "sketch.*" + path[len(path.rstrip("[]")) :]
    parts = path.split(".")
    if parts and parts[0].split("[")[0] in NAMED and len(parts) > 1:
        parts[1] = "*" + parts[1][len(parts[1].split("[")[0]) :]
    if len(parts) > 3 and parts[0] == "links" and parts[2] in ("points", "counterweights"):
        parts[3] = "*" + parts[3][len(parts[3].split("[")[0]) :]
    return ".".join(parts)


class Walk:
    """What the loader did while instrumented."""

    def __init__(self):
        self.allowed: dict[str, set[str]] = defaultdict(set)  # mapping pattern -> keys accepted
        self.present: dict[str, set[str]] = defaultdict(set)  # mapping pattern -> keys given
        self.numbers: dict[str, set] = defaultdict(set)  # number pattern -> kinds
        self.read: dict[int, tuple] = {}  # id(node) -> (node, pattern): every number read
        self.checked: set[int] = set()  # id(node) of the numbers bounded by MAGNITUDE

    @property
    def unbounded(self) -> set[str]:
        """Patterns of the numbers read somewhere without a MAGNITUDE check."""
        return {p for k, (_, p) in self.read.items() if k not in self.checked}


@contextmanager
def instrumented():
    walk = Walk()
    Entry = spec.Entry
    check_keys, number, within, raw_number = (
        Entry.check_keys,
        Entry.number,
        Entry.within,
        Entry.raw_number,
    )

    def check_keys_(self, required=(), optional=()):
        p = pattern(self.where.path)
        walk.allowed[p] |= set(required) | set(optional)
        walk.present[p] |= set(self.keys())
        return check_keys(self, required, optional)

    def number_(self, kind, **kw):
        walk.numbers[pattern(self.where.path)].add(kind)
        return number(self, kind, **kw)

    def within_(self, value, kind, *a, **kw):
        walk.checked.add(id(self.node))
        return within(self, value, kind, *a, **kw)

    def raw_number_(self):
        walk.read[id(self.node)] = (self.node, pattern(self.where.path))
        return raw_number(self)

    Entry.check_keys, Entry.number, Entry.within, Entry.raw_number = (
        check_keys_,
        number_,
        within_,
        raw_number_,
    )
    try:
        yield walk
    finally:
        Entry.check_keys, Entry.number, Entry.within, Entry.raw_number = (
            check_keys,
            number,
            within,
            raw_number,
        )
