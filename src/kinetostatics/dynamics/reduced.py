"""Setting a driver free (:func:`with_effort`) and the equivalent (reduced) quantities of
a 1-DOF, fully driven system (:func:`equivalent`, used by the flywheel design)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..kinematics.derivatives import derivatives
from ..kinetics.conditions import travel_extremes
from ..kinetics.forces import mass_vector
from ..kinetics.inverse import kinetics
from ..kinetics.reactions import effort_ratio
from ..model import EffortLaw, Model
from ..structure.system import System

__all__ = ["with_effort", "equivalent", "equivalent_inertia"]


def with_effort(model: Model, driver: str, effort: float | EffortLaw) -> Model:
    """The model with ``driver`` applying a known ``effort`` instead of a prescribed motion."""
    names = [d.name for d in model.drivers]
    if driver not in names:
        raise KeyError(f"no driver '{driver}'; the drivers are: {', '.join(names)}")
    drivers = tuple(
        replace(d, motion=None, effort=effort, balance_at=None) if d.name == driver else d
        for d in model.drivers
    )
    return replace(model, drivers=drivers)


def _law(effort) -> EffortLaw:
    return effort if isinstance(effort, EffortLaw) else EffortLaw("constant", value=float(effort))


def equivalent_inertia(system: System, tangent: np.ndarray) -> np.ndarray:
    """J_e = Σ m|v_S/ψ̇|² + J(ω/ψ̇)² from ``tangent`` = ∂q/∂ψ (q̇ at ψ̇ = 1), ``(...,)``."""
    return np.einsum("...n,...n->...", tangent, mass_vector(system) * tangent)


def equivalent(
    system: System,
    q: np.ndarray,
    psi: np.ndarray,
    *,
    speed: float = 1.0,
    extremes: dict | None = None,
) -> dict[str, np.ndarray]:
    """Equivalent (reduced) quantities of a 1-DOF, fully driven system at positions
    ``q (n, n_q)`` with driver coordinates ``psi (n,)``, all referred to the driver's
    coordinate ψ (the crank), wherever its effort is taken (``balance_at``):

    - ``inertia`` J_e = Σ m|v_S/ψ̇|² + J(ω/ψ̇)² = 2T/ψ̇² (> 0), from the masses and the
      velocities per unit ψ̇; by virtual power it equals ρ·[τ(ψ̈ = 1) − τ(ψ̈ = 0)] of
      :func:`kinetics`, without that product's loss of digits where ρ is small;
    - ``inertia_derivative`` dJ_e/dψ = 2 Σ (m v_S·a_S + J ω α)/ψ̇³ at ψ̈ = 0;
    - ``torque`` the equivalent torque (force) of gravity and the external loads
      at driver speed ``speed`` (the sign matters for loads opposing the velocity):
      their power divided by ψ̇;
    - ``effort_ratio`` ρ, the relative speed of the joint that carries the driver's
      effort τ per unit ψ̇ (1 without ``balance_at``; −z2/z1 at a pinion driving the
      crank's gear through an external mesh).

    The effort needed for a motion (ψ, ψ̇, ψ̈), referred to ψ (the effort times ρ), is
    then J_e ψ̈ + ½ J_e' ψ̇² − torque.
    ``extremes``: the extremes of ``travel`` conditions (``Result.extremes``); by default
    they are located over the whole motion (:func:`~kinetostatics.analysis.travel_extremes`).
    """
    if len(system.motion_drivers) != 1:
        raise ValueError("equivalent quantities need exactly one motion driver")
    q = np.asarray(q, dtype=float)
    n = q.shape[0]
    qb = np.concatenate((q, q))
    pd = np.concatenate((np.full(n, speed), np.ones(n)))[:, None]
    pdd = np.zeros((2 * n, 1))
    psib = np.concatenate((psi, psi))[:, None]
    qd, qdd, lu = derivatives(system, qb, pd, pdd)
    if extremes is None:
        extremes = travel_extremes(system)
    kin = kinetics(system, qb, qd, qdd, psib, lu=lu, ref_speed=abs(speed), extremes=extremes)
    tangent = qd[n:]
    loads = (kin.q_gravity + kin.q_external + kin.q_element)[:n]
    return {
        "inertia": equivalent_inertia(system, tangent),
        "effort_ratio": effort_ratio(system, q, tangent),
        "inertia_derivative": -2.0 * np.einsum("...n,...n->...", tangent, kin.q_inertia[n:]),
        "torque": np.einsum("...n,...n->...", tangent, loads),
    }
