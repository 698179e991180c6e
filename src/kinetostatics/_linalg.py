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
    except np.linalg.LinAlgError:            # exactly singular somewhere: least squares there
        return np.linalg.pinv(a)


class BlockFactor:
    """Factorisation of a stacked Φ_q ``(..., n, n)`` along the group partition."""

    def __init__(self, jac: np.ndarray, blocks: list[tuple[np.ndarray, np.ndarray]]):
        self.jac, self.blocks = jac, blocks
        self.inv = [_inv(jac[..., rows[:, None], cols]) for rows, cols in blocks]
        self.n = jac.shape[-1]

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """x with Φ_q x = rhs (forward substitution)."""
        x = np.zeros(rhs.shape[:-1] + (self.n,))
        done = np.zeros(0, dtype=int)
        for (rows, cols), inv in zip(self.blocks, self.inv):
            r = rhs[..., rows]
            if done.size:
                r = r - np.einsum("...ij,...j->...i", self.jac[..., rows[:, None], done], x[..., done])
            x[..., cols] = np.einsum("...ij,...j->...i", inv, r)
            done = np.concatenate((done, cols))
        return x

    def solve_transposed(self, rhs: np.ndarray) -> np.ndarray:
        """y with Φ_qᵀ y = rhs (back substitution over the groups)."""
        y = np.zeros(rhs.shape[:-1] + (self.jac.shape[-2],))
        later = np.zeros(0, dtype=int)
        for (rows, cols), inv in zip(reversed(self.blocks), reversed(self.inv)):
            r = rhs[..., cols]
            if later.size:
                r = r - np.einsum("...ji,...j->...i", self.jac[..., later[:, None], cols], y[..., later])
            y[..., rows] = np.einsum("...ji,...j->...i", inv, r)
            later = np.concatenate((later, rows))
        return y

    def inverse(self) -> np.ndarray:
        """Φ_q⁻¹ ``(..., n, n)`` (for the friction iteration)."""
        eye = np.eye(self.n)
        return np.stack([self.solve(np.broadcast_to(eye[k], self.jac.shape[:-1]))
                         for k in range(self.n)], axis=-1)
