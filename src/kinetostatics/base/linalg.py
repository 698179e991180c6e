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
    """Factorisation of a stacked Φ_q ``(..., n, n)`` along the group partition."""

    def __init__(self, jac: np.ndarray, blocks: list[tuple[np.ndarray, np.ndarray]]):
        self.jac, self.blocks = jac, blocks
        self.inv = [_inv(jac[..., rows[:, None], cols]) for rows, cols in blocks]
        self.n = jac.shape[-1]
        self._upper = None
        self._lower = []  # each group's rows × the earlier groups' columns
        done = np.zeros(0, dtype=int)
        for rows, cols in blocks:
            self._lower.append((done, jac[..., rows[:, None], done] if done.size else None))
            done = np.concatenate((done, cols))

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

    def solve_transposed(self, rhs: np.ndarray) -> np.ndarray:
        """y with Φ_qᵀ y = rhs (back substitution over the groups)."""
        if self._upper is None:  # each group's columns × the later groups' rows
            self._upper, later = [], np.zeros(0, dtype=int)
            for rows, cols in reversed(self.blocks):
                self._upper.append(
                    (
                        later,
                        np.swapaxes(self.jac[..., later[:, None], cols], -1, -2)
                        if later.size
                        else None,
                    )
                )
                later = np.concatenate((later, rows))
        y = np.zeros(rhs.shape[:-1] + (self.jac.shape[-2],))
        for (rows, cols), inv, (later, upper) in zip(
            reversed(self.blocks), reversed(self.inv), self._upper
        ):
            r = rhs[..., cols]
            if upper is not None:
                r = r - np.einsum("...ij,...j->...i", upper, y[..., later])
            y[..., rows] = np.einsum("...ji,...j->...i", inv, r)
        return y
