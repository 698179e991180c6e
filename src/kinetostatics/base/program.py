"""Straight-line programs run position by position: the compiled backend's fused stages.

A stage traced into :class:`~kinetostatics.base.trace.Lines` (one operation a line,
``e<k> = a op b``) is *assembled* here into a table of operations on registers
(:func:`assembled`), and :func:`execute` — one numba kernel for every program, compiled
once and cached on disk as the joints' kernels are (base/kernels.py) — runs the table
over the positions in blocks (:func:`block`): each operation over one block's
registers, which stay in the first caches, instead of one whole-array NumPy call per
operation over all the positions (whose temporaries leave them) or one generated
function per system (which numba takes seconds to compile).  The operations are the
traced ones in their order on the same operands, each rounded as NumPy rounds it, so a
program gives its lines' numbers run over whole arrays (a compiler may still fuse a
multiply and an add: the compiled backend's contract is 1e-12 of each column's scale,
docs/python.md).

The lines a program takes (each written by its stage's generator):

- ``e<k> = a op b`` with ``op`` one of ``+ - * /``, ``e<k> = -a``, ``e<k> = abs(a)``,
  ``e<k> = sqrt(a)``, ``e<k> = max(a, b)`` (NaN when either is, as ``np.maximum``),
  ``e<k> = positive_or_one(a)`` (a where a > 0, else 1: ``np.where(a > 0, a, 1.0)``)
  and ``e<k> = finite_or_inf(a)`` (a where finite, else ∞), each operand a local or a
  number;
- ``e<k> = <input>[i, j]``: entry ``[i, j]`` of one of the inputs at the position, the
  inputs being ``(…, N)`` arrays named in :data:`INPUTS`;
- ``out[r] = a``: row r of the output ``(rows, N)`` at the position;
- ``check a <= x`` and ``check a != 0``: a position where it fails is counted (the
  caller then takes another path for the call).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from . import kernels

__all__ = ["Program", "assembled", "block", "execute", "run", "INPUTS"]

# the operations of a program (its table's first column)
(ADD, SUB, MUL, DIV, NEG, ABS, MAX, CONST, LOAD0, LOAD1, LOAD2, STORE, CHECK_LE, CHECK_NZ) = range(
    14
)
SQRT, POSITIVE, FINITE = range(14, 17)
INPUTS = ("PE", "psi_d", "psi_dd")
"""The inputs a program reads, in :func:`execute`'s order: the links' poses ``(n + 1, 5,
N)``, the motion drivers' ψ̇ and ψ̈ ``(n_d, 1, N)`` (component-major, every array of
three axes so that one kernel reads them all)."""
REGISTER_BYTES = 2**18
"""The registers of one block take about this much memory (they stay in the second-level
cache): 256 KiB, blocks of 64–1,024 positions (:func:`block`).  Over 36,000 positions
the slotting machine's derivative stage (55 registers) ran in 9.0 ms in blocks of 64,
6.2 ms of 256, 5.9 ms of 1,024 and 2,048: each output row is written in longer runs."""


def block(registers: int) -> int:
    """Positions per block for a program of ``registers`` registers."""
    return max(64, min(1024, REGISTER_BYTES // (8 * registers)))


_BINARY = {"+": ADD, "-": SUB, "*": MUL, "/": DIV}
_UNARY = {"abs": ABS, "sqrt": SQRT, "positive_or_one": POSITIVE, "finite_or_inf": FINITE}
_LINE = re.compile(
    r"^    (?:(?P<local>e\d+) = (?P<expr>.+)|out\[(?P<row>\d+)\] = (?P<stored>\S+)"
    r"|check (?P<checked>\S+) (?P<test><=|!=) (?P<limit>\S+))$"
)
_OPERAND = r"(e\d+|\(?-?[\d.e+-]+\)?|\(?-?inf\)?|nan)"
_EXPR = [
    (re.compile(rf"^{_OPERAND} ([-+*/]) {_OPERAND}$"), "binary"),
    (re.compile(r"^-(e\d+)$"), "neg"),
    (re.compile(rf"^(abs|sqrt|positive_or_one|finite_or_inf)\({_OPERAND}\)$"), "unary"),
    (re.compile(rf"^max\({_OPERAND}, {_OPERAND}\)$"), "max"),
    (re.compile(r"^(\w+)\[(\d+), (\d+)\]$"), "load"),
]


@dataclass(frozen=True, eq=False)
class Program:
    """An assembled program: ``ops (n_ops, 4)`` (operation, destination register, two
    operands: registers, or an input's entry), ``values (n_ops,)`` (a constant's value, a
    check's limit), the registers it needs and the rows of its output."""

    ops: np.ndarray
    values: np.ndarray
    registers: int
    rows: int


def _number(text: str) -> float:
    return float(text.strip("()"))


def assembled(lines: list[str], rows: int) -> Program:
    """The program of ``lines`` (see the module's docs) writing ``rows`` output rows; a
    register is reused once the value it held is read for the last time."""
    ops: list[list] = []  # [operation, destination name, operand, operand, value]
    consts: dict[str, str] = {}  # a number's text (−0 and 0 apart) -> its register's name

    def operand(text: str) -> str:
        if text.startswith("e"):
            return text
        x = _number(text)
        key = repr(x)
        name = consts.get(key)
        if name is None:
            name = consts[key] = f"c{len(consts)}"
            ops.insert(len(consts) - 1, [CONST, name, None, None, x])
        return name

    for line in lines:
        m = _LINE.match(line)
        if m is None:
            raise ValueError(f"not a line of a program: {line!r}")
        if m["row"] is not None:
            ops.append([STORE, None, operand(m["stored"]), int(m["row"]), 0.0])
        elif m["checked"] is not None:
            code = CHECK_LE if m["test"] == "<=" else CHECK_NZ
            ops.append([code, None, operand(m["checked"]), None, _number(m["limit"])])
        else:
            ops.append(_expression(m["local"], m["expr"], operand))
    return _allocated(ops, rows)


def _expression(local: str, expr: str, operand) -> list:
    for pattern, kind in _EXPR:
        m = pattern.match(expr)
        if m is None:
            continue
        if kind == "binary":
            return [_BINARY[m[2]], local, operand(m[1]), operand(m[3]), 0.0]
        if kind == "load":
            return [LOAD0 + INPUTS.index(m[1]), local, int(m[2]), int(m[3]), 0.0]
        if kind == "unary":
            return [_UNARY[m[1]], local, operand(m[2]), None, 0.0]
        code = NEG if kind == "neg" else MAX
        return [code, local, operand(m[1]), operand(m[2]) if kind == "max" else None, 0.0]
    raise ValueError(f"not an operation of a program: {expr!r}")


def _allocated(ops: list[list], rows: int) -> Program:
    """Registers for the named values: a constant keeps its own, any other value takes a
    register freed by a value read for the last time before it."""
    read = [[x for x in op[2:4] if isinstance(x, str)] for op in ops]
    last = {name: k for k, names in enumerate(read) for name in names}
    reg: dict[str, int] = {}
    free: list[int] = []
    count = 0
    table = np.zeros((len(ops), 4), dtype=np.int64)
    for k, (code, dst, a, b, _) in enumerate(ops):
        table[k, 0] = code
        for c, x in ((2, a), (3, b)):
            table[k, c] = reg[x] if isinstance(x, str) else (x if x is not None else 0)
        for x in dict.fromkeys(read[k]):  # freed after this operation: its destination may take one
            if last[x] == k and not x.startswith("c"):
                free.append(reg[x])
        if dst is not None:
            if dst not in last:  # never read: the traced lines were pruned of these
                raise ValueError(f"{dst} is written and never read")
            if free and not dst.startswith("c"):
                reg[dst] = free.pop()
            else:
                reg[dst], count = count, count + 1
            table[k, 1] = reg[dst]
    values = np.array([op[4] for op in ops], dtype=float)
    return Program(table, values, max(count, 1), rows)


def execute(ops, values, reg, PE, psi_d, psi_dd, out) -> int:  # noqa: C901, N803  a kernel: a branch per operation, plain arrays
    """Run the program ``ops``, ``values`` at every position of ``out (rows, N)``, in blocks
    of as many positions as the registers ``reg (registers, block)`` hold (its rows
    written where the program stores them); returns the failed checks' count."""
    n, size = out.shape[1], reg.shape[1]
    failed = 0
    for start in range(0, n, size):
        m = min(size, n - start)
        for k in range(ops.shape[0]):
            code, d, a, b = ops[k, 0], ops[k, 1], ops[k, 2], ops[k, 3]
            if code == ADD:
                for i in range(m):
                    reg[d, i] = reg[a, i] + reg[b, i]
            elif code == SUB:
                for i in range(m):
                    reg[d, i] = reg[a, i] - reg[b, i]
            elif code == MUL:
                for i in range(m):
                    reg[d, i] = reg[a, i] * reg[b, i]
            elif code == DIV:
                for i in range(m):
                    reg[d, i] = reg[a, i] / reg[b, i]
            elif code == NEG:
                for i in range(m):
                    reg[d, i] = -reg[a, i]
            elif code == ABS:
                for i in range(m):
                    reg[d, i] = abs(reg[a, i])
            elif code == MAX:
                for i in range(m):
                    x, y = reg[a, i], reg[b, i]
                    reg[d, i] = x if (x >= y or x != x) else y
            elif code == CONST:
                for i in range(m):
                    reg[d, i] = values[k]
            elif code == LOAD0:
                for i in range(m):
                    reg[d, i] = PE[a, b, start + i]
            elif code == LOAD1:
                for i in range(m):
                    reg[d, i] = psi_d[a, b, start + i]
            elif code == LOAD2:
                for i in range(m):
                    reg[d, i] = psi_dd[a, b, start + i]
            elif code == STORE:
                for i in range(m):
                    out[b, start + i] = reg[a, i]
            elif code == SQRT:
                for i in range(m):
                    reg[d, i] = np.sqrt(reg[a, i])
            elif code == POSITIVE or code == FINITE:  # the value where it is so, else 1 or ∞
                for i in range(m):
                    x = reg[a, i]
                    kept = x > 0.0 if code == POSITIVE else abs(x) < np.inf
                    reg[d, i] = x if kept else (1.0 if code == POSITIVE else np.inf)
            else:  # CHECK_LE, CHECK_NZ: a position failing its test counted
                for i in range(m):
                    x = reg[a, i]
                    failed += (not x <= values[k]) if code == CHECK_LE else (x == 0.0)
    return failed


def run(program: Program, inputs: tuple[np.ndarray, ...], out: np.ndarray) -> int:
    """:func:`execute` compiled (base/kernels.py), ``program`` over ``inputs`` (as
    :data:`INPUTS`) into ``out (program.rows, N)``; the failed checks' count."""
    reg = np.empty((program.registers, block(program.registers)))
    return kernels.compiled(execute)(program.ops, program.values, reg, *inputs, out)
