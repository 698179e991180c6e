"""Block-triangular solves over the Assur groups (internal).

In the solve order, group g's constraints involve only links of groups ≤ g,
so Φ_q is block lower-triangular with square diagonal blocks (rows of g ×
columns of g).  Inverting the small diagonal blocks once serves q̇, q̈
(forward substitution) and the reactions, Φ_qᵀ λ = −Q (back substitution).
"""

from __future__ import annotations

import numpy as np

__all__ = ["BlockFactor"]


def _inv(a: np.ndarray) -> np.ndarray:
    try:
        return np.linalg.inv(a)
    except np.linalg.LinAlgError:  # exactly singular somewhere: least squares there
        return np.linalg.pinv(a)


class BlockFactor:
    """Factorisation of a stacked Φ_q ``(..., n, n)`` along the group partition.

    ``blocks``: each group's (rows, cols).  Give either the whole ``jac`` or, with
    ``jac=None``, ``parts``: each group's (diagonal block, rows × the earlier groups'
    columns or None), as :func:`~kinetostatics.structure.system.jacobian_blocks`
    builds them without the structural zeros.
    """

    def __init__(
        self,
        jac: np.ndarray | None,
        blocks: list[tuple[np.ndarray, np.ndarray]],
        parts: list[tuple[np.ndarray, np.ndarray | None]] | None = None,
    ):
        self.blocks = blocks
        self._jac = jac
        self.n = sum(len(cols) for _, cols in blocks)
        if parts is None:
            parts, done = [], np.zeros(0, dtype=int)
            for rows, cols in blocks:
                lower = jac[..., rows[:, None], done] if done.size else None
                parts.append((jac[..., rows[:, None], cols], lower))
                done = np.concatenate((done, cols))
        self.diag = [d for d, _ in parts]
        self.inv = [_inv(d) for d in self.diag]
        self._lower, done = [], np.zeros(0, dtype=int)  # each group's rows × earlier columns
        for (_, cols), (_, lower) in zip(blocks, parts):
            self._lower.append((done, lower))
            done = np.concatenate((done, cols))
        self._upper = None

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
        """x with Φ_q x = rhs (forward substitution)."""
        return self.solve_many(rhs[..., None])[..., 0]

    def solve_many(self, rhs: np.ndarray) -> np.ndarray:
        """X with Φ_q X = rhs for ``rhs (..., n, k)`` (k right-hand sides at once)."""
        x = np.zeros(rhs.shape[:-2] + (self.n, rhs.shape[-1]))
        for (rows, cols), inv, (done, lower) in zip(self.blocks, self.inv, self._lower):
            r = rhs[..., rows, :]
            if lower is not None:
                r = r - lower @ x[..., done, :]
            x[..., cols, :] = inv @ r
        return x

    def _coupling(self, g: int, h: int) -> np.ndarray:
        """Φ_q's block rows of group h × columns of group g < h."""
        start = sum(len(cols) for _, cols in self.blocks[:g])
        return self._lower[h][1][..., start : start + len(self.blocks[g][1])]

    def solve_transposed(self, rhs: np.ndarray) -> np.ndarray:
        """y with Φ_qᵀ y = rhs (back substitution over the groups)."""
        n_g = len(self.blocks)
        if self._upper is None:  # each group's columns × the later groups' rows
            self._upper, later = [], np.zeros(0, dtype=int)
            for g in reversed(range(n_g)):
                rows, _ = self.blocks[g]
                upper = None
                if later.size:
                    upper = np.swapaxes(
                        np.concatenate(
                            [self._coupling(g, h) for h in reversed(range(g + 1, n_g))], axis=-2
                        ),
                        -1,
                        -2,
                    )
                self._upper.append((later, upper))
                later = np.concatenate((later, rows))
        n_rows = sum(len(rows) for rows, _ in self.blocks)
        y = np.zeros(rhs.shape[:-1] + (n_rows,))
        for (rows, cols), inv, (later, upper) in zip(
            reversed(self.blocks), reversed(self.inv), self._upper
        ):
            r = rhs[..., cols]
            if upper is not None:
                r = r - np.einsum("...ij,...j->...i", upper, y[..., later])
            y[..., rows] = np.einsum("...ji,...j->...i", inv, r)
        return y
