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
from dataclasses import dataclass

import numpy as np

from ..base import linalg
from ..base.arrays import entries_first
from ..base.trace import Lines, Sym, larger, magnitude, operand, pruned
from .newton import WHOLE_ARRAY_NAMES, block_condition, traced_condition

__all__ = ["RUNTIME", "TRACED_FROM", "WrittenInverse", "entry", "inverse_line"]

TRACED_FROM = 1024
"""Rows of a call from which a plan's substitutions run as lines written over the blocks'
entries that are not zero (a dyad's 6×6 inverse has 16 such entries, 5 of them ±1;
:mod:`.plan_solve`) rather than as products over whole blocks (``einsum``): below, the
lines' calls cost more than the products save.  The condition numbers are written as
lines at any number of rows: cheaper than ``condition_number``'s passes even over a few
rows (0.92–0.99× the analysis's time at 3 to 1,000 positions; docs/accuracy.md, §8)."""

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


@dataclass(frozen=True)
class WrittenInverse:
    """A group block's written inverse: the plan's ``call`` (it returns True where a
    matrix of the call was inverted again, by ``small_inverse``, LAPACK or the
    pseudo-inverse: then ``INV[g]`` may differ from ``pattern`` anywhere), the ``source``
    of ``INVERSE<g>``, and the inverse's entries as written (``pattern[i][j]``: a number,
    or None for an array read from ``INV[g]``)."""

    call: str
    source: list[str]
    pattern: list[list[float | None]]


def inverse_line(  # noqa: PLR0913  the block, where it is, and what is written of it
    env: dict,
    g: int,
    at: tuple[int, int, int],
    view: str,
    m: list[list],
    first,
    l_ref: float | None = None,
) -> WrittenInverse | None:
    """Group ``g``'s diagonal block (at ``at`` = (offset, rows, columns) of ``buf``,
    ``view`` the text of its ``(n, r, c)`` view) inverted into ``INV[g]`` by a function
    ``INVERSE<g>`` (the names it reads put into ``env``), its entries ``m`` (numbers, the
    plan's locals, :data:`RUNTIME`), ``first`` the numbers of a block of its kind (the
    start pose's: the row order of an elimination); None where it cannot be written (a
    block larger than 3×3 without ``first``, or a test on numbers alone fails: then
    ``small_inverse`` at every call).  With ``l_ref`` (one model's L_ref) the function
    also writes the block's condition number into ``CND[g]``
    (:func:`~.newton.condition_number`): traced from the same entries, the zeros and
    numbers folded (the same number to rounding: the inverse's squares summed by
    columns), and as ``condition_number`` computes it from the inverse written at the
    matrices inverted again (:func:`recondition`)."""
    n = len(m)
    if first is None:
        if n > 3:
            return None
        first = np.zeros((n, n))  # the adjugate has no row order
    inner = Lines("v")
    reads: dict[str, None] = {}  # the plan's locals the function takes, in order
    block = [
        [_leaf(inner, reads, at, i, j, x) for j, x in enumerate(row)] for i, row in enumerate(m)
    ]
    checks: list[tuple] = []
    inv = linalg.traced_inverse(block, first, checks.append)
    if inv is None:
        return None
    body = inner.take()
    fallback = _fallback(inner, checks)
    if fallback is None:
        return None
    body += inner.take() + [
        f"    out[{i}, {j}] = {operand(v)}"
        for i, row in enumerate(inv)
        for j, v in enumerate(row)
        if isinstance(v, Sym) or v != 0.0
    ]
    if l_ref is not None:  # traced, at any number of rows (fewer passes than its own)
        cond = traced_condition(inner, block, inv, l_ref, arrays=True)
        body += inner.take() + [f"    cnd[...] = {operand(cond)}"]
    body += fallback + _again(block, l_ref)
    env.update(_SCOPE)
    head = _head(env, g, block, first, l_ref, list(reads))
    cnd = [f"CND[{g}]"] if l_ref is not None else []
    call = f"INVERSE{g}({', '.join([view, f'INV[{g}]', 'buf', 'Z', *cnd, *reads])})"
    source = [*head, "    with np.errstate(all='ignore'):", *_indented(pruned(body, "v"))]
    pattern = [[None if isinstance(v, Sym) else float(v) for v in row] for row in inv]
    return WrittenInverse(
        call, [*source, "    return any(x is not None for x in redo)", ""], pattern
    )


def _leaf(inner: Lines, reads: dict, at: tuple, i: int, j: int, x):
    """Entry (i, j) of the block at ``at`` in the function: a plan's local it takes, read
    from the buffer (:data:`RUNTIME`), or a number."""
    if isinstance(x, Sym):
        reads[x.name] = None
        return inner.value(x.name)
    if x == RUNTIME:
        off, _, c = at
        return inner.value(f"buf[{off + i * c + j}]")
    return float(x)


def _again(block: list[list], l_ref: float | None) -> list[str]:
    """The lines inverting again the matrices with an entry not finite, and writing the
    condition numbers again where a matrix was (with ``l_ref``)."""
    out = []
    leaves = [x for row in block for x in row if isinstance(x, Sym)]
    if leaves:  # their sum is not finite where one is not (or where it overflows)
        total = " + ".join(x.name for x in leaves)
        out.append(f"    redo.append(again_where_not_finite(view, out, {total}, Z))")
    if l_ref is not None:
        out.append(f"    recondition(cnd, view, out, {l_ref!r}, redo, Z)")
    return out


def _head(  # noqa: PLR0913  what the function's first lines depend on
    env: dict, g: int, block: list[list], first, l_ref: float | None, reads: list[str]
) -> list[str]:
    """``INVERSE<g>``'s signature and, for a block larger than 3×3, ``small_inverse``'s own
    choice at the call: this elimination, or another, or LAPACK (then True)."""
    args = ["view", "out", "buf", "Z", *(["cnd"] if l_ref is not None else []), *reads]
    head = [f"def INVERSE{g}({', '.join(args)}):"]
    if len(block) > 3:
        env[f"PATTERN{g}"] = np.array([[not _zero(x) for x in row] for row in block])
        env[f"ORDER{g}"] = linalg.pivot_order(first)
        again = [] if l_ref is None else [f"        condition_into(cnd, view, out, {l_ref!r})"]
        head += [
            f"    if not eliminates(view, PATTERN{g}, ORDER{g}):",
            "        Z()",  # the whole block read, into an inverse of zeros
            "        out[...] = 0.0",
            "        invert(view, out)",
            *again,
            "        return True",
        ]
    return head + ["    redo = []"]


def condition_into(cnd: np.ndarray, a: np.ndarray, inv: np.ndarray, l_ref: float) -> None:
    """The condition numbers of the matrices ``a (N, n, n)`` and their inverses ``inv (n,
    n, N)`` into ``cnd (N,)``, as :func:`~.newton.condition_number` gives them."""
    cnd[...] = block_condition(entries_first(a), inv, l_ref)


def recondition(  # noqa: PLR0913  the block, its inverse and what was redone
    cnd: np.ndarray, a: np.ndarray, inv: np.ndarray, l_ref: float, redo: list, ready=None
):
    """The condition numbers ``cnd`` again, as :func:`~.newton.condition_number` gives
    them from the inverses ``inv`` written, at the matrices of ``a (N, n, n)`` inverted
    again (``redo``: the masks of the fallbacks, None where none was; ``ready`` as
    :func:`again_where_not_finite` has it)."""
    masks = [m for m in redo if m is not None]
    if masks:
        if ready is not None:
            ready()
        bad = np.logical_or.reduce(masks)
        cnd[bad] = block_condition(entries_first(a[bad]), inv[:, :, bad], l_ref)


def again_where_not_finite(
    a: np.ndarray, out: np.ndarray, total: np.ndarray, ready=None
) -> np.ndarray | None:
    """The matrices of ``a (N, n, n)`` whose entries' ``total`` is not finite (an entry
    not finite, or a sum that overflows) inverted again by ``small_inverse`` into ``out
    (n, n, N)``: an entry the written inverse multiplies by a folded zero would not carry
    its NaN (x·0 is written 0) as ``small_inverse`` does.  ``ready``: called before ``a``
    is read, where it is (the plan's buffers: :mod:`.plan_buffers`)."""
    bad = ~np.isfinite(total)
    if bad.any():
        if ready is not None:
            ready()
        out[:, :, bad] = entries_first(linalg.small_inverse(a[bad]))
        return bad
    return None


_SCOPE = {
    "np": np,
    "invert": linalg.small_inverse,
    "eliminates": linalg.eliminates,
    "lapack_where_pivots_fail": linalg.lapack_where_pivots_fail,
    "pinv_where_singular": linalg.pinv_where_singular,
    "again_where_not_finite": again_where_not_finite,
    "recondition": recondition,
    "condition_into": condition_into,
    "TRACED_FROM": TRACED_FROM,
    **WHOLE_ARRAY_NAMES,
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
            at = f"view, out.transpose(2, 0, 1), {det.name}, Z"
            return [f"    redo.append(pinv_where_singular({at}))"]
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
    at = f"view.transpose(1, 2, 0), out, {worst.name}, Z"
    return [f"    redo.append(lapack_where_pivots_fail({at}))"]
