"""Inverse dynamics at given states: loads, reactions and efforts, friction, power.

:func:`kinetics` is the stage of :func:`~kinetostatics.analysis.analyze` after the
kinematics, and the engine of forward dynamics (:mod:`~kinetostatics.dynamics`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..base.linalg import BlockFactor
from ..errors import Location, SingularEquilibriumWarning, StructureError
from ..kinematics.motion import Motion
from ..structure.system import System, coordinate_gradient
from . import friction as fr
from .conditions import travel_extremes
from .elements import ElementStates, element_states
from .forces import external_forces, gravity_forces, inertia_forces, mass_vector
from .reactions import (
    EFFORT_SPEED_TOL,
    effort_joints,
    effort_speed_ratio,
    equilibrium_matrix,
    invert_equilibrium,
    solve_equilibrium,
)

__all__ = ["Kinetics", "inverse_dynamics", "kinetics", "redundant_joints"]


@dataclass
class Kinetics:
    """Loads, reactions, friction and power at given states (arrays over positions)."""

    q_gravity: np.ndarray
    q_inertia: np.ndarray
    q_external: np.ndarray
    a_given: np.ndarray | None  # equilibrium matrix A, (..., n_q, n_lam); None: Φ_qᵀ of ``lu``
    x0: np.ndarray  # frictionless multipliers and driver efforts
    indeterminate: bool
    friction: dict | None  # setup, x_approx, e_approx, solution (see friction.py)
    power: dict
    singular: np.ndarray | None = None  # (...) A singular there: x0 NaN, friction.status 2
    condition: np.ndarray | None = None  # (...) scaled condition number of a square A
    lu: BlockFactor | None = None  # the kinematic factors where A = Φ_qᵀ
    elements: ElementStates | None = None  # springs and dampers (None: the model has none)

    @property
    def a(self) -> np.ndarray:
        """Equilibrium matrix A, ``(..., n_q, n_lam)`` (Φ_qᵀ assembled on demand)."""
        return self.a_given if self.a_given is not None else np.swapaxes(self.lu.jac, -1, -2)

    @property
    def q_element(self) -> np.ndarray:
        """Generalized force of the springs and dampers (zeros without elements)."""
        return 0.0 * self.q_gravity if self.elements is None else self.elements.q

    @property
    def q_load(self) -> np.ndarray:
        return self.q_gravity + self.q_inertia + self.q_external + self.q_element


def inverse_dynamics(
    system: System,
    motion: Motion,
    *,
    ref_speed: float,
    extremes: dict | None = None,
    friction: bool = False,
) -> Kinetics:
    """Inverse dynamics at the rows of ``motion`` (a
    :class:`~kinetostatics.kinematics.motion.Motion`: its states, driver coordinates and
    kinematic factors), as :func:`kinetics`."""
    return kinetics(
        system,
        motion.q,
        motion.qd,
        motion.qdd,
        motion.psi,
        lu=motion.lu,
        ref_speed=ref_speed,
        extremes=extremes,
        friction=friction,
    )


def kinetics(
    system: System,
    q: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    psi: np.ndarray,
    *,
    ref_speed: float,
    lu=None,
    extremes: dict | None = None,
    friction: bool = False,
) -> Kinetics:
    """Inverse dynamics at states (q, q̇, q̈) with driver coordinates ``psi (..., n_d)``.

    Loads (gravity, d'Alembert inertia, external loads active at these states),
    the frictionless reactions and driver efforts, the friction solutions when
    ``friction`` and the model has friction, and the power terms.  ``lu``: the
    kinematic factorisation of Φ_q at q, if at hand; ``extremes``: the extremes of
    ``travel`` conditions (``Result.extremes``; by default :func:`travel_extremes`, over
    the whole motion); ``ref_speed``: the driver speed that scales the zero-speed thresholds.
    """
    model = system.model
    if extremes is None:
        extremes = travel_extremes(system)
    q_grav = gravity_forces(system, q.shape[:-1])
    q_inert = inertia_forces(system, qdd)
    q_ext = external_forces(system, q, qd, psi[..., 0], extremes, ref_speed)
    q_load = q_grav + q_inert + q_ext
    elements = element_states(system, q, qd) if model.elements else None
    if elements is not None:
        q_load = q_load + elements.q
    own_efforts = all(d.driver.balance_at is None for d in system.motion_drivers)
    singular, condition, a_inv = np.zeros(q.shape[:-1], dtype=bool), None, None
    if lu is not None and own_efforts:
        a = None  # A = Φ_qᵀ: the kinematic factors stand for it (square)
        x0, indeterminate = lu.solve_transposed(-q_load), False
    else:
        a = equilibrium_matrix(system, q)
        if a.shape[-1] == a.shape[-2]:  # singular positions: NaN rows, the rest intact
            a_inv, singular, condition = invert_equilibrium(a, system.l_ref)
            if not own_efforts and len(system.motion_drivers) == 1:
                # the effort's joint (nearly) at rest: no effort to round-off accuracy there
                near = effort_speed_ratio(system, q, qd) <= EFFORT_SPEED_TOL
                singular |= near
                a_inv[near] = np.nan
            bad = ~np.isfinite(a_inv[..., 0, 0])
            x0 = np.linalg.solve(
                np.where(bad[..., None, None], np.eye(a.shape[-1]), a), -q_load[..., None]
            )[..., 0]
            x0[bad], indeterminate = np.nan, False
            if singular.any():
                _warn_singular_equilibrium(system, singular, psi[..., 0])
        else:
            x0, indeterminate = solve_equilibrium(a, -q_load)
    fric = None
    if friction and model.has_friction and a is not None and a.shape[-1] != a.shape[-2]:
        raise StructureError([(Location(model.source, path="joints"), _not_square(system, a))])
    if friction and model.has_friction:
        fs = fr.setup(system, q, qd, ref_speed)
        if lu is not None and own_efforts:
            solve_a = lu.solve_transposed  # A = Φ_qᵀ: back substitution over the groups
        else:
            if a_inv is None:
                a_inv = np.linalg.inv(a)
            solve_a = lambda rhs: np.einsum("...ij,...j->...i", a_inv, rhs)  # noqa: E731
        xa, ea = fr.approximate(system, fs, solve_a, q_load, x0)
        a_full = lu if a is None else a  # Φ_qᵀ by its blocks: no dense matrix assembled
        cons = fr.consistent(system, fs, a_full, solve_a, q_load, x0)
        fric = dict(setup=fs, x_approx=xa, e_approx=ea, solution=cons)
    eff = effort_joints(system)
    rel = np.stack(
        [np.einsum("...n,...n->...", coordinate_gradient(system, q, k), qd) for k in eff], axis=-1
    )
    n_j = system.n_joint_rows
    power = {
        "input": np.sum(x0[..., n_j:] * rel, axis=-1),
        "kinetic": np.einsum("...n,...n->...", qd, mass_vector(system) * qdd),
        "potential": -np.einsum("...n,...n->...", qd, q_grav),
        "external": -np.einsum("...n,...n->...", qd, q_ext),
    }
    stored = 0.0
    if elements is not None:  # the rate of the springs' energy; the dampers' dissipation
        power["elastic"] = elements.total("power", springs=True)
        power["damping"] = elements.total("power", springs=False)
        stored = power["elastic"] + power["damping"]
    power["residual"] = (
        power["input"] - power["kinetic"] - power["potential"] - power["external"] - stored
    )
    if fric is not None:
        cons = fric["solution"]
        loss = np.sum(np.abs(cons.e * fric["setup"].speed), axis=-1)
        power["friction"] = loss
        power["input_friction"] = np.sum(cons.x[..., n_j:] * rel, axis=-1)
        power["residual_friction"] = (
            power["input_friction"]
            - power["kinetic"]
            - power["potential"]
            - power["external"]
            - stored
            - loss
        )
    return Kinetics(
        q_grav, q_inert, q_ext, a, x0, indeterminate, fric, power, singular, condition, lu, elements
    )


def _not_square(system: System, a: np.ndarray) -> str:
    """Why friction cannot be solved with a non-square equilibrium matrix A (n_q × n_λ)."""
    n_q, n_lam = a.shape[-2:]
    n_m, mob = len(system.motion_drivers), system.structure.mobility
    if n_lam < n_q:
        return (
            f"friction needs the efforts of as many motion drivers as the mobility ({mob}); "
            f"there are {n_m}: the loads are not balanced by unknown efforts (the "
            f"equilibrium has {n_q} equations and {n_lam} unknowns)"
        )
    redundant = redundant_joints(system, a.reshape((-1,) + a.shape[-2:])[0])
    return (
        f"the linkage is overconstrained: joint(s) {', '.join(redundant) or '?'} "
        f"are redundant ({n_lam} unknown reactions and efforts for {n_q} equations), so "
        "their reactions are statically indeterminate (the frictionless analysis reports "
        "the minimum-norm ones, flagged indeterminate) and the friction that depends on "
        "them is not determined either: analyse without friction (friction=False) or "
        "remove the redundant joints"
    )


def redundant_joints(system: System, a: np.ndarray) -> list[str]:
    """Joints whose constraint columns of A (one position, ``(n_q, n_λ)``) add nothing to
    the rank of those before them (in file order): the redundant ones.  A is scaled as in
    :func:`~kinetostatics.kinetics.reactions.invert_equilibrium` (moment rows / L_ref, unit
    columns); a column adds rank where its residual from the earlier ones exceeds 1e-9."""
    s = np.array(a, dtype=float)
    s[2::3, :] /= float(np.max(system.l_ref))
    norms = np.linalg.norm(s, axis=0)
    s /= np.where(norms > 0, norms, 1.0)
    basis = np.zeros((s.shape[0], 0))
    out = []
    for k, j in enumerate(system.model.joints):
        cols = s[:, system.rows_of(k)]
        if basis.shape[1]:
            cols = cols - basis @ (basis.T @ cols)
        u, sv, _ = np.linalg.svd(cols, full_matrices=False)
        keep = sv > 1e-9
        if not keep.all():
            out.append(j.name)
        basis = np.concatenate((basis, u[:, keep]), axis=1)
    return out


def _warn_singular_equilibrium(system: System, singular: np.ndarray, coord: np.ndarray) -> None:
    """Warn of the positions where no finite effort balances the loads, naming them."""
    d = system.motion_drivers[0]
    at = np.broadcast_to(coord, singular.shape)[singular]
    where = ", ".join(
        f"{np.degrees(c) % 360:.6g}°" if d.joint.angular else f"{c * 1e3:.6g} mm" for c in at[:8]
    ) + (f" and {at.size - 8} more" if at.size > 8 else "")
    joints = sorted({(m.driver.balance_at or m.joint.name) for m in system.motion_drivers})
    warnings.warn(
        f"the equilibrium is singular at {d.name} = {where}: the effort at "
        f"{', '.join(joints)} cannot balance the loads there (a dead centre); the "
        "reactions and efforts there are NaN, friction.status 2, listed among the "
        "singular positions as 'equilibrium'",
        SingularEquilibriumWarning,
        stacklevel=3,
    )
