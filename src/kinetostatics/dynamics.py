"""Forward dynamics from the inverse-dynamics engine (:func:`~kinetostatics.analysis.kinetics`).

The free coordinates are the coordinates of the ``effort:`` drivers; ``motion:``
drivers stay prescribed (mixed cases).  For the equations of motion every
effort driver is turned into a motion driver of a *fully driven* copy of the
model, so that the Newton–Euler solution of :func:`kinetics` gives, at any state
(ψ, ψ̇, ψ̈), the efforts the drivers must apply.  Those are affine in the free
accelerations a = ψ̈_f (frictionless):

    τ_f(ψ, ψ̇, a) = M(ψ) a + h(ψ, ψ̇)

so one batched call with a = 0 and a = unit vectors gives the generalised
mass matrix M (the equivalent inertia J_e for one coordinate) and the bias h
(velocity products, gravity, external loads, prescribed accelerations).  The
motion follows from the applied efforts τ_app(ψ, ψ̇) (constant, table, motor
curve) and added inertias J_x (a flywheel on a free coordinate):

    (M + J_x) a = τ_app − h.

With friction, τ_f is not affine in a: the consistent friction solution of
:func:`kinetics` is used and the small nonlinear equation
τ_app − J_x a − τ_f(a) = 0 is solved at every right-hand-side evaluation
(Broyden's method started from the frictionless a with the Jacobian −(M + J_x)).
Coulomb friction is *not* regularised.  At rest the sense of friction is
undetermined: a breakaway check compares the applied effort with the efforts
needed to start moving either way (friction and velocity-opposing loads taken
in that sense); the machine starts in that sense or stays at rest (stuck).

Positions are not integrated: the state is (ψ_f, ψ̇_f), and the positions are
solved from ψ at every evaluation (:func:`~kinetostatics.positions.positions_near`),
so they lie on the constraint manifold to the Newton tolerance; the guess is a
second-order Taylor prediction from the last solved state along ψ, in steps
≤ 10° with a jump check, which keeps the solver's branch.

Loads switch (``active:`` conditions, a resistance reversing, a friction joint's
relative speed through zero) at exactly located times: each switching function
is a terminal event of ``solve_ivp``.  An integration piece holds the loads'
switching state it started with (:meth:`Dynamics.load_mode`), so its right-hand
side is smooth and continues smoothly past the switch; the switch is the root on
the piece's dense output and the next piece starts from the state there, with the
loads' state read a little past it on the old piece's continuation.  (Friction
senses still come from the state inside the friction solution.)

``scipy.integrate`` is imported only by :func:`simulate`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .conditions import travel_extremes
from .errors import (
    KinetostaticsError,
    Location,
    SelfLockingError,
    SingularConfigurationError,
    StructureError,
)
from .forces import ZERO_SPEED, activity, mass_vector, point_state, zero_speed
from .inverse import kinetics
from .model import EffortLaw, Model, MotionLaw
from .positions import derivatives, positions_near, start_pose
from .reactions import effort_joints, effort_ratio
from .schedule import schedule as _schedule
from .system import System, build_system, coordinate_gradient

__all__ = [
    "Dynamics",
    "Simulation",
    "simulate",
    "with_effort",
    "equivalent",
    "speed_fluctuation",
    "write_csv",
    "STEP",
]

STEP = np.radians(10.0)  # largest driver step of one position projection
JUMP = 0.35  # |corrector| / |move| above which a projection is a jump
PROBE = 1e-6  # probe speed at rest, × the reference speed


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
    loads = (kin.q_gravity + kin.q_external)[:n]
    return {
        "inertia": np.einsum("...n,...n->...", tangent, mass_vector(system) * tangent),
        "effort_ratio": effort_ratio(system, q, tangent),
        "inertia_derivative": -2.0 * np.einsum("...n,...n->...", tangent, kin.q_inertia[n:]),
        "torque": np.einsum("...n,...n->...", tangent, loads),
    }


@dataclass
class _Eval:
    """The terms of the equations of motion at one state."""

    t: float
    psi: np.ndarray  # (n_d,) all driver coordinates
    psi_d: np.ndarray  # (n_d,) speeds used (a probe speed at rest)
    q: np.ndarray
    qd: np.ndarray
    qdd0: np.ndarray  # q̈ at zero free accelerations
    dqdd: np.ndarray  # (n_f, n_q) q̈ per unit free acceleration
    tau0: np.ndarray  # (n_d,) efforts at zero free accelerations
    dtau: np.ndarray  # (n_f, n_d) efforts per unit free acceleration
    tangent: np.ndarray  # (n_d, n_q) ∂q/∂ψ
    accel: np.ndarray | None = None  # free accelerations, once solved
    tau: np.ndarray | None = None  # efforts the linkage needs at accel (without J_x a)
    applied: np.ndarray | None = None
    effort: np.ndarray | None = None  # efforts applied: the laws (free), the required (prescribed)
    mode: tuple | None = None  # the loads' frozen switching state (None: from the state)


class Dynamics:
    """Equations of motion of a model whose ``effort:`` drivers are free.

    Parameters
    ----------
    model : Model
        At least one ``effort:`` driver; motion drivers + effort drivers = mobility.
    inertia : mapping, optional
        Added inertia (kg·m², or kg for a prismatic driver) on free coordinates by
        driver name: a flywheel on that shaft.
    friction : bool, optional
        Friction inside the equations of motion (default: when the model has
        friction).  Needs one free coordinate and no prescribed motion.
    sense : ±1
        The expected sense of motion of the first free coordinate (the sense in
        which ``angle`` load conditions are measured, as in ``analyze``).
    ref_speed : float, optional
        Speed scale (rad/s) of the zero-speed thresholds (SPEC.md: |x| ≤ 1e-9·x_ref
        counts as zero); default the largest prescribed speed, else 1 rad/s.
    """

    def __init__(
        self,
        model: Model,
        *,
        inertia: Mapping[str, float] | None = None,
        friction: bool | None = None,
        sense: float = 1.0,
        ref_speed: float | None = None,
    ):
        motion = [d for d in model.drivers if d.motion is not None]
        free = [d for d in model.drivers if d.motion is None]
        if not free:
            raise StructureError(
                [
                    (
                        Location(model.source, path="drivers"),
                        "nothing to simulate: every driver prescribes a motion; give "
                        "the driver(s) to be set free an effort: instead of a motion:",
                    )
                ]
            )
        self.original = model
        sense = 1.0 if sense >= 0 else -1.0
        drivers = tuple(motion) + tuple(
            replace(d, motion=MotionLaw(sense), effort=None) for d in free
        )
        self.model = replace(model, drivers=drivers)
        self.system = system = build_system(self.model)
        mobility = system.structure.mobility
        if len(drivers) != mobility:
            raise StructureError(
                [
                    (
                        Location(model.source, path="drivers"),
                        f"simulate needs one driver per degree of freedom (mobility "
                        f"{mobility}); the file has {len(drivers)}: each free "
                        "coordinate is an effort driver's (effort: 0 for a passive "
                        "joint)",
                    )
                ]
            )
        self.names = [d.name for d in drivers]
        self.free_names = [d.name for d in free]
        self.n_d, self.n_f = len(drivers), len(free)
        self.free = np.arange(len(motion), len(drivers))
        self.fixed = np.arange(len(motion))
        self.laws = [_law(d.effort) for d in free]
        cons = system.motion_drivers
        self.angular = np.array([c.joint.angular for c in cons])
        self.scale = np.where(self.angular, 1.0, system.l_ref)
        self.drive = _schedule(system)
        self.added = np.zeros(self.n_f)
        for name, value in (inertia or {}).items():
            if name not in self.free_names:
                raise KeyError(
                    f"added inertia on '{name}': not a free (effort) driver; the free "
                    f"drivers are: {', '.join(self.free_names)}"
                )
            self.added[self.free_names.index(name)] += float(value)
        self.friction = (
            bool(model.has_friction if friction is None else friction) and model.has_friction
        )
        self.coulomb = self.friction or any(load.kind == "resistance" for load in model.loads)
        if self.friction and (self.n_f != 1 or motion):
            raise StructureError(
                [
                    (
                        Location(model.source, path="drivers"),
                        "forward dynamics with friction needs one free coordinate and "
                        "no prescribed motion; simulate with friction: false",
                    )
                ]
            )
        speeds = [abs(d.motion.speed) for d in motion]
        self.ref_speed = float(ref_speed or max(speeds, default=0.0) or 1.0)
        self.n_j = system.n_joint_rows
        # prescribed drivers whose effort is taken at another joint (balance_at): their
        # effort's power is effort × that joint's relative speed, not × the driver speed
        self._moved = [
            (d, k)
            for d, (c, k) in enumerate(zip(cons, effort_joints(system)))
            if c.driver.balance_at not in (None, c.joint.name)
        ]
        self.mass_vector = mass_vector(system)
        self.extremes = self._extremes()
        q0, _ = start_pose(system, self.drive)
        self._anchor = self._with_tangent(self.drive(np.array([0.0]))[0][0], q0)
        self._cache: dict = {}
        self._modes: dict = {}
        self.evaluations = 0
        self._switches = self._switching_functions()

    # -- set-up ------------------------------------------------------------------
    def _extremes(self) -> dict:
        """Extremes of ``travel`` conditions over the whole motion (a cycle of the first
        driver, :func:`~kinetostatics.analysis.travel_extremes`)."""
        return travel_extremes(self.system, self.drive)

    def prescribed(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        p, pd, _ = self.drive(np.array([t]))
        return p[0][self.fixed], pd[0][self.fixed]

    def start(self) -> np.ndarray:
        """Default initial coordinates of the free drivers (the drive's start)."""
        return self.drive(np.array([0.0]))[0][0][self.free]

    def _full(self, t: float, psi_f: np.ndarray, psid_f: np.ndarray):
        psi, psid = np.empty(self.n_d), np.empty(self.n_d)
        psi[self.fixed], psid[self.fixed] = self.prescribed(t)
        psi[self.free], psid[self.free] = psi_f, psid_f
        return psi, psid

    # -- positions on the manifold and on the branch ----------------------------------
    def _with_tangent(self, psi, q):
        eye = np.eye(self.n_d)
        qd, qdd, _ = derivatives(
            self.system,
            np.broadcast_to(q, (self.n_d, q.size)).copy(),
            eye,
            np.zeros((self.n_d, self.n_d)),
        )
        return psi.copy(), q.copy(), qd, qdd

    def _weights(self):
        return np.tile(
            [1.0 / self.system.l_ref, 1.0 / self.system.l_ref, 1.0], len(self.system.links)
        )

    def positions(self, psi: np.ndarray) -> np.ndarray:
        """q at driver coordinates ``psi (n_d,)`` on the branch followed so far.

        Steps of ≤ 10° from the last solved state with a second-order predictor
        along ψ; a step whose Newton correction is large compared with the move
        (a jump to another branch) or that fails is halved.
        """
        p, q, tan, curv = self._anchor
        target = np.asarray(psi, dtype=float)
        w = self._weights()
        limit = STEP
        while True:
            d = target - p
            size = float(np.max(np.abs(d) / self.scale)) if d.size else 0.0
            if size == 0.0:
                return q
            if size > limit:
                d = d * (limit / size)
            pred = q + d @ tan + 0.5 * (d**2) @ curv
            try:
                qn = positions_near(self.system, (p + d)[None], pred[None], self.drive)[0]
                corr = np.max(np.abs((qn - pred) * w))
                move = np.max(np.abs((qn - q) * w))
                ok = corr <= JUMP * move or corr <= 1e-9
            except KinetostaticsError:
                ok = False
            if not ok:
                limit = min(limit, size) * 0.5
                if limit < 1e-7:
                    raise SingularConfigurationError(
                        "free coordinates",
                        ", ".join(f"{n} = {v:.6g}" for n, v in zip(self.names, p + d)),
                        "the positions cannot be continued smoothly (a singular position: "
                        "the free coordinates do not describe the motion here)",
                    )
                continue
            p, q = p + d, qn
            if np.allclose(p, target, rtol=0, atol=1e-15):
                return q
            p, q, tan, curv = self._with_tangent(p, q)
            self._anchor = (p, q, tan, curv)
            limit = min(STEP, 2 * limit)

    # -- the terms of the equations of motion -------------------------------------
    def evaluate(
        self, t: float, psi_f, psid_f, direction: float = 0.0, mode: tuple | None = None
    ) -> _Eval:
        """Positions, velocities, M, h and the efforts at a state (no accelerations yet).

        ``direction``: at rest (|ψ̇_f| below the zero-speed threshold) the probe sense
        of the free coordinate used for friction and velocity-opposing loads.
        ``mode``: the loads' switching state frozen for an integration piece
        (:meth:`load_mode`); None decides it from the state.
        """
        psi_f = np.atleast_1d(np.asarray(psi_f, dtype=float))
        psid_f = np.atleast_1d(np.asarray(psid_f, dtype=float)).copy()
        if direction and self._at_rest(psid_f):
            psid_f = direction * PROBE * self.ref_speed * self.scale[self.free]
        psi, psid = self._full(t, psi_f, psid_f)
        q = self.positions(psi)
        nf, nd = self.n_f, self.n_d
        nb = 1 + nf + nd
        qb = np.broadcast_to(q, (nb, q.size)).copy()
        pd = np.concatenate((np.broadcast_to(psid, (1 + nf, nd)), np.eye(nd)))
        pdd = np.zeros((nb, nd))
        pdd[: 1 + nf, self.fixed] = self.drive(np.array([t]))[2][0][self.fixed]
        pdd[1 + np.arange(nf), self.free] = 1.0
        qd, qdd, lu = derivatives(self.system, qb, pd, pdd)
        self._anchor = (psi, q, qd[1 + nf :], qdd[1 + nf :])
        kin = kinetics(
            self._loaded(mode),
            qb,
            qd,
            qdd,
            np.broadcast_to(psi, (nb, nd)),
            lu=lu,
            ref_speed=self.ref_speed,
            extremes=self.extremes,
        )
        tau = kin.x0[:, self.n_j :]
        self.evaluations += 1
        return _Eval(
            t,
            psi,
            psid,
            q,
            qd[0],
            qdd[0],
            qdd[1 : 1 + nf] - qdd[0],
            tau[0],
            tau[1 : 1 + nf] - tau[0],
            qd[1 + nf :],
            mode=mode,
        )

    # -- loads frozen on an integration piece ------------------------------------------
    def load_mode(self, ev: _Eval) -> tuple:
        """The loads' switching state at an evaluated state: per load, whether it is
        active and (a resistance) the sign of the velocity it opposes."""
        system = self.system
        out = []
        for load in self.model.loads:
            on = bool(activity(system, load, ev.q, ev.qd, ev.psi[0], self.extremes, self.ref_speed))
            sign = 0.0
            if load.kind == "resistance":
                k = system.link_index(load.link)
                p = system.model.link(load.link).points[load.point] if load.point else np.zeros(2)
                v = float(point_state(ev.q, ev.qd, None, k, p)[1] @ load.axis)
                sign = float(np.sign(v)) if abs(v) > zero_speed(system, self.ref_speed) else 0.0
            out.append((on, sign))
        return tuple(out)

    def _loaded(self, mode: tuple | None) -> System:
        """The system whose loads are those of ``mode``, held fixed: an active load
        without its conditions (a resistance as the constant force it is on this
        piece), an inactive one left out; so the right-hand side is smooth on a piece
        and continues smoothly past its end (where the events are located)."""
        if mode is None or not self.model.loads:
            return self.system
        cached = self._modes.get(mode)
        if cached is None:
            loads = []
            for load, (on, sign) in zip(self.model.loads, mode):
                if not on or (load.kind == "resistance" and sign == 0.0):
                    continue
                if load.kind == "resistance":
                    direction = -sign * np.asarray(load.axis, dtype=float)
                    table = (
                        None
                        if load.table is None
                        else (
                            load.table[0],
                            np.asarray(load.table[1], dtype=float)[..., None] * direction,
                        )
                    )
                    load = replace(
                        load,
                        kind="force",
                        active=(),
                        table=table,
                        value=np.asarray(load.value, dtype=float)[..., None] * direction,
                    )
                else:
                    load = replace(load, active=())
                loads.append(load)
            cached = replace(self.system, model=replace(self.system.model, loads=tuple(loads)))
            self._modes[mode] = cached
        return cached

    def _at_rest(self, psid_f) -> bool:
        thr = ZERO_SPEED * self.ref_speed * self.scale[self.free]
        return bool(np.all(np.abs(psid_f) <= thr))

    def applied(self, psi_f, psid_f) -> np.ndarray:
        """The applied efforts of the free drivers (their laws)."""
        return np.array(
            [
                law(p, v, 2 * np.pi if a else None)
                for law, p, v, a in zip(self.laws, psi_f, psid_f, self.angular[self.free])
            ],
            dtype=float,
        )

    def _required_friction(self, ev: _Eval, accel: np.ndarray) -> np.ndarray:
        """Efforts of all drivers with friction (consistent solution) at ``accel``."""
        qdd = ev.qdd0 + accel @ ev.dqdd
        kin = kinetics(
            self._loaded(ev.mode),
            ev.q[None],
            ev.qd[None],
            qdd[None],
            ev.psi[None],
            ref_speed=self.ref_speed,
            extremes=self.extremes,
            friction=True,
        )
        x = kin.friction["solution"].x[0, self.n_j :]
        if not np.all(np.isfinite(x)):
            at = ", ".join(f"{n} = {v:.6g}" for n, v in zip(self.names, ev.psi))
            raise SelfLockingError(
                f"self-locking at {at}: the consistent friction solution does not exist"
            )
        return x

    def accelerations(self, ev: _Eval, psid_f) -> _Eval:
        """Solve (M + J_x) a = τ_app − h (frictionless) or, with friction,
        τ_app − J_x a − τ_f(a) = 0 by Broyden's method."""
        free = self.free
        mass = ev.dtau[:, free].T + np.diag(self.added)
        applied = self.applied(ev.psi[free], psid_f)
        accel = np.linalg.solve(mass, applied - ev.tau0[free])
        tau = ev.tau0 + accel @ ev.dtau
        if self.friction:
            jac = -mass
            tau = self._required_friction(ev, accel)
            r = applied - self.added * accel - tau[free]
            for _ in range(50):
                scale = max(
                    np.max(np.abs(applied)),
                    np.max(np.abs(tau)),
                    np.max(np.abs(mass @ accel)),
                    1e-300,
                )
                if np.max(np.abs(r)) <= 1e-11 * scale:
                    break
                step = -np.linalg.solve(jac, r)
                accel = accel + step
                tau = self._required_friction(ev, accel)
                rn = applied - self.added * accel - tau[free]
                jac = jac + np.outer(rn - r - jac @ step, step) / (step @ step)
                r = rn
            else:
                raise SelfLockingError(
                    "the acceleration with friction did not converge at "
                    + ", ".join(f"{n} = {v:.6g}" for n, v in zip(self.names, ev.psi))
                )
        ev.accel, ev.tau, ev.applied = accel, tau, applied
        ev.effort = tau.copy()
        ev.effort[free] = applied
        return ev

    def state(
        self, t: float, y: np.ndarray, direction: float = 0.0, mode: tuple | None = None
    ) -> _Eval:
        """The solved state (accelerations and efforts) at (t, y), cached."""
        nf = self.n_f
        key = (t, y[: 2 * nf].tobytes(), direction, mode)
        ev = self._cache.get(key)
        if ev is None or ev.accel is None:
            psid_f = y[nf : 2 * nf]
            ev = self.accelerations(ev or self.evaluate(t, y[:nf], psid_f, direction, mode), psid_f)
            if len(self._cache) > 8:
                self._cache.clear()
            self._cache[key] = ev
        return ev

    def rhs(
        self, t: float, y: np.ndarray, direction: float = 0.0, mode: tuple | None = None
    ) -> np.ndarray:
        """d/dt (ψ_f, ψ̇_f, W): W the work of all drivers."""
        nf = self.n_f
        ev = self.state(t, y, direction, mode)
        power = float(ev.effort @ self._effort_speeds(ev, self._speeds(t, y)))
        return np.concatenate((y[nf : 2 * nf], ev.accel, [power]))

    def _speeds(self, t, y):
        s = np.empty(self.n_d)
        s[self.fixed] = self.prescribed(t)[1]
        s[self.free] = y[self.n_f : 2 * self.n_f]
        return s

    def _effort_speeds(self, ev: _Eval, speeds: np.ndarray) -> np.ndarray:
        """The relative speeds of the joints that carry the efforts: the driver speeds,
        except for a driver whose effort is taken at another joint (``balance_at``)."""
        for d, k in self._moved:
            speeds[d] = float(coordinate_gradient(self.system, ev.q, k) @ ev.qd)
        return speeds

    # -- breakaway -------------------------------------------------------------------
    def breakaway(self, t: float, psi_f) -> dict[str, Any]:
        """At rest (one free coordinate): the efforts needed to start moving either way
        and the sense in which the applied effort starts the motion (0: stays at rest)."""
        if self.n_f != 1:
            return {"sense": 0.0, "checked": False}
        psi_f = np.atleast_1d(psi_f)
        zero = np.zeros(1)
        need = {}
        for s in (1.0, -1.0):
            ev = self.evaluate(t, psi_f, zero, direction=s)
            tau = self._required_friction(ev, zero) if self.friction else ev.tau0
            need[s] = float(tau[self.free][0])
        applied = float(self.applied(psi_f, zero)[0])
        sense = 1.0 if applied > need[1.0] else -1.0 if applied < need[-1.0] else 0.0
        return {
            "sense": sense,
            "applied": applied,
            "to_start_positive": need[1.0],
            "to_start_negative": need[-1.0],
            "checked": True,
        }

    # -- switching functions ----------------------------------------------------------
    def _switching_functions(self) -> list[tuple[str, Callable, float]]:
        """(label, f(q, qd, psi) -> value, zero threshold) of every load switch."""
        system, out = self.system, []
        vthr = ZERO_SPEED * self.ref_speed * system.l_ref
        for load in self.model.loads:
            for c in load.active:
                if c.kind == "angle":
                    for b in c.bounds:
                        out.append(
                            (
                                f"{load.name}: angle {np.degrees(b):g}°",
                                lambda q, qd, psi, b=b: np.sin(psi[0] - b),
                                1e-12,
                            )
                        )
                    continue
                k = system.link_index(c.link)
                p = system.model.link(c.link).points[c.point] if c.point else np.zeros(2)
                if c.kind == "moving":
                    out.append(
                        (
                            f"{load.name}: moving",
                            lambda q, qd, psi, k=k, p=p, c=c: (
                                point_state(q, qd, None, k, p)[1] @ c.axis
                            ),
                            vthr,
                        )
                    )
                else:
                    for b in c.bounds:
                        out.append(
                            (
                                f"{load.name}: travel {b * 1e3:g} mm",
                                lambda q, qd, psi, k=k, p=p, c=c, b=b: (
                                    point_state(q, qd, None, k, p)[0] @ c.axis
                                    - self.extremes[id(c)]
                                    - b
                                ),
                                1e-9 * system.l_ref,
                            )
                        )
            if load.kind == "resistance":
                k = system.link_index(load.link)
                p = system.model.link(load.link).points[load.point] if load.point else np.zeros(2)
                out.append(
                    (
                        f"{load.name}: reverses",
                        lambda q, qd, psi, k=k, p=p, a=load.axis: (
                            point_state(q, qd, None, k, p)[1] @ a
                        ),
                        vthr,
                    )
                )
        if self.friction:
            for k, j in enumerate(system.model.joints):
                if j.has_friction:
                    thr = ZERO_SPEED * self.ref_speed * (1.0 if j.angular else system.l_ref)
                    out.append(
                        (
                            f"{j.name}: friction reverses",
                            lambda q, qd, psi, k=k: coordinate_gradient(system, q, k) @ qd,
                            thr,
                        )
                    )
        return out

    def switching_values(
        self, t: float, y: np.ndarray, direction: float = 0.0, mode: tuple | None = None
    ) -> np.ndarray:
        if not self._switches:
            return np.zeros(0)
        ev = self._evaluated(t, y, direction, mode)
        return np.array([f(ev.q, ev.qd, ev.psi) for _, f, _ in self._switches])

    def _evaluated(
        self, t: float, y: np.ndarray, direction: float = 0.0, mode: tuple | None = None
    ) -> _Eval:
        key = (t, y[: 2 * self.n_f].tobytes(), direction, mode)
        ev = self._cache.get(key)
        if ev is None:
            ev = self.evaluate(t, y[: self.n_f], y[self.n_f : 2 * self.n_f], direction, mode)
            self._cache[key] = ev
        return ev

    def mode_at(self, t: float, y: np.ndarray, direction: float = 0.0) -> tuple:
        """The loads' switching state decided from the state (t, y)."""
        return self.load_mode(self._evaluated(t, y, direction))

    # -- energy -----------------------------------------------------------------------
    def energy(self, ev: _Eval) -> tuple[float, float]:
        """(kinetic, potential) energy at a state: ½ q̇ᵀMq̇ + ½ J_x ψ̇_f², −Σ m g·r_S."""
        kinetic = 0.5 * float(
            np.sum(self.mass_vector * ev.qd**2) + np.sum(self.added * ev.psi_d[self.free] ** 2)
        )
        g = np.tile(np.append(self.system.model.gravity, 0.0), len(self.system.links))
        return kinetic, -float(np.sum(self.mass_vector * g * ev.q))


@dataclass
class _Segment:
    t0: float
    t1: float
    sol: Callable | None  # OdeSolution, or None for a constant state
    y: np.ndarray | None = None  # the constant state
    mode: tuple | None = None  # the loads' switching state on this piece


@dataclass
class Simulation:
    """A forward-dynamics run: the state over time and what happened.

    ``sample(t)`` gives (ψ_f, ψ̇_f, W) at any times (the solver's dense output);
    ``table(t)`` the columns of ``simulation.csv``; ``events`` the load switches,
    stops and breakaway checks; ``nfev`` right-hand-side evaluations.
    """

    dynamics: Dynamics
    segments: list
    events: list = field(default_factory=list)
    nfev: int = 0
    status: str = "done"
    marks: np.ndarray = field(default_factory=lambda: np.zeros(0))
    options: dict = field(default_factory=dict)

    @property
    def t_end(self) -> float:
        return self.segments[-1].t1

    @property
    def stuck(self) -> bool:
        return self.status == "stuck"

    def sample(self, t) -> np.ndarray:
        """States (len(t), 2 n_f + 1) at times t (within [0, t_end])."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.empty((t.size, 2 * self.dynamics.n_f + 1))
        idx = self._pieces(t)
        for k in np.unique(idx):
            seg, sel = self.segments[k], idx == k
            out[sel] = (
                np.broadcast_to(seg.y, (int(sel.sum()), seg.y.size))
                if seg.sol is None
                else seg.sol(t[sel]).T
            )
        return out

    def _pieces(self, t: np.ndarray) -> np.ndarray:
        """Index of the piece holding each time (a piece's start belongs to it)."""
        starts = np.array([s.t0 for s in self.segments])
        return np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(self.segments) - 1)

    def table(self, t=None, points: int = 501) -> tuple[dict[str, np.ndarray], dict[str, str]]:
        """Columns over time: driver coordinates, speeds, accelerations and efforts
        (applied; for a free driver also ``_linkage``, the effort passed on to the
        linkage, applied − J_x a, with an added inertia J_x), the equivalent inertia
        (one free coordinate), energies and the drivers' work."""
        dyn = self.dynamics
        t = np.linspace(0.0, self.t_end, points) if t is None else np.asarray(t, dtype=float)
        y = self.sample(t)
        cols: dict[str, list] = {}
        units: dict[str, str] = {"time": "s"}
        cons = dyn.system.motion_drivers
        for tk, yk, piece in zip(t, y, self._pieces(np.atleast_1d(t))):
            direction = self._direction_at(tk)
            ev = dyn.state(float(tk), yk, direction, self.segments[piece].mode)
            acc = np.zeros(dyn.n_d)
            acc[dyn.free] = ev.accel
            speeds = dyn._speeds(tk, yk)
            row = {"time": tk}
            for d, name in enumerate(dyn.names):
                ang = cons[d].joint.angular
                row[f"{name}.{'angle' if ang else 'position'}"] = (
                    np.degrees(ev.psi[d]) if ang else ev.psi[d]
                )
                row[f"{name}.speed"] = speeds[d]
                row[f"{name}.acceleration"] = acc[d]
                word = "torque" if ang else "force"
                row[f"{name}.{word}"] = ev.effort[d]
                if d in dyn.free:
                    row[f"{name}.{word}_linkage"] = ev.tau[d]
                    units[f"{name}.{word}_linkage"] = "N*m" if ang else "N"
                units.update(
                    {
                        f"{name}.angle": "deg",
                        f"{name}.position": "m",
                        f"{name}.speed": "rad/s" if ang else "m/s",
                        f"{name}.acceleration": "rad/s^2" if ang else "m/s^2",
                        f"{name}.torque": "N*m",
                        f"{name}.force": "N",
                    }
                )
            if dyn.n_f == 1:
                row["equivalent.inertia"] = float(ev.dtau[0, dyn.free[0]])
                units["equivalent.inertia"] = "kg*m^2" if dyn.angular[dyn.free[0]] else "kg"
            kin, pot = dyn.energy(replace(ev, psi_d=speeds))
            row.update(
                {
                    "energy.kinetic": kin,
                    "energy.potential": pot,
                    "energy.total": kin + pot,
                    "work.drivers": yk[-1],
                }
            )
            for k, v in row.items():
                cols.setdefault(k, []).append(float(v))
        units.update(
            {
                "energy.kinetic": "J",
                "energy.potential": "J",
                "energy.total": "J",
                "work.drivers": "J",
            }
        )
        return {k: np.array(v) for k, v in cols.items()}, {k: units[k] for k in cols}

    def _direction_at(self, t: float) -> float:
        for e in reversed(self.events):
            if e["t"] <= t and "sense" in e:
                return e["sense"]
        return 0.0

    def to_csv(self, path, t=None, points: int = 501) -> None:
        """Write ``simulation.csv``: a ``# units:`` line, the header, one row per time."""
        write_csv(path, *self.table(t, points))


def write_csv(path, cols: dict, units: dict) -> None:
    """Columns (see :meth:`Simulation.table`) as CSV with a ``# units:`` line."""
    import csv

    names = list(cols)
    with open(path, "w", newline="") as fh:
        fh.write("# units: " + ",".join(units[n] for n in names) + "\n")
        w = csv.writer(fh)
        w.writerow(names)
        for row in np.column_stack([cols[n] for n in names]):
            w.writerow([repr(float(v)) for v in row])


def simulate(
    model: Model | Dynamics,
    until: float,
    *,
    initial: Mapping[str, float | tuple[float, float]] | None = None,
    inertia: Mapping[str, float] | None = None,
    friction: bool | None = None,
    method: str = "RK45",
    rtol: float = 1e-8,
    atol: float | None = None,
    max_step: float = np.inf,
    stop_at: float | None = None,
    mark: float | None = None,
    ref_speed: float | None = None,
) -> Simulation:
    """Integrate the motion of the free (``effort:``) coordinates from t = 0 to ``until`` s.

    Parameters
    ----------
    model : Model or Dynamics
    initial : mapping, optional
        Per free driver, its initial coordinate (rad or m) or (coordinate, speed);
        default the analysis start (or the sketch) at rest.
    inertia, friction, ref_speed
        See :class:`Dynamics` (ignored when a Dynamics is given).
    method, rtol, atol, max_step
        ``scipy.integrate.solve_ivp`` options; ``atol`` defaults to ``rtol`` for
        coordinates (rad, or × L_ref m) and ``rtol`` × the reference speed for speeds.
    stop_at : float, optional
        Stop when the first free coordinate reaches this value (rad or m).
    mark : float, optional
        Record the times at which the first free coordinate passes ``mark`` (mod 2π
        for a revolute): the cycle boundaries, ``Simulation.marks``.
    """
    from scipy.integrate import solve_ivp

    from ._checks import real_number

    until = real_number("until", until, low=0.0, strict_low=True, why="s")
    rtol = real_number("rtol", rtol, low=0.0, high=1.0, strict_low=True)
    if atol is not None:
        atol = real_number("atol", atol, low=0.0, strict_low=True)
    if not (isinstance(max_step, (int, float, np.integer, np.floating)) and max_step > 0):
        raise ValueError(f"max_step = {max_step!r}: expected a positive number (or inf)")
    for name, v in (("stop_at", stop_at), ("mark", mark)):
        if v is not None:
            real_number(name, v)
    if ref_speed is not None:
        real_number("ref_speed", ref_speed, low=0.0, strict_low=True)
    initial = dict(initial or {})
    for name, v in initial.items():
        for k, x in enumerate(v if isinstance(v, (tuple, list)) else (v,)):
            real_number(
                f"initial['{name}']" + (f"[{k}]" if isinstance(v, (tuple, list)) else ""), x
            )
    first_speed = 0.0
    if isinstance(model, Dynamics):
        dyn = model
    else:
        free = [d.name for d in model.drivers if d.motion is None]
        v = initial.get(free[0]) if free else None
        first_speed = float(v[1]) if isinstance(v, (tuple, list)) else 0.0
        sense = np.sign(first_speed) or _sense_of_effort(model, free)
        dyn = Dynamics(
            model,
            inertia=inertia,
            friction=friction,
            sense=sense,
            ref_speed=ref_speed or (abs(first_speed) or None),
        )
    nf = dyn.n_f
    psi0, psid0 = dyn.start(), np.zeros(nf)
    for name, v in initial.items():
        if name not in dyn.free_names:
            raise KeyError(
                f"initial state of '{name}': not a free (effort) driver; the free "
                f"drivers are: {', '.join(dyn.free_names)}"
            )
        k = dyn.free_names.index(name)
        psi0[k], psid0[k] = v if isinstance(v, (tuple, list)) else (v, 0.0)
    y = np.concatenate((psi0, psid0, [0.0]))
    scale = dyn.scale[dyn.free]
    if atol is None:
        atol_v = np.concatenate((rtol * scale, rtol * dyn.ref_speed * scale, [np.inf]))
    else:
        atol_v = np.concatenate((atol * scale, atol * dyn.ref_speed * scale, [np.inf]))
    sim = Simulation(dyn, [], options=dict(method=method, rtol=rtol, atol=atol))
    marks: list[float] = []
    t, direction, first_step = 0.0, 0.0, None
    evaluations0 = dyn.evaluations
    thresholds = np.array([thr for _, _, thr in dyn._switches])

    def rhs(d, m):
        return lambda tt, yy: dyn.rhs(tt, yy, d, m)

    pending = None  # the loads' state just past a switch (known from the last piece)
    mark_event = None
    if mark is not None:
        mark_event = _event(
            (lambda tt, yy: np.sin(0.5 * (yy[0] - mark)))
            if dyn.angular[dyn.free[0]]
            else (lambda tt, yy: yy[0] - mark),
            False,
        )

    stop_event = None if stop_at is None else _event(lambda tt, yy: yy[0] - stop_at, True)
    short = [e for e in (mark_event, stop_event) if e is not None]  # watched on a nudge too

    def add_marks(found):
        for x in found:  # a mark at a switch is seen by both pieces
            if not marks or abs(float(x) - marks[-1]) > 1e-9 * max(1.0, abs(float(x))):
                marks.append(float(x))

    for _ in range(100_000):
        if t >= until:
            break
        if nf == 1 and dyn._at_rest(y[nf : 2 * nf]):
            check = dyn.breakaway(t, y[:nf])
            direction = check.pop("sense")
            sim.events.append({"t": t, "kind": "rest", "sense": direction, **check})
            y[nf : 2 * nf] = 0.0
            if direction == 0.0:
                sim.segments.append(_Segment(t, until, None, y.copy()))
                sim.status = "stuck"
                break
        elif not dyn._at_rest(y[nf : 2 * nf]):
            direction = 0.0
        # switching functions at their threshold now (a start at rest, or on a band
        # edge): first a short piece without events carries them off zero
        near = np.abs(dyn.switching_values(t, y, direction)) <= 2 * thresholds
        if near.any():
            tau = 1e-10 / dyn.ref_speed
            for _ in range(30):
                tau = min(tau, until - t)
                sol0 = solve_ivp(
                    rhs(direction, pending),
                    (t, t + tau),
                    y,
                    method=method,
                    rtol=rtol,
                    atol=atol_v,
                    dense_output=True,
                    events=short or None,
                )
                if sol0.status == 1:  # the stop lies in the nudge
                    break
                y0 = sol0.y[:, -1]
                g0 = dyn.switching_values(t + tau, y0, direction)
                if np.all(np.abs(g0[near]) > 2 * thresholds[near]) or t + tau >= until:
                    break
                tau *= 4.0
            if mark_event is not None:
                add_marks(sol0.t_events[0])
            if sol0.status == 1:
                t_s = float(sol0.t[-1])
                sim.segments.append(_Segment(t, t_s, sol0.sol, mode=pending))
                sim.events.append({"t": t_s, "kind": "stop"})
                t, y = t_s, sol0.y[:, -1].copy()
                sim.status = "stopped"
                break
            sim.segments.append(_Segment(t, t + tau, sol0.sol, mode=pending))
            t, y = t + tau, y0.copy()
            near &= np.abs(g0) <= 2 * thresholds  # still on zero: not watched here
            if not dyn._at_rest(y[nf : 2 * nf]):
                direction = 0.0
            if t >= until:
                break
        # the loads' state is held fixed on the piece: its right-hand side is smooth and
        # extends smoothly past the next switch, where the event is located
        mode = pending if pending is not None else dyn.mode_at(t, y, direction)
        pending = None
        events, kinds = [], []
        for k in range(len(dyn._switches)):
            if not near[k]:
                events.append(
                    _event(
                        lambda tt, yy, k=k, d=direction, m=mode: dyn.switching_values(tt, yy, d, m)[
                            k
                        ],
                        True,
                    )
                )
                kinds.append(("switch", k))
        if dyn.coulomb and nf == 1:
            s = direction or np.sign(y[nf])
            events.append(_event(lambda tt, yy: yy[nf], True, -s))
            kinds.append(("rest", None))
        if stop_event is not None:
            events.append(stop_event)
            kinds.append(("stop", None))
        if mark_event is not None:
            events.append(mark_event)
            kinds.append(("mark", None))
        opts = {} if first_step is None else {"first_step": min(first_step, until - t)}
        sol = solve_ivp(
            rhs(direction, mode),
            (t, until),
            y,
            method=method,
            rtol=rtol,
            atol=atol_v,
            dense_output=True,
            events=events or None,
            max_step=max_step,
            **opts,
        )
        if sol.status == -1:
            raise RuntimeError(f"integration failed at t = {sol.t[-1]:.6g} s: {sol.message}")
        for (kind, _), te in zip(kinds, sol.t_events or []):
            if kind == "mark":
                add_marks(te)
        if len(sol.t) > 2:
            first_step = float(sol.t[-2] - sol.t[-3]) or None
        t_e, y_e = float(sol.t[-1]), sol.y[:, -1].copy()
        if sol.status == 0:
            sim.segments.append(_Segment(t, t_e, sol.sol, mode=mode))
            t, y = t_e, y_e
            break
        fired = [
            (kind, k)
            for (kind, k), te in zip(kinds, sol.t_events)
            if kind != "mark" and te.size and abs(te[-1] - t_e) <= 1e-12 * max(1.0, t_e)
        ]
        if any(kind == "stop" for kind, _ in fired):
            sim.segments.append(_Segment(t, t_e, sol.sol, mode=mode))
            sim.events.append({"t": t_e, "kind": "stop"})
            t, y = t_e, y_e
            sim.status = "stopped"
            break
        if any(kind == "rest" for kind, _ in fired):
            sim.segments.append(_Segment(t, t_e, sol.sol, mode=mode))
            y_e[nf : 2 * nf] = 0.0
            t, y = t_e, y_e
            continue
        # a load switch: the piece ends at the event and the next one starts from the
        # state there (the root found on this piece's dense output: its right-hand side is
        # smooth through the event).  Which side the loads take next is read a little past
        # the event on this piece's smooth continuation; the state is not moved there.
        idx = [k for kind, k in fired if kind == "switch"]
        sim.segments.append(_Segment(t, t_e, sol.sol, mode=mode))
        sim.events.append({"t": t_e, "kind": "switch", "what": [dyn._switches[k][0] for k in idx]})
        tau = 1e-10 / dyn.ref_speed
        for _ in range(17):  # at most ~1e-5 s × (1 rad/s / ref_speed)
            y_p = np.asarray(sol.sol(t_e + tau), dtype=float)
            g = dyn.switching_values(t_e + tau, y_p, direction, mode)
            if all(abs(g[k]) > 2 * thresholds[k] for k in idx):
                break
            tau *= 2.0
        pending = dyn.load_mode(dyn._evaluated(t_e + tau, y_p, direction, mode))
        t, y = t_e, y_e
    else:
        raise RuntimeError("too many integration pieces (chattering load switches?)")
    sim.nfev = dyn.evaluations - evaluations0
    sim.marks = np.array(marks)
    return sim


def _sense_of_effort(model: Model, free: list[str]) -> float:
    """The sense in which the first free driver's effort pushes (at rest), else +1."""
    if not free:
        return 1.0
    law = _law(next(d for d in model.drivers if d.name == free[0]).effort)
    v = float(law(0.0, 0.0))
    return float(np.sign(v)) or 1.0


def _bisect(f, a: float, b: float) -> float:
    fa = f(a)
    for _ in range(200):
        m = 0.5 * (a + b)
        if m in (a, b):
            break
        if fa * f(m) <= 0:
            b = m
        else:
            a, fa = m, f(m)
    return 0.5 * (a + b)


def _event(f, terminal: bool, direction: float = 0.0):
    f.terminal, f.direction = terminal, float(direction)
    return f


def speed_fluctuation(sim: Simulation, t0: float, t1: float, samples: int = 4001) -> dict:
    """ω_max, ω_min, ω_mean (= travel / time) and δ = (ω_max − ω_min)/ω_mean of the first
    free coordinate over [t0, t1].

    The extremes are those of the solution itself: on every integration piece the
    speed is smooth, so its extremes are the piece's ends (the load switches, where ω
    has a corner, and t0, t1) and the interior stationary points (ω̇ = 0), each located
    on the piece's dense output by a bounded scalar search around the sampled local
    extreme; ``samples`` (spread over [t0, t1]) only brackets them.
    """
    from scipy.optimize import minimize_scalar

    nf = sim.dynamics.n_f
    bounds = [s.t0 for s in sim.segments[1:]]
    edges = np.unique(np.clip([t0, t1] + [b for b in bounds if t0 < b < t1], t0, t1))
    candidates: list[float] = []
    for a, b in zip(edges[:-1], edges[1:]):
        seg = sim.segments[int(sim._pieces(np.array([0.5 * (a + b)]))[0])]
        n = max(16, int(np.ceil(samples * (b - a) / (t1 - t0))))
        t = np.linspace(a, b, n)
        w = np.abs(seg.sol(t)[nf]) if seg.sol is not None else np.full(n, abs(seg.y[nf]))
        candidates += [w[0], w[-1]]  # the piece's own values at its ends
        if seg.sol is None:
            continue
        for k in range(n):
            for sign in (1.0, -1.0):
                # a sampled local extreme, or an extreme just inside a piece end (where
                # ω may turn within the first or last sampling interval)
                if (
                    k == 0
                    or k == n - 1
                    or sign * (w[k] - w[k - 1]) > 0
                    and sign * (w[k] - w[k + 1]) >= 0
                ):
                    lo, hi = t[max(k - 1, 0)], t[min(k + 1, n - 1)]
                    r = minimize_scalar(
                        lambda tt: -sign * abs(float(seg.sol(tt)[nf])),
                        bounds=(lo, hi),
                        method="bounded",
                        options={"xatol": 1e-14 * max(1.0, abs(b))},
                    )
                    candidates.append(max(w[k], -r.fun) if sign > 0 else min(w[k], r.fun))
    w_max, w_min = max(candidates), min(candidates)
    travel = sim.sample([t0, t1])[:, 0]
    mean = abs(travel[-1] - travel[0]) / (t1 - t0)
    return {
        "omega_max": float(w_max),
        "omega_min": float(w_min),
        "omega_mean": float(mean),
        "omega_average": 0.5 * float(w_max + w_min),
        "delta": float((w_max - w_min) / mean),
        "t0": float(t0),
        "t1": float(t1),
    }
