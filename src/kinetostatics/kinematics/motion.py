"""The record of the kinematic stage: the rows of a run in time and their states.

:class:`Motion` is what :func:`~kinetostatics.analysis.analyze` carries from the
kinematics to the later stages (load events, event rows, inverse dynamics, the result's
columns), instead of six loose arrays: ``stage(system, motion, …)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.blocks import BlockFactor, Conditions
from ..structure.system import System
from .plan import derivatives_at
from .schedule import Schedule

__all__ = ["Motion", "motion_at"]


@dataclass(frozen=True, eq=False)
class Motion:
    """The states of the rows of a run (arrays over positions; stacked variants lead).

    ``t (N,)`` the times (s; None for states given without them); ``psi``, ``psi_d``,
    ``psi_dd`` ``(..., N, n_d)`` the motion drivers' coordinates (rad or m) and their first
    and second time derivatives (None where not known: a state given by a caller); ``q``,
    ``qd``, ``qdd`` ``(..., N, n_q)`` the link coordinates and their rates; ``lu`` the block
    factorisation of Φ_q at ``q`` that gave q̇ and q̈ (None when they came by differences or
    rows were added after it: the inverse dynamics then assembles its own equilibrium
    matrix).
    """

    t: np.ndarray | None
    psi: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    psi_d: np.ndarray | None = None
    psi_dd: np.ndarray | None = None
    lu: BlockFactor | Conditions | None = None

    @property
    def times(self) -> np.ndarray:
        """``t`` of a motion whose rows have times (every motion the pipeline makes)."""
        if self.t is None:
            raise ValueError("this motion's rows have no times (a state given by a caller)")
        return self.t

    @property
    def coordinate(self) -> np.ndarray:
        """The first motion driver's coordinate, ``(..., N)`` (rad or m)."""
        return self.psi[..., 0]


def motion_at(
    system: System, sched: Schedule, t: np.ndarray, q: np.ndarray, factors: bool = True
) -> Motion:
    """The :class:`Motion` at times ``t`` and solved positions ``q``: the drivers' schedule
    there, and q̇, q̈ from the constraint Jacobian (Φ_q q̇ = ν, Φ_q q̈ = γ; ``lu`` its
    factors): by the system's generated plan where it covers the rows (:mod:`.plan`), else
    by the general stage.  Without ``factors`` (the kinematics alone) ``lu`` may be the
    groups' :class:`~kinetostatics.base.blocks.Conditions` only."""
    psi, psi_d, psi_dd = sched(t)
    qd, qdd, lu = derivatives_at(system, q, psi_d, psi_dd, factors)
    return Motion(t, psi, q, qd, qdd, psi_d, psi_dd, lu)
