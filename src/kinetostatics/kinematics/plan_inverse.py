"""The kinematic plan's block inverses, written out once per system

:func:`~kinetostatics.base.linalg.small_inverse` finds, at every call, the nonzero
pattern of a group's diagonal blocks, the row order of their elimination and its
written plan, and reads each entry from Φ_q's buffer.  The plan knows much of that when
it is made: which entries a joint's traced formulas give (a revolute pair's ±1, a
prismatic pair's constant offsets are numbers) and which are never written (zero).
Here each block's inverse is traced (:func:`~kinetostatics.base.linalg.traced_inverse`,
the operations ``small_inverse`` runs) once, into a function of its own: the entries
that are numbers folded (x·1, 1/1, x − 0 cost nothing), the others read as the plan's
locals or from the buffer.  It gives ``small_inverse``'s numbers, a zero's sign aside,
wherever ``small_inverse`` would run that elimination — up to 3×3 always (the adjugate),
larger where the call's first matrix picks the traced row order and the elimination
pays (:func:`~kinetostatics.base.linalg.eliminates`) — and calls ``small_inverse``
elsewhere; a matrix failing a pivot check, or exactly singular, is inverted again as
``small_inverse`` does it, and so is a matrix with an entry not finite (a NaN that a
folded zero would not carry; tests/kinematics/test_plan_inverse.py compares them).
"""

from __future__ import annotations

import numbers

import numpy as np

from ..base import linalg
from ..base.arrays import entries_first
from ..base.trace import Lines, Sym, larger, magnitude, operand

__all__ = ["RUNTIME", "entry", "inverse_line"]

RUNTIME = "runtime"
"""An entry of Φ_q's buffer the plan knows only when it runs (a set evaluated through the
contract, or a sum of traced terms): read from the buffer."""


def entry(writes: list[tuple[str, object]] | str | None) -> object:
    """What a buffer slot holds after the plan's writes to it (``(op, value)`` in order,
    ``=`` or ``+=`` onto zeros; :data:`RUNTIME`; None for none): a number, a traced
    local, or :data:`RUNTIME` where a local would be summed."""
    if writes is None:
        return 0.0
    if writes == RUNTIME:
        return RUNTIME
    value: object = 0.0
    for op, v in writes:
        if op == "=" or (isinstance(value, numbers.Real) and value == 0.0):
            value = v  # 0 + x is x (a zero's sign aside)
        elif isinstance(v, numbers.Real) and isinstance(value, numbers.Real):
            value = value + v  # as NumPy adds them, element by element
        else:
            return RUNTIME
    return value


def inverse_line(
    env: dict, g: int, at: tuple[int, int, int], view: str, m: list[list], first
) -> tuple[str, list[str]] | None:
    """The plan's line inverting group ``g``'s diagonal block (at ``at`` = (offset, rows,
    columns) of ``buf``, ``view`` the text of its ``(n, r, c)`` view) into ``INV[g]``, and
    the source of the function ``INVERSE<g>`` it calls (the names it reads put into
    ``env``), its entries ``m`` (numbers, the plan's locals, :data:`RUNTIME`), ``first``
    the numbers of a block of its kind (the start pose's: the row order of an
    elimination); None where it cannot be written (a block larger than 3×3 without
    ``first``, or a test on numbers alone fails: then ``small_inverse`` at every call)."""
    n = len(m)
    if first is None:
        if n > 3:
            return None
        first = np.zeros((n, n))  # the adjugate has no row order
    off, _, c = at
    inner = Lines("v")
    reads: dict[str, None] = {}  # the plan's locals the function takes, in order

    def leaf(i: int, j: int, x):
        if isinstance(x, Sym):
            reads[x.name] = None
            return inner.value(x.name)
        if x == RUNTIME:
            return inner.value(f"buf[{off + i * c + j}]")
        return float(x)

    block = [[leaf(i, j, x) for j, x in enumerate(row)] for i, row in enumerate(m)]
    checks: list[tuple] = []
    inv = linalg.traced_inverse(block, first, checks.append)
    if inv is None:
        return None
    body = inner.take()
    fallback = _fallback(inner, checks)
    if fallback is None:
        return None
    body += inner.take()
    body += [
        f"    out[{i}, {j}] = {operand(v)}"
        for i, row in enumerate(inv)
        for j, v in enumerate(row)
        if isinstance(v, Sym) or v != 0.0
    ]
    body += fallback
    leaves = [x for row in block for x in row if isinstance(x, Sym)]
    if leaves:  # their sum is not finite where one is not (or where it overflows)
        total = " + ".join(x.name for x in leaves)
        body.append(f"    again_where_not_finite(view, out, {total})")
    env.update(_SCOPE)
    head = [f"def INVERSE{g}({', '.join(['view', 'out', 'buf', *reads])}):"]
    if n > 3:  # small_inverse's own choice: this elimination, or another, or LAPACK
        env[f"PATTERN{g}"] = np.array([[not _zero(x) for x in row] for row in block])
        env[f"ORDER{g}"] = linalg.pivot_order(first)
        head += [
            f"    if not eliminates(view, PATTERN{g}, ORDER{g}):",
            "        invert(view, out)",
            "        return",
        ]
    call = f"    INVERSE{g}({', '.join([view, f'INV[{g}]', 'buf', *reads])})"
    return call, [*head, "    with np.errstate(all='ignore'):", *_indented(body), ""]


def again_where_not_finite(a: np.ndarray, out: np.ndarray, total: np.ndarray) -> None:
    """The matrices of ``a (N, n, n)`` whose entries' ``total`` is not finite (an entry
    not finite, or a sum that overflows) inverted again by ``small_inverse`` into ``out
    (n, n, N)``: an entry the written inverse multiplies by a folded zero would not carry
    its NaN (x·0 is written 0) as ``small_inverse`` does."""
    bad = ~np.isfinite(total)
    if bad.any():
        out[:, :, bad] = entries_first(linalg.small_inverse(a[bad]))


_SCOPE = {
    "np": np,
    "invert": linalg.small_inverse,
    "eliminates": linalg.eliminates,
    "lapack_where_pivots_fail": linalg.lapack_where_pivots_fail,
    "pinv_where_singular": linalg.pinv_where_singular,
    "again_where_not_finite": again_where_not_finite,
}


def _zero(x) -> bool:
    return isinstance(x, numbers.Real) and x == 0.0


def _indented(lines: list[str]) -> list[str]:
    return ["    " + line for line in lines]


def _fallback(inner: Lines, checks: list[tuple]) -> list[str] | None:
    """The lines that invert again, as ``small_inverse`` does, the matrices its tests
    send to LAPACK (a pivot check above 1 / PIVOT_RATIO or NaN) or to the pseudo-inverse
    (a zero determinant), the tests written as ``small_inverse``'s elimination writes
    them; None where a test on numbers alone fails."""
    worst = None
    for test in checks:
        if test[0] == "det":
            det = test[1]
            if not isinstance(det, Sym):
                return None if det == 0 else []
            return ["    pinv_where_singular(view, out.transpose(2, 0, 1), " + det.name + ")"]
        _, pivot, below, recip = test
        if not below:  # 1, or NaN where the pivot is 0 or not finite
            t = pivot * recip
        else:
            t = magnitude(inner, pivot, "np.abs")
            for x in below:
                t = larger(inner, t, magnitude(inner, x, "np.abs"), "np.maximum")
            t = t * magnitude(inner, recip, "np.abs")
        if not isinstance(t, Sym):
            if not t <= 1.0 / linalg.PIVOT_RATIO:
                return None
            continue
        worst = t if worst is None else larger(inner, worst, t, "np.maximum")
    if worst is None:
        return []
    return [f"    lapack_where_pivots_fail(view.transpose(1, 2, 0), out, {worst.name})"]
