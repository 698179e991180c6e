"""Straight-line source from scalar kernels (internal).

A joint type's compiled-backend kernels (``joints/``: ``jacobian_kernel``,
``gamma_kernel``…) are plain arithmetic on the entries of their arrays, position by
position.  Run once on :class:`Sym` entries instead of numbers, they *write* their
formulas: each operation becomes one line ``e<k> = a op b`` of a :class:`Lines`, the
operands named as they are in the generated function (a link's cos θ over all the
positions, a constant written exactly by ``repr``).  The lines, run over whole arrays,
are the kernel's operations in its order on the same operands — the same numbers to
the bit — without a Python call per formula or per entry.  An operation already
written (the same operator on the same operands) is not written again, so the kernels
of one function share their common terms (a prismatic pair's frame: its Jacobian's and
its γ's).  Operations on two numbers are done by Python at once (IEEE arithmetic, as
NumPy's over an array), and the identities x·1 = x, x ± 0 = x, 0 − x = −x, x·(−1) = −x
and x·0 = 0 are applied instead of written (a point on a link's x axis has a zero
coordinate, the ground's frame is (1, 0)): the values are the kernel's for every finite
x, a zero's sign aside (x·0 for an infinite or NaN x is NaN, which the other terms of
such a row carry anyway).
"""

from __future__ import annotations

import numbers
import re
from collections import Counter

import numpy as np

__all__ = [
    "Sym",
    "Lines",
    "Leaves",
    "operand",
    "pruned",
    "traced_kernel",
    "magnitude",
    "larger",
]


class Lines:
    """The lines written so far (``lines``, each indented by four spaces) and the name of
    each operation already written (``names``: its text -> its local)."""

    def __init__(self, prefix: str = "e"):
        self.lines: list[str] = []
        self.names: dict[str, str] = {}
        self.negated: dict[str, Sym] = {}  # a local written as −x -> x: −(−x) is x itself
        self.prefix = prefix

    def take(self) -> list[str]:
        """The lines written since the last take (the later ones still reuse their names)."""
        out, self.lines = self.lines, []
        return out

    def value(self, text: str) -> Sym:
        """The local set to the expression ``text`` (written once)."""
        name = self.names.get(text)
        if name is None:
            name = self.names[text] = f"{self.prefix}{len(self.names)}"
            self.lines.append(f"    {name} = {text}")
        return Sym(name, self)


def pruned(lines: list[str], prefix: str = "e") -> list[str]:
    """``lines`` without the traced locals (``<prefix><k> = …``) that nothing reads: a
    kernel's entry written as a zero (not scattered), a term only an identity read."""
    name = re.compile(rf"\b{prefix}\d+\b")
    defined = re.compile(rf"    ({prefix}\d+) = (.*)$")
    uses = Counter(name.findall("\n".join(lines)))
    keep = [True] * len(lines)
    changed = True
    while changed:
        changed = False
        for k in range(len(lines) - 1, -1, -1):
            m = defined.match(lines[k]) if keep[k] else None
            if m and uses[m.group(1)] == 1:  # its definition only
                keep[k], changed = False, True
                uses.subtract(name.findall(lines[k]))
    return [line for line, kept in zip(lines, keep) if kept]


def operand(x) -> str:
    """The text of an operand: a local's name, or a number written exactly."""
    if isinstance(x, Sym):
        return x.name
    if isinstance(x, numbers.Real):
        text = repr(float(x))
        return f"({text})" if text.startswith("-") or text in ("inf", "nan") else text
    raise TypeError(f"a traced kernel read {type(x).__name__}, not a number")


def magnitude(lines: Lines, x, fn: str = "abs"):
    """|x|: a number's at once, a local's by the call ``fn`` (``abs`` in a program of
    scalars, ``np.abs`` over whole arrays)."""
    return lines.value(f"{fn}({x.name})") if isinstance(x, Sym) else abs(x)


def larger(lines: Lines, a, b, fn: str = "max"):
    """The larger of ``a`` and ``b``, NaN where either is (as ``np.maximum``): two numbers'
    at once, else by the call ``fn`` (``max`` in a program, ``np.maximum`` over arrays)."""
    if isinstance(a, Sym) or isinstance(b, Sym):
        return lines.value(f"{fn}({operand(a)}, {operand(b)})")
    return a if (a >= b or a != a) else b


def _binary(op: str, a, b):
    """``a op b``, one of them a :class:`Sym`; an identity with a number (x·1, x ± 0, x·0
    and the like) is not written but given."""
    sym, num = (a, b) if isinstance(a, Sym) else (b, a)
    if isinstance(num, numbers.Real):
        known = _IDENTITY.get((op, num is b, float(num)))
        if known is not None:
            return known(sym)
    return sym.lines.value(f"{operand(a)} {op} {operand(b)}")


# (operator, the number on the right, its value) -> the result, given the other operand x
_IDENTITY = {
    ("*", True, 1.0): lambda x: x,
    ("*", False, 1.0): lambda x: x,
    ("/", True, 1.0): lambda x: x,
    ("*", True, -1.0): lambda x: -x,
    ("*", False, -1.0): lambda x: -x,
    ("+", True, 0.0): lambda x: x,
    ("+", False, 0.0): lambda x: x,
    ("-", True, 0.0): lambda x: x,
    ("-", False, 0.0): lambda x: -x,
    ("*", True, 0.0): lambda x: 0.0,
    ("*", False, 0.0): lambda x: 0.0,
}


class Sym:
    """A value of a traced kernel: the local ``name`` of :class:`Lines` ``lines``."""

    __slots__ = ("name", "lines")
    __array_ufunc__ = None  # NumPy's scalars and arrays defer to the operators below

    def __init__(self, name: str, lines: Lines):
        self.name = name
        self.lines = lines

    def __add__(self, other):
        return _binary("+", self, other)

    def __radd__(self, other):
        return _binary("+", other, self)

    def __sub__(self, other):
        return _binary("-", self, other)

    def __rsub__(self, other):
        return _binary("-", other, self)

    def __mul__(self, other):
        return _binary("*", self, other)

    def __rmul__(self, other):
        return _binary("*", other, self)

    def __truediv__(self, other):
        return _binary("/", self, other)

    def __rtruediv__(self, other):
        return _binary("/", other, self)

    def __mod__(self, other):
        return _binary("%", self, other)

    def __neg__(self):
        inner = self.lines.negated.get(self.name)
        if inner is not None:  # −(−x): x, the same bits (a negation is exact)
            return inner
        out = self.lines.value(f"-{self.name}")
        self.lines.negated[out.name] = self
        return out

    def __bool__(self):
        raise TypeError("a traced kernel branched on a value (its formulas must be plain)")


class Leaves:
    """A kernel's ``P (n + 1, 5, 1)`` or ``V (n + 1, 3, 1)`` when traced: entry ``[i, c,
    0]`` is component c of link i over all the positions, the local ``<array>[i, c]`` (of
    the component-major poses or rates) written at its first read; the ground's (the
    last link) are numbers: its pose (0, 0, 0, 1, 0), its rates 0."""

    def __init__(self, lines: Lines, array: str, n_links: int, ground: tuple):
        self.lines, self.array, self.ground = lines, array, n_links
        self.shape = (n_links + 1, len(ground), 1)
        self.at_ground = ground

    def __getitem__(self, key):
        i, c, _ = key
        if i == self.ground:
            return self.at_ground[c]
        return self.lines.value(f"{self.array}[{i}, {c}]")


def traced_kernel(kernel, out_shapes: tuple, *args) -> list[np.ndarray]:
    """The entries a kernel writes, traced: object arrays of ``out_shapes`` (the
    positions' axis of length 1) holding a local or a number each."""
    outs = [np.empty(shape, dtype=object) for shape in out_shapes]
    kernel(*args, *outs)
    return outs
