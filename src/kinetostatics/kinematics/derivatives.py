"""Velocities and accelerations at solved positions: Φ_q q̇ = ν and Φ_q q̈ = γ."""

from __future__ import annotations

import numpy as np

from ..base.blocks import BlockFactor
from ..structure.system import System, gamma, jacobian, jacobian_blocks, nu

__all__ = ["derivatives", "velocities", "accelerations"]


def derivatives(
    system: System, q: np.ndarray, psi_d: np.ndarray, psi_dd: np.ndarray
) -> tuple[np.ndarray, np.ndarray, BlockFactor]:
    """(q̇, q̈, factorised Φ_q): Φ_q q̇ = ν and Φ_q q̈ = γ by block forward
    substitution over the Assur groups, ``(..., n_q)`` each."""
    blocks = [(p.rows, p.cols) for p in system.plans]
    lu = BlockFactor(None, blocks, jacobian_blocks(system, q))
    qd = lu.solve(nu(system, psi_d))
    return qd, lu.solve(gamma(system, q, qd, psi_dd)), lu


def velocities(system: System, q: np.ndarray, psi_d: np.ndarray) -> np.ndarray:
    """q̇ from Φ_q q̇ = ν, ``(..., n_q)``."""
    return np.linalg.solve(jacobian(system, q), nu(system, psi_d)[..., None])[..., 0]


def accelerations(system: System, q: np.ndarray, qd: np.ndarray, psi_dd: np.ndarray) -> np.ndarray:
    """q̈ from Φ_q q̈ = γ, ``(..., n_q)``."""
    return np.linalg.solve(jacobian(system, q), gamma(system, q, qd, psi_dd)[..., None])[..., 0]
