"""Block-triangular solves over the Assur groups (internal).

In the solve order, group g's constraints involve only links of groups ≤ g,
so Φ_q is block lower-triangular with square diagonal blocks (rows of g ×
columns of g).  Inverting the small diagonal blocks once (base/linalg.py) serves q̇,
q̈ (forward substitution) and the reactions, Φ_qᵀ λ = −Q (back substitution).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from .arrays import as_run, entries_first, entries_last
from .linalg import small_inverse

__all__ = ["BlockFactor", "Conditions", "TRANSPOSED_ROWS_FROM"]


@functools.lru_cache(maxsize=1024)
def _coupling_index(cols: tuple[int, ...], own: tuple[int, ...]) -> tuple:
    """Which of a coupling block's columns ``cols`` are group g's ``own`` (their indices
    there, a slice for a run; None for none), and where they go among g's columns (None:
    all of them, in order).  Cached: the same few groups recur in every analysis."""
    at = [k for k, c in enumerate(cols) if c in own]
    if not at:
        return None, None
    if len(at) == len(own) and all(cols[a] == c for a, c in zip(at, own)):
        run = as_run(at)  # a run: a view, not a gather
        return (run if isinstance(run, slice) else at), None
    return at, [own.index(cols[a]) for a in at]


TRANSPOSED_ROWS_FROM = 3000
"""Above this many positions :meth:`BlockFactor.solve_transposed` (the frictionless
equilibrium) runs as :meth:`BlockFactor.solve_transposed_rows` with one right-hand side:
its products whole-array passes over runs of positions, its y stored component-major
(a position-major view).  Measured on the slotting machine's blocks: 0.22 against 0.16
ms at 4,000 positions, 0.70 against 0.41 at 10,000; below ~3,000 the passes over
position-major vectors cost less, and the reactions' columns read them faster."""


@dataclass(frozen=True)
class Conditions:
    """In place of a :class:`BlockFactor` where a stage asked for the rates alone (an
    analysis of the kinematics on the compiled backend, kinematics/fused.py): the groups'
    condition numbers ``{g: (...)}`` (but the driven groups'), and no factors to solve
    with."""

    conditions: dict


class BlockFactor:
    """Factorisation of a stacked Φ_q ``(..., n, n)`` along the group partition.

    ``blocks``: each group's (rows, cols).  Give either the whole ``jac`` or, with
    ``jac=None``, ``parts``: each group's (diagonal block, coupling block, its columns):
    the group's rows × the earlier groups' columns its constraints touch (None and an
    empty array for none), as :func:`~kinetostatics.structure.system.jacobian_blocks`
    builds them without the structural zeros.  Given ``jac``, a coupling block spans all
    the earlier columns.  ``inv``: the diagonal blocks' inverses, if computed already;
    ``conditions``: the groups' condition numbers ``{g: (...)}``, if computed with them
    (the compiled backend's fused stage, kinematics/fused.py), else None;
    ``transposed``: Y = solve of Φ_qᵀ Y = R for ``R (k, n, ...)`` component-major, written
    out over these blocks' nonzero entries (the kinematic plan's, kinematics/plan_solve.py),
    which :meth:`solve_transposed_rows` then calls, else None — or the pair (that,
    ``product``): Φ_qᵀ y for ``y (n_rows, N)`` component-major, written out likewise, which
    :meth:`product_transposed_components` then calls; ``ready``: called
    once before the blocks or the inverses are first read whole (a plan's buffers, their
    structural zeros written where first needed: kinematics/plan_buffers.py), else None.
    """

    def __init__(
        self,
        jac: np.ndarray | None,
        blocks: list[tuple[np.ndarray, np.ndarray]],
        parts: list[tuple[np.ndarray, np.ndarray | None, np.ndarray]] | None = None,
        inv: list[np.ndarray] | None = None,
        conditions: dict | None = None,
        transposed=None,
        ready=None,
    ):
        self.blocks = blocks
        self.conditions = conditions
        self.transposed, self.product = (
            transposed if isinstance(transposed, tuple) else (transposed, None)
        )
        self._jac = jac
        self.n = sum(len(cols) for _, cols in blocks)
        if parts is None:
            parts, done = [], np.zeros(0, dtype=int)
            for rows, cols in blocks:
                lower = jac[..., rows[:, None], done] if done.size else None
                parts.append((jac[..., rows[:, None], cols], lower, done))
                done = np.concatenate((done, cols))
        self._ready = ready
        self._diag = [d for d, _, _ in parts]
        self._inv = [small_inverse(d) for d in self._diag] if inv is None else inv
        self._lower_parts = [(cols, lower) for _, lower, cols in parts]  # coupling: rows × cols
        self._upper = None
        self._at = None

    def _read(self, x):
        """``x``, one of the stored parts, once ``ready`` has run."""
        if self._ready is not None:
            ready, self._ready = self._ready, None
            ready()
        return x

    @property
    def diag(self) -> list[np.ndarray]:
        """Each group's diagonal block ``(..., rows, cols)``."""
        return self._read(self._diag)

    @property
    def inv(self) -> list[np.ndarray]:
        """Each diagonal block's inverse ``(..., cols, rows)``."""
        return self._read(self._inv)

    @property
    def _lower(self) -> list[tuple[np.ndarray, np.ndarray | None]]:
        """Each group's coupling block (its columns, the block or None)."""
        return self._read(self._lower_parts)

    @property
    def jac(self) -> np.ndarray:
        """The whole Φ_q ``(..., n_rows, n)``, assembled from the blocks if not given."""
        if self._jac is None:
            n_rows = sum(len(rows) for rows, _ in self.blocks)
            jac = np.zeros(self.diag[0].shape[:-2] + (n_rows, self.n))
            for (rows, cols), d, (done, lower) in zip(self.blocks, self.diag, self._lower):
                jac[..., rows[:, None], cols] = d
                if lower is not None:
                    jac[..., rows[:, None], done] = lower
            self._jac = jac
        return self._jac

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """x with Φ_q x = rhs (forward substitution); matrix–vector products by einsum
        (over many positions ~1.5–2× faster than ``@`` with a trailing axis of one)."""
        x = np.zeros(rhs.shape[:-1] + (self.n,))
        for (rows, cols), inv, (done, lower) in zip(self.blocks, self.inv, self._lower):
            r = rhs[..., rows]
            if lower is not None:
                r = r - np.einsum("...ij,...j->...i", lower, x[..., done])
            x[..., cols] = np.einsum("...ij,...j->...i", inv, r)
        return x

    def product_transposed(self, y: np.ndarray) -> np.ndarray:
        """Φ_qᵀ y, ``(..., n)``, by the blocks (the dense Φ_q is never assembled)."""
        out = np.zeros(y.shape[:-1] + (self.n,))
        for (rows, cols), d, (done, lower) in zip(self.blocks, self.diag, self._lower):
            r = y[..., rows]
            out[..., cols] += np.einsum("...ji,...j->...i", d, r)
            if lower is not None:
                out[..., done] += np.einsum("...ji,...j->...i", lower, r)
        return out

    def product_transposed_components(self, y_t: np.ndarray) -> np.ndarray:
        """Φ_qᵀ y with y and the product stored component-major, ``(n_rows, ...)`` →
        ``(n, ...)``: each product a whole-array ``einsum`` over runs of positions (the
        blocks as the plan stores them; ~5× faster over 36,000 positions than
        :meth:`product_transposed` over position-major vectors); by the plan's lines over
        the entries that are not zero where it has them (``product``, one model's rows)."""
        if self.product is not None and y_t.ndim == 2:
            return self.product(y_t)
        out = np.empty((self.n,) + y_t.shape[1:])  # each column is a group's: written first
        for (rows, cols, _), d, (done, lower) in zip(self._runs(), self.diag, self._lower):
            r = y_t[rows]
            if isinstance(cols, slice):
                np.einsum("ji...,j...->i...", entries_first(d), r, out=out[cols])
            else:
                out[cols] = np.einsum("ji...,j...->i...", entries_first(d), r)
            if lower is not None:  # the earlier groups' columns, written already
                out[as_run(done)] += np.einsum("ji...,j...->i...", entries_first(lower), r)
        return out

    def transposed_at(self, index) -> np.ndarray:
        """Φ_qᵀ at one position ``index`` of the leading axes, ``(n, n_rows)``."""
        return np.swapaxes(self.jac[index], -1, -2)

    def solve_many(self, rhs: np.ndarray) -> np.ndarray:
        """X with Φ_q X = rhs for ``rhs (..., n, k)`` (k right-hand sides at once)."""
        x = np.zeros(rhs.shape[:-2] + (self.n, rhs.shape[-1]))
        for (rows, cols), inv, (done, lower) in zip(self.blocks, self.inv, self._lower):
            r = rhs[..., rows, :]
            if lower is not None:
                r = r - lower @ x[..., done, :]
            x[..., cols, :] = inv @ r
        return x

    def _coupling(self, g: int, h: int) -> np.ndarray | None:
        """Φ_q's block rows of group h × columns of group g < h (None: no entries)."""
        cols, lower = self._lower[h]
        if lower is None:
            return None
        own = self.blocks[g][1]
        at, where = _coupling_index(tuple(cols.tolist()), tuple(own.tolist()))
        if at is None:
            return None
        lower = entries_first(lower)  # (rows, cols, ...): each entry's run of positions
        if where is None:
            return lower[:, at]
        out = np.zeros((lower.shape[0], own.size) + lower.shape[2:])
        out[:, where] = lower[:, at]
        return out

    def _upper_parts(self) -> list[tuple[np.ndarray, np.ndarray | None]]:
        """Per group, the last first: the later rows that touch its columns, and Φ_qᵀ's
        block of its columns × those rows (None for none)."""
        if self._upper is None:
            n_g = len(self.blocks)
            self._upper = []
            for g in reversed(range(n_g)):
                parts = [(h, self._coupling(g, h)) for h in reversed(range(g + 1, n_g))]
                parts = [(h, c) for h, c in parts if c is not None]
                upper, later = None, np.zeros(0, dtype=int)
                if parts:
                    later = np.concatenate([self.blocks[h][0] for h, _ in parts])
                    both = parts[0][1] if len(parts) == 1 else np.concatenate([c for _, c in parts])
                    upper = entries_last(both.swapaxes(0, 1))
                self._upper.append((later, upper))
        return self._upper

    def solve_transposed(self, rhs: np.ndarray) -> np.ndarray:
        """y with Φ_qᵀ y = rhs (back substitution over the groups, through the coupling
        blocks that exist), the groups from the last: y_g = inv_gᵀ (rhs_g − upper_g y_later)."""
        if self.transposed is not None or rhs[..., 0].size > TRANSPOSED_ROWS_FROM:  # see it
            return self.solve_transposed_rows(rhs[..., None, :])[..., 0, :]
        n_rows = sum(len(rows) for rows, _ in self.blocks)
        y = np.zeros(rhs.shape[:-1] + (n_rows,))
        for (rows, cols), inv, (later, upper) in zip(
            reversed(self.blocks), reversed(self.inv), self._upper_parts()
        ):
            r = rhs[..., cols]
            if upper is not None:
                r = r - np.einsum("...ij,...j->...i", upper, y[..., later])
            y[..., rows] = np.einsum("...ji,...j->...i", inv, r)
        return y

    def solve_transposed_rows(self, rhs: np.ndarray) -> np.ndarray:
        """Y with Φ_qᵀ yᵢ = rᵢ for k right-hand sides given as the rows of ``rhs (..., k, n)``,
        ``(..., k, n_rows)``: each yᵢ a row, so that a combination Σ cᵢ yᵢ runs over the
        rows (an inner axis of n_rows, not of k).

        Solved component-major — each component of each right-hand side one contiguous
        run over the positions, as the blocks' entries and inverses are stored — and
        returned as a view of that storage, ``(k, n_rows, ...)``, which
        ``entries_first`` gives back without a copy: the products are whole-array
        ``einsum`` passes instead of ``matmul`` over matrices whose entries lie a whole
        array apart (~3× faster over 36,000 positions)."""
        r_all = entries_first(rhs)  # (k, n, ...): a view (each component a run, if so stored)
        if self.transposed is not None:
            return entries_last(self.transposed(r_all))
        runs = self._runs()
        n_rows = sum(len(rows) for rows, _ in self.blocks)
        y = np.empty(r_all.shape[:1] + (n_rows,) + r_all.shape[2:])  # each row is a group's
        for (rows, cols, later), inv, (_, upper) in zip(
            reversed(runs), reversed(self.inv), self._upper_parts()
        ):
            r = r_all[:, cols]
            if upper is not None:
                r = r - np.einsum("ab...,kb...->ka...", entries_first(upper), y[:, later])
            if isinstance(rows, slice):
                np.einsum("ji...,kj...->ki...", entries_first(inv), r, out=y[:, rows])
            else:
                y[:, rows] = np.einsum("ji...,kj...->ki...", entries_first(inv), r)
        return entries_last(y)

    def _runs(self) -> list[tuple]:
        """Per group: its rows, its columns and the later rows that touch its columns
        (:meth:`_upper_parts`), each a slice where it is a run (a view, not a gather)."""
        if self._at is None:
            later = [rows for rows, _ in reversed(self._upper_parts())]
            self._at = [
                (as_run(rows), as_run(cols), as_run(after))
                for (rows, cols), after in zip(self.blocks, later)
            ]
        return self._at
