"""The kinematic plan's substitutions: q̇ and q̈ by forward substitution over the groups

Written into the plan (:mod:`.plan`) two ways: as products over whole blocks
(:func:`substitution`, ``einsum`` over each group's inverse and coupling block, every
vector component-major), and, for long chunks of rows, as lines over the blocks' entries
that are not zero (:func:`traced_substitution`) — a dyad's 6×6 inverse has 16 such
entries, 5 of them ±1, and its coupling block a few, so that over thousands of rows the
lines cost about half the products (the slotting machine's kinematics at 36,000
positions ~0.8 of its time).  The lines run where no block of the chunk was inverted
again (:func:`either`): a fallback's inverse (LAPACK, the pseudo-inverse) has no zeros
known in advance.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.arrays import as_run
from ..base.trace import Lines, Sym, operand, pruned
from ..structure.system import System
from .plan_inverse import RUNTIME, TRACED_FROM, entry

__all__ = [
    "Written",
    "TRACED_FROM",
    "index",
    "substitution",
    "either",
    "traced_substitution",
    "traced_transposed",
    "transposed_in_runs",
    "traced_product",
    "product_in_runs",
]


def index(name: str, at: np.ndarray) -> str:
    """The text indexing the rows ``at`` (kept in the plan's names as ``name``): a slice
    where they run in order (a view: no gather, and a product can write into it)."""
    run = as_run(at)
    return f"{run.start}:{run.stop}" if isinstance(run, slice) else name


def substitution(system: System, x: str, rhs_of) -> list[str]:
    """``x`` by forward substitution over the groups, group g's right-hand side
    ``rhs_of(g)`` (as :meth:`BlockFactor.solve` runs it), every vector stored
    component-major (``(k, n)``: each component one contiguous run over the positions, as
    the blocks' inverses are; a product over them runs ~2.5–3.5× faster than over
    position-major vectors at 360 and 36,000 positions), into the caller's ``<x>T``."""
    layout = system.layout
    assert layout is not None
    lines = []
    for g, p in enumerate(system.plans):
        rhs = rhs_of(g)  # None: zero
        if layout.lower[g] is not None:
            done = index(f"DONE{g}", layout.lower_cols[g])
            rhs = f"{rhs or ''} - np.einsum('ijn,jn->in', LT{g}, {x}T[{done}])".lstrip()
        elif rhs is None:
            rhs = f"np.zeros(({len(p.rows)}, n))"
        cols, inv = index(f"COLS{g}", p.cols), f"INV[{g}]"
        if ":" in cols:
            lines.append(f"    np.einsum('ijn,jn->in', {inv}, {rhs}, out={x}T[{cols}])")
        else:
            lines.append(f"    {x}T[{cols}] = np.einsum('ijn,jn->in', {inv}, {rhs})")
    return lines


@dataclass(frozen=True)
class Written:
    """What the plan knows of the blocks it writes: each group's inverse as written
    (``WrittenInverse.pattern``) and each slot's writes of Φ_q's buffer (:func:`entry`)."""

    patterns: list
    writes: dict


def either(dense: list[str], traced: list[str] | None) -> list[str]:
    """``dense`` lines, or, where the plan writes the substitutions out, ``traced`` ones
    for chunks of :data:`TRACED_FROM` rows and more in which no block was inverted again
    (a fallback's inverse has no known zeros); the dense ones read the blocks whole, their
    unwritten entries zeroed first (``Z``: :mod:`.plan_buffers`)."""
    if traced is None:
        return dense
    return [
        "    if redone or n < TRACED_FROM:",
        "        Z()",
        *("    " + line for line in dense),
        "    else:",
        *("    " + line for line in traced),
    ]


def traced_substitution(system: System, x: str, row, written: Written) -> list[str]:
    """The substitution of :func:`substitution` written out over the blocks' entries that
    are not zero (the inverses' as written, read from ``INV[g]`` or folded where a
    number; the coupling blocks' as the plan's locals, numbers or ``buf``'s slots): the
    same products and sums in the same order, the zero terms left out.  ``row(sub, r)``:
    row r of the right-hand side (a local or a number)."""
    layout = system.layout
    assert layout is not None
    sub = Lines(f"{x}_")
    done: dict[int, object] = {}  # each column of x solved so far: a local or a number
    for g, p in enumerate(system.plans):
        rhs = [row(sub, int(r)) for r in p.rows]
        if layout.lower[g] is not None:
            off, r, c = layout.lower[g]
            for i in range(r):
                acc: object = 0.0
                for j, col in enumerate(layout.lower_cols[g].tolist()):
                    a = _known(sub, written.writes, off + i * c + j)
                    if not (isinstance(a, float) and a == 0.0):
                        acc = acc + a * done[col]
                rhs[i] = rhs[i] - acc
        for i, col in enumerate(p.cols.tolist()):
            acc = 0.0
            for j, a in enumerate(written.patterns[g][i]):
                if a is None:
                    a = sub.value(f"INV[{g}][{i}, {j}]")
                if not (isinstance(a, float) and a == 0.0):
                    acc = acc + a * rhs[j]
            done[col] = acc
            sub.lines.append(f"    {x}T[{col}] = {operand(acc)}")
    return pruned(sub.take(), sub.prefix)


def _known(sub: Lines, writes: dict, slot: int, reads: bool = True):
    """A slot of Φ_q's buffer as the plan knows it: a number, or its value over the rows —
    the plan's local (``reads``) or read from the buffer."""
    e = entry(writes.get(slot))
    if e == RUNTIME or (isinstance(e, Sym) and not reads):
        return sub.value(f"buf[{slot}]")
    return sub.value(e.name) if isinstance(e, Sym) else float(e)


def traced_transposed(system: System, written: Written) -> list[str]:
    """``transposed(R, buf, INV, Y)``: Y with Φ_qᵀ yᵢ = rᵢ for the right-hand sides ``R
    (k, n_q, N)`` (component-major), into ``Y (k, n_rows, N)``, as
    :meth:`~kinetostatics.base.blocks.BlockFactor.solve_transposed_rows` solves it — the
    groups from the last, y_g = inv_gᵀ (r_g − the later rows' coupling terms) — written
    over the entries of the inverses and coupling blocks that are not zero (the
    inverses' read from ``INV[g]`` or folded where a number, the coupling blocks' from
    ``buf`` or folded), each operation over all k right-hand sides at once.  Valid where
    no block was inverted again (a fallback's inverse has no known zeros)."""
    layout = system.layout
    assert layout is not None
    sub = Lines("t")
    lines = ["def transposed(R, buf, INV, Y):"]
    y: dict[int, object] = {}  # each row of y solved so far: a local or a number
    plans = system.plans
    for g in reversed(range(len(plans))):
        r = []
        for col in plans[g].cols.tolist():
            acc: object = 0.0
            for h in reversed(range(g + 1, len(plans))):
                if layout.lower[h] is None:
                    continue
                off, _, c = layout.lower[h]
                for j in np.flatnonzero(layout.lower_cols[h] == col).tolist():
                    for i, row in enumerate(plans[h].rows.tolist()):
                        a = _known(sub, written.writes, off + i * c + j, reads=False)
                        if not (isinstance(a, float) and a == 0.0):
                            acc = acc + a * y[row]
            r.append(sub.value(f"R[:, {col}]") - acc)
        for i, row in enumerate(plans[g].rows.tolist()):
            acc = 0.0
            for j, rj in enumerate(r):
                a = written.patterns[g][j][i]  # inv_gᵀ
                if a is None:
                    a = sub.value(f"INV[{g}][{j}, {i}]")
                if not (isinstance(a, float) and a == 0.0):
                    acc = acc + a * rj
            y[row] = acc
            sub.lines.append(f"    Y[:, {row}] = {operand(acc)}")
    return [*lines, *pruned(sub.take(), sub.prefix)]


RUN_BYTES = 2**17
"""The bytes of a run's right-hand sides' component (k × its positions) in
:func:`transposed_in_runs`, so that the lines' operands stay in the caches.  The slotting
machine's full analysis at 36,000 positions, every column read (its friction's seven
efforts, k = 7): 242 ms in one run, 170 in runs of 8 kB, 158 of 32 kB, 155 of 128 kB
and of 1 MB, against 184 with the products over whole blocks (2026-11-30)."""


def transposed_in_runs(transposed, buf: np.ndarray, inv: list, r: np.ndarray) -> np.ndarray:
    """``transposed`` (:func:`traced_transposed`, of the plan whose blocks are ``buf`` and
    ``inv``) over ``r (k, n_q, N)``, in runs of positions whose k right-hand sides take
    :data:`RUN_BYTES` each: ``Y (k, n_rows, N)``.  Each line is a pass over k × the run's
    positions; over all 36,000 positions and the friction's seven efforts its operands
    (2 MB each) left the caches and the lines cost twice the products over whole blocks."""
    k, n = r.shape[0], r.shape[-1]
    y = np.empty((k, sum(len(x) for x in inv)) + r.shape[2:])  # the blocks are square
    per = max(RUN_BYTES // (8 * k), 256)
    for a in range(0, n, per):
        b = min(a + per, n)
        transposed(r[..., a:b], buf[:, a:b], [x[..., a:b] for x in inv], y[..., a:b])
    return y


def traced_product(system: System, written: Written) -> list[str]:
    """``product(Y, buf, OUT)``: Φ_qᵀ y for ``Y (n_rows, N)`` (component-major) into ``OUT
    (n_q, N)``, as :meth:`~kinetostatics.base.blocks.BlockFactor.product_transposed_components`
    computes it — a column's terms in its group's rows, then the later groups' — written
    over Φ_q's entries that are not zero (numbers folded, the others read from ``buf``):
    the friction solutions' residual reads no structural zero (nor zeroes any)."""
    layout = system.layout
    assert layout is not None
    terms: dict[int, list[tuple[int, int]]] = {}  # column of q -> [(slot, row of Φ)]
    for g, p in enumerate(system.plans):
        blocks = [(layout.diag[g], p.cols)]
        if layout.lower[g] is not None:
            blocks.append((layout.lower[g], layout.lower_cols[g]))
        for (off, _, c), cols in blocks:
            for i, row in enumerate(p.rows.tolist()):
                for j, col in enumerate(cols.tolist()):
                    terms.setdefault(col, []).append((off + i * c + j, row))
    sub = Lines("u")
    for col in range(system.n_q):
        acc: object = 0.0
        for slot, row in terms.get(col, []):
            a = _known(sub, written.writes, slot, reads=False)
            if not (isinstance(a, float) and a == 0.0):
                acc = acc + a * sub.value(f"Y[{row}]")
        sub.lines.append(f"    OUT[{col}] = {operand(acc)}")
    return ["def product(Y, buf, OUT):", *pruned(sub.take(), sub.prefix)]


def product_in_runs(product, buf: np.ndarray, n_q: int, y: np.ndarray) -> np.ndarray:
    """``product`` (:func:`traced_product`, of the plan whose blocks are ``buf``) over ``y
    (n_rows, N)``, in runs of :data:`RUN_BYTES` of positions: ``(n_q, N)``."""
    n = y.shape[-1]
    out = np.empty((n_q, n))
    per = max(RUN_BYTES // 8, 256)
    for a in range(0, n, per):
        b = min(a + per, n)
        product(y[:, a:b], buf[:, a:b], out[:, a:b])
    return out
