"""Sweeps: a declaration of parameter values → an ordered list of variants.

Pure: nothing here analyses.  A variant is ``(variant_id, {parameter: value})``
with values in the mechanism file's units.  A sweep is a sequence of *blocks*
combined by cartesian product, the first block outermost:

- ``grid: {K: [1.8, 2.0], H: {range: {from: 90, to: 110, step: 10}}}`` — every
  combination of its parameters;
- ``zip: {c: [100, 125], d: [100, 120]}`` — parallel lists of one length;
- ``random: {n: 100, seed: 1, params: {K: {uniform: [1.5, 2.5]}}}`` — samples
  from ``uniform [lo, hi]``, ``normal [mean, sd]``, ``loguniform [lo, hi]``,
  ``integers [lo, hi]`` (inclusive) or ``choice [v1, v2, ...]``, drawn with
  ``numpy.random.default_rng(seed)`` parameter by parameter in the written order;
- ``table: FILE.csv`` — one variant per row; a header of parameter names, an
  optional ``variant`` (or ``name``) column of ids, ``#`` comment lines, an
  empty cell keeps the file's value.

A parameter's values (in ``grid`` and ``zip``) are a number, a list of numbers,
or one of ``{values: [...]}``, ``{range: {from, to, step}}`` (``to`` included
when a step lands on it) and ``{linspace: {from, to, num}}``.

Variant ids are ``1 … N`` zero-padded to one width, or the table's ids when the
sweep is a single table with an id column.  On the command line,
:func:`from_options` turns ``--set NAME=SPEC`` (``a``, ``a,b,c``, ``a:b:n`` =
``n`` values from ``a`` to ``b``; with ``--random N``: ``a:b`` uniform, ``a,b,c``
a choice), ``--table`` and ``--random N --seed S`` into blocks the same way.

>>> grid = {"a": [1, 2], "b": {"linspace": {"from": 0, "to": 1, "num": 2}}}
>>> [v for _, v in expand([{"grid": grid}])]
[{'a': 1.0, 'b': 0.0}, {'a': 1.0, 'b': 1.0}, {'a': 2.0, 'b': 0.0}, {'a': 2.0, 'b': 1.0}]
"""

from __future__ import annotations

import csv
import itertools
import math
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from ..base.names import is_name
from ..errors import Location, did_you_mean
from .limits import (
    BYTES_PER_VARIANT,
    MAX_VARIANTS,
    SweepError,
    available_memory,
    check_size,
    gigabytes,  # noqa: F401 - sweeps.gigabytes, as before limits.py
)

__all__ = [
    "Variant",
    "SweepError",
    "load_sweep",
    "expand",
    "parse_set",
    "from_options",
    "read_table",
    "check_parameters",
    "MAX_VARIANTS",
    "BYTES_PER_VARIANT",
    "available_memory",
    "check_size",
]

Variant = tuple[str, dict[str, float]]
BLOCKS = ("grid", "zip", "random", "table")
DISTRIBUTIONS = ("uniform", "normal", "loguniform", "integers", "choice")
ID = re.compile(r"[A-Za-z0-9_.\-]+\Z")


# -- YAML with locations ---------------------------------------------------------------
@dataclass(frozen=True)
class Node:
    """A YAML value with where it was written (``value`` holds plain Python for
    scalars, a list of Node for sequences, a dict str → Node for mappings)."""

    value: Any
    where: Location

    def plain(self) -> Any:
        if isinstance(self.value, list):
            return [n.plain() for n in self.value]
        if isinstance(self.value, dict):
            return {k: n.plain() for k, n in self.value.items()}
        return self.value


def _node(y: yaml.Node, where: Location) -> Node:
    here = Location(where.file, y.start_mark.line + 1, y.start_mark.column + 1, where.path)
    if isinstance(y, yaml.MappingNode):
        out: dict[str, Node] = {}
        for k, v in y.value:
            key = str(k.value)
            out[key] = _node(v, here.child(key, k.start_mark.line + 1, k.start_mark.column + 1))
        return Node(out, here)
    if isinstance(y, yaml.SequenceNode):
        return Node([_node(v, here.child(i)) for i, v in enumerate(y.value)], here)
    return Node(yaml.SafeLoader("").construct_object(y), here)


def load_sweep(text: str, file: str, *, key: str | None = None) -> list[Node] | None:
    """The blocks of a sweep written in YAML ``text`` (a sweep file, or with
    ``key="sweep"`` the ``sweep:`` section of a mechanism file; ``None`` when
    that section is absent).  Blocks are returned in the order written."""
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 1 if mark else None
        raise SweepError(
            Location(file, line, mark.column + 1 if mark else None),
            f"not valid YAML: {getattr(exc, 'problem', exc)}",
        ) from None
    top = _node(root, Location(file)) if root is not None else Node(None, Location(file, 1, 1))
    if key is not None:
        if not isinstance(top.value, dict) or key not in top.value:
            return None
        top = top.value[key]
    if not isinstance(top.value, dict) or not top.value:
        raise SweepError(top.where, f"a sweep is a mapping of blocks ({', '.join(BLOCKS)})")
    for name, block in top.value.items():
        if name not in BLOCKS:
            raise SweepError(
                block.where,
                f"unknown sweep block '{name}'"
                f"{did_you_mean(name, BLOCKS)}; use {', '.join(BLOCKS)}",
            )
    return [Node({name: block}, block.where) for name, block in top.value.items()]


# -- values ----------------------------------------------------------------------------
def _number(n: Node, what: str = "a number") -> float:
    v = n.value
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise SweepError(n.where, f"expected {what}, got {v!r}")
    return float(v)


def _mapping(n: Node, required: Sequence[str], optional: Sequence[str] = ()) -> dict[str, Node]:
    """The entries of a mapping node (any keys when neither list is given)."""
    if not isinstance(n.value, dict):
        raise SweepError(
            n.where,
            f"expected a mapping{' with ' if required else ''}"
            f"{', '.join(required)}, got {n.plain()!r}",
        )
    for k, v in n.value.items():
        if (required or optional) and k not in (*required, *optional):
            raise SweepError(
                v.where,
                f"unknown key '{k}'"
                f"{did_you_mean(k, (*required, *optional))}; "
                f"expected {', '.join((*required, *optional))}",
            )
    for k in required:
        if k not in n.value:
            raise SweepError(n.where, f"missing '{k}' (expected {', '.join(required)})")
    return n.value


def _count(n: Node, what: str) -> int:
    v = n.value
    if isinstance(v, bool) or not isinstance(v, int) or v < 1:
        raise SweepError(n.where, f"{what} must be a positive whole number, got {v!r}")
    return v


def arange(start: float, stop: float, step: float) -> list[float]:
    """``start, start+step, …`` up to ``stop`` inclusive (within 1e-9 step).

    >>> arange(1.5, 2.0, 0.25)
    [1.5, 1.75, 2.0]
    """
    n = int(math.floor((stop - start) / step + 1e-9)) + 1
    return [start + k * step for k in range(max(n, 0))]


def _values(n: Node) -> list[float]:
    """A parameter's values: number, list, {values}, {range}, {linspace}."""
    if isinstance(n.value, list):
        if not n.value:
            raise SweepError(n.where, "an empty list of values")
        return [_number(v) for v in n.value]
    if not isinstance(n.value, dict):
        return [_number(n, "a number, a list, or one of values/range/linspace")]
    if len(n.value) != 1:
        raise SweepError(n.where, "give one of values, range, linspace")
    form, spec = next(iter(n.value.items()))
    if form == "values":
        if not isinstance(spec.value, list):
            raise SweepError(spec.where, f"expected a list of numbers, got {spec.plain()!r}")
        return _values(spec)
    if form == "range":
        m = _mapping(spec, ("from", "to", "step"))
        start, stop, step = (_number(m[k]) for k in ("from", "to", "step"))
        if step == 0 or (stop - start) * step < 0:
            raise SweepError(
                m["step"].where, f"step {step:g} does not lead from {start:g} to {stop:g}"
            )
        if (stop - start) / step + 1 > MAX_VARIANTS:
            raise SweepError(m["step"].where, f"more than {MAX_VARIANTS} values")
        check_size(int((stop - start) / step + 1 + 1e-9), m["step"].where, "the range")
        return arange(start, stop, step)
    if form == "linspace":
        m = _mapping(spec, ("from", "to", "num"))
        num = _count(m["num"], "num")
        if num > MAX_VARIANTS:
            raise SweepError(m["num"].where, f"more than {MAX_VARIANTS} values")
        check_size(num, m["num"].where, "the linspace")
        return [float(x) for x in np.linspace(_number(m["from"]), _number(m["to"]), num)]
    raise SweepError(
        spec.where,
        f"unknown form '{form}'"
        f"{did_you_mean(form, ('values', 'range', 'linspace'))}; "
        "use values, range or linspace",
    )


def _param_name(name: str, where: Location) -> str:
    if not is_name(name):
        raise SweepError(where, f"'{name}' is not a parameter name")
    return name


# -- blocks → partial variants (lists of {param: value}) ------------------------------
def _grid(n: Node) -> list[dict[str, float]]:
    m = _mapping(n, ())
    if not m:
        raise SweepError(n.where, "an empty grid")
    names = [_param_name(k, v.where) for k, v in m.items()]
    axes = [_values(v) for v in m.values()]
    if math.prod(len(a) for a in axes) > MAX_VARIANTS:
        raise SweepError(n.where, f"the grid has more than {MAX_VARIANTS} variants")
    check_size(math.prod(len(a) for a in axes), n.where, "the grid")
    return [dict(zip(names, combo)) for combo in itertools.product(*axes)]


def _zip(n: Node) -> list[dict[str, float]]:
    m = _mapping(n, ())
    if not m:
        raise SweepError(n.where, "an empty zip")
    cols = {_param_name(k, v.where): _values(v) for k, v in m.items()}
    lengths = {k: len(v) for k, v in cols.items()}
    if len(set(lengths.values())) > 1:
        raise SweepError(
            n.where,
            "zip lists differ in length: " + ", ".join(f"{k} {v}" for k, v in lengths.items()),
        )
    names = list(cols)
    check_size(next(iter(lengths.values())), n.where, "the zip")
    return [dict(zip(names, vals)) for vals in zip(*cols.values())]


def _pair(n: Node, form: str) -> tuple[float, float]:
    if not isinstance(n.value, list) or len(n.value) != 2:
        raise SweepError(n.where, f"{form} takes [a, b], got {n.plain()!r}")
    return _number(n.value[0]), _number(n.value[1])


def sample(rng: np.random.Generator, form: str, args: Sequence[float], n: int) -> np.ndarray:
    """``n`` draws of one distribution (the forms of the module docstring)."""
    if form == "uniform":
        return rng.uniform(args[0], args[1], n)
    if form == "normal":
        return rng.normal(args[0], args[1], n)
    if form == "loguniform":
        return np.exp(rng.uniform(np.log(args[0]), np.log(args[1]), n))
    if form == "integers":
        return rng.integers(int(args[0]), int(args[1]), n, endpoint=True).astype(float)
    return rng.choice(np.asarray(args, dtype=float), n)


def _distribution(name: str, n: Node) -> tuple[str, list[float]]:
    if isinstance(n.value, (list, int, float)) and not isinstance(n.value, bool):
        return "choice", _values(n)  # a fixed value or a list: a choice
    if not isinstance(n.value, dict) or len(n.value) != 1:
        raise SweepError(n.where, f"give one distribution: {', '.join(DISTRIBUTIONS)}")
    form, spec = next(iter(n.value.items()))
    if form not in DISTRIBUTIONS:
        raise SweepError(
            spec.where,
            f"unknown distribution '{form}'"
            f"{did_you_mean(form, DISTRIBUTIONS)}; "
            f"use {', '.join(DISTRIBUTIONS)}",
        )
    if form == "choice":
        return form, _values(spec)
    a, b = _pair(spec, form)
    bad = {
        "uniform": a >= b,
        "loguniform": not 0 < a < b,
        "integers": a > b or a != int(a) or b != int(b),
        "normal": b < 0,
    }[form]
    if bad:
        need = {
            "uniform": "lo < hi",
            "loguniform": "0 < lo < hi",
            "integers": "whole numbers lo <= hi",
            "normal": "[mean, sd] with sd >= 0",
        }[form]
        raise SweepError(spec.where, f"{form} of '{name}' needs {need}, got [{a:g}, {b:g}]")
    return form, [a, b]


def _random(n: Node) -> list[dict[str, float]]:
    m = _mapping(n, ("n", "seed", "params"))
    count = _count(m["n"], "n")
    if count > MAX_VARIANTS:
        raise SweepError(m["n"].where, f"more than {MAX_VARIANTS} variants")
    check_size(count, m["n"].where, "the random sample")
    seed = m["seed"].value
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise SweepError(m["seed"].where, f"seed must be a whole number >= 0, got {seed!r}")
    params = _mapping(m["params"], ())
    if not params:
        raise SweepError(m["params"].where, "no parameters to sample")
    rng = np.random.default_rng(seed)
    cols = {}
    for name, spec in params.items():
        form, args = _distribution(_param_name(name, spec.where), spec)
        cols[name] = sample(rng, form, args, count)
    return [{k: float(v[i]) for k, v in cols.items()} for i in range(count)]


def read_table(path: str | Path, where: Location | None = None) -> list[Variant]:
    """A CSV table of variants: ``[(id, {param: value})]`` (ids ``""`` when the
    table has no ``variant``/``name`` column).  Errors name ``FILE:LINE``."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except OSError as exc:
        raise SweepError(
            where or Location(str(path)), f"cannot read the table {str(path)!r}: {exc.strerror}"
        ) from None
    lines = [
        (k, line)
        for k, line in enumerate(text.splitlines(), 1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not lines:
        raise SweepError(
            Location(str(path)), "the table is empty: it needs a header of parameter names"
        )
    reader = csv.reader([line for _, line in lines])
    header = [h.strip() for h in next(reader)]
    at = lines[0][0]
    id_col = next((k for k, h in enumerate(header) if h in ("variant", "name")), None)
    for k, h in enumerate(header):
        if k != id_col and not is_name(h):
            raise SweepError(
                Location(str(path), at, None), f"column {k + 1}: '{h}' is not a parameter name"
            )
    if len(set(header)) != len(header):
        raise SweepError(Location(str(path), at), "a column name is repeated in the header")
    out: list[Variant] = []
    seen: set[str] = set()
    for (line, _), cells in zip(lines[1:], reader):
        loc = Location(str(path), line)
        if len(cells) != len(header):
            raise SweepError(loc, f"{len(cells)} cells for {len(header)} columns")
        values: dict[str, float] = {}
        vid = ""
        for k, (h, cell) in enumerate(zip(header, cells)):
            cell = cell.strip()
            if k == id_col:
                vid = cell
                if not ID.match(vid) or vid in seen:
                    raise SweepError(
                        loc,
                        f"variant id {vid!r} is "
                        + ("repeated" if vid in seen else "not made of letters, digits, _ . -"),
                    )
                seen.add(vid)
            elif cell:
                try:
                    values[h] = float(cell)
                except ValueError:
                    raise SweepError(loc, f"column '{h}': {cell!r} is not a number") from None
                if not math.isfinite(values[h]):
                    raise SweepError(loc, f"column '{h}': {cell!r} is not a finite number")
        out.append((vid, values))
    if not out:
        raise SweepError(Location(str(path), at), "the table has a header but no rows")
    return out


def _table(n: Node, base: Path) -> list[Variant]:
    if not isinstance(n.value, str):
        raise SweepError(n.where, f"table takes a CSV file name, got {n.plain()!r}")
    return read_table(base / n.value, n.where)


# -- combining -------------------------------------------------------------------------
def expand(blocks: Iterable[Node | Mapping[str, Any]], base: str | Path = ".") -> list[Variant]:
    """The variants of ``blocks`` (from :func:`load_sweep` or plain one-key
    mappings): the cartesian product of the blocks, first outermost.  Table
    files are read relative to ``base``."""
    parts: list[list[tuple[str, dict[str, float]]]] = []
    owner: dict[str, Location] = {}
    for block in blocks:
        if not isinstance(block, Node):
            block = _node(
                yaml.compose(yaml.safe_dump(dict(block), sort_keys=False)), Location("<sweep>")
            )
        ((form, spec),) = block.value.items()
        rows = (
            _table(spec, Path(base))
            if form == "table"
            else [("", r) for r in {"grid": _grid, "zip": _zip, "random": _random}[form](spec)]
        )
        for name in {k for _, r in rows for k in r}:
            if name in owner:
                raise SweepError(
                    spec.where, f"parameter '{name}' is swept twice (also at {owner[name]})"
                )
            owner[name] = spec.where
        parts.append(rows)
    if not parts:
        return []
    if math.prod(len(p) for p in parts) > MAX_VARIANTS:
        raise SweepError(
            next(iter(owner.values()), Location()),
            f"the sweep has more than {MAX_VARIANTS} variants",
        )
    check_size(math.prod(len(p) for p in parts), next(iter(owner.values()), Location()))
    combos = itertools.product(*parts)
    if len(parts) == 1 and all(vid for vid, _ in parts[0]):
        return [(vid, dict(values)) for vid, values in parts[0]]
    out = [{k: v for _, r in combo for k, v in r.items()} for combo in combos]
    width = len(str(len(out)))
    return [(f"{k:0{width}d}", v) for k, v in enumerate(out, 1)]


def parse_set(text: str, *, random: bool = False) -> tuple[str, Any]:
    """``--set NAME=SPEC`` → ``(name, block value)`` in the YAML forms.

    >>> parse_set("K=1.5:2.5:3")
    ('K', {'linspace': {'from': 1.5, 'to': 2.5, 'num': 3}})
    >>> parse_set("H=90,100")
    ('H', [90.0, 100.0])
    >>> parse_set("K=1.5:2.5", random=True)
    ('K', {'uniform': [1.5, 2.5]})
    """

    def bad(why: str) -> SweepError:
        return SweepError(Location("--set"), f"{text!r}: {why}")

    name, eq, spec = text.partition("=")
    name, spec = name.strip(), spec.strip()
    if not eq or not is_name(name):
        raise bad("expected NAME=VALUES, e.g. K=1.8,2.0 or K=1.5:2.5:11")

    def num(s: str) -> float:
        try:
            v = float(s)
        except ValueError:
            raise bad(f"'{s}' is not a number") from None
        if not math.isfinite(v):
            raise bad(f"'{s}' is not a finite number")
        return v

    if ":" in spec:
        parts = spec.split(":")
        if random and len(parts) == 2:
            lo, hi = num(parts[0]), num(parts[1])
            if lo >= hi:
                raise bad("a random range LO:HI needs LO < HI")
            return name, {"uniform": [lo, hi]}
        if random or len(parts) != 3:
            raise bad(
                "a range is FROM:TO:NUM"
                + (" (or LO:HI with --random)" if not random else "; with --random give LO:HI")
            )
        count = num(parts[2])
        if count != int(count) or count < 1:
            raise bad(f"NUM must be a whole number of values >= 1, got '{parts[2]}'")
        if count > MAX_VARIANTS:
            raise bad(f"NUM {parts[2]} is more than the limit of {MAX_VARIANTS} values")
        return name, {"linspace": {"from": num(parts[0]), "to": num(parts[1]), "num": int(count)}}
    values = [num(s) for s in spec.split(",")]
    if random:
        return name, {"choice": values}
    return name, values if len(values) > 1 else values[0]


def from_options(
    sets: Sequence[str] = (),
    table: str | None = None,
    random: int | None = None,
    seed: int | None = None,
) -> list[Node]:
    """The blocks of the command-line options: ``--set`` as a grid (or, with
    ``--random N``, as the sampled parameters), then ``--table``."""
    blocks: list[dict[str, Any]] = []
    if random is not None:
        if not 1 <= random <= MAX_VARIANTS:
            raise SweepError(
                Location("--random"), f"N must be from 1 to {MAX_VARIANTS}, got {random}"
            )
        if not sets:
            raise SweepError(
                Location("--random"), "needs --set NAME=LO:HI for each sampled parameter"
            )
        blocks.append(
            {
                "random": {
                    "n": random,
                    "seed": 0 if seed is None else seed,
                    "params": dict(parse_set(s, random=True) for s in sets),
                }
            }
        )
    elif seed is not None:
        raise SweepError(Location("--seed"), "is used with --random N")
    elif sets:
        grid = {}
        for s in sets:
            name, value = parse_set(s)
            if name in grid:
                raise SweepError(Location("--set"), f"'{name}' is set twice")
            grid[name] = value
        blocks.append({"grid": grid})
    out = [
        _node(yaml.compose(yaml.safe_dump(b, sort_keys=False)), Location("--set")) for b in blocks
    ]
    if table is not None:
        out.append(Node({"table": Node(table, Location("--table"))}, Location("--table")))
    return out


def check_parameters(variants: Sequence[Variant], declared: Iterable[str], file: str) -> None:
    """Fail fast, before any analysis, on a parameter the file does not declare."""
    declared = list(declared)
    known = set(declared)
    for _, values in variants:
        for name in values:
            if name not in known:
                raise SweepError(
                    Location(file, path="parameters"),
                    f"the sweep sets '{name}', which the file does not declare"
                    f"{did_you_mean(name, declared)}; its parameters: "
                    f"{', '.join(declared) or 'none'}",
                )
