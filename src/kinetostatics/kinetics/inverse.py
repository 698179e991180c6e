"""Inverse dynamics at given states: loads, reactions and efforts, friction, power.

:func:`kinetics` is the stage of :func:`~kinetostatics.analysis.analyze` after the
kinematics, and the engine of forward dynamics (:mod:`~kinetostatics.dynamics`).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..base.blocks import BlockFactor
from ..errors import Location, SingularEquilibriumWarning, StructureError
from ..kinematics.motion import Motion
from ..structure.system import System
from . import friction as fr
from .conditions import travel_extremes
from .elements import ElementStates, element_states
from .forces import external_forces, gravity_forces, inertia_forces
from .reactions import (
    EFFORT_SPEED_TOL,
    effort_speed_ratio,
    effort_speeds,
    equilibrium_matrix,
    invert_equilibrium,
    solve_equilibrium,
)

__all__ = [
    "Kinetics",
    "Loads",
    "Equilibrium",
    "FrictionSolutions",
    "Power",
    "inverse_dynamics",
    "kinetics",
    "loads",
    "equilibrium",
    "friction_solutions",
    "power_terms",
    "load_powers",
    "redundant_joints",
]


@dataclass(frozen=True, eq=False)
class Loads:
    """The generalized forces of the loads at the rows, ``(..., n_q)`` each: gravity,
    d'Alembert inertia, the external loads acting there, and the springs' and dampers'
    states (None: the model has none); ``extremes``: the extremes of the ``travel``
    conditions the external loads were switched by (``Result.extremes``)."""

    gravity: np.ndarray
    inertia: np.ndarray
    external: np.ndarray
    elements: ElementStates | None = None
    extremes: dict | None = None

    @property
    def total(self) -> np.ndarray:
        """The sum the reactions and efforts balance, Q."""
        q_load = self.gravity + self.inertia + self.external
        return q_load if self.elements is None else q_load + self.elements.q


@dataclass(frozen=True, eq=False)
class Equilibrium:
    """The frictionless reactions and driver efforts ``x0 (..., n_λ)`` balancing the loads.

    ``a_given`` the equilibrium matrix A ``(..., n_q, n_λ)``, or None where A = Φ_qᵀ is
    stood for by the kinematic factors ``lu``; ``a_inv`` its inverse where A is square
    and was inverted (NaN rows at singular positions); ``singular`` the rows where A is
    singular (x0 NaN there); ``condition`` the scaled condition number of a square A;
    ``indeterminate`` a least-squares (minimum-norm) solution of a non-square A."""

    x0: np.ndarray
    a_given: np.ndarray | None
    lu: BlockFactor | None
    singular: np.ndarray
    condition: np.ndarray | None = None
    a_inv: np.ndarray | None = None
    indeterminate: bool = False

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """x with A x = ``rhs`` at every row (the friction solutions' solve)."""
        if self.a_given is None:
            return self.lu.solve_transposed(rhs)  # A = Φ_qᵀ: back substitution over the groups
        a_inv = self.a_inv if self.a_inv is not None else np.linalg.inv(self.a_given)
        return np.einsum("...ij,...j->...i", a_inv, rhs)


@dataclass(frozen=True, eq=False)
class FrictionSolutions:
    """The friction solutions (docs/friction.md): the per-row ``setup``, the approximate
    reactions and efforts ``x_approx``, ``e_approx``, and the consistent ``solution``
    (:class:`~kinetostatics.kinetics.friction.FrictionSolution`).  ``fric["solution"]``
    reads a field by its name, as the dict of before did."""

    setup: fr.FrictionSetup
    x_approx: np.ndarray
    e_approx: np.ndarray
    solution: fr.FrictionSolution

    def __getitem__(self, name: str):
        if name not in ("setup", "x_approx", "e_approx", "solution"):
            raise KeyError(name)
        return getattr(self, name)


@dataclass(frozen=True, eq=False)
class Power(Mapping):
    """The power terms at the rows (W, ``(...)`` each): the drivers' ``input``, the rate of
    the ``kinetic`` and ``potential`` energy, the power taken by the ``external`` loads, the
    springs' (``elastic``) and dampers' (``damping``) when the model has elements, and the
    ``residual`` of the balance; with friction also the ``friction`` loss, the drivers'
    ``input_friction`` and ``residual_friction``.  A read-only mapping of the terms
    present, in that order (``power["input"]``, ``power.items()``)."""

    input: np.ndarray
    kinetic: np.ndarray
    potential: np.ndarray
    external: np.ndarray
    residual: np.ndarray
    elastic: np.ndarray | None = None
    damping: np.ndarray | None = None
    friction: np.ndarray | None = None
    input_friction: np.ndarray | None = None
    residual_friction: np.ndarray | None = None

    _ORDER = (
        "input",
        "kinetic",
        "potential",
        "external",
        "elastic",
        "damping",
        "residual",
        "friction",
        "input_friction",
        "residual_friction",
    )

    def __getitem__(self, name: str) -> np.ndarray:
        value = getattr(self, name, None) if name in self._ORDER else None
        if value is None:
            raise KeyError(name)
        return value

    def __post_init__(self):
        # the terms present, in order, listed when the record is made (it is frozen, and
        # every reader of an analysis asks: the finiteness check, the columns)
        present = {n: v for n in self._ORDER if (v := getattr(self, n)) is not None}
        object.__setattr__(self, "_present", present)

    def __iter__(self):
        return iter(self._present)

    def __len__(self) -> int:
        return len(self._present)

    def __contains__(self, name: object) -> bool:
        return name in self._present

    def keys(self):
        return self._present.keys()

    def values(self):
        return self._present.values()

    def items(self):
        return self._present.items()


@dataclass(frozen=True, eq=False)
class Kinetics:
    """Loads, reactions, friction and power at given states (arrays over positions): the
    records of the stages :func:`loads`, :func:`equilibrium`, :func:`friction_solutions`
    (None without friction) and :func:`power_terms`."""

    loads: Loads
    equilibrium: Equilibrium
    friction: FrictionSolutions | None
    power: Power

    @property
    def x0(self) -> np.ndarray:
        """Frictionless multipliers and driver efforts, ``(..., n_λ)``."""
        return self.equilibrium.x0

    @property
    def indeterminate(self) -> bool:
        return self.equilibrium.indeterminate

    @property
    def singular(self) -> np.ndarray:
        """``(...)`` A singular there: x0 NaN, friction.status 2."""
        return self.equilibrium.singular

    @property
    def condition(self) -> np.ndarray | None:
        """``(...)`` scaled condition number of a square A (None otherwise)."""
        return self.equilibrium.condition

    @property
    def lu(self) -> BlockFactor | None:
        """The kinematic factors where A = Φ_qᵀ."""
        return self.equilibrium.lu

    @property
    def a_given(self) -> np.ndarray | None:
        """Equilibrium matrix A, (..., n_q, n_λ); None: Φ_qᵀ of ``lu``."""
        return self.equilibrium.a_given

    @property
    def a(self) -> np.ndarray:
        """Equilibrium matrix A, ``(..., n_q, n_lam)`` (Φ_qᵀ assembled on demand)."""
        return self.a_given if self.a_given is not None else np.swapaxes(self.lu.jac, -1, -2)

    @property
    def q_gravity(self) -> np.ndarray:
        return self.loads.gravity

    @property
    def q_inertia(self) -> np.ndarray:
        return self.loads.inertia

    @property
    def q_external(self) -> np.ndarray:
        return self.loads.external

    @property
    def extremes(self) -> dict | None:
        """The extremes of the ``travel`` conditions the loads were evaluated with."""
        return self.loads.extremes

    @property
    def elements(self) -> ElementStates | None:
        """Springs and dampers (None: the model has none)."""
        return self.loads.elements

    @property
    def q_element(self) -> np.ndarray:
        """Generalized force of the springs and dampers (zeros without elements)."""
        return 0.0 * self.q_gravity if self.elements is None else self.elements.q

    @property
    def q_load(self) -> np.ndarray:
        return self.q_gravity + self.q_inertia + self.q_external + self.q_element


# -- the stages -------------------------------------------------------------------------
def inverse_dynamics(
    system: System,
    motion: Motion,
    *,
    ref_speed: float,
    extremes: dict | None = None,
    friction: bool = False,
) -> Kinetics:
    """Inverse dynamics at the rows of ``motion`` (a
    :class:`~kinetostatics.kinematics.motion.Motion`: its states, the drivers' coordinates
    ``psi (..., n_d)`` and the kinematic factorisation ``lu`` of Φ_q, if at hand).

    The stages in turn: the loads (gravity, d'Alembert inertia, external loads active at
    these states, springs and dampers), the frictionless reactions and driver efforts,
    the friction solutions when ``friction`` and the model has friction, and the power
    terms.  ``extremes``: the extremes of ``travel`` conditions (``Result.extremes``; by
    default :func:`travel_extremes`, over the whole motion); ``ref_speed``: the driver
    speed that scales the zero-speed thresholds.
    """
    if extremes is None:
        extremes = travel_extremes(system)
    q_loads = loads(system, motion, extremes, ref_speed)
    eq = equilibrium(system, motion, q_loads)
    fric = None
    if friction and system.model.has_friction:
        fric = friction_solutions(system, motion, q_loads, eq, ref_speed)
    return Kinetics(q_loads, eq, fric, power_terms(system, motion, q_loads, eq, fric))


def kinetics(  # noqa: PLR0913  the arrays' call of before, kept for users and dynamics/
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
    """Inverse dynamics at states (q, q̇, q̈) with driver coordinates ``psi (..., n_d)``:
    :func:`inverse_dynamics` of the :class:`~kinetostatics.kinematics.motion.Motion` they
    make (``lu``: the kinematic factorisation of Φ_q at q, if at hand)."""
    motion = Motion(None, psi, q, qd, qdd, lu=lu)
    return inverse_dynamics(
        system, motion, ref_speed=ref_speed, extremes=extremes, friction=friction
    )


def loads(system: System, motion: Motion, extremes: dict, ref_speed: float) -> Loads:
    """The generalized forces at the rows of ``motion``: gravity, d'Alembert inertia, the
    external loads acting there (their ``travel`` conditions against ``extremes``; the
    zero-speed thresholds scaled by ``ref_speed``), and the springs and dampers."""
    q, qd = motion.q, motion.qd
    return Loads(
        gravity_forces(system, q.shape[:-1]),
        inertia_forces(system, motion.qdd),
        external_forces(system, q, qd, motion.psi[..., 0], extremes, ref_speed),
        element_states(system, q, qd) if system.model.elements else None,
        extremes,
    )


def _own_efforts(system: System) -> bool:
    """Every motion driver's effort acts at its own joint (no ``balance_at``)."""
    return all(d.driver.balance_at is None for d in system.motion_drivers)


def equilibrium(system: System, motion: Motion, q_loads: Loads) -> Equilibrium:
    """The frictionless reactions and driver efforts that balance ``q_loads``: by the
    kinematic factors where A = Φ_qᵀ (``motion.lu``, each effort at its own joint); else
    by A, inverted where square (NaN rows and a warning at singular positions, and where
    the effort's joint is at rest), in least squares where not (indeterminate)."""
    q, lu = motion.q, motion.lu
    q_load = q_loads.total
    singular = np.zeros(q.shape[:-1], dtype=bool)
    own_efforts = _own_efforts(system)
    if lu is not None and own_efforts:  # A = Φ_qᵀ: the kinematic factors stand for it
        return Equilibrium(lu.solve_transposed(-q_load), None, lu, singular)
    a = equilibrium_matrix(system, q)
    if a.shape[-1] != a.shape[-2]:
        x0, indeterminate = solve_equilibrium(a, -q_load)
        return Equilibrium(x0, a, lu, singular, indeterminate=indeterminate)
    # singular positions: NaN rows, the rest intact
    a_inv, singular, condition = invert_equilibrium(a, system.l_ref)
    if not own_efforts and len(system.motion_drivers) == 1:
        # the effort's joint (nearly) at rest: no effort to round-off accuracy there
        near = effort_speed_ratio(system, q, motion.qd) <= EFFORT_SPEED_TOL
        singular |= near
        a_inv[near] = np.nan
    bad = ~np.isfinite(a_inv[..., 0, 0])
    x0 = np.linalg.solve(
        np.where(bad[..., None, None], np.eye(a.shape[-1]), a), -q_load[..., None]
    )[..., 0]
    x0[bad] = np.nan
    if singular.any():
        _warn_singular_equilibrium(system, singular, motion.psi[..., 0])
    return Equilibrium(x0, a, lu, singular, condition, a_inv)


def friction_solutions(
    system: System, motion: Motion, q_loads: Loads, eq: Equilibrium, ref_speed: float
) -> FrictionSolutions:
    """The approximate and the consistent friction solutions from the frictionless ``eq``
    (:mod:`~kinetostatics.kinetics.friction`); a StructureError where A is not square."""
    a = eq.a_given
    if a is not None and a.shape[-1] != a.shape[-2]:
        raise StructureError(
            [(Location(system.model.source, path="joints"), _not_square(system, a))]
        )
    q_load = q_loads.total
    fs = fr.setup(system, motion.q, motion.qd, ref_speed)
    solve_a = eq.solve
    a_full = eq.lu if a is None else a  # Φ_qᵀ by its blocks: no dense matrix assembled
    xa, ea = fr.approximate(system, fs, solve_a, q_load, eq.x0, a_full)  # A⁻¹(−g_k) shared
    cons = fr.consistent(system, fs, a_full, solve_a, q_load, eq.x0)
    return FrictionSolutions(fs, xa, ea, cons)


def load_powers(system: System, motion: Motion, q_loads: Loads) -> dict:
    """The power the loads take at the rows (W, ``(...)`` each): the rate of the
    ``kinetic`` and ``potential`` energy, the ``external`` loads' (−Q_ext·q̇), and with
    elements the springs' (``elastic``) and dampers' (``damping``), else None; their sum is
    what the drivers put in, frictionless (the power method of the balancing effort)."""
    qd = motion.qd
    elements = q_loads.elements
    return dict(  # the kinetic energy's rate q̇·M q̈ from d'Alembert's −M q̈ (negated exactly)
        kinetic=-np.einsum("...n,...n->...", qd, q_loads.inertia),
        potential=-np.einsum("...n,...n->...", qd, q_loads.gravity),
        external=-np.einsum("...n,...n->...", qd, q_loads.external),
        # the rate of the springs' energy; the dampers' dissipation
        elastic=None if elements is None else elements.total("power", springs=True),
        damping=None if elements is None else elements.total("power", springs=False),
    )


def power_terms(
    system: System,
    motion: Motion,
    q_loads: Loads,
    eq: Equilibrium,
    fric: FrictionSolutions | None,
) -> Power:
    """The power balance at the rows: the drivers' input (frictionless, and with friction),
    the rates of kinetic, potential and elastic energy, the external loads', the dampers'
    and the friction loss, and the residuals (zero to round-off: ``analysis/checks.py``)."""
    q, qd = motion.q, motion.qd
    rel = effort_speeds(system, q, qd)
    n_j = system.n_joint_rows
    p_input = np.sum(eq.x0[..., n_j:] * rel, axis=-1)
    terms = load_powers(system, motion, q_loads)
    stored = 0.0 if terms["elastic"] is None else terms["elastic"] + terms["damping"]
    kinetic, potential, external = terms["kinetic"], terms["potential"], terms["external"]
    terms.update(input=p_input, residual=p_input - kinetic - potential - external - stored)
    if fric is not None:
        loss = np.sum(np.abs(fric.solution.e * fric.setup.speed), axis=-1)
        input_friction = np.sum(fric.solution.x[..., n_j:] * rel, axis=-1)
        terms.update(
            friction=loss,
            input_friction=input_friction,
            residual_friction=input_friction - kinetic - potential - external - stored - loss,
        )
    return Power(**terms)


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
    texts = list(  # each once: nodes of the cycle integral on both sides of one dead centre
        dict.fromkeys(
            f"{np.degrees(c) % 360:.6g}°" if d.joint.angular else f"{c * 1e3:.6g} mm" for c in at
        )
    )
    where = ", ".join(texts[:8]) + (f" and {len(texts) - 8} more" if len(texts) > 8 else "")
    joints = sorted({(m.driver.balance_at or m.joint.name) for m in system.motion_drivers})
    warnings.warn(
        f"the equilibrium is singular at {d.name} = {where}: the effort at "
        f"{', '.join(joints)} cannot balance the loads there (a dead centre); the "
        "reactions and efforts there are NaN, friction.status 2, listed among the "
        "singular positions as 'equilibrium'",
        SingularEquilibriumWarning,
        stacklevel=4,  # the caller of inverse_dynamics (through equilibrium)
    )
