"""The kinematic plan's buffers: Φ_q's entries and the blocks' inverses, zeroed only where read

A plan writes Φ_q's entries into one buffer of the group blocks and the blocks' inverses
into arrays of their own (:mod:`.plan`), each entry one run over the positions.  Most of
their entries are structural zeros: the slotting machine's plan writes 43 of its 136
slots and 38 of its inverses' 81 entries.  Zeroing them all is a pass over memory that
the analysis never reads in its common course — over 36,000 positions ~40 MB and ~25 MB,
about a tenth of the kinematics — since the plan's straight lines read only the entries
it writes (:mod:`.plan_solve`), numbers and zeros folded.

So where the plan writes every slot it reads as a line (each joint's entries by its
traced kernel, every group's inverse written out: :class:`Unwritten`), the buffers over
:data:`~.plan_inverse.TRACED_FROM` rows or more are allocated without zeroing, and the
entries left unwritten are zeroed by a :class:`Zeros` of each chunk the plan runs over,
once, where something first reads a block whole: a fallback of a block's inverse
(LAPACK, the pseudo-inverse, an entry not finite: called by the plan), the products over
whole blocks of a short chunk or of a chunk whose block was inverted again, and, after
the run, the :class:`~kinetostatics.base.blocks.BlockFactor`'s blocks (Φ_q or a product
asked of them whole, a condition number asked later) and the ground's alone (the shaking
force); the friction solutions read Φ_qᵀ y by the plan's lines too.  Each
chunk's first position is zeroed at once (the row order of an elimination is read from
its first matrix, ``small_inverse``'s choice).  The numbers are those of zeroed buffers:
tests/kinematics/test_plan.py fills the unwritten entries with NaN and compares.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..structure.system import System
from .plan_solve import Written

__all__ = ["NOZERO", "Unwritten", "Zeros", "filled", "run_in_chunks", "block", "unwritten_of"]


def NOZERO() -> None:  # noqa: N802  the name the plan's text reads
    """A plan's buffers that are zeros already: nothing to write."""


@dataclass(frozen=True, eq=False)
class Unwritten:
    """What a plan never writes: ``rows``, the slots of Φ_q's buffer (its structural zeros
    and the spare slot); ``inverse``, each group's entries ``(i, j)`` of its inverse
    (the zeros of the inverse as written)."""

    rows: np.ndarray
    inverse: tuple[tuple[np.ndarray, np.ndarray], ...]


class Zeros:
    """The unwritten entries of one chunk's buffers ``buf (slots, n)`` and inverses ``inv``
    (``(c, c, n)`` each), zeroed where first needed: the first position at once, all of
    them at the first call (and never again: a fallback's inverse, written after, stays)."""

    __slots__ = ("buf", "inv", "unwritten", "done")

    def __init__(self, buf: np.ndarray, inv: list[np.ndarray], unwritten: Unwritten):
        self.buf, self.inv, self.unwritten, self.done = buf, inv, unwritten, False
        buf[unwritten.rows, :1] = 0.0  # the first matrix, whose pivots pick the row order

    def __call__(self) -> None:
        if self.done:
            return
        self.done = True
        self.buf[self.unwritten.rows] = 0.0
        for x, (i, j) in zip(self.inv, self.unwritten.inverse):
            x[i, j] = 0.0


def filled(zeros: list[Zeros] | None, at: tuple[int, int, int] | None = None):
    """The function that zeroes the chunks' unwritten entries (``zeros``, as
    :func:`run_in_chunks` returns them), or, with ``at`` (offset, rows, cols), those of
    that block of Φ_q's buffer alone (the plan never writes them: zeroing them again is
    harmless, and it keeps no inverse alive); None where the buffers were zeros."""
    if not zeros:
        return None
    if at is None:

        def fill() -> None:
            for z in zeros:
                z()

        return fill
    lo, hi = at[0], at[0] + at[1] * at[2]
    rows = zeros[0].unwritten.rows
    rows = rows[(rows >= lo) & (rows < hi)]
    bufs = [z.buf for z in zeros]

    def fill_block() -> None:
        for buf in bufs:
            buf[rows] = 0.0

    return fill_block


def unwritten_of(system: System, written: Written) -> Unwritten:
    """What the plan of ``system`` leaves unwritten, where its lines write every entry they
    read (``written``: :class:`~.plan_solve.Written`): the slots no line writes, and each
    inverse's entries written as 0."""
    slots = set(range(system.layout.size + 1)) - set(written.writes)
    zeros = [[[isinstance(x, float) and x == 0.0 for x in r] for r in p] for p in written.patterns]
    return Unwritten(np.array(sorted(slots), dtype=np.intp), tuple(np.nonzero(z) for z in zeros))


def run_in_chunks(  # noqa: PLR0913  the plan's arguments
    run, per: int, rows: tuple, into: tuple, inv: list, cnd: list, unwritten: Unwritten | None
) -> tuple[bool, list[Zeros]]:
    """The plan's ``run`` over the rows ``(pe, psi_d, psi_dd)`` into ``(buf, qdT, qddT)``,
    the inverses ``inv`` and the condition numbers ``cnd`` (None: a group without), in
    chunks of ``per`` rows at most, alike: whether a block was
    inverted again (by ``small_inverse``, LAPACK or the pseudo-inverse) in any chunk,
    and, with ``unwritten`` (the buffers not zeroed), each chunk's :class:`Zeros` (for
    :func:`filled`; none without)."""
    n = len(rows[0])
    if n <= per:
        spans = [slice(None)]
    else:  # alike, none tiny
        cuts = np.linspace(0, n, -(-n // per) + 1).astype(int).tolist()
        spans = [slice(a, b) for a, b in zip(cuts[:-1], cuts[1:])]
    redone, zeros = False, []
    for at in spans:
        buf, qd, qdd = (x[:, at] for x in into)
        part = [x[..., at] for x in inv]
        z = NOZERO if unwritten is None else Zeros(buf, part, unwritten)
        c = [None if x is None else x[at] for x in cnd]
        redone |= bool(run(*(x[at] for x in rows), buf, qd, qdd, part, c, z))
        if unwritten is not None:
            zeros.append(z)
    return redone, zeros


def block(buf: np.ndarray, at, shape: tuple) -> np.ndarray:
    """A block ``shape + (rows, cols)`` of the entries ``buf`` at ``at`` (offset, rows,
    cols), a view."""
    off, r, c = at
    view = buf[off : off + r * c].reshape((r, c) + shape)
    return view.transpose(tuple(range(2, 2 + len(shape))) + (0, 1))
